#pragma once
// The interface the integrators see: an explicit ODE y' = f(t, y) with optional analytic Jacobian,
// root functions (contact transitions) and an implicit residual form for the DAE integrator.
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  class OdeSystem
  {
  public:
    virtual ~OdeSystem() = default;

    virtual unsigned n_states() const = 0;

    // y' = f(t, y). Not const: a contact law may keep the impact speed of the current impact.
    virtual void rhs(double t, const double *y, double *y_dot) = 0;

    // Dense Jacobian df/dy, row-major n x n. Only called when has_jacobian().
    virtual bool has_jacobian() const { return false; }
    virtual void jacobian(double /*t*/, const double * /*y*/, double * /*jac*/) const {}
    // 0: a dense Jacobian. b > 0: jacobian() is block diagonal with n / b equal b x b blocks, so
    // that an integrator may factorise one block for all (a system with its sensitivities).
    virtual unsigned jacobian_block_size() const { return 0; }
    // f and df/dy at one (t, y), for callers that need both at every point (the variational
    // equations); a system may share the work of the two. Only called when has_jacobian().
    virtual void rhs_and_jacobian(double t, const double *y, double *y_dot, double *jac)
    {
      rhs(t, y, y_dot);
      jacobian(t, y, jac);
    }

    // The period of f's explicit dependence on t (0: none, or not periodic). Integrators may use
    // it for starting values: a periodic steady state repeats itself one period later.
    virtual double forcing_period() const { return 0.0; }

    // Root functions g_i(t, y) whose sign changes are events (contact transitions).
    virtual unsigned n_roots() const { return 0; }
    virtual void     roots(double /*t*/, const double * /*y*/, double * /*g*/) const {}
    // Called at a located root (adaptive integrators) or at the end of the step in which a root
    // function changed sign (fixed step). `directions[i]` is +1/-1 for a root of g_i crossed
    // upwards/downwards, 0 otherwise. May change y; returns true if it did.
    virtual bool handle_event(double /*t*/, double * /*y*/, const int * /*directions*/)
    {
      return false;
    }
    // Whether the sign change of root function r at (t, y) is only the seam of a root function
    // defined piecewise -- its definition changes on the surface of another root, whose own event
    // is the switching there -- and no switching of the vector field of its own: the
    // sensitivities then take no saltation matrix for it (they would count that switching twice).
    virtual bool root_seam(double /*t*/, const double * /*y*/, unsigned /*r*/) const
    {
      return false;
    }

    // Residual form for the DAE integrator: r = M(t, y) y' - g(t, y) with M possibly singular
    // (an algebraic equation where it vanishes). The default is r = y' - f(t, y).
    virtual void residual(double t, const double *y, const double *y_dot, double *r);
    // Whether component i is differential (1) or algebraic (0) in the residual form.
    virtual std::vector<double> differential_components() const
    {
      return std::vector<double>(n_states(), 1.0);
    }
    // A consistent y' for the residual form at (t, y); may adjust algebraic components of y.
    virtual void consistent_initial_derivative(double t, double *y, double *y_dot);

    // Absolute tolerance per component from the absolute tolerance on displacements.
    virtual std::vector<double> absolute_tolerances(double displacement_tolerance) const
    {
      return std::vector<double>(n_states(), displacement_tolerance);
    }

    // Human-readable state for error messages ("x = ... um, x' = ... m/s").
    virtual std::string describe_state(const double *y) const;

    // |y| beyond these bounds (per component) is a blow-up.
    virtual std::vector<double> blow_up_bounds() const
    {
      return std::vector<double>(n_states(), 1.0e100);
    }
  };
} // namespace hertzgear::dynamics
