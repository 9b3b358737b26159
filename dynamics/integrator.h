#pragma once
// Time integrators for an OdeSystem: the paper's fixed-step RK4, three SUNDIALS integrators
// (ARKODE explicit RK, CVODE BDF with a dense Jacobian, IDA for the residual/DAE form) and a
// Radau IIA collocation of high order for small stiff systems (radau_integrator.cc). The
// adaptive ones locate every root of the system's root functions and restart cleanly there.
#include "dynamics/ode_system.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  enum class IntegratorKind
  {
    rk4,
    arkode_erk,
    cvode_bdf,
    arkode_dirk,
    ida,
    radau_iia
  };

  IntegratorKind     integrator_kind_from_name(const std::string &name); // rk4 | arkode-erk | ...
  std::string        integrator_name(IntegratorKind kind);

  struct IntegratorSettings
  {
    // radau-iia: the cheapest at every accuracy on the cases of docs/accuracy-dynamics.md.
    IntegratorKind kind                  = IntegratorKind::radau_iia;
    double         relative_tolerance    = 1.0e-8;
    double         absolute_tolerance    = 1.0e-13; // on displacements; see OdeSystem
    double         fixed_step            = 0.0;     // rk4 only [s]
    long           max_steps_per_output  = 500000;  // adaptive: between two output samples
    double         max_step              = 0.0;     // adaptive: 0 = unlimited [s]
    int            max_order             = 0;       // cvode-bdf, ida: 0 = the default 5
    // cvode-bdf: BDF orders 3-5 are unstable for lightly damped modes near the imaginary axis
    // (the mesh mode with zeta ~ 0.015); stability limit detection lowers the order there.
    bool           stability_limit_detection = true;
    int            stages                = 0; // radau-iia: 3, 5, 7 or 9; 0 = by the tolerance
    // radau-iia: Newton starting values from the steps one forcing period earlier when they are
    // nearer the solution than the extrapolated last step (a periodic steady state).
    bool           periodic_start        = true;
  };

  struct IntegratorStats
  {
    std::string name;
    long        steps          = 0;
    long        rejected_steps = 0; // error-test plus nonlinear-convergence failures
    long        rhs_evals      = 0;
    long        jacobian_evals = 0;
    long        root_evals     = 0;
    long        events         = 0;
    double      wall_time_s    = 0.0;

    IntegratorStats &operator+=(const IntegratorStats &other);
  };

  // JSON with the member names as keys (nlohmann's to_json / from_json).
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(IntegratorStats, name, steps, rejected_steps, rhs_evals,
                                     jacobian_evals, root_evals, events, wall_time_s)

  // Called at every output time with the state there.
  using Observer = std::function<void(double t, const double *y)>;

  // The integrator's continuous solution inside one step (its dense output): writes y(t) for
  // t in the step's interval. Valid only during the StepObserver call it is passed to.
  using DenseOutput = std::function<void(double t, double *y)>;
  // Called after every accepted step with the interval [t_begin, t_end] it covers (up to the
  // event when the step located one; t_begin is where the previous report ended) and the
  // integrator's interpolant over it: radau-iia its collocation polynomial, the SUNDIALS
  // integrators CVodeGetDky / ERKStepGetDky / ARKStepGetDky / IDAGetDky, rk4 the cubic Hermite
  // polynomial through the values and derivatives at the step's ends.
  using StepObserver = std::function<void(double t_begin, double t_end, const DenseOutput &y_at)>;

  class Integrator
  {
  public:
    virtual ~Integrator() = default;

    // Integrate from t0 to t0 + n_outputs * output_interval, calling `observer` at t0 and at every
    // output time. `y` holds the initial state and receives the final one. Throws NumericalError
    // with the time, the state and a remedy on failure, NaN or blow-up.
    virtual void integrate(OdeSystem &system, double t0, std::vector<double> &y,
                           double output_interval, long n_outputs, const Observer &observer) = 0;

    const IntegratorStats &stats() const { return statistics; }

    // Installs (or, with an empty function, removes) the observer of accepted steps. It sees
    // the solution between the output times; the steps taken do not depend on it.
    void set_step_observer(StepObserver observer) { step_observer = std::move(observer); }

  protected:
    IntegratorStats statistics;
    StepObserver    step_observer;
  };

  std::unique_ptr<Integrator> make_integrator(const IntegratorSettings &settings);

  // Throws NumericalError if y has a NaN/inf or leaves the system's blow-up bounds.
  void check_state(const OdeSystem &system, double t, const double *y, const std::string &who,
                   const std::string &remedy);
  // The same with the bounds fetched once (system.blow_up_bounds()), for checks at every step.
  void check_state(const OdeSystem &system, const std::vector<double> &bounds, double t,
                   const double *y, const std::string &who, const std::string &remedy);
} // namespace hertzgear::dynamics
