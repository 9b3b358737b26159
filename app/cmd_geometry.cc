// `hertzgear geometry SCENE [--json]`: gear geometry, pair kinematics and ISO 6336-1 stiffness.
#include "app/command.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "common/errors.h"
#include "common/progress.h"
#include "stiffness/iso6336.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>

namespace hertzgear
{
  namespace
  {
    constexpr double rad_to_deg = 180.0 / M_PI;

    nlohmann::json gear_json(const meshing::GearGeometry &g)
    {
      nlohmann::json j;
      j["teeth"]                   = g.n_teeth();
      j["reference_radius_mm"]     = g.reference_radius_mm();
      j["base_radius_mm"]          = g.base_radius_mm();
      j["tip_radius_mm"]           = g.tip_radius_mm();
      j["root_radius_mm"]          = g.root_radius_mm();
      j["form_radius_mm"]          = g.form_radius_mm();
      j["bore_radius_mm"]          = g.bore_radius_mm();
      j["reference_tooth_thickness_mm"] = g.reference_tooth_thickness_mm();
      j["top_land_mm"]             = g.top_land_mm();
      j["thickness_reduction_mm"]  = g.parameters().thickness_reduction_mm;
      const double R               = g.crowning_radius_mm();
      j["crowning_radius_mm"]      = std::isfinite(R) ? nlohmann::json(R) : nlohmann::json(nullptr);
      j["crowning_um"]             = g.parameters().crowning_mm * 1e3;
      return j;
    }

    nlohmann::json geometry_json(const meshing::PairKinematics &pair, const Scene &scene)
    {
      nlohmann::json j;
      j["contact_ratio"]                = pair.contact_ratio();
      j["center_distance_mm"]           = pair.center_distance_mm();
      j["reference_center_distance_mm"] = pair.reference_center_distance_mm();
      j["operating_pressure_angle_deg"] = pair.operating_pressure_angle_rad() * rad_to_deg;
      j["base_pitch_mm"]                = pair.base_pitch_mm();
      j["path_of_contact_mm"]           = pair.path_of_contact_mm();
      j["line_of_action_length_mm"]     = pair.line_of_action_length_mm();
      j["backlash_loa_mm"]              = pair.backlash_loa_mm();
      j["pinion"]                       = gear_json(pair.pinion());
      j["gear"]                         = gear_json(pair.gear());
      j["pinion"]["operating_pitch_radius_mm"] = pair.operating_pitch_radius_mm(0);
      j["gear"]["operating_pitch_radius_mm"]   = pair.operating_pitch_radius_mm(1);
      for (const char c : {'A', 'B', 'C', 'D', 'E'})
        {
          const auto p = pair.point(c);
          j["points"][std::string(1, c)] = {{"roll_distance_mm", p.roll_distance_mm},
                                            {"rho_pinion_mm", p.rho_pinion_mm},
                                            {"rho_gear_mm", p.rho_gear_mm},
                                            {"radius_pinion_mm", p.radius_pinion_mm},
                                            {"radius_gear_mm", p.radius_gear_mm}};
        }
      const auto iso = stiffness::iso6336_method_b(pair, scene.operating.torque_Nm);
      j["iso6336"] = {{"c_prime_th_N_per_mm_um", iso.c_prime_th_N_per_mm_um},
                      {"c_prime_N_per_mm_um", iso.c_prime_N_per_mm_um},
                      {"c_gamma_alpha_N_per_mm_um", iso.c_gamma_alpha_N_per_mm_um},
                      {"C_M", iso.C_M},
                      {"C_R", iso.C_R},
                      {"C_B", iso.C_B},
                      {"load_factor", iso.load_factor},
                      {"line_load_N_per_mm", iso.line_load_N_per_mm},
                      {"within_validity", iso.within_validity}};
      return j;
    }

    void print_summary(std::ostream &out, const nlohmann::json &j)
    {
      out << std::fixed << std::setprecision(4);
      out << "spur pair geometry (lengths in mm)\n"
          << "  centre distance          " << j["center_distance_mm"].get<double>()
          << "  (reference " << j["reference_center_distance_mm"].get<double>() << ")\n"
          << "  operating pressure angle " << j["operating_pressure_angle_deg"].get<double>() << " deg\n"
          << "  base pitch               " << j["base_pitch_mm"].get<double>() << "\n"
          << "  path of contact          " << j["path_of_contact_mm"].get<double>() << "\n"
          << "  contact ratio eps_alpha  " << j["contact_ratio"].get<double>() << "\n"
          << "  backlash (line of action)" << " " << j["backlash_loa_mm"].get<double>() << "\n";
      for (const char *body : {"pinion", "gear"})
        {
          const auto &g = j[body];
          out << "  " << std::left << std::setw(7) << body << std::right
              << " z " << g["teeth"].get<int>() << "  r " << g["reference_radius_mm"].get<double>()
              << "  r_b " << g["base_radius_mm"].get<double>() << "  r_a "
              << g["tip_radius_mm"].get<double>() << "  r_f " << g["root_radius_mm"].get<double>()
              << "  r_F " << g["form_radius_mm"].get<double>() << "  top land "
              << g["top_land_mm"].get<double>() << "  crowning radius "
              << (g["crowning_radius_mm"].is_null() ? std::string("none")
                                                    : std::to_string(g["crowning_radius_mm"].get<double>()))
              << "\n";
        }
      out << "  point  roll from T1  rho pinion  rho gear\n";
      for (const char *c : {"A", "B", "C", "D", "E"})
        {
          const auto &p = j["points"][c];
          out << "  " << c << "      " << std::setw(10) << p["roll_distance_mm"].get<double>()
              << "  " << std::setw(10) << p["rho_pinion_mm"].get<double>() << "  " << std::setw(8)
              << p["rho_gear_mm"].get<double>() << "\n";
        }
      const auto &iso = j["iso6336"];
      out << "  ISO 6336-1 method B: c'_th " << iso["c_prime_th_N_per_mm_um"].get<double>()
          << "  c' " << iso["c_prime_N_per_mm_um"].get<double>() << "  c_gamma_alpha "
          << iso["c_gamma_alpha_N_per_mm_um"].get<double>() << " N/(mm um)\n";
    }

    int run_geometry(const CommandContext &ctx, const bool json)
    {
      const Scene scene = load_scene(ctx.scene_file, ctx.overrides);
      const auto  pair  = make_pair(scene);
      auto        j     = geometry_json(pair, scene);
      j["scene_hash"]   = scene.hash;
      if (json)
        std::cout << j.dump(2) << std::endl;
      else
        print_summary(std::cout, j);
      if (!ctx.out_dir.empty())
        {
          RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
          dir.write_json("geometry.json", j);
          dir.finish(PhaseTimer());
        }
      return 0;
    }
  } // namespace

  void add_geometry_commands(CommandRegistry &registry)
  {
    auto      json = std::make_shared<bool>(false);
    CLI::App *geometry = registry.add_command(
      {"geometry", "Gear geometry, pair kinematics and ISO 6336-1 stiffness of a scene", true, true},
      [json](const CommandContext &ctx) { return run_geometry(ctx, *json); });
    geometry->add_flag("--json", *json, "Print one JSON object instead of the summary");
  }
} // namespace hertzgear
