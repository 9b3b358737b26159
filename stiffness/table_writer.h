#pragma once
// The one writer of a stiffness result: stiffness.csv (a row per mesh position, units in the
// column names) and stiffness.json (the dynamics' table, schema hertzgear-stiffness-table/1, plus
// the fits of k_total and STE, means, peak-to-peak STE and the source's notes). Schema in
// docs/architecture.md, "Stiffness table schema".
#include "stiffness/stiffness_source.h"

#include <nlohmann/json.hpp>

#include <string>

namespace hertzgear::stiffness
{
  std::string    stiffness_csv(const StiffnessResult &result);
  nlohmann::json stiffness_json(const StiffnessResult &result);
  // The load and design map (StiffnessResult::map): stiffness_map.csv, the rows of every case
  // with its torque, crowning and misalignment in front; and its summary per case (the "map"
  // array of stiffness.json).
  std::string    stiffness_map_csv(const StiffnessResult &result);
  nlohmann::json stiffness_map_json(const StiffnessResult &result);
  // contact_pattern.csv: the loaded cells on the pinion flank per position, case -1 for the
  // scene's own cycle, then the map's cases.
  std::string contact_pattern_csv(const StiffnessResult &result);

  // Peak-to-peak of the loaded STE over the rows [um].
  double ste_peak_to_peak_um(const StiffnessResult &result);
} // namespace hertzgear::stiffness
