// `hertzgear accuracy stiffness SCENE --out DIR`: what accuracy costs in the FE stiffness stage.
//
// Two ladders, each of at least three rungs:
//  - FE refinement levels (each level halves the element size in the contact band; the reference
//    depth d = 3 h and the patch radius 1.5 h follow the element size h) at the scene's contact
//    grid;
//  - contact-grid sizes (profile cells, and face cells in 3D, times 1, 2, 4 by default) with the
//    FE bodies of the scene's level, solved on the same factorised bodies.
// For mean k_total, STE peak-to-peak and k_mh the three finest rungs of each ladder give the
// observed order and the Richardson-extrapolated value (the generalised procedure of Celik et al.
// 2008, "Procedure for estimation and reporting of uncertainty due to discretization in CFD
// applications", J. Fluids Eng. 130, 078001), and every rung its error against it. Writes
// accuracy_stiffness.csv, accuracy_stiffness.json and accuracy_stiffness.png (matplotlib).
#include "app/command.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "app/stiffness_setup.h"
#include "common/richardson.h"
#include "stiffness/fe_tca.h"
#include "common/processes.h"
#include "stiffness/registry.h"
#include "stiffness/table_writer.h"
#include "common/errors.h"
#include "common/progress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

namespace hertzgear
{
  namespace
  {
    namespace fs = std::filesystem;

    struct Rung
    {
      std::string study; // fe_level | contact_grid
      int         level = 0, degree = 0, profile_cells = 0, face_cells = 0;
      double      h     = 0; // representative size: band element size [mm] or grid cell [mm]
      std::size_t dofs  = 0;
      double      wall_time_s = 0;
      double      k_total = 0, ste_pp_um = 0, k_mh = 0, k_rest = 0; // SI (N/m, um, N/m^n)
    };

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

