#pragma once
// The load and design map of a contact analysis (StiffnessInput's torque_map_percent,
// crowning_map_mm, misalignment_map_mm): which cases it holds and the pair of each. Each case is a
// further contact cycle on the same bodies (docs/theory-tca.md, "Torque maps and design
// variants"). No deal.II: the FE source runs the cases, these only name them.
#include "meshing/gear_parameters.h"
#include "stiffness/stiffness_source.h"

#include <vector>

namespace hertzgear::stiffness
{
  // Every torque (none: the input's) with every lead crowning variant (each on both gears; none:
  // the pair's own crowning), then every misalignment variant at the input's torque with every
  // crowning variant. Empty without a map. Rows and pattern left empty.
  std::vector<MapCase> map_cases(const StiffnessInput &input);

  // The pair of a case: the input's with the case's crowning and mesh misalignment.
  meshing::PairParameters map_case_pair(const StiffnessInput &input, const MapCase &c);

  // Before any work: every torque positive, variants along the face only in 3D, and every case a
  // pair the kinematics accept. Throws ParameterError naming the map's field.
  void check_map(const StiffnessInput &input);

  // Before any work: a load ladder of at least 2 positive, increasing loads whose top reaches
  // the nominal torque (100 %). Throws ParameterError naming load_ladder_percent.
  void check_load_ladder(const StiffnessInput &input);
} // namespace hertzgear::stiffness
