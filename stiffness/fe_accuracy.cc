#include "stiffness/fe_accuracy.h"

#include "common/errors.h"
#include "stiffness/fe_tca.h"
#include "stiffness/registry.h"
#include "stiffness/table_writer.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hertzgear::stiffness
{
  namespace
  {
    // Expected orders: the FE part of a compliance converges like the energy, O(h^2p); the
    // reading at depth d ~ h and the straight-sided boundary cells (O(h^2)) cap it at 2. The
    // contact grid's piecewise constant pressures give O(h^2) in the approach.
    constexpr double fe_expected_order   = 2.0;
    constexpr double grid_expected_order = 2.0;

    struct Quantity
    {
      const char *name;
      double AccuracyRung::*member;
    };
    const Quantity quantities[] = {{"mean_k_total_N_per_m", &AccuracyRung::k_total},
                                   {"ste_peak_to_peak_um", &AccuracyRung::ste_pp_um},
                                   {"k_mh_N_per_m_pow_n", &AccuracyRung::k_mh},
                                   {"mean_k_rest_N_per_m", &AccuracyRung::k_rest}};

    AccuracyRung rung_of(const StiffnessResult &r, const std::size_t dofs)
    {
      AccuracyRung g;
      g.k_total     = r.k_total_N_per_m.mean;
      g.ste_pp_um   = ste_peak_to_peak_um(r);
      g.k_mh        = r.table.k_hertz_N_per_m_pow_n.mean;
      g.k_rest      = r.mean_k_rest_N_per_m;
      g.dofs        = dofs;
      g.wall_time_s = r.contact_time_s;
      return g;
    }

    void report(const AccuracyRung &g)
    {
      if (g.study == "fe_level")
        progress_line("accuracy", msg("level ", g.level, "  Q", g.degree, "  ", g.dofs, " DOFs  ",
                                      std::setprecision(4), g.wall_time_s, " s  mean k_total ",
                                      std::setprecision(7), g.k_total, " N/m  STE p-p ",
                                      g.ste_pp_um, " um  k_mh ", g.k_mh));
      else
        progress_line("accuracy", msg("contact grid ", g.profile_cells, " x ", g.face_cells,
                                      "  mean k_total ", std::setprecision(7), g.k_total,
                                      " N/m  STE p-p ", g.ste_pp_um, " um  k_mh ", g.k_mh));
    }

    // The grid ladder of one FE level: the level's own grid (factor 1) and the extra grids.
    void add_grid_rungs(FeAccuracyStudy &study, const StiffnessResult &r, const AccuracyRung &fe,
                        const std::vector<int> &factors, const int dim)
    {
      const double band = r.notes.at("contact_band_half_width_mm").get<double>();
      std::size_t  k    = 0;
      for (const int f : factors)
        {
          // The grid rungs share the FE bodies: their time is the contact part only.
          AccuracyRung g  = rung_of(f == 1 ? r : r.extra_grids[k++], fe.dofs);
          g.study         = "contact_grid";
          g.level         = fe.level;
          g.degree        = fe.degree;
          g.profile_cells = fe.profile_cells * f;
          g.face_cells    = fe.face_cells * (dim == 2 ? 1 : f);
          g.h             = 2.0 * band / g.profile_cells;
          study.grid_rungs.push_back(g);
          report(g);
        }
    }

    Extrapolation extrapolate(const std::vector<AccuracyRung> &rungs, double AccuracyRung::*q,
                              const double expected)
    {
      const std::size_t   m = rungs.size();
      const AccuracyRung &a = rungs[m - 3], &b = rungs[m - 2], &c = rungs[m - 1];
      return richardson(a.h, b.h, c.h, a.*q, b.*q, c.*q, expected);
    }
  } // namespace

  double FeAccuracyStudy::relative_error(const AccuracyRung &g, const std::string &quantity) const
  {
    const auto &x = (g.study == "fe_level" ? fe_extrapolation : grid_extrapolation).at(quantity);
    double      v = 0;
    for (const auto &q : quantities)
      if (quantity == q.name)
        v = g.*q.member;
    return std::isfinite(x.value) && x.value != 0 ? std::abs(v - x.value) / std::abs(x.value) :
                                                    std::numeric_limits<double>::quiet_NaN();
  }

  std::string FeAccuracyStudy::csv() const
  {
    std::ostringstream csv;
    csv << std::setprecision(10);
    csv << "study,fe_level,fe_degree,contact_profile_cells,contact_face_cells,size_mm,dofs,"
           "wall_time_s,mean_k_total_N_per_m,ste_peak_to_peak_um,k_mh_N_per_m_pow_n,"
           "mean_k_rest_N_per_m,k_total_relative_error,ste_pp_relative_error,"
           "k_mh_relative_error,k_rest_relative_error\n";
    for (const auto *ladder : {&fe_rungs, &grid_rungs})
      for (const auto &g : *ladder)
        {
          csv << g.study << ',' << g.level << ',' << g.degree << ',' << g.profile_cells << ','
              << g.face_cells << ',' << g.h << ',' << g.dofs << ',' << g.wall_time_s << ','
              << g.k_total << ',' << g.ste_pp_um << ',' << g.k_mh << ',' << g.k_rest;
          for (const auto &q : quantities)
            csv << ',' << relative_error(g, q.name);
          csv << '\n';
        }
    return csv.str();
  }

  namespace
  {
    // The verdict on the FE rung of one level: its errors and those of the coarsest grid rung
    // (the input's grid at the input's level) against the extrapolations.
    struct Verdict
    {
      const AccuracyRung *rung = nullptr;
      double k_fe = 0, ste_fe = 0, k_grid = 0, ste_grid = 0;
      bool   within_1_percent = false;
    };

    Verdict verdict(const FeAccuracyStudy &study, const int level)
    {
      Verdict v;
      for (const auto &g : study.fe_rungs)
        if (g.level == level && !study.grid_rungs.empty())
          {
            const auto &grid   = study.grid_rungs.front();
            v.rung             = &g;
            v.k_fe             = study.relative_error(g, "mean_k_total_N_per_m");
            v.ste_fe           = study.relative_error(g, "ste_peak_to_peak_um");
            v.k_grid           = study.relative_error(grid, "mean_k_total_N_per_m");
            v.ste_grid         = study.relative_error(grid, "ste_peak_to_peak_um");
            v.within_1_percent = v.k_fe <= 0.01 && v.ste_fe <= 0.01 && v.k_grid <= 0.01 &&
                                 v.ste_grid <= 0.01;
          }
      return v;
    }
  } // namespace

  nlohmann::json FeAccuracyStudy::json(const int scene_level) const
  {
    nlohmann::json j;
    j["reference_depth_mm"] = reference_depth_mm;
    for (const auto &[name, x] : fe_extrapolation)
      for (const auto &[ladder, e] : {std::pair{"fe_level", x},
                                      std::pair{"contact_grid", grid_extrapolation.at(name)}})
        j["extrapolation"][ladder][name] = {{"value", e.value},
                                            {"observed_order", e.order},
                                            {"asymptotic", e.asymptotic},
                                            {"note", e.note}};
    j["rows"] = nlohmann::json::array();
    for (const auto *ladder : {&fe_rungs, &grid_rungs})
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
                             {"k_total_relative_error", relative_error(g, "mean_k_total_N_per_m")},
                             {"ste_pp_relative_error", relative_error(g, "ste_peak_to_peak_um")},
                             {"k_mh_relative_error", relative_error(g, "k_mh_N_per_m_pow_n")},
                             {"k_rest_relative_error", relative_error(g, "mean_k_rest_N_per_m")}});
    if (const Verdict v = verdict(*this, scene_level); v.rung)
      j["scene_default"] = {{"fe_level", v.rung->level},
                            {"contact_profile_cells", v.rung->profile_cells},
                            {"k_total_relative_error_fe", v.k_fe},
                            {"ste_pp_relative_error_fe", v.ste_fe},
                            {"k_total_relative_error_grid", v.k_grid},
                            {"ste_pp_relative_error_grid", v.ste_grid},
                            {"within_1_percent", v.within_1_percent}};
    return j;
  }

  void FeAccuracyStudy::report(const int scene_level) const
  {
    if (const Verdict v = verdict(*this, scene_level); v.rung)
      progress_line("accuracy", msg("scene default (level ", v.rung->level, ", ",
                                    v.rung->profile_cells, " profile cells): k_total error ",
                                    100 * v.k_fe, " % (FE) ", 100 * v.k_grid,
                                    " % (grid), STE p-p error ", 100 * v.ste_fe, " % (FE) ",
                                    100 * v.ste_grid, " % (grid): ",
                                    v.within_1_percent ? "within" : "NOT within", " 1 %"));
    for (const auto &[ladder, xs] :
         {std::pair{"FE", &fe_extrapolation}, std::pair{"grid", &grid_extrapolation}})
      for (const auto &[name, x] : *xs)
        progress_line("accuracy", msg(ladder, " ladder ", name, ": extrapolated ", x.value,
                                      ", order ", x.order, " (", x.note, ")"));
  }

  FeAccuracyStudy run_fe_accuracy_study(const StiffnessInput &base, const std::vector<int> &levels,
                                        const std::vector<int> &factors,
                                        const std::filesystem::path &mesh_root, PhaseTimer &timer)
  {
    if (levels.size() < 3)
      throw ParameterError("level", "a ladder of fewer than three levels: the study needs at least three");
    if (factors.size() < 3 || factors.front() < 1)
      throw ParameterError("contact_grid_profile_cells",
                           "a ladder of fewer than three grid factors >= 1: the study needs three");
    const int dim = base.fe.dimension;
    FeAccuracyStudy study;
    // The split between FE and half-space is held at the input's reference depth on every level
    // (with d = 3 h following each level the quantity itself would change: k_mh of line contact
    // depends on d).
    study.reference_depth_mm = fe_reference_depth_mm(base.fe, base.pair.pinion.module_mm);
    progress_line("accuracy", msg("reference depth held at ", study.reference_depth_mm,
                                  " mm on every level; finest level first"));
    for (auto it = levels.rbegin(); it != levels.rend(); ++it)
      {
        StiffnessInput input        = base;
        input.fe.level              = *it;
        input.fe.reference_depth_mm = study.reference_depth_mm;
        input.fe.fields_dir.clear();
        input.fe.mesh_dir = mesh_root / ("mesh_level" + std::to_string(*it));
        const bool with_grids = *it == base.fe.level;
        const int  p0 = base.fe.contact_grid_profile_cells, f0 = dim == 2 ? 1 : base.fe.contact_grid_face_cells;
        if (with_grids)
          for (const int f : factors)
            if (f != 1)
              input.fe.extra_contact_grids.emplace_back(p0 * f, dim == 2 ? 1 : f0 * f);
        PhaseTimer        level_timer;
        const auto        t0 = std::chrono::steady_clock::now();
        StiffnessResult   r;
        {
          PhaseTimer::Scope scope(timer, "level " + std::to_string(*it));
          r = find_source("fem").compute(input, level_timer);
        }
        double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        for (const auto &extra : r.extra_grids)
          wall -= extra.contact_time_s;
        AccuracyRung g  = rung_of(r, r.notes.at("dofs").get<std::size_t>());
        g.study         = "fe_level";
        g.level         = *it;
        g.degree        = base.fe.degree;
        g.profile_cells = p0;
        g.face_cells    = f0;
        g.h             = r.notes.at("band_element_size_mm").get<double>();
        g.wall_time_s   = wall;
        study.fe_rungs.insert(study.fe_rungs.begin(), g);
        report(g);
        if (with_grids)
          add_grid_rungs(study, r, g, factors, dim);
      }
    for (const auto &q : quantities)
      {
        study.fe_extrapolation[q.name]   = extrapolate(study.fe_rungs, q.member, fe_expected_order);
        study.grid_extrapolation[q.name] = extrapolate(study.grid_rungs, q.member, grid_expected_order);
      }
    return study;
  }
} // namespace hertzgear::stiffness
