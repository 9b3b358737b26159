#pragma once
// Periodic orbits followed in a parameter (speed, torque, damping ratio, ...) by pseudo-arclength
// continuation (Keller 1977; Seydel, Practical Bifurcation and Stability Analysis, 3rd ed. 2010,
// Ch. 4; docs/dynamics.md "Continuation of periodic orbits"), with their Floquet multipliers
// from the shooting method (periodic_orbit.h). The unknowns are the scaled orbit start
// u = x(0) / scale and the scaled parameter l = (lambda - lambda_min) / (lambda_max - lambda_min);
// a step predicts along the tangent of the branch and corrects by Newton's method on
//   G(u, l) = (phi_kT(x; lambda) - x) / scale = 0,   tau^T ((u, l) - predicted) = 0,
// so that folds, where lambda turns back, are passed like any other point. At a grazing contact
// the period map of the piecewise-smooth model is continuous but its derivative jumps, and the
// branch has a corner: when the step collapses there, larger steps with more corrector iterations
// start beyond the corner. Along the branch:
//   fold             the parameter component of the tangent changes sign (a multiplier at +1);
//   period doubling  prod_i (mu_i + 1) changes sign (a real multiplier through -1);
//   Neimark-Sacker   prod_{i<j} (mu_i mu_j - 1) changes sign with a complex pair through |mu| = 1;
// each located by bisection on the step length, reported as a point of the branch. At a period
// doubling the period-2k branch is started from x* + eps v (v the eigenvector of the multiplier
// -1) along v and followed as a branch of its own.
#include "dynamics/periodic_orbit.h"

#include <functional>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  // A one-parameter family of gear pairs: the model's parameters at lambda.
  struct ParameterFamily
  {
    std::string                                       name; // e.g. "speed_rpm"
    std::function<GearPairParameters(double lambda)> at;
  };

  struct ContinuationSettings
  {
    ShootingSettings shooting;          // the integrator, the Newton tolerance, the start's k
    RunSettings      analysis;          // samples per period, dense extremes of each point
    double lambda_min   = 0.0;
    double lambda_max   = 1.0;
    double lambda_start = 0.0;          // where the first orbit is found
    int    direction    = +1;           // +1: towards lambda_max first; -1: towards lambda_min
    // Step lengths in the scaled arclength (l spans 0 ... 1 over the parameter range).
    double step_initial = 0.005;
    double step_min     = 1e-7;
    double step_max     = 0.02;
    int    max_points   = 5000;         // per branch
    int    corrector_iterations = 8;    // a corrector that needs more halves the step
    bool   follow_period_doubling = true;
    int    max_branches = 4;            // the first branch and the period-doubled ones
    // Bifurcations are located to this fraction of the step length.
    double location_tolerance = 1e-6;
  };

  // Throws ParameterError naming the field of ContinuationSettings that is out of range.
  void check_continuation_settings(const ContinuationSettings &settings);

  enum class Bifurcation
  {
    none,
    fold,
    period_doubling,
    neimark_sacker
  };
  std::string bifurcation_name(Bifurcation b); // "", fold, period-doubling, neimark-sacker

  struct ContinuationPoint
  {
    double                            lambda          = 0.0;
    int                               branch          = 0;
    int                               period_multiple = 1;
    double                            arclength       = 0.0; // along its branch, scaled
    std::vector<double>               state;                 // x(0)
    std::vector<std::complex<double>> multipliers;
    bool                              stable          = false;
    Bifurcation                       bifurcation     = Bifurcation::none;
    int                               corrector_iterations = 0;
    long                              events_per_period    = 0;
    SteadyStateSummary                summary;               // the orbit analysed
  };

  struct ContinuationBranch
  {
    int                            id              = 0;
    int                            period_multiple = 1;
    int                            parent          = -1; // the branch whose period doubling starts it
    double                         start_lambda    = 0.0;
    std::vector<ContinuationPoint> points;               // in arclength order
    std::string                    end_reason;           // why the continuation stopped
    bool                           ended_in_failure = false; // step collapsed below step_min
    int                            corners = 0; // non-smooth points passed (grazing contacts)
  };

  struct ContinuationResult
  {
    std::vector<ContinuationBranch> branches;
    IntegratorStats                 stats;
    int                             orbits_solved = 0; // corrector iterations, all branches
  };

  // Progress: called after every point (bifurcation points included).
  using ContinuationProgress =
    std::function<void(const ContinuationBranch &branch, const ContinuationPoint &point)>;

  // Follows the periodic orbits of `family` from the one found near `guess` at lambda_start.
  // Throws NumericalError (exit 3) when no periodic orbit is found at the start; a branch whose
  // step collapses ends with ended_in_failure and the reason, and the others go on.
  ContinuationResult continue_periodic_orbits(const ParameterFamily &family,
                                              const std::vector<double> &guess,
                                              const ContinuationSettings &settings,
                                              const ContinuationProgress &progress = {});
} // namespace hertzgear::dynamics
