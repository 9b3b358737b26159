#include "dynamics/ode_system.h"

#include <sstream>

namespace hertzgear::dynamics
{
  void OdeSystem::residual(const double t, const double *y, const double *y_dot, double *r)
  {
    rhs(t, y, r);
    for (unsigned i = 0; i < n_states(); ++i)
      r[i] = y_dot[i] - r[i];
  }

  void OdeSystem::consistent_initial_derivative(const double t, double *y, double *y_dot)
  {
    rhs(t, y, y_dot);
  }

  std::string OdeSystem::describe_state(const double *y) const
  {
    std::ostringstream os;
    os.precision(6);
    os << "y = (";
    for (unsigned i = 0; i < n_states(); ++i)
      os << (i ? ", " : "") << y[i];
    os << ")";
    return os.str();
  }
} // namespace hertzgear::dynamics
