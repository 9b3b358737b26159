// `hertzgear validate hertz [SCENE] [--case NAME] [--coarse] --out DIR`: the Hertz closed forms
// (contact/hertz) and the TCA's hybrid local compliance (contact/mesh_cycle) against resolved FE contact
// (fem/resolved_contact), per canonical case of data/scenes/validation/. Writes
// hertz_validation.csv (case, quantity, closed_form, fe, relative_error, level, dofs,
// wall_time_s), hertz_rates.csv, pressure_profiles.csv, the used parameters and, when
// /usr/bin/python3 has matplotlib, the figures of scripts/plot_hertz_validation.py.
// Method and measured numbers: docs/validation-hertz.md.
#include "app/cmd_validate_hertz.h"

#include "app/meshing_setup.h"
#include "app/stiffness_setup.h"
#include "stiffness/fe_tca.h"
#include "app/scripts.h"
#include "app/scene.h"
#include "app/validation_scene.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/progress.h"
#include "common/processes.h"
#include "fem/hertz_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    bool is_root() { return processes::is_root(); }

    void say(const std::string &text)
    {
      if (is_root())
        progress_line("validate", text);
    }

    std::string percent(const double closed, const double fe)
    {
      std::ostringstream os;
      os << std::showpos << std::fixed << std::setprecision(3) << 100.0 * (fe - closed) / closed
         << " %";
      return os.str();
    }

    // The library's input of one case: the scene's values, and for the crowned flank the pair of
    // its gear scene with the TCA's contact grid and reference depth.
    fem::HertzCaseInput case_input(const ValidationScene &v, const bool coarse)
    {
      fem::HertzCaseInput in;
      in.name                          = v.name;
      in.kind                          = v.kind;
      in.load_N                        = v.load_N;
      in.load_per_length_N_per_mm      = v.load_per_length_N_per_mm;
      in.roller_half_length_mm         = v.roller_half_length_mm;
      auto &f                          = in.fe;
      f.youngs_modulus_MPa             = v.youngs_modulus_MPa;
      f.poisson_ratio                  = v.poisson_ratio;
      f.radius_x_mm                    = v.radius_x_mm;
      f.radius_y_mm                    = v.radius_y_mm;
      f.half_width_x_mm                = v.half_width_x_mm;
      f.half_width_y_mm                = v.half_width_y_mm;
      f.depth_mm                       = v.depth_mm;
      f.reading_depths_mm              = v.reading_depths_mm;
      f.initial_cells_per_semi_axis    = static_cast<unsigned int>(v.initial_cells_per_semi_axis);
      f.n_levels                       = static_cast<unsigned int>(coarse ? v.ci_levels : v.levels);
      f.kelly_fraction                 = v.kelly_fraction;
      f.max_active_set_iterations      = static_cast<unsigned int>(v.max_active_set_iterations);
      if (v.kind == "crowned-flank")
        {
          const Scene scene = load_scene(v.gear_scene);
          const auto  input = stiffness_input(scene);
          auto       &g     = in.gear;
          g.pair            = input.pair;
          g.pinion_material = input.pinion_material;
          g.gear_material   = input.gear_material;
          g.torque_Nm       = input.torque_Nm;
          g.grid.profile_cells  = static_cast<unsigned int>(input.fe.contact_grid_profile_cells);
          g.grid.face_cells     = static_cast<unsigned int>(input.fe.contact_grid_face_cells);
          g.grid.hertz_exponent = input.hertz_exponent;
          g.grid.plane_strain   = false;
          g.grid.max_contact_iterations = static_cast<unsigned int>(input.fe.contact_max_iterations);
          g.reference_depth_mm = stiffness::fe_reference_depth_mm(input.fe, input.pair.pinion.module_mm);
          g.source             = v.gear_scene.string();
        }
      return in;
    }

    std::vector<fs::path> case_files(const CommandContext &ctx, const std::string &only)
    {
      if (!ctx.scene_file.empty())
        return {fs::path(ctx.scene_file)};
      const fs::path dir = fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "scenes" / "validation";
      HG_REQUIRE_INPUT(fs::is_directory(dir), "the validation scenes folder ", dir.string(),
                       " does not exist");
      std::vector<fs::path> files;
      for (const auto &e : fs::directory_iterator(dir))
        if (e.path().extension() == ".prm" && e.path().stem().string().rfind("bad_", 0) != 0)
          files.push_back(e.path());
      std::sort(files.begin(), files.end());
      if (only.empty())
        return files;
      std::string names;
      for (const auto &f : files)
        {
          if (f.stem() == only)
            return {f};
          names += (names.empty() ? "" : ", ") + f.stem().string();
        }
      throw InputError(msg("--case ", only, ": no such validation case (available: ", names, ")"));
    }

    int run_validate_hertz(const CommandContext &ctx, const std::string &only, const bool coarse)
    {
      PhaseTimer            timer;
      std::vector<ValidationScene> scenes;
      {
        PhaseTimer::Scope scope(timer, "scenes");
        for (const auto &f : case_files(ctx, only))
          scenes.push_back(load_validation_scene(f, ctx.overrides));
      }
      fem::HertzValidationStudy study;
      std::ostringstream used;
      for (const auto &v : scenes)
        {
          PhaseTimer::Scope scope(timer, v.name);
          const fem::HertzCase c = fem::make_hertz_case(case_input(v, coarse));
          if (!c.notes.empty())
            say(v.name + ": " + c.notes);
          say(msg(v.name, ": Hertz ", c.line ? "b " : "a_x ", c.a_x, " mm",
                  c.line ? std::string() : msg(", a_y ", c.a_y, " mm"), ", p0 ", c.p0, " MPa; block ",
                  c.fe.half_width_x_mm / c.a_x, " a_x wide, ", c.fe.depth_mm / c.a_x, " a_x deep"));
          const auto report = [&](const fem::ResolvedContactLevel &l) {
            study.add_level(v.name, c, l);
            say(msg(v.name, " level ", l.level, ": ", l.n_dofs, " dofs, ", l.n_active,
                    " active nodes, ", l.n_iterations, " active-set iterations, contact cell ",
                    l.contact_cell_mm, " mm; ", c.line ? "b " : "a_x ",
                    percent(c.a_x, l.semi_axis_x_mm),
                    c.line ? std::string() : ", a_y " + percent(c.a_y, l.semi_axis_y_mm),
                    ", p0 ", percent(c.p0, l.peak_pressure_MPa), "  (", l.wall_time_s, " s)"));
          };
          const auto levels = c.dim == 2 ? fem::solve_resolved_contact<2>(c.fe, report) :
                                           fem::solve_resolved_contact<3>(c.fe, report);
          study.add_profiles(v.name, c, levels.back());
          used << "# ---- case " << v.name << " (" << v.file.string() << ")\n"
               << v.used_parameters_prm;
        }

      const std::string csv = study.results_csv();
      const std::string rates = study.rates_csv();
      if (is_root())
        {
          // Observed rates of the quantities of the acceptance, on stderr.
          std::istringstream in(rates);
          std::string        line;
          std::getline(in, line);
          while (std::getline(in, line))
            if (line.find(",semi_axis_x,") != std::string::npos ||
                line.find(",semi_axis_y,") != std::string::npos ||
                line.find(",half_width,") != std::string::npos ||
                line.find(",peak_pressure,") != std::string::npos)
              say("rate " + line);
        }

      if (is_root())
        {
          if (ctx.out_dir.empty())
            std::cout << csv;
          else
            {
              PhaseTimer::Scope scope(timer, "write");
              const fs::path    dir(ctx.out_dir);
              fs::create_directories(dir);
              write_file_atomically(dir / "hertz_validation.csv", csv);
              write_file_atomically(dir / "hertz_rates.csv", rates);
              write_file_atomically(dir / "pressure_profiles.csv", study.profiles_csv());
              write_file_atomically(dir / "used_parameters.prm",
                                    "# " + ctx.command_line + "\n" + used.str());
              draw_figure("plot_hertz_validation.py", {dir.string()});
            }
          timer.print_summary(progress_stream());
        }
      return 0;
    }
  } // namespace

  void add_validation_commands(CommandRegistry &registry, CLI::App &top)
  {
    CLI::App *validate = command_group(top, "validate", "Validation studies against closed forms");
    auto only   = std::make_shared<std::string>();
    auto coarse = std::make_shared<bool>(false);
    CLI::App *hertz = registry.add_command(
      {"hertz",
       "Hertz closed forms and the TCA's local compliance against resolved FE contact "
       "(data/scenes/validation/, or the one SCENE given)",
       false, true},
      [only, coarse](const CommandContext &ctx) { return run_validate_hertz(ctx, *only, *coarse); },
      validate);
    hertz->add_option("--case", *only, "Run only this case (a file stem in data/scenes/validation)");
    hertz->add_flag("--coarse", *coarse, "Solve only the Refinement/ci_levels coarse levels");
  }
} // namespace hertzgear
