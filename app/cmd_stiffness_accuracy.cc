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

    // accuracy_stiffness.json: the rungs, the extrapolations and the verdict on the scene's level.
    nlohmann::json summary_json(const stiffness::FeAccuracyStudy &study, const Scene &base)
    {
      nlohmann::json j;
      j["reference_depth_mm"] = study.reference_depth_mm;
      for (const auto &[name, x] : study.fe_extrapolation)
        for (const auto &[ladder, e] : {std::pair{"fe_level", x},
                                        std::pair{"contact_grid", study.grid_extrapolation.at(name)}})
          j["extrapolation"][ladder][name] = {{"value", e.value},
                                              {"observed_order", e.order},
                                              {"asymptotic", e.asymptotic},
                                              {"note", e.note}};
      j["rows"] = nlohmann::json::array();
      for (const auto *ladder : {&study.fe_rungs, &study.grid_rungs})
        for (const auto &g : *ladder)
          j["rows"].push_back({{"study", g.study},
                               {"fe_level", g.level},
                               {"fe_degree", g.degree},
                               {"contact_profile_cells", g.profile_cells},
                               {"contact_face_cells", g.face_cells},
                               {"size_mm", g.h},
                               {"dofs", g.dofs},
                               {"wall_time_s", g.wall_time_s},
                               {"mean_k_total_N_per_m", g.k_total},
                               {"ste_peak_to_peak_um", g.ste_pp_um},
                               {"k_mh_N_per_m_pow_n", g.k_mh},
                               {"mean_k_rest_N_per_m", g.k_rest},
                               {"k_total_relative_error", study.relative_error(g, "mean_k_total_N_per_m")},
                               {"ste_pp_relative_error", study.relative_error(g, "ste_peak_to_peak_um")},
                               {"k_mh_relative_error", study.relative_error(g, "k_mh_N_per_m_pow_n")},
                               {"k_rest_relative_error", study.relative_error(g, "mean_k_rest_N_per_m")}});
      // The verdict on the scene's defaults: within 1 % of the extrapolated values?
      for (const auto &g : study.fe_rungs)
        if (g.level == base.stiffness.fe_level && !study.grid_rungs.empty())
          {
            const auto  &grid = study.grid_rungs.front();
            const double ek = study.relative_error(g, "mean_k_total_N_per_m");
            const double es = study.relative_error(g, "ste_peak_to_peak_um");
            const double gk = study.relative_error(grid, "mean_k_total_N_per_m");
            const double gs = study.relative_error(grid, "ste_peak_to_peak_um");
            const bool   ok = ek <= 0.01 && es <= 0.01 && gk <= 0.01 && gs <= 0.01;
            j["scene_default"] = {{"fe_level", g.level},
                                  {"contact_profile_cells", g.profile_cells},
                                  {"k_total_relative_error_fe", ek},
                                  {"ste_pp_relative_error_fe", es},
                                  {"k_total_relative_error_grid", gk},
                                  {"ste_pp_relative_error_grid", gs},
                                  {"within_1_percent", ok}};
            progress_line("accuracy", msg("scene default (level ", g.level, ", ", g.profile_cells,
                                          " profile cells): k_total error ", 100 * ek, " % (FE) ",
                                          100 * gk, " % (grid), STE p-p error ", 100 * es,
                                          " % (FE) ", 100 * gs, " % (grid): ",
                                          ok ? "within" : "NOT within", " 1 %"));
          }
      for (const auto &[ladder, xs] : {std::pair{"FE", &study.fe_extrapolation},
                                       std::pair{"grid", &study.grid_extrapolation}})
        for (const auto &[name, x] : *xs)
          progress_line("accuracy", msg(ladder, " ladder ", name, ": extrapolated ", x.value,
                                        ", order ", x.order, " (", x.note, ")"));
      return j;
    }

    int run_accuracy_stiffness(const CommandContext &ctx, const std::string &levels_text,
                               const std::string &grid_factors_text)
    {
      std::ostringstream silent;
      if (!processes::is_root())
        set_progress_stream(&silent);
      PhaseTimer  timer;
      const Scene base = load_scene(ctx.scene_file, ctx.overrides);
      HG_REQUIRE_INPUT(base.stiffness.source == "fem", "Stiffness/source = ", base.stiffness.source,
                       ": the stiffness accuracy study needs source = fem");
      const auto     levels  = ladder_levels(base, levels_text);
      const auto     factors = grid_factors(grid_factors_text);
      const fs::path meshes  = ctx.out_dir.empty() ?
                                 fs::temp_directory_path() / "hertzgear_accuracy_stiffness" :
                                 fs::path(ctx.out_dir);
      const auto study = stiffness::run_fe_accuracy_study(stiffness_input(base), levels, factors,
                                                          meshes, timer);
      const nlohmann::json summary = summary_json(study, base);
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
      set_progress_stream(nullptr);
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
