#include "dynamics/result_writer.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hertzgear::dynamics
{
  std::string csv_number(const double v)
  {
    std::ostringstream os;
    os.precision(12);
    os << v;
    return os.str();
  }

  nlohmann::json summary_json(const GearPairModel &model, const SimulationResult &result,
                              const SteadyStateSummary &s, const nlohmann::json &model_description)
  {
    nlohmann::json j;
    // Lengths in um.
    for (const auto &[key, metres] : {std::pair{"rms_dte_um", s.rms_dte_m},
                                      {"rms_dte_fluctuation_um", s.rms_dte_fluctuation_m},
                                      {"mean_dte_um", s.mean_dte_m},
                                      {"min_dte_um", s.min_dte_m},
                                      {"max_dte_um", s.max_dte_m},
                                      {"max_penetration_um", s.max_penetration_m}})
      j[key] = 1e6 * metres;
    j["mean_mesh_force_N"] = s.mean_force_N;
    j["static_force_N"]    = s.static_force_N;
    j["max_mesh_force_N"]  = s.max_force_N;
    j["min_mesh_force_N"]  = s.min_force_N;
    j["dynamic_factor"]    = s.dynamic_factor;
    j.update({{"contact_loss_fraction", s.contact_loss_fraction},
              {"contact_losses_per_period", s.contact_losses_per_period},
              {"backside_impacts", s.backside_impacts},
              {"period_multiplicity", s.period_multiplicity}});
    // How the period was decided (detect_period): "period-k", "not settled" (with the nearest
    // period, the contraction per mesh period and the distance from it relative to the DTE
    // scale, all estimated from the Poincare section) or "aperiodic".
    j["period_status"]                 = s.period_status;
    j["period_candidate"]              = s.period_candidate;
    j["period_contraction_per_period"] = s.period_contraction;
    j["period_distance_relative"]      = s.period_distance;
    // "dense output": the extremes above (DTE, mesh force, penetration, dynamic factor) are
    // maxima of the integrator's interpolant inside every step; "samples": of the samples only.
    j["extremes_from"] = s.extremes_from;
    j["impacts"]       = s.n_impacts;
    // The mean of the loop integrals of F d(delta) over the impacts: the contact damping's
    // dissipation when k_h is constant under load, else with the stiffness variation's work.
    j["mean_loop_work_per_impact_J"] = s.mean_loop_work_per_impact_J;
    // Where the force law's data end (the FE law's top rung) and how much of the steady window
    // lies above it, extrapolated (docs/dynamics.md, "The FE force law"); null limit: none.
    j["force_law"] = {{"tabulated_force_limit_N", s.tabulated_force_limit_N > 0.0 ?
                                                    nlohmann::json(s.tabulated_force_limit_N) :
                                                    nlohmann::json()},
                      {"extrapolated_fraction", s.extrapolated_fraction},
                      {"extrapolated", s.force_law_extrapolated}};
    j.update({{"state_dimension", model.n_states()},
              {"effects", model.parameters().effects.describe()},
              {"equivalent_mass_kg", model.parameters().equivalent_mass_kg},
              {"steady_periods", result.steady_periods},
              {"mesh_period_s", result.mesh_period_s},
              {"model", model_description},
              {"integrator", nlohmann::json(result.stats)},
              {"wall_time_s", result.stats.wall_time_s}});
    return j;
  }

  namespace
  {
    // `header`, then one row by `row` per sample of the last `last_periods` mesh periods of the
    // steady window (all of it when 0 or more).
    template <typename Row>
    std::string steady_window_csv(const SimulationResult &result, const int last_periods,
                                  const char *header, const Row &row)
    {
      const auto       &s     = result.steady;
      const std::size_t first = (last_periods > 0 && last_periods < result.steady_periods) ?
                                  s.size() - 1 - std::size_t(last_periods) * result.samples_per_period :
                                  0;
      std::ostringstream os;
      os << header;
      for (std::size_t i = first; i < s.size(); ++i)
        row(os, s[i]);
      return os.str();
    }
  } // namespace

  std::string timeseries_csv(const SimulationResult &result, const int last_periods)
  {
    return steady_window_csv(
      result, last_periods, "time_s,dte_um,dte_rate_m_per_s,penetration_um,mesh_force_N,contact\n",
      [](std::ostream &os, const Sample &s) {
        os << csv_number(s.t_s) << ',' << csv_number(1e6 * s.dte_m) << ','
           << csv_number(s.dte_rate_m_per_s) << ',' << csv_number(1e6 * s.penetration_m) << ','
           << csv_number(s.force_N) << ',' << s.contact << '\n';
      });
  }

  std::string poincare_csv(const SimulationResult &result)
  {
    std::ostringstream os;
    os << "period,time_s,dte_um,dte_rate_m_per_s\n";
    for (std::size_t i = 0; i < result.poincare.size(); ++i)
      os << i << ',' << csv_number(result.poincare[i].t_s) << ','
         << csv_number(1e6 * result.poincare[i].dte_m) << ','
         << csv_number(result.poincare[i].dte_rate_m_per_s) << '\n';
    return os.str();
  }

  std::string spectrum_csv(const SimulationResult &result)
  {
    std::ostringstream os;
    os << "frequency_Hz,mesh_order,amplitude_um\n";
    for (const auto &l : dte_spectrum(result))
      os << csv_number(l.frequency_Hz) << ',' << csv_number(l.mesh_order) << ','
         << csv_number(1e6 * l.amplitude_m) << '\n';
    return os.str();
  }

  std::string force_penetration_csv(const SimulationResult &result, const int last_periods)
  {
    // The loops of the written time window (impacts_csv holds the energy of every closed loop).
    return steady_window_csv(result, last_periods, "time_s,penetration_um,mesh_force_N,contact\n",
                             [](std::ostream &os, const Sample &s) {
                               os << csv_number(s.t_s) << ',' << csv_number(1e6 * s.penetration_m)
                                  << ',' << csv_number(s.force_N) << ',' << s.contact << '\n';
                             });
  }

  std::string impacts_csv(const SimulationResult &result)
  {
    std::ostringstream os;
    os << "start_s,end_s,max_force_N,max_penetration_um,loop_work_J\n";
    for (const auto &l : force_penetration_loops(result))
      os << csv_number(l.start_s) << ',' << csv_number(l.end_s) << ','
         << csv_number(l.max_force_N) << ',' << csv_number(1e6 * l.max_penetration_m) << ','
         << csv_number(l.loop_work_J) << '\n';
    return os.str();
  }

  std::string sweep_csv(const std::vector<SweepRow> &rows)
  {
    std::ostringstream os;
    os << "speed_rpm,direction,rms_dte_um,min_dte_um,max_dte_um,dynamic_factor,"
          "contact_loss_fraction,period_multiplicity,extremes_from,extrapolated_fraction\n";
    for (const auto &r : rows)
      os << csv_number(r.speed_rpm) << ',' << sweep_branch_name(r.branch) << ','
         << csv_number(1e6 * r.summary.rms_dte_m) << ','
         << csv_number(1e6 * r.summary.min_dte_m) << ','
         << csv_number(1e6 * r.summary.max_dte_m) << ','
         << csv_number(r.summary.dynamic_factor) << ','
         << csv_number(r.summary.contact_loss_fraction) << ','
         << r.summary.period_multiplicity << ',' << r.summary.extremes_from << ','
         << csv_number(r.summary.extrapolated_fraction) << '\n';
    return os.str();
  }

  std::string bifurcation_csv(const std::vector<SweepRow> &rows, const bool independent)
  {
    std::ostringstream os;
    os << "speed_rpm,poincare_dte_um\n";
    for (const auto &r : rows)
      if (independent == (r.branch == SweepBranch::independent))
        for (const double x : r.poincare_dte_m)
          os << csv_number(r.speed_rpm) << ',' << csv_number(1e6 * x) << '\n';
    return os.str();
  }

  namespace
  {
    // "re+imi;re-imi;..." with 9 significant digits.
    std::string multipliers_text(const std::vector<std::complex<double>> &mu)
    {
      std::ostringstream os;
      os.precision(9);
      for (std::size_t i = 0; i < mu.size(); ++i)
        os << (i ? ";" : "") << mu[i].real() << (mu[i].imag() < 0 ? "" : "+") << mu[i].imag() << 'i';
      return os.str();
    }
  } // namespace

  std::string response_csv(const ContinuationResult &result, const std::string &column)
  {
    std::ostringstream os;
    os << column
       << ",branch,period_multiple,stable,bifurcation,rms_dte_um,min_dte_um,max_dte_um,"
          "dynamic_factor,contact_loss_fraction,max_penetration_um,max_multiplier_modulus,"
          "multipliers,events_per_period,arclength,method\n";
    for (const auto &b : result.branches)
      for (const auto &p : b.points)
        {
          const auto &s = p.summary;
          os << csv_number(p.lambda) << ',' << p.branch << ',' << p.period_multiple << ','
             << (p.stable ? 1 : 0) << ',' << bifurcation_name(p.bifurcation) << ','
             << csv_number(1e6 * s.rms_dte_m) << ',' << csv_number(1e6 * s.min_dte_m) << ','
             << csv_number(1e6 * s.max_dte_m) << ',' << csv_number(s.dynamic_factor) << ','
             << csv_number(s.contact_loss_fraction) << ','
             << csv_number(1e6 * s.max_penetration_m) << ','
             << csv_number(std::abs(p.multipliers.front())) << ','
             << multipliers_text(p.multipliers) << ',' << p.events_per_period << ','
             << csv_number(p.arclength) << ",shooting\n";
        }
    return os.str();
  }

  nlohmann::json response_json(const ContinuationResult &result, const std::string &column,
                               const double wall_time_s)
  {
    nlohmann::json j;
    j["parameter"]     = column;
    j["orbits_solved"] = result.orbits_solved;
    j["integrator"]    = nlohmann::json(result.stats);
    j["wall_time_s"]   = wall_time_s;
    j["branches"]      = nlohmann::json::array();
    j["bifurcations"]  = nlohmann::json::array();
    // Orbits whose mesh force goes above the force law's data (the FE law's top rung).
    int    extrapolated = 0;
    double limit        = 0.0;
    for (const auto &b : result.branches)
      for (const auto &p : b.points)
        {
          extrapolated += p.summary.force_law_extrapolated ? 1 : 0;
          limit = std::max(limit, p.summary.tabulated_force_limit_N);
        }
    j["force_law"] = {{"tabulated_force_limit_N", limit > 0.0 ? nlohmann::json(limit) : nlohmann::json()},
                      {"extrapolated_orbits", extrapolated}};
    for (const auto &b : result.branches)
      {
        int stable = 0;
        for (const auto &p : b.points)
          stable += p.stable ? 1 : 0;
        j["branches"].push_back({{"id", b.id},
                                 {"period_multiple", b.period_multiple},
                                 {"parent", b.parent},
                                 {"start", b.start_lambda},
                                 {"points", b.points.size()},
                                 {"stable_points", stable},
                                 {"end_reason", b.end_reason},
                                 {"ended_in_failure", b.ended_in_failure},
                                 {"corners_passed", b.corners},
                                 {"notes", [&] {
                                    auto notes = nlohmann::json::array();
                                    for (const auto &note : b.notes)
                                      notes.push_back({{"type", note.kind == Bifurcation::fold ?
                                                                  std::string("turning point") :
                                                                  bifurcation_name(note.kind)},
                                                       {column + "_from", note.lambda_from},
                                                       {column + "_to", note.lambda_to},
                                                       {"text", note.text}});
                                    return notes;
                                  }()}});
        for (const auto &p : b.points)
          if (p.bifurcation != Bifurcation::none)
            j["bifurcations"].push_back({{"type", bifurcation_name(p.bifurcation)},
                                         {column, p.lambda},
                                         {"branch", p.branch},
                                         {"period_multiple", p.period_multiple},
                                         {"rms_dte_um", 1e6 * p.summary.rms_dte_m},
                                         {"multipliers", multipliers_text(p.multipliers)}});
      }
    return j;
  }

  namespace
  {
    // A CSV field in double quotes, inner quotes doubled.
    std::string quoted(const std::string &s)
    {
      std::string t = "\"";
      for (const char ch : s)
        t += (ch == '"') ? std::string("\"\"") : std::string(1, ch);
      return t + "\"";
    }
  } // namespace

  std::string work_precision_csv(const WorkPrecisionStudy &study)
  {
    std::ostringstream csv;
    csv << "integrator,stages,relative_tolerance,steps_per_period,wall_time_s,rhs_evals,steps,"
           "rms_dte_um,rms_dte_relative_error,poincare_max_error_um,poincare_relative_error,"
           "max_force_relative_error,status\n";
    csv.precision(6);
    for (const auto &p : study.points)
      csv << integrator_name(p.case_.kind) << ',' << (p.case_.stages > 0 ? msg(p.case_.stages) : "")
          << ',' << (p.case_.rtol > 0 ? msg(p.case_.rtol) : "")
          << ',' << (p.case_.steps_per_period > 0 ? msg(p.case_.steps_per_period) : "") << ','
          << p.stats.wall_time_s << ',' << p.stats.rhs_evals << ',' << p.stats.steps << ','
          << 1e6 * p.rms_dte_m << ',' << p.rms_relative_error << ',' << 1e6 * p.poincare_max_error_m
          << ',' << p.poincare_relative_error << ',' << p.max_force_relative_error << ','
          << quoted(p.status) << '\n';
    return csv.str();
  }

  nlohmann::json work_precision_reference_json(const WorkPrecisionStudy &study)
  {
    return {{"reference_name", study.reference_name},
            {"reference", nlohmann::json(study.reference_stats)},
            {"reference_rms_dte_um", 1e6 * study.reference_summary.rms_dte_m},
            {"reference_max_force_N", study.reference_summary.max_force_N},
            {"reference_check_rms_relative_difference", study.check_rms_relative_difference},
            {"reference_check_poincare_max_difference_um",
             1e6 * study.check_poincare_max_difference_m},
            {"reference_check_max_force_relative_difference",
             study.check_max_force_relative_difference}};
  }
} // namespace hertzgear::dynamics
