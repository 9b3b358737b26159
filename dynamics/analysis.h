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

  struct SimulationResult
  {
    double                     mesh_period_s = 0.0;
    int                        samples_per_period = 0;
    int                        steady_periods     = 0;
    std::vector<Sample>        steady;   // steady_periods * samples_per_period + 1 samples
    std::vector<PoincarePoint> poincare; // one per mesh period of the steady window, and its end
    std::vector<double>        final_state;
    IntegratorStats            stats;
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
    double energy_dissipated_J  = 0.0; // loop area, the integral of F d(delta) over the episode
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
    int    period_multiplicity   = 0; // 1..8, 0 aperiodic
    double mean_energy_per_impact_J = 0.0;
    int    n_impacts             = 0;
  };
  // JSON with the member names as keys (nlohmann's to_json / from_json).
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SteadyStateSummary, rms_dte_m, rms_dte_fluctuation_m, mean_dte_m,
                                     min_dte_m, max_dte_m, mean_force_N, max_force_N, min_force_N,
                                     static_force_N, dynamic_factor, max_penetration_m,
                                     contact_loss_fraction, contact_losses_per_period,
                                     backside_impacts, period_multiplicity,
                                     mean_energy_per_impact_J, n_impacts)

  // Smallest k in 1..max_k with |x_{j+k} - x_j| <= relative_tolerance * x_scale and
  // |x'_{j+k} - x'_j| <= relative_tolerance * v_scale over the last 2k + 8 points of the section
  // (at least two repetitions of the pattern), 0 (aperiodic) if none. The scales are the
  // peak-to-peak DTE and the largest |x'| of the steady motion.
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
