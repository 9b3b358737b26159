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
#include "app/stiffness_stage.h"
#include "common/errors.h"
#include "common/progress.h"

#include <deal.II/base/mpi.h>

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

    struct Extrapolation
    {
      double      value    = std::numeric_limits<double>::quiet_NaN();
      double      order    = std::numeric_limits<double>::quiet_NaN();
      bool        asymptotic = false;
      std::string note;
    };

    // Observed order and extrapolated value from three rungs f1 (coarsest), f2, f3 (finest) of
    // sizes h1 > h2 > h3 (Celik et al. 2008, eqs. 3-6, with its fixed-point iteration for
    // non-constant refinement ratios).
    Extrapolation richardson(const double h1, const double h2, const double h3, const double f1,
                             const double f2, const double f3, const double expected_order)
    {
      Extrapolation x;
      const double  e21 = f2 - f1, e32 = f3 - f2;
      const double  r21 = h1 / h2, r32 = h2 / h3;
      if (e32 == 0.0)
        {
          x.value = f3;
          x.order = std::numeric_limits<double>::infinity();
          x.note  = "the two finest rungs agree exactly";
          return x;
        }
      if (e21 == 0.0)
        {
          x.note = "the two coarsest rungs agree exactly: no order can be observed";
          return x;
        }
      const double ratio = e32 / e21;
      const double s     = ratio > 0 ? 1.0 : -1.0;
      double       p     = std::abs(std::log(std::abs(1.0 / ratio))) / std::log(r21);
      for (int it = 0; it < 100; ++it)
        {
          const double q  = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
          const double pn = std::abs(std::log(std::abs(1.0 / ratio)) + q) / std::log(r21);
          if (!std::isfinite(pn))
            break;
          if (std::abs(pn - p) < 1e-10)
            {
              p = pn;
              break;
            }
          p = pn;
        }
      x.order = p;
      x.value = f3 + (f3 - f2) / (std::pow(r32, p) - 1.0);
      if (ratio < 0)
        x.note = "oscillatory convergence (the differences change sign): not in the asymptotic range";
      else if (std::abs(ratio) >= 1)
        x.note = "the differences grow with refinement: not in the asymptotic range";
      else if (p < 0.5 * expected_order || p > 2.0 * expected_order)
        x.note = msg("observed order ", p, " is far from the expected ", expected_order,
                     ": not in the asymptotic range");
      else
        {
          x.asymptotic = true;
          x.note       = "monotone, observed order near the expected one";
        }
      return x;
    }

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

    Rung rung_from(const StiffnessStageResult &r, const fem::MeshCycleResult &cycle, const double n)
    {
      Rung   g;
      double ste_min = 1e300, ste_max = -1e300;
      for (const auto &p : cycle.positions)
        {
          ste_min = std::min(ste_min, p.ste_mm);
          ste_max = std::max(ste_max, p.ste_mm);
        }
      g.k_total   = cycle.k_total.mean * 1e3;
      g.ste_pp_um = (ste_max - ste_min) * 1e3;
      g.k_mh      = cycle.k_hertz.mean * std::pow(1e3, n);
      g.k_rest    = cycle.mean_k_rest_N_per_mm * 1e3;
      g.dofs      = r.metadata.at("dofs").get<std::size_t>();
      return g;
    }

    int run_accuracy_stiffness(const CommandContext &ctx, const std::string &levels_text,
                               const std::string &grid_factors_text)
    {
      std::ostringstream silent;
      if (!is_root_rank())
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
      const double n      = base.stiffness.hertz_exponent;
      const int    p0     = base.stiffness.contact_grid_profile_points;
      const int    f0     = dim == 2 ? 1 : base.stiffness.contact_grid_face_points;
      const double module = base.pinion.module_mm;
      std::vector<Rung> fe_rungs, grid_rungs;
      nlohmann::json    summary;

      // The split between FE and half-space is held at the scene's reference depth on every
      // level, so that the ladder refines one problem (with d = 3 h following each level, the
      // quantity itself would change with the level: k_mh of line contact depends on d).
      const double depth_mm = reference_depth_mm(base);
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
          const Scene           scene = load_scene(ctx.scene_file, overrides);
          StiffnessStageOptions options;
          const bool            with_grids = level == base.stiffness.fe_level;
          if (with_grids)
            for (const int f : factors)
              if (f != 1)
                options.extra_contact_grids.emplace_back(p0 * f, dim == 2 ? 1 : f0 * f);
          const fs::path mesh_dir =
            (ctx.out_dir.empty() ? fs::temp_directory_path() / "hertzgear_accuracy_stiffness" :
                                   fs::path(ctx.out_dir)) /
            ("mesh_level" + std::to_string(level));
          PhaseTimer stage_timer;
          const auto t0 = std::chrono::steady_clock::now();
          StiffnessStageResult r;
          {
            PhaseTimer::Scope scope(timer, "level " + std::to_string(level));
            r = run_stiffness_stage(scene, mesh_dir, stage_timer, options);
          }
          const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          double       grid_time = 0;
          for (const auto &[phase, seconds] : stage_timer.phases())
            if (phase == "contact over the mesh cycle (grid ladder)")
              grid_time = seconds;
          Rung g        = rung_from(r, r.cycle, n);
          summary["reference_depth_mm"] = depth_mm;
          g.study       = "fe_level";
          g.level       = level;
          g.degree      = scene.stiffness.fe_degree;
          g.profile_cells = p0;
          g.face_cells  = f0;
          g.h           = r.metadata.at("band_element_size_mm").get<double>();
          g.wall_time_s = wall - grid_time;
          fe_rungs.push_back(g);
          progress_line("accuracy",
                        msg("level ", level, "  Q", g.degree, "  ", g.dofs, " DOFs  ",
                            std::setprecision(4), g.wall_time_s, " s  mean k_total ",
                            std::setprecision(7), g.k_total, " N/m  STE p-p ", g.ste_pp_um,
                            " um  k_mh ", g.k_mh));
          if (with_grids)
            {
              const double band = r.metadata.at("contact_band_half_width_mm").get<double>();
              const double contact_time = stage_timer.seconds("contact over the mesh cycle");
              for (const int f : factors)
                {
                  const fem::MeshCycleResult *c = &r.cycle;
                  if (f != 1)
                    {
                      std::size_t k = 0;
                      for (const int ff : factors)
                        if (ff != 1 && ff < f)
                          ++k;
                      c = &r.extra_cycles[k];
                    }
                  Rung gg          = rung_from(r, *c, n);
                  gg.study         = "contact_grid";
                  gg.level         = level;
                  gg.degree        = g.degree;
                  gg.profile_cells = p0 * f;
                  gg.face_cells    = f0 * (dim == 2 ? 1 : f);
                  gg.h             = 2.0 * band / gg.profile_cells;
                  // The grid rungs share the FE bodies: their time is the contact part only.
                  gg.wall_time_s = f == 1 ? contact_time : grid_time / (factors.size() - 1);
                  grid_rungs.push_back(gg);
                  progress_line("accuracy", msg("contact grid ", gg.profile_cells, " x ",
                                                gg.face_cells, "  mean k_total ",
                                                std::setprecision(7), gg.k_total, " N/m  STE p-p ",
                                                gg.ste_pp_um, " um  k_mh ", gg.k_mh));
                }
            }
        }
      (void)module;
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

      if (is_root_rank())
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
