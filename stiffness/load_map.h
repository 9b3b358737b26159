#pragma once
// The load and design map of a contact analysis (StiffnessInput's torque_map_percent,
// crowning_map_mm, misalignment_map_mm, helix_slope_map_mm, map_product): which cases it holds
// and the pair of each. Each case is a
// further contact cycle on the same bodies (docs/theory-tca.md, "Torque maps and design
// variants"). No deal.II: the FE source runs the cases, these only name them.
#include "meshing/gear_parameters.h"
#include "stiffness/stiffness_source.h"

#include <vector>

namespace hertzgear::stiffness
{
  // Without map_product: every torque (none: the input's) with every lead crowning variant (each
  // on both gears; none: the pair's own crowning), then every misalignment variant and then every
  // helix slope variant (the pinion's f_Hb; the gear keeps its own) at the input's torque, each
  // with every crowning variant. With map_product: every crowning x f_Hb x misalignment x torque
  // (nested in that order, an empty axis the pair's own value, no torques 100 %). Empty without
  // a map. Rows and pattern left empty.
  std::vector<MapCase> map_cases(const StiffnessInput &input);

  // The pair of a case: the input's with the case's crowning, mesh misalignment and helix slope
  // deviations.
  meshing::PairParameters map_case_pair(const StiffnessInput &input, const MapCase &c);

  // Before any work: every torque positive, variants along the face only in 3D, and every case a
  // pair the kinematics accept. Throws ParameterError naming the map's field whose value the pair
  // does not take alone, or map_combination for a case whose values it takes alone but not
  // together.
  void check_map(const StiffnessInput &input);

  // Before any work: a load ladder of at least 2 positive, increasing loads whose top reaches
  // the nominal torque (100 %). Throws ParameterError naming load_ladder_percent.
  void check_load_ladder(const StiffnessInput &input);
} // namespace hertzgear::stiffness