    Rung rung_from(const stiffness::StiffnessResult &r, const std::size_t dofs)
    {
      Rung g;
      g.k_total     = r.k_total_N_per_m.mean;
      g.ste_pp_um   = stiffness::ste_peak_to_peak_um(r);
      g.k_mh        = r.table.k_hertz_N_per_m_pow_n.mean;
      g.k_rest      = r.mean_k_rest_N_per_m;
      g.dofs        = dofs;
      g.wall_time_s = r.contact_time_s;
      return g;
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
      std::vector<int> levels;
      if (levels_text.empty())
        for (int l = std::max(0, base.stiffness.fe_level - 1); levels.size() < 3; ++l)
          levels.push_back(l);
      else
        levels = parse_int_list(levels_text, "--levels");
      std::sort(levels.begin(), levels.end());
      levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
      HG_REQUIRE_INPUT(levels.size() >= 3, "--levels = \"", levels_text,
                       "\": the study needs at least three distinct refinement levels");
      HG_REQUIRE_INPUT(levels.front() >= 0 && levels.back() <= 6, "--levels = \"", levels_text,
                       "\": levels must lie in 0..6 (Stiffness/fe_level)");
      std::vector<int> factors = parse_int_list(grid_factors_text, "--grid-factors");
      std::sort(factors.begin(), factors.end());
      factors.erase(std::unique(factors.begin(), factors.end()), factors.end());
      HG_REQUIRE_INPUT(factors.size() >= 3 && factors.front() >= 1, "--grid-factors = \"",
                       grid_factors_text, "\": the study needs at least three distinct factors >= 1");

      const int    dim    = base.stiffness.fe_dimension;
      const int    p0     = base.stiffness.contact_grid_profile_points;
      const int    f0     = dim == 2 ? 1 : base.stiffness.contact_grid_face_points;
      const double module = base.pinion.module_mm;
      std::vector<Rung> fe_rungs, grid_rungs;
      nlohmann::json    summary;

      // The split between FE and half-space is held at the scene's reference depth on every
      // level, so that the ladder refines one problem (with d = 3 h following each level, the
      // quantity itself would change with the level: k_mh of line contact depends on d).
      const double depth_mm = stiffness::fe_reference_depth_mm(stiffness_input(base).fe, module);
      progress_line("accuracy", msg("reference depth held at ", depth_mm, " mm on every level"));
      // The finest level first: a level that does not fit the machine (the MUMPS memory guard,
      // fem/petsc_ksp.h) stops the study at once, not after the coarser levels have run.
      progress_line("accuracy", "finest level first, so that one too large for the machine stops "
                                "the study before the others have run");
      for (auto it = levels.rbegin(); it != levels.rend(); ++it)
        {
          const int level = *it;
          std::vector<std::string> overrides = ctx.overrides;
          overrides.push_back("Stiffness/fe_level=" + std::to_string(level));
          overrides.push_back("Stiffness/reference_depth_mm=" + msg(depth_mm));
          const Scene scene = load_scene(ctx.scene_file, overrides);
          auto        input = stiffness_input(scene);
          const bool  with_grids = level == base.stiffness.fe_level;
          if (with_grids)
            for (const int f : factors)
              if (f != 1)
                input.fe.extra_contact_grids.emplace_back(p0 * f, dim == 2 ? 1 : f0 * f);
          input.fe.mesh_dir =
            (ctx.out_dir.empty() ? fs::temp_directory_path() / "hertzgear_accuracy_stiffness" :
                                   fs::path(ctx.out_dir)) /
            ("mesh_level" + std::to_string(level));
          PhaseTimer stage_timer;
          const auto t0 = std::chrono::steady_clock::now();
          stiffness::StiffnessResult r;
          {
            PhaseTimer::Scope scope(timer, "level " + std::to_string(level));
            r = stiffness::find_source("fem").compute(input, stage_timer);
          }
          const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          double       grid_time = 0;
          for (const auto &extra : r.extra_grids)
            grid_time += extra.contact_time_s;
          const auto dofs = r.notes.at("dofs").get<std::size_t>();
          Rung       g    = rung_from(r, dofs);
          summary["reference_depth_mm"] = depth_mm;
          g.study       = "fe_level";
          g.level       = level;
          g.degree      = scene.stiffness.fe_degree;
          g.profile_cells = p0;
          g.face_cells  = f0;
          g.h           = r.notes.at("band_element_size_mm").get<double>();
          g.wall_time_s = wall - grid_time;
          fe_rungs.push_back(g);
          progress_line("accuracy",
                        msg("level ", level, "  Q", g.degree, "  ", g.dofs, " DOFs  ",
                            std::setprecision(4), g.wall_time_s, " s  mean k_total ",
                            std::setprecision(7), g.k_total, " N/m  STE p-p ", g.ste_pp_um,
                            " um  k_mh ", g.k_mh));
          if (with_grids)
            {
              const double band = r.notes.at("contact_band_half_width_mm").get<double>();
              for (const int f : factors)
                {
                  const stiffness::StiffnessResult *c = &r;
                  if (f != 1)
                    {
                      std::size_t k = 0;
                      for (const int ff : factors)
                        if (ff != 1 && ff < f)
                          ++k;
                      c = &r.extra_grids[k];
                    }
                  // The grid rungs share the FE bodies: their time is the contact part only.
                  Rung gg          = rung_from(*c, dofs);
                  gg.study         = "contact_grid";
                  gg.level         = level;
                  gg.degree        = g.degree;
                  gg.profile_cells = p0 * f;
                  gg.face_cells    = f0 * (dim == 2 ? 1 : f);
                  gg.h             = 2.0 * band / gg.profile_cells;
                  grid_rungs.push_back(gg);
                  progress_line("accuracy", msg("contact grid ", gg.profile_cells, " x ",
                                                gg.face_cells, "  mean k_total ",
                                                std::setprecision(7), gg.k_total, " N/m  STE p-p ",
                                                gg.ste_pp_um, " um  k_mh ", gg.k_mh));
                }
            }
        }
      // Run finest first; the table and the extrapolation go from coarse to fine.
      std::sort(fe_rungs.begin(), fe_rungs.end(),
                [](const Rung &a, const Rung &b) { return a.level < b.level; });

      // Extrapolations from the three finest rungs of each ladder.
      const auto extrapolate = [&](const std::vector<Rung> &rungs, double Rung::*q,
                                   const double expected) {
        const std::size_t m = rungs.size();
        const Rung &a = rungs[m - 3], &b = rungs[m - 2], &c = rungs[m - 1];
        return richardson(a.h, b.h, c.h, a.*q, b.*q, c.*q, expected);
      };
      // Expected orders: the FE part of a compliance converges like the energy, O(h^2p); the
      // reading at depth d ~ h and the straight-sided boundary cells (O(h^2)) cap it at 2. The
      // contact grid's piecewise constant pressures give O(h^2) in the approach.
      const double fe_expected   = 2.0;
      const double grid_expected = 2.0;
      struct Quantity
      {
        const char *name;
        double Rung::*member;
      };
      const Quantity quantities[] = {{"mean_k_total_N_per_m", &Rung::k_total},
                                     {"ste_peak_to_peak_um", &Rung::ste_pp_um},
                                     {"k_mh_N_per_m_pow_n", &Rung::k_mh},
                                     {"mean_k_rest_N_per_m", &Rung::k_rest}};
      std::map<std::string, Extrapolation> fe_x, grid_x;
      for (const auto &qq : quantities)
        {
          fe_x[qq.name]   = extrapolate(fe_rungs, qq.member, fe_expected);
          grid_x[qq.name] = extrapolate(grid_rungs, qq.member, grid_expected);
          for (const auto &[study, x] : {std::pair{"fe_level", fe_x[qq.name]},
                                         std::pair{"contact_grid", grid_x[qq.name]}})
            summary["extrapolation"][study][qq.name] = {{"value", x.value},
                                                       {"observed_order", x.order},
                                                       {"asymptotic", x.asymptotic},
                                                       {"note", x.note}};
        }

      std::ostringstream csv;
      csv << std::setprecision(10);
      csv << "study,fe_level,fe_degree,contact_profile_cells,contact_face_cells,size_mm,dofs,"
             "wall_time_s,mean_k_total_N_per_m,ste_peak_to_peak_um,k_mh_N_per_m_pow_n,"
             "mean_k_rest_N_per_m,k_total_relative_error,ste_pp_relative_error,"
             "k_mh_relative_error,k_rest_relative_error\n";
      const auto rel = [](const double v, const Extrapolation &x) {
        return std::isfinite(x.value) && x.value != 0 ? std::abs(v - x.value) / std::abs(x.value) :
                                                        std::numeric_limits<double>::quiet_NaN();
      };
      nlohmann::json rows = nlohmann::json::array();
      for (const auto *ladder : {&fe_rungs, &grid_rungs})
        for (const auto &g : *ladder)
          {
            auto &x = g.study == "fe_level" ? fe_x : grid_x;
            const double e[4] = {rel(g.k_total, x["mean_k_total_N_per_m"]),
                                 rel(g.ste_pp_um, x["ste_peak_to_peak_um"]),
                                 rel(g.k_mh, x["k_mh_N_per_m_pow_n"]),
                                 rel(g.k_rest, x["mean_k_rest_N_per_m"])};
            csv << g.study << ',' << g.level << ',' << g.degree << ',' << g.profile_cells << ','
                << g.face_cells << ',' << g.h << ',' << g.dofs << ',' << g.wall_time_s << ','
                << g.k_total << ',' << g.ste_pp_um << ',' << g.k_mh << ',' << g.k_rest << ','
                << e[0] << ',' << e[1] << ',' << e[2] << ',' << e[3] << '\n';
            rows.push_back({{"study", g.study},
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
                            {"k_total_relative_error", e[0]},
                            {"ste_pp_relative_error", e[1]},
                            {"k_mh_relative_error", e[2]},
                            {"k_rest_relative_error", e[3]}});
          }
      summary["rows"] = rows;

      // The verdict on the scene's defaults: within 1 % of the extrapolated values?
      const Rung *def = nullptr;
      for (const auto &g : fe_rungs)
        if (g.level == base.stiffness.fe_level)
          def = &g;
      if (def)
        {
          const double ek = rel(def->k_total, fe_x["mean_k_total_N_per_m"]);
          const double es = rel(def->ste_pp_um, fe_x["ste_peak_to_peak_um"]);
          const double gk = grid_rungs.empty() ? 0 : rel(grid_rungs.front().k_total, grid_x["mean_k_total_N_per_m"]);
          const double gs = grid_rungs.empty() ? 0 : rel(grid_rungs.front().ste_pp_um, grid_x["ste_peak_to_peak_um"]);
          const bool   ok = ek <= 0.01 && es <= 0.01 && gk <= 0.01 && gs <= 0.01;
          summary["scene_default"] = {{"fe_level", base.stiffness.fe_level},
                                      {"contact_profile_cells", p0},
                                      {"k_total_relative_error_fe", ek},
                                      {"ste_pp_relative_error_fe", es},
                                      {"k_total_relative_error_grid", gk},
                                      {"ste_pp_relative_error_grid", gs},
                                      {"within_1_percent", ok}};
          progress_line("accuracy",
                        msg("scene default (level ", base.stiffness.fe_level, ", ", p0,
                            " profile cells): k_total error ", 100 * ek, " % (FE) ", 100 * gk,
                            " % (grid), STE p-p error ", 100 * es, " % (FE) ", 100 * gs,
                            " % (grid): ", ok ? "within" : "NOT within", " 1 %"));
        }
      for (const auto &[name, x] : fe_x)
        progress_line("accuracy", msg("FE ladder ", name, ": extrapolated ", x.value, ", order ",
                                      x.order, " (", x.note, ")"));
      for (const auto &[name, x] : grid_x)
        progress_line("accuracy", msg("grid ladder ", name, ": extrapolated ", x.value, ", order ",
                                      x.order, " (", x.note, ")"));

      if (processes::is_root())
        {
          if (ctx.out_dir.empty())
            std::cout << csv.str();
          else
            {
              RunDirectory dir(ctx.out_dir, base, ctx.command_line);
              dir.write_text("accuracy_stiffness.csv", csv.str());
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
