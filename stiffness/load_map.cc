#include "stiffness/load_map.h"

#include "common/errors.h"
#include "meshing/pair_kinematics.h"

#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace hertzgear::stiffness
{
  std::vector<MapCase> map_cases(const StiffnessInput &in)
  {
    std::vector<MapCase> cases;
    if (!in.has_map())
      return cases;
    // An empty axis keeps the pair's own value: NaN marks it (a crowning variant crowns both
    // gears, an f_Hb variant is the pinion's).
    constexpr double own       = std::numeric_limits<double>::quiet_NaN();
    const auto       or_own    = [&](std::vector<double> axis) {
      if (axis.empty())
        axis.push_back(own);
      return axis;
    };
    const std::vector<double> crownings = or_own(in.crowning_map_mm);
    const std::vector<double> slopes    = or_own(in.helix_slope_map_mm);
    const std::vector<double> tilts     = or_own(in.misalignment_map_mm);
    std::vector<double>       percents  = in.torque_map_percent;
    const auto add = [&](const double percent, const double crowning, const double misalignment,
                         const double slope) {
      MapCase c;
      c.torque_percent                  = percent;
      c.torque_Nm                       = in.torque_Nm * percent / 100.0;
      c.pinion_crowning_mm              = std::isnan(crowning) ? in.pair.pinion.crowning_mm : crowning;
      c.gear_crowning_mm                = std::isnan(crowning) ? in.pair.gear.crowning_mm : crowning;
      c.mesh_misalignment_mm            = std::isnan(misalignment) ? in.pair.mesh_misalignment_mm : misalignment;
      c.pinion_helix_slope_deviation_mm = std::isnan(slope) ? in.pair.pinion.helix_slope_deviation_mm : slope;
      c.gear_helix_slope_deviation_mm   = in.pair.gear.helix_slope_deviation_mm;
      cases.push_back(c);
    };
    if (in.map_product)
      {
        // Every combination; torque innermost, so that each design's STE-against-torque curve
        // is contiguous, crowning outermost.
        if (percents.empty())
          percents.push_back(100.0);
        for (const double crowning : crownings)
          for (const double slope : slopes)
            for (const double misalignment : tilts)
              for (const double percent : percents)
                add(percent, crowning, misalignment, slope);
        return cases;
      }
    if (percents.empty() && !in.crowning_map_mm.empty())
      percents.push_back(100.0);
    for (const double crowning : crownings)
      for (const double percent : percents)
        add(percent, crowning, own, own);
    for (const double crowning : crownings)
      for (const double misalignment : in.misalignment_map_mm)
        add(100.0, crowning, misalignment, own);
    for (const double crowning : crownings)
      for (const double slope : in.helix_slope_map_mm)
        add(100.0, crowning, own, slope);
    return cases;
  }

  meshing::PairParameters map_case_pair(const StiffnessInput &in, const MapCase &c)
  {
    meshing::PairParameters p          = in.pair;
    p.pinion.crowning_mm               = c.pinion_crowning_mm;
    p.gear.crowning_mm                 = c.gear_crowning_mm;
    p.mesh_misalignment_mm             = c.mesh_misalignment_mm;
    p.pinion.helix_slope_deviation_mm  = c.pinion_helix_slope_deviation_mm;
    p.gear.helix_slope_deviation_mm    = c.gear_helix_slope_deviation_mm;
    return p;
  }

  // The map's inputs before any work: positive torques, and every variant a valid pair.
  void check_map(const StiffnessInput &in)
  {
    for (const double percent : in.torque_map_percent)
      if (!(percent > 0))
        throw ParameterError("torque_map_percent",
                             msg(percent, ": every torque of the map must be positive (% of {torque_Nm})"));
    struct Axis
    {
      const char *field, *what;
      const std::vector<double> &values;
      double MapCase::*member; // the case's value this axis sets
    };
    const Axis axes[] = {
      {"crowning_map_mm", "a lead crowning", in.crowning_map_mm, &MapCase::pinion_crowning_mm},
      {"misalignment_map_mm", "a misalignment", in.misalignment_map_mm, &MapCase::mesh_misalignment_mm},
      {"helix_slope_map_mm", "a helix slope deviation", in.helix_slope_map_mm,
       &MapCase::pinion_helix_slope_deviation_mm}};
    if (in.has_map() && in.fe.dimension != 3)
      for (const Axis &axis : axes)
        if (!axis.values.empty())
          throw ParameterError(axis.field, msg(axis.values.front() * 1e3, " um: ", axis.what,
                                               " varies along the face: it needs {dimension} = 3"));
    if (!in.has_map())
      return;
    const auto refusal = [&](const MapCase &c) -> std::optional<std::string> {
      try
        {
          meshing::PairKinematics kinematics(map_case_pair(in, c));
        }
      catch (const InputError &e)
        {
          return std::string(e.what());
        }
      return std::nullopt;
    };
    // Each value alone on the pair names its own field; then a combination of values each of
    // which the pair takes alone names the combination.
    MapCase own;
    own.pinion_crowning_mm              = in.pair.pinion.crowning_mm;
    own.gear_crowning_mm                = in.pair.gear.crowning_mm;
    own.mesh_misalignment_mm            = in.pair.mesh_misalignment_mm;
    own.pinion_helix_slope_deviation_mm = in.pair.pinion.helix_slope_deviation_mm;
    own.gear_helix_slope_deviation_mm   = in.pair.gear.helix_slope_deviation_mm;
    for (const Axis &axis : axes)
      for (const double value : axis.values)
        {
          MapCase c     = own;
          c.*axis.member = value;
          if (axis.member == &MapCase::pinion_crowning_mm)
            c.gear_crowning_mm = value;
          if (const auto why = refusal(c))
            throw ParameterError(axis.field, msg(value * 1e3, " um: ", *why));
        }
    for (const auto &c : map_cases(in))
      if (const auto why = refusal(c))
        throw ParameterError("map_combination",
                             msg(in.map_product ? "product" : "separate", ": crowning ",
                                 c.pinion_crowning_mm * 1e3, " um with misalignment ",
                                 c.mesh_misalignment_mm * 1e3, " um and helix slope deviation ",
                                 c.pinion_helix_slope_deviation_mm * 1e3, " um, each of which the pair "
                                 "takes alone, together: ", *why));
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
