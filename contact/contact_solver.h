#pragma once
// The discrete normal contact problem of a contact grid (frictionless, one rigid approach):
//
//   find p >= 0 (pressure per cell) and delta such that
//     h_i = g_i + sum_j C_ij p_j - delta >= 0,   p_i h_i = 0,   sum_j p_j A_j = F,
//
// with g the unloaded gap, C the compliance (closing displacement at i per unit pressure on j,
// both bodies, any number of zones), A the cell areas, F the total load and delta the rigid
// approach of the two bodies. Solved by a primal-dual active-set method (Hintermueller, Ito &
// Kunisch 2002; the semismooth Newton method of deal.II's step-41/42): each iteration solves the
// bordered system of the active cells exactly (Eigen LU), so the converged answer satisfies the
// conditions to round-off. C need not be symmetric (the hybrid FE/half-space compliance is only
// approximately so). Equations and choices: docs/theory-contact.md.
#include <Eigen/Dense>

#include <vector>

namespace hertzgear::contact
{
  struct ContactProblem
  {
    Eigen::MatrixXd compliance; // n x n
    Eigen::VectorXd gap;        // n
    Eigen::VectorXd area;       // n, > 0
    double          load = 0;   // F > 0
  };

  struct ContactSettings
  {
    unsigned int max_iterations = 100;
  };

  struct ContactSolution
  {
    Eigen::VectorXd   pressure;     // p, zero outside the contact
    double            approach = 0; // delta
    Eigen::VectorXd   loaded_gap;   // h = g + C p - delta, zero in the contact
    std::vector<bool> in_contact;
    unsigned int      n_iterations = 0;

    unsigned int n_active() const;
    // Total force carried by the cells selected by `mask` (e.g. one tooth pair).
    double       force(const Eigen::VectorXd &area, const std::vector<bool> &mask) const;
  };

  class ContactSolver
  {
  public:
    explicit ContactSolver(const ContactSettings &settings = ContactSettings());

    // Throws InputError for inconsistent sizes, F <= 0, non-positive areas; NumericalError when
    // the active set cycles or the iteration cap is reached (the message lists the history).
    ContactSolution solve(const ContactProblem &problem) const;

  private:
    ContactSettings settings;
  };
} // namespace hertzgear::contact
