#pragma once
// Running the gear-pair model over many mesh periods and analysing its steady state the way
// gear-dynamics papers do: RMS and extremes of the DTE, mesh force and dynamic factor, contact
// loss, back-side impacts, Poincare section and period-k detection, FFT spectrum (FFTW) and
// force-penetration loops.
#include "dynamics/gear_pair_model.h"
#include "dynamics/integrator.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  struct RunSettings
  {
    IntegratorSettings integrator;
    int                periods            = 800;
    int                transient_periods  = 400;
    int                samples_per_period = 100;
    int                steps_per_period   = 100; // rk4 only
    // Extremes (DTE, mesh force, penetration) located on the integrator's dense output between
    // the samples, not only at the samples.
    bool               dense_extremes     = true;
  };

  // One output sample.
  struct Sample
  {
    double t_s           = 0.0;
    double dte_m         = 0.0;
    double dte_rate_m_per_s = 0.0;
    double penetration_m = 0.0;
    double force_N       = 0.0;
    int    contact       = 0; // 1 forward, 0 none, -1 back side
  };

  struct PoincarePoint
  {
    double t_s              = 0.0;
    double dte_m            = 0.0;
    double dte_rate_m_per_s = 0.0;
  };

  // The extremes of the steady window, each with the time it is reached.
  struct SteadyExtremes
  {
    double min_dte_m = 0.0, max_dte_m = 0.0, min_force_N = 0.0, max_force_N = 0.0,
           max_penetration_m = 0.0; // max |delta|
    double t_min_dte_s = 0.0, t_max_dte_s = 0.0, t_min_force_s = 0.0, t_max_force_s = 0.0,
           t_max_penetration_s = 0.0;
  };

  struct SimulationResult
  {
    double                     mesh_period_s = 0.0;
    int                        samples_per_period = 0;
    int                        steady_periods     = 0;
    std::vector<Sample>        steady;   // steady_periods * samples_per_period + 1 samples
    std::vector<PoincarePoint> poincare; // one per mesh period of the steady window, and its end
    std::vector<double>        final_state;
    IntegratorStats            stats;
    double                     relative_tolerance = 0.0; // the integrator's (period detection)
    // Located on the dense output (RunSettings::dense_extremes); else only the samples count.
    bool                       has_dense_extremes = false;
    SteadyExtremes             dense_extremes;
  };

  // Progress: called after each chunk with (periods done, periods in all).
  using ProgressCallback = std::function<void(int done, int total)>;

  SimulationResult simulate(GearPairModel &model, const RunSettings &settings,
                            std::vector<double> initial_state,
                            const ProgressCallback &progress = {});

  struct ImpactLoop
  {
    double start_s              = 0.0;
    double end_s                = 0.0;
    double max_force_N          = 0.0;
    double max_penetration_m    = 0.0;
    // The loop integral of F d(delta) over the episode (trapezoids over the samples): the net
    // work the mesh force does on the Hertzian penetration. With k_h constant during the contact
    // it is the energy the contact damping dissipates (>= 0); with k_h(t) varying under load it
    // also holds the work of the stiffness variation and can be negative (docs/dynamics.md).
    double loop_work_J          = 0.0;
  };

  struct SteadyStateSummary
  {
    double rms_dte_m             = 0.0; // sqrt(mean x^2), the mean included (as the paper)
    double rms_dte_fluctuation_m = 0.0; // about the mean
    double mean_dte_m            = 0.0;
    double min_dte_m             = 0.0;
    double max_dte_m             = 0.0;
    double mean_force_N          = 0.0;
    double max_force_N           = 0.0;
    double min_force_N           = 0.0; // < 0 when a viscous part pulls (docs/dynamics.md)
    double static_force_N        = 0.0;
    double dynamic_factor        = 0.0; // max F / F_0 (0 when F_0 = 0)
    double max_penetration_m     = 0.0;
    double contact_loss_fraction = 0.0;
    double contact_losses_per_period = 0.0;
    int    backside_impacts      = 0;
    int    period_multiplicity   = 0; // 1..8 when settled; 0 aperiodic or not settled
    // "period-k", "not settled" or "aperiodic" (PeriodDetection); when not settled, the nearest
    // period and the estimates that decided it.
    std::string period_status;
    int    period_candidate           = 0;
    double period_contraction         = 0.0; // per mesh period, estimated from the section
    double period_distance            = 0.0; // estimated distance from the limit, / scale
    double mean_loop_work_per_impact_J = 0.0; // mean ImpactLoop::loop_work_J
    int    n_impacts             = 0;
    // Where the extremes (min/max DTE and force, max penetration, dynamic factor) come from:
    // "dense output" (the integrator's interpolant, maximised inside every step of the steady
    // window, and the samples) or "samples" (the output samples only).
    std::string extremes_from;
    // The force law's data end (MeshForceLaw::tabulated_force_limit: the FE law's top rung; 0 for
    // a closed-form law without one), and the fraction of the steady window's samples whose mesh
    // force lies above it, where the law extrapolates (docs/dynamics.md, "The FE force law").
    // force_law_extrapolated: the largest force (dense output included) lies above it.
    double tabulated_force_limit_N = 0.0;
    double extrapolated_fraction   = 0.0;
    bool   force_law_extrapolated  = false;
  };
  // JSON with the member names as keys (nlohmann's to_json / from_json).
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SteadyStateSummary, rms_dte_m, rms_dte_fluctuation_m, mean_dte_m,
                                     min_dte_m, max_dte_m, mean_force_N, max_force_N, min_force_N,
                                     static_force_N, dynamic_factor, max_penetration_m,
                                     contact_loss_fraction, contact_losses_per_period,
                                     backside_impacts, period_multiplicity, period_status,
                                     period_candidate, period_contraction, period_distance,
                                     mean_loop_work_per_impact_J, n_impacts, extremes_from,
                                     tabulated_force_limit_N, extrapolated_fraction,
                                     force_law_extrapolated)

  // Period-k detection from the convergence of the Poincare section, not from the size of its
  // differences alone. For k = 1..max_k, the k-step differences
  //   d_j = max(|x_{j+k} - x_j| / x_scale, |x'_{j+k} - x'_j| / v_scale)
  // over the last 2k + 8 points are fitted by d_j ~ C r^j (least squares on log d_j): r is the
  // contraction per mesh period towards a period-k motion, and the last point's distance from it
  // is at most about D = d_last r^k / (1 - r^k), the geometric tail. A motion is settled period-k when
  // every d_j is at most `settle_tolerance`, or when d_last and D are (r < 1). A slowly decaying
  // transient, such as a Floquet multiplier of -0.998 alternating the points, has small 2-step
  // differences but r^2 ~ 0.996 and D ~ 250 d_last: it is not settled. The smallest settled k is
  // the multiplicity; without one, the contracting k with the smallest D is the candidate
  // ("not settled"), and "aperiodic" when none contracts.
  struct PeriodDetection
  {
    int         multiplicity = 0; // settled k, 0 otherwise
    int         candidate    = 0; // the nearest period-k when not settled (0: none contracts)
    double      contraction  = 0.0; // r, per mesh period, of the candidate or the settled k
    double      distance     = 0.0; // D / scale of the candidate or the settled k
    double      tolerance    = 0.0; // settle_tolerance used
    std::string status;             // "period-k", "not settled" or "aperiodic"
  };
  PeriodDetection detect_period(const std::vector<PoincarePoint> &section, double x_scale,
                                double v_scale, double settle_tolerance, int max_k = 8);

  // The settle tolerance of detect_period for an integration at relative tolerance rtol: the
  // Poincare points of a settled motion repeat to their integration error, measured at 10 to 100
  // rtol of the peak-to-peak DTE across contact loss (cvode-bdf, rtol 1e-6 to 1e-10;
  // docs/dynamics.md); 1000 rtol keeps a margin above that, and 1e-12 bounds it at rounding level.
  double period_settle_tolerance(double relative_tolerance);

  // detect_period(...).multiplicity with the settle tolerance `relative_tolerance`.
  int period_multiplicity(const std::vector<PoincarePoint> &section, double x_scale, double v_scale,
                          double relative_tolerance = 1e-4, int max_k = 8);

  std::vector<ImpactLoop> force_penetration_loops(const SimulationResult &result);

  SteadyStateSummary analyse(const GearPairModel &model, const SimulationResult &result);

  struct SpectrumLine
  {
    double frequency_Hz = 0.0;
    double mesh_order   = 0.0; // frequency / mesh frequency
    double amplitude_m  = 0.0;
  };
  // One-sided amplitude spectrum of the steady DTE (mean removed), by FFTW.
  std::vector<SpectrumLine> dte_spectrum(const SimulationResult &result);
} // namespace hertzgear::dynamics
