// `hertzgear accuracy stiffness SCENE --out DIR`: what accuracy costs in the FE source, the ladders
// of stiffness/fe_accuracy.h. Writes accuracy_stiffness.csv, accuracy_stiffness.json and
// accuracy_stiffness.png (matplotlib).
#include "app/command.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "app/stiffness_setup.h"
#include "common/errors.h"
#include "common/processes.h"
#include "common/progress.h"
#include "stiffness/fe_accuracy.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace hertzgear
{
  namespace
  {
    namespace fs = std::filesystem;

    std::vector<int> parse_int_list(const std::string &text, const std::string &what)
    {
      std::vector<int>   v;
      std::stringstream  ss(text);
      for (std::string item; std::getline(ss, item, ',');)
        {
          try
            {
              std::size_t used = 0;
              v.push_back(std::stoi(item, &used));
              HG_REQUIRE_INPUT(used == item.size(), "");
            }
          catch (const std::exception &)
            {
              throw InputError(msg(what, " = \"", text, "\": expected a comma list of integers"));
            }
        }
      return v;
    }

    // Sorted, distinct levels: the given ones, or the scene's level, one below and one above.
    std::vector<int> ladder_levels(const Scene &base, const std::string &text)
    {
      std::vector<int> levels;
      if (text.empty())
        for (int l = std::max(0, base.stiffness.fe_level - 1); levels.size() < 3; ++l)
          levels.push_back(l);
      else
        levels = parse_int_list(text, "--levels");
      std::sort(levels.begin(), levels.end());
      levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
      HG_REQUIRE_INPUT(levels.size() >= 3, "--levels = \"", text,
                       "\": the study needs at least three distinct refinement levels");
      HG_REQUIRE_INPUT(levels.front() >= 0 && levels.back() <= 6, "--levels = \"", text,
                       "\": levels must lie in 0..6 (Stiffness/fe_level)");
      return levels;
    }

    std::vector<int> grid_factors(const std::string &text)
    {
      std::vector<int> factors = parse_int_list(text, "--grid-factors");
      std::sort(factors.begin(), factors.end());
      factors.erase(std::unique(factors.begin(), factors.end()), factors.end());
      HG_REQUIRE_INPUT(factors.size() >= 3 && factors.front() >= 1, "--grid-factors = \"", text,
                       "\": the study needs at least three distinct factors >= 1");
      return factors;
    }

    int run_accuracy_stiffness(const CommandContext &ctx, const std::string &levels_text,
                               const std::string &grid_factors_text)
    {
      const QuietOtherRanks quiet;
      PhaseTimer            timer;
      const Scene base = load_scene(ctx.scene_file, ctx.overrides);
      HG_REQUIRE_INPUT(base.stiffness.source == "fem", "Stiffness/source = ", base.stiffness.source,
                       ": the stiffness accuracy study needs source = fem");
      const auto     levels  = ladder_levels(base, levels_text);
      const auto     factors = grid_factors(grid_factors_text);
      const fs::path meshes  = ctx.out_dir.empty() ?
                                 fs::temp_directory_path() / "hertzgear_accuracy_stiffness" :
                                 fs::path(ctx.out_dir);
      ctx.start->begin({meshes}, ctx.out_dir.empty() ? "the study's mesh folder" : "--out");
      const auto study = stiffness::run_fe_accuracy_study(stiffness_input(base), levels, factors,
                                                          meshes, timer);
      const nlohmann::json summary = study.json(base.stiffness.fe_level);
      study.report(base.stiffness.fe_level);
      if (processes::is_root())
        {
          if (ctx.out_dir.empty())
            std::cout << study.csv();
          else
            {
              RunDirectory dir(ctx.out_dir, base, ctx.command_line);
              dir.write_text("accuracy_stiffness.csv", study.csv());
              nlohmann::json j = summary;
              j.update(provenance(base));
              dir.write_json("accuracy_stiffness.json", j);
              dir.finish(timer, {{"stage", "accuracy stiffness"}});
              draw_figure("plot_accuracy_stiffness.py",
                          {(dir.path() / "accuracy_stiffness.csv").string(),
                           (dir.path() / "accuracy_stiffness.png").string()});
            }
        }
      return 0;
    }
  } // namespace

  void add_accuracy_stiffness_command(CommandRegistry &registry, CLI::App *top)
  {
    CLI::App *accuracy = command_group(*top, "accuracy", "Work-precision studies: error versus time");
    auto      levels  = std::make_shared<std::string>();
    auto      factors = std::make_shared<std::string>("1,2,4");
    CLI::App *sub     = registry.add_command(
      {"stiffness", "Refinement study of the FE stiffness stage: FE levels and contact grids, "
                    "Richardson extrapolation, error versus DOFs and time"},
      [levels, factors](const CommandContext &ctx) {
        return run_accuracy_stiffness(ctx, *levels, *factors);
      },
      accuracy);
    sub->add_option("--levels", *levels,
                    "FE refinement levels, comma separated (default: scene level - 1 .. + 1, "
                    "at least three)");
    sub->add_option("--grid-factors", *factors,
                    "Contact-grid multipliers of the scene's grid at its level (default 1,2,4)");
  }
} // namespace hertzgear
