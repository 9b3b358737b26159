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
//   fold             the parameter component of the tangent changes sign and a real multiplier
//                    is +1 (within fold_multiplier_tolerance at the located point);
//   corner turn      the parameter turns back where the number of switchings per period changes
//                    (a grazing contact) and no multiplier is 1: a non-smooth turning point;
//   period doubling  prod_i (mu_i + 1) changes sign (a real multiplier through -1);
//   Neimark-Sacker   prod_{i<j} (mu_i mu_j - 1) changes sign with a complex pair through |mu| = 1;
// each located by bisection on the step length, reported as a point of the branch. A turning
// point that is neither (no multiplier at 1, the same switchings on both sides: the period map is
// not integrated accurately enough for its Newton tolerance), or one that cannot be located, is
// not reported: the branch goes on and its notes say where and why. A corrected point farther from its predictor than the step length
// is refused (the step is halved), so that a step cannot jump to another branch. At a period
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
    // A located turning point is a fold when a real multiplier lies this close to +1. Near a fold
    // mu - 1 grows like the square root of the parameter's distance to it: at 1e-4 the fold lies
    // within about 1e-9 of the parameter; at the folds of the paper's tables (integration at
    // 1e-10, Newton at 1e-6) the nearest multiplier lies up to 9.4e-5 from 1 after the located
    // point has passed this test (a step that fails it is retaken shorter), while a bisection that
    // closed on a jump across the fold, not on it, left 1.5e-2 or more (0.979, 0.945, 1.07).
    double fold_multiplier_tolerance = 1e-4;
  };

  // Throws ParameterError naming the field of ContinuationSettings that is out of range.
  void check_continuation_settings(const ContinuationSettings &settings);

  enum class Bifurcation
  {
    none,
    fold,
    period_doubling,
    neimark_sacker,
    corner_turn // a turning point at a non-smooth point of the branch (no multiplier at 1)
  };
  // "", fold, period-doubling, neimark-sacker, corner-turn
  std::string bifurcation_name(Bifurcation b);

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
    // Turning points or bifurcations the branch passed without reporting them, each with where
    // (the parameter range of its step) and why (not located: a corrector failed at it; no
    // multiplier at 1 without a corner).
    struct Note
    {
      Bifurcation kind = Bifurcation::fold; // fold: a turning point
      double      lambda_from = 0.0, lambda_to = 0.0;
      std::string text;
    };
    std::vector<Note>              notes;
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
