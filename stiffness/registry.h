#pragma once
// The registry of stiffness sources: the one list that the scene's Stiffness/source, the
// pipeline, the `stiffness` command and the generated docs read. A source is registered by one
// line in registry.cc (docs/architecture.md, "Adding a stiffness source").
#include "stiffness/stiffness_source.h"

#include <string>
#include <vector>

namespace hertzgear::stiffness
{
  // Every source, in the order of the registry (sources this build cannot compute included:
  // available() says so).
  const std::vector<const StiffnessSource *> &sources();

  // The names, in registry order.
  std::vector<std::string> source_names();

  // The source of that name. Throws ParameterError("source", ...) for an unknown name (listing
  // the known ones) and for a source this build cannot compute.
  const StiffnessSource &find_source(const std::string &name);
} // namespace hertzgear::stiffness
