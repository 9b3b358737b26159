#pragma once
// A stiffness table file as an input (sources table and fourier): read as a regular file of
// bounded size and nesting, and tied to the pair and load it was computed for. The writer records
// the pair (pair_record, under "pair" in stiffness.json) beside "load_N"; reading refuses a table
// of another pair, micro-geometry or misalignment, and warns when the load differs. An entry a
// table does not record (written before the record held it) is not checked: a warning names it
// when the scene's value is not zero.
#include "meshing/gear_parameters.h"
#include "stiffness/stiffness_source.h"

#include <nlohmann/json.hpp>

namespace hertzgear::stiffness
{
  // The pair's defining values in the units of the scene keys: teeth, module, pressure angle,
  // face widths, profile shifts, lead crowning, the micro-geometry of each gear (tip relief with
  // its length and, when there is one, its shape; helix slope deviation, lead end relief, profile
  // crowning, root relief) and the misalignment of the pair (mesh misalignment, axis inclination
  // and deviation).
  nlohmann::json pair_record(const meshing::PairParameters &pair);

  // The table of input.table_file. Throws ParameterError("table_file", ...) for a file that is
  // missing, not a regular file, too large, not a table, or computed for another pair; prints a
  // warning line when its load differs from input.torque_Nm's.
  table::StiffnessTable read_table_for(const StiffnessInput &input);
} // namespace hertzgear::stiffness
