// `hertzgear geometry SCENE [--json]`: gear geometry, pair kinematics and ISO 6336-1 stiffness.
#include "app/command.h"
#include "common/processes.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "common/errors.h"
#include "common/progress.h"
#include "meshing/geometry_json.h"
#include "stiffness/iso6336.h"

#include <iomanip>
#include <iostream>

namespace hertzgear
{
  namespace
  {
    void print_summary(std::ostream &out, const nlohmann::json &j)
    {
      const bool helical = j["helix_angle_deg"].get<double>() != 0;
      out << std::fixed << std::setprecision(4);
      out << (helical ? "helical" : "spur") << " pair geometry (lengths in mm"
          << (helical ? ", transverse section" : "") << ")\n";
      if (helical)
        out << "  helix angle beta         " << j["helix_angle_deg"].get<double>() << " deg\n"
            << "  base helix angle beta_b  " << j["base_helix_angle_deg"].get<double>() << " deg\n";
      out << "  centre distance          " << j["center_distance_mm"].get<double>()
          << "  (reference " << j["reference_center_distance_mm"].get<double>() << ")\n"
          << "  operating pressure angle " << j["operating_pressure_angle_deg"].get<double>() << " deg\n"
          << "  base pitch               " << j["base_pitch_mm"].get<double>() << "\n"
          << "  path of contact          " << j["path_of_contact_mm"].get<double>() << "\n"
          << "  contact ratio eps_alpha  " << j["contact_ratio"].get<double>() << "\n";
      if (helical)
        out << "  overlap ratio eps_beta   " << j["face_contact_ratio"].get<double>() << "\n"
            << "  total ratio eps_gamma    " << j["total_contact_ratio"].get<double>() << "\n";
      out << "  backlash (line of action)" << " " << j["backlash_loa_mm"].get<double>() << "\n";
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
          << iso["c_gamma_alpha_N_per_mm_um"].get<double>();
      if (helical)
        out << "  c_gamma_beta " << iso["c_gamma_beta_N_per_mm_um"].get<double>();
      out << " N/(mm um)\n";
    }

    int run_geometry(const CommandContext &ctx, const bool json)
    {
      const Scene scene = load_scene(ctx.scene_file, ctx.overrides);
      const auto  pair  = make_pair(scene);
      auto        j     = meshing::pair_json(pair);
      j["iso6336"]      = stiffness::iso6336_method_b(pair, scene.operating.torque_Nm);
      j["scene_hash"]   = scene.hash;
      begin_on_out(ctx);
      if (!processes::is_root())
        return 0;
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
