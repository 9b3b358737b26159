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
      return nlohmann::json{{"teeth", g.teeth},
                            {"face_width_mm", g.face_width_mm},
                            {"profile_shift_coefficient", g.profile_shift_coefficient},
                            {"crowning_um", g.crowning_mm * 1e3}};
    };
    return {{"module_mm", pair.pinion.module_mm},
            {"pressure_angle_deg", pair.pinion.pressure_angle_rad * 180 / M_PI},
            {"pinion", gear(pair.pinion)},
            {"gear", gear(pair.gear)}};
  }

  namespace
  {
    // The entries of two pair records that differ (relative 1e-9), as "key a (table) / b (scene)".
    void differences(const nlohmann::json &table, const nlohmann::json &scene, const std::string &path,
                     std::ostringstream &out)
    {
      for (const auto &[key, value] : scene.items())
        {
          const std::string name = path.empty() ? key : path + "/" + key;
          if (!table.contains(key))
            continue;
          if (value.is_object())
            differences(table.at(key), value, name, out);
          else if (table.at(key).is_number() && value.is_number())
            {
              const double a = table.at(key).get<double>(), b = value.get<double>();
              if (std::abs(a - b) > 1e-9 * std::max({1.0, std::abs(a), std::abs(b)}))
                out << (out.tellp() > 0 ? ", " : "") << name << " " << a << " (table) / " << b << " (scene)";
            }
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
        std::ostringstream diff;
        differences(json.at("pair"), pair_record(input.pair), "", diff);
        if (diff.tellp() > 0)
          throw ParameterError("table_file",
                               msg(file, " was computed for another pair: ", diff.str(),
                                   "; compute the table for this scene (hertzgear stiffness)"));
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
