// Stiffness source table: a stiffness table file (stiffness.json of a stiffness run, or the tables
// shipped in data/stiffness/), read by the dynamics directly.
#include "common/errors.h"
#include "common/input_file.h"
#include "common/progress.h"
#include "meshing/gear_geometry.h"
#include "stiffness/stiffness_source.h"
#include "stiffness/table_file.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace hertzgear::stiffness
{
  namespace
  {
    class TableSource : public DirectSource
    {
    public:
      TableSource()
        : DirectSource("table", "a stiffness table file, no meshing or FE")
      {}

      StiffnessResult compute(const StiffnessInput &input, PhaseTimer &) const override
      {
        StiffnessResult r;
        r.table = read_table_for(input);
        if (!(std::abs(r.table.hertz_exponent - input.hertz_exponent) < 1e-12))
          throw ParameterError("hertz_exponent",
                               msg(input.hertz_exponent, ", but the stiffness table ",
                                   input.table_file.string(), " has hertz_exponent = ",
                                   r.table.hertz_exponent, "; make them agree"));
        r.table.check();
        return r;
      }
    };
  } // namespace

  nlohmann::json pair_record(const meshing::PairParameters &pair)
  {
    const auto gear = [](const meshing::GearParameters &g) {
      nlohmann::json j = {{"teeth", g.teeth},
                          {"face_width_mm", g.face_width_mm},
                          {"profile_shift_coefficient", g.profile_shift_coefficient},
                          {"crowning_um", g.crowning_mm * 1e3},
                          {"tip_relief_um", g.tip_relief_mm * 1e3},
                          {"tip_relief_length_mm", g.tip_relief_length_mm},
                          {"helix_slope_deviation_um", g.helix_slope_deviation_mm * 1e3},
                          {"lead_end_relief_um", g.lead_end_relief_mm * 1e3},
                          {"lead_end_relief_length_mm", g.lead_end_relief_length_mm},
                          {"profile_crowning_um", g.profile_crowning_mm * 1e3},
                          {"root_relief_um", g.root_relief_mm * 1e3},
                          {"root_relief_length_mm", g.root_relief_length_mm}};
      if (g.tip_relief_mm != 0) // the shape of no relief is no property of the table
        j["tip_relief_shape"] =
          g.tip_relief_shape == meshing::TipReliefShape::parabolic ? "parabolic" : "linear";
      if (g.helix_angle_rad != 0) // a spur pair's record is the one it had before helical pairs
        {
          j["helix_angle_deg"] = g.helix_angle_rad * 180 / M_PI;
          j["hand"]            = g.hand == meshing::HelixHand::left ? "left" : "right";
        }
      return j;
    };
    return {{"module_mm", pair.pinion.module_mm},
            {"pressure_angle_deg", pair.pinion.pressure_angle_rad * 180 / M_PI},
            {"pinion", gear(pair.pinion)},
            {"gear", gear(pair.gear)},
            {"mesh_misalignment_um", pair.mesh_misalignment_mm * 1e3},
            {"axis_inclination_um", pair.axis_inclination_mm * 1e3},
            {"axis_deviation_um", pair.axis_deviation_mm * 1e3}};
  }

  namespace
  {
    // The input field a pair record's entry comes from, as {field} (app/ names its scene key):
    // "pinion/tip_relief_um" -> {pinion.tip_relief_mm}, "module_mm" -> {pinion.module_mm}.
    std::string field_of(const std::string &path)
    {
      const auto  slash = path.find('/');
      std::string gear  = slash == std::string::npos ? "" : path.substr(0, slash);
      std::string key   = slash == std::string::npos ? path : path.substr(slash + 1);
      if (key.size() > 3 && key.compare(key.size() - 3, 3, "_um") == 0)
        key.replace(key.size() - 3, 3, "_mm");
      if (key == "pressure_angle_deg" || key == "helix_angle_deg")
        key.replace(key.size() - 3, 3, "rad");
      if (gear.empty() && (key == "module_mm" || key == "pressure_angle_rad"))
        gear = "pinion";
      return "{" + (gear.empty() ? key : gear + "." + key) + "}";
    }

    // The entries of two pair records that differ (relative 1e-9), as "{field} a (table) / b
    // (scene)", and in `unrecorded` the entries the table lacks where the scene's value is not
    // zero (a table written before its record held them: "not recorded", not checked).
    void differences(const nlohmann::json &table, const nlohmann::json &scene, const std::string &path,
                     std::ostringstream &out, std::vector<std::string> &unrecorded)
    {
      for (const auto &[key, value] : scene.items())
        {
          const std::string name = path.empty() ? key : path + "/" + key;
          if (!table.contains(key))
            {
              if ((value.is_number() && value.get<double>() != 0) || value.is_string())
                unrecorded.push_back(name);
              continue;
            }
          if (value.is_object())
            differences(table.at(key), value, name, out, unrecorded);
          else if (table.at(key).is_number() && value.is_number())
            {
              const double a = table.at(key).get<double>(), b = value.get<double>();
              if (std::abs(a - b) > 1e-9 * std::max({1.0, std::abs(a), std::abs(b)}))
                out << (out.tellp() > 0 ? ", " : "") << field_of(name) << " " << a << " (table) / "
                    << b << " (scene)";
            }
          else if (table.at(key).is_string() && value.is_string() && table.at(key) != value)
            out << (out.tellp() > 0 ? ", " : "") << field_of(name) << " "
                << table.at(key).get<std::string>() << " (table) / " << value.get<std::string>()
                << " (scene)";
        }
    }
  } // namespace

  table::StiffnessTable read_table_for(const StiffnessInput &input)
  {
    const std::string file = input.table_file.string();
    std::string       text;
    try
      {
        text = read_input_file(input.table_file, "stiffness table", table::max_table_bytes);
      }
    catch (const ParameterError &)
      {
        throw;
      }
    catch (const InputError &e)
      {
        throw ParameterError("table_file", e.what());
      }
    const std::size_t depth = json_nesting_depth(text);
    if (depth > max_json_nesting)
      throw ParameterError("table_file", msg(file, ": nested ", depth, " levels deep, more than the ",
                                             max_json_nesting, " levels a stiffness table can have"));
    table::StiffnessTable table;
    nlohmann::json           json;
    try
      {
        table = table::stiffness_table_from_json_text(text, file);
        json  = nlohmann::json::parse(text);
      }
    catch (const InputError &e)
      {
        const std::string what = e.what();
        throw ParameterError("table_file", what.rfind(file, 0) == 0 ? what : msg(file, ": ", what));
      }
    if (json.contains("pair") && json.at("pair").is_object())
      {
        // The geometry, micro-geometry and misalignment shape the table as much as the pair's
        // teeth do: a table of other values is refused, whichever differs.
        std::ostringstream       diff;
        std::vector<std::string> unrecorded;
        // A record without a helix angle is a spur pair's (the scene's, and every table written
        // before helical pairs): compared as 0 both ways, a spur table never serves a helical
        // scene nor a helical table a spur one.
        nlohmann::json recorded = json.at("pair"), scene = pair_record(input.pair);
        for (nlohmann::json *record : {&recorded, &scene})
          for (const char *gear : {"pinion", "gear"})
            if (record->contains(gear) && record->at(gear).is_object() &&
                !record->at(gear).contains("helix_angle_deg"))
              (*record)[gear]["helix_angle_deg"] = 0.0;
        differences(recorded, scene, "", diff, unrecorded);
        if (diff.tellp() > 0)
          throw ParameterError("table_file",
                               msg(file, " was computed for another pair: ", diff.str(),
                                   "; compute the table for this scene (hertzgear stiffness)"));
        if (!unrecorded.empty())
          {
            std::string list;
            for (const auto &name : unrecorded)
              list += (list.empty() ? "" : ", ") + name;
            progress_line("stiffness",
                          msg("warning: the stiffness table ", file, " does not record ", list,
                              " of its pair (a table written before its pair record held the "
                              "micro-geometry and misalignment): this scene's values of them "
                              "are not checked against the table"));
          }
      }
    if (json.contains("load_N") && json.at("load_N").is_number() && input.torque_Nm > 0)
      {
        const double table_load = json.at("load_N").get<double>();
        const double load = input.torque_Nm * 1e3 / meshing::base_radius_mm(input.pair.pinion);
        if (std::abs(table_load - load) > 1e-6 * load)
          progress_line("stiffness",
                        msg("warning: the stiffness table ", file, " was computed at a mesh load of ",
                            table_load, " N; this run's torque gives ", load,
                            " N (the loaded stiffness depends on the load)"));
      }
    return table;
  }

  const StiffnessSource &table_source() { return the_source<TableSource>(); }
} // namespace hertzgear::stiffness
