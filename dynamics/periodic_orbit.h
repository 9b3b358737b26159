#pragma once
// Periodic steady states found directly (docs/dynamics.md, "Periodic orbits by shooting"): the
// state x0 at t0 with x(t0 + kT) = x0 for the forcing period T, by Newton's method on the period
// map. Its Jacobian, the monodromy matrix, comes from the variational equations Phi' = J Phi
// integrated with the state by the same integrator, with a saltation matrix at every switching
// event of the piecewise-smooth model (contact loss, back-side contact, the Hertzian layer
// opening and closing):
//   S = I + (f+ - f-) grad(g)^T / (grad(g) . f- + dg/dt),
// f- and f+ the vector fields on either side of the switching surface g = 0 at the event
// (Leine & Nijmeijer, Dynamics and Bifurcations of Non-Smooth Mechanical Systems, 2004, Sec. 3.5).
// The eigenvalues of the monodromy matrix are the Floquet multipliers of the orbit. Multiple
// shooting splits kT into segments whose ends are unknowns too, for orbits whose single-period
// map is too sensitive for Newton from a rough start.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/integrator.h"

#include <Eigen/Dense>

#include <complex>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  // The state and its first-order sensitivities: y' = f(t, y) and Phi' = (df/dy) Phi with
  // Phi(t0) = I, as one system of n + n^2 states (Phi column-major behind y), whose events apply
  // the saltation matrix to Phi. Phi's absolute tolerances are the state's divided by the
  // scale of the perturbed component, so that the response to a perturbation of one scale is
  // controlled like the state itself. Phi must be in the error test: in a quasi-static steady
  // state (the paper's pair at 150 rpm) the state alone lets an L-stable integrator take steps
  // far longer than the mesh mode's period, which damps the mode's free response in Phi to
  // nothing; measured without Phi in the test, |mu|max = 6e-20 instead of 0.9996 for the pair
  // without damping.
  class SensitivitySystem : public OdeSystem
  {
  public:
    // `scales`: a characteristic size per state component (GearPairModel::state_scales).
    SensitivitySystem(OdeSystem &base, std::vector<double> scales);

    unsigned n_states() const override { return n + n * n; }
    void     rhs(double t, const double *y, double *y_dot) override;
    bool     has_jacobian() const override { return true; }
    // The block diagonal of the exact Jacobian (the state's Jacobian, and J once per column of
    // Phi); d(J Phi)/dy, which needs second derivatives, is left out: the simplified Newton
    // iterations of the implicit integrators converge with it, and the error test is unchanged.
    void     jacobian(double t, const double *y, double *jac) const override;
    // That Jacobian is n + 1 copies of the state's n x n Jacobian on the diagonal.
    unsigned jacobian_block_size() const override { return n; }
    double   forcing_period() const override { return base.forcing_period(); }
    unsigned n_roots() const override { return base.n_roots(); }
    void     roots(double t, const double *y, double *g) const override { base.roots(t, y, g); }
    bool     handle_event(double t, double *y, const int *directions) override;
    std::vector<double> absolute_tolerances(double displacement_tolerance) const override;
    std::string         describe_state(const double *y) const override { return base.describe_state(y); }
    std::vector<double> blow_up_bounds() const override;

    // Saltation matrices applied so far, and the smallest |grad(g) . f- + dg/dt| relative to its
    // scale among them (a grazing contact makes it 0 and the saltation matrix unbounded).
    long   events() const { return n_events; }
    double smallest_crossing_speed() const { return min_crossing; }

  private:
    // The base's Jacobian (analytic, or central differences when it has none).
    void   base_jacobian(double t, const double *y, double *jac) const;
    // f on one side of root function r's surface at (t, y): extrapolated to g = 0 from two
    // points at g = side eps and side 2 eps, where the base's branch is that side's.
    void   one_side(double t, const double *y, unsigned r, int side, const double *grad,
                    double *f) const;

    OdeSystem          &base;
    unsigned            n;
    std::vector<double> scale;
    long                n_events     = 0;
    double              min_crossing = 1e300;
  };

  // The flow of `system` from (t0, y0) over `duration` with its sensitivity dy(t0 + duration)/dy0.
  struct FlowWithSensitivity
  {
    std::vector<double> y;
    Eigen::MatrixXd     jacobian;
    long                events = 0;
  };
  FlowWithSensitivity flow_with_sensitivity(OdeSystem &system, const std::vector<double> &scales,
                                            Integrator &integrator, double t0,
                                            const std::vector<double> &y0, double duration);

  // The integrator settings for flows over one period with their sensitivities: those given,
  // without Radau IIA's periodic starting values, and with 7 stages below rtol 1e-7 where the
  // stage count is left to the tolerance.
  IntegratorSettings sensitivity_integrator(IntegratorSettings settings);

  struct ShootingSettings
  {
    // Any adaptive integrator that locates events (rk4 cannot serve: it has no event location).
    IntegratorSettings integrator;
    int    period_multiple = 1;   // k: the orbit closes after k forcing periods
    int    segments        = 1;   // multiple shooting: segments per k periods (1: single)
    // Newton stops when the scaled correction max_i |dx_i| / scale_i is below this, and fails
    // after max_iterations or when the scaled residual is not reduced by halving the step 8 times.
    double tolerance       = 1e-9;
    int    max_iterations  = 40;
  };

  // Throws ParameterError naming the field of ShootingSettings that is out of range.
  void check_shooting_settings(const ShootingSettings &settings);

  struct PeriodicOrbit
  {
    bool                              converged = false;
    std::string                       failure; // why not, when not converged
    double                            t0_s      = 0.0;
    double                            period_s  = 0.0; // k T
    int                               period_multiple = 1;
    std::vector<double>               state;           // x(t0) = x(t0 + kT)
    Eigen::MatrixXd                   monodromy;       // dx(t0 + kT)/dx(t0)
    std::vector<std::complex<double>> multipliers;     // eigenvalues, largest modulus first
    double                            largest_multiplier_modulus = 0.0;
    bool                              stable     = false; // every |mu| < 1
    int                               iterations = 0;
    double                            correction = 0.0; // last scaled Newton correction
    double                            residual   = 0.0; // max_i |x_i(t0 + kT) - x_i(t0)| / scale_i
    long                              events_per_period = 0; // switching events in kT
    IntegratorStats                   stats;
  };

  // Newton's method on the k-period map of `model` from the guess x(t0) = `guess` (t0 = 0).
  // Returns the orbit, or converged = false with the reason; throws NumericalError only when
  // the integrator itself fails.
  PeriodicOrbit find_periodic_orbit(GearPairModel &model, const std::vector<double> &guess,
                                    const ShootingSettings &settings);

  // The Floquet multipliers of a monodromy matrix, largest modulus first.
  std::vector<std::complex<double>> floquet_multipliers(const Eigen::MatrixXd &monodromy);

  // The orbit sampled over its k periods and analysed like the steady window of a time-marched
  // run (RMS and extremes of the DTE, forces, dynamic factor, contact loss); the period fields
  // say "period-k" from the orbit itself.
  SteadyStateSummary analyse_orbit(GearPairModel &model, const PeriodicOrbit &orbit,
                                   const RunSettings &run);
} // namespace hertzgear::dynamics
