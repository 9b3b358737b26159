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
#include "app/scripts.h"
#include "app/scene.h"
#include "app/validation_scene.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/progress.h"
#include "common/processes.h"
#include "fem/hertz_validation.h"
#include "stiffness/fe_hertz_case.h"

#include <algorithm>
#include <filesystem>
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

    // The library's input of one case: the scene's values, and for the crowned flank the pair of
    // its gear scene with the TCA's contact grid and reference depth.
    fem::HertzCaseInput case_input(const ValidationScene &v, const bool coarse)
    {
      fem::HertzCaseInput in          = v.input;
      in.fe.initial_cells_per_semi_axis = static_cast<unsigned int>(v.initial_cells_per_semi_axis);
      in.fe.n_levels = static_cast<unsigned int>(coarse ? v.ci_levels : v.levels);
      in.fe.max_active_set_iterations = static_cast<unsigned int>(v.max_active_set_iterations);
      if (in.kind == "crowned-flank")
        {
          in.gear        = stiffness::hertz_case_gear_pair(stiffness_input(load_scene(v.gear_scene)));
          in.gear.source = v.gear_scene.string();
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
      begin_on_out(ctx);
      fem::HertzValidationStudy study;
      std::ostringstream used;
      for (const auto &v : scenes)
        {
          PhaseTimer::Scope scope(timer, v.name);
          study.run_case(case_input(v, coarse), say);
          used << "# ---- case " << v.name << " (" << v.file.string() << ")\n"
               << v.used_parameters_prm;
        }

      const std::string csv = study.results_csv();
      const std::string rates = study.rates_csv();
      for (const auto &line : study.acceptance_rates()) // observed rates, on stderr
        say("rate " + line);

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
