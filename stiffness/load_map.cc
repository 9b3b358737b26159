#include "stiffness/load_map.h"

#include "common/errors.h"
#include "meshing/pair_kinematics.h"

#include <cmath>
#include <limits>

namespace hertzgear::stiffness
{
  std::vector<MapCase> map_cases(const StiffnessInput &in)
  {
    std::vector<MapCase> cases;
    if (!in.has_map())
      return cases;
    // A crowning variant crowns both gears; without variants each keeps its own (NaN).
    std::vector<double> crownings = in.crowning_map_mm;
    if (crownings.empty())
      crownings.push_back(std::numeric_limits<double>::quiet_NaN());
    std::vector<double> percents = in.torque_map_percent;
    if (percents.empty() && !in.crowning_map_mm.empty())
      percents.push_back(100.0);
    const auto add = [&](const double percent, const double crowning, const double misalignment) {
      MapCase c;
      c.torque_percent       = percent;
      c.torque_Nm            = in.torque_Nm * percent / 100.0;
      c.pinion_crowning_mm   = std::isnan(crowning) ? in.pair.pinion.crowning_mm : crowning;
      c.gear_crowning_mm     = std::isnan(crowning) ? in.pair.gear.crowning_mm : crowning;
      c.mesh_misalignment_mm = misalignment;
      cases.push_back(c);
    };
    for (const double crowning : crownings)
      for (const double percent : percents)
        add(percent, crowning, in.pair.mesh_misalignment_mm);
    for (const double crowning : crownings)
      for (const double misalignment : in.misalignment_map_mm)
        add(100.0, crowning, misalignment);
    return cases;
  }

  meshing::PairParameters map_case_pair(const StiffnessInput &in, const MapCase &c)
  {
    meshing::PairParameters p = in.pair;
    p.pinion.crowning_mm      = c.pinion_crowning_mm;
    p.gear.crowning_mm        = c.gear_crowning_mm;
    p.mesh_misalignment_mm    = c.mesh_misalignment_mm;
    return p;
  }

  // The map's inputs before any work: positive torques, and every variant a valid pair.
  void check_map(const StiffnessInput &in)
  {
    for (const double percent : in.torque_map_percent)
      if (!(percent > 0))
        throw ParameterError("torque_map_percent",
                             msg(percent, ": every torque of the map must be positive (% of {torque_Nm})"));
    if (in.has_map() && in.fe.dimension != 3 &&
        (!in.crowning_map_mm.empty() || !in.misalignment_map_mm.empty()))
      throw ParameterError(in.crowning_map_mm.empty() ? "misalignment_map_mm" : "crowning_map_mm",
                           "lead crowning and misalignment vary along the face: they need {dimension} = 3");
    for (const auto &c : map_cases(in))
      try
        {
          meshing::PairKinematics kinematics(map_case_pair(in, c));
        }
      catch (const InputError &e)
        {
          const bool crowning = c.pinion_crowning_mm != in.pair.pinion.crowning_mm ||
                                c.gear_crowning_mm != in.pair.gear.crowning_mm;
          throw ParameterError(crowning ? "crowning_map_mm" : "misalignment_map_mm",
                               msg(crowning ? c.pinion_crowning_mm * 1e3 : c.mesh_misalignment_mm * 1e3,
                                   " um: ", e.what()));
        }
  }

  void check_load_ladder(const StiffnessInput &in)
  {
    const auto &l = in.load_ladder_percent;
    if (l.empty())
      return;
    if (l.size() < 2)
      throw ParameterError("load_ladder_percent",
                           msg(l.size(), " load: the FE force law interpolates between at least 2"));
    for (std::size_t j = 0; j < l.size(); ++j)
      {
        if (!(l[j] > 0))
          throw ParameterError("load_ladder_percent",
                               msg(l[j], ": every load of the ladder must be positive (% of {torque_Nm})"));
        if (j > 0 && !(l[j] > l[j - 1]))
          throw ParameterError("load_ladder_percent",
                               msg(l[j - 1], ", then ", l[j], ": the loads of the ladder must increase"));
      }
    if (l.back() < 100.0)
      throw ParameterError("load_ladder_percent",
                           msg(l.back(), " %: the ladder does not reach the nominal load (100 % of "
                                         "{torque_Nm}); the dynamics visit loads up to several times it"));
  }
} // namespace hertzgear::stiffness
