#include "contact/contact_solver.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace hertzgear::contact
{
  unsigned int ContactSolution::n_active() const
  {
    return static_cast<unsigned int>(std::count(in_contact.begin(), in_contact.end(), true));
  }

  double ContactSolution::force(const Eigen::VectorXd &area, const std::vector<bool> &mask) const
  {
    HG_REQUIRE_INPUT(static_cast<Eigen::Index>(mask.size()) == pressure.size() &&
                       area.size() == pressure.size(),
                     "force(): mask and area must have one entry per cell");
    double f = 0;
    for (Eigen::Index i = 0; i < pressure.size(); ++i)
      if (mask[i])
        f += pressure[i] * area[i];
    return f;
  }

  ContactSolver::ContactSolver(const ContactSettings &settings)
    : settings(settings)
  {
    HG_REQUIRE_INPUT(settings.max_iterations > 0, "the contact solver needs at least one iteration");
  }

  ContactSolution ContactSolver::solve(const ContactProblem &problem) const
  {
    const Eigen::Index n = problem.gap.size();
    HG_REQUIRE_INPUT(n > 0, "the contact grid is empty");
    HG_REQUIRE_INPUT(problem.compliance.rows() == n && problem.compliance.cols() == n &&
                       problem.area.size() == n,
                     "contact problem sizes differ: gap ", n, ", compliance ", problem.compliance.rows(),
                     " x ", problem.compliance.cols(), ", area ", problem.area.size());
    HG_REQUIRE_INPUT(problem.load > 0 && std::isfinite(problem.load),
                     "the contact load must be positive and finite, got ", problem.load);
    HG_REQUIRE_INPUT(problem.area.minCoeff() > 0, "contact cell areas must be positive");
    HG_REQUIRE_INPUT(problem.gap.allFinite() && problem.compliance.allFinite(),
                     "the contact gap or compliance holds NaN or infinity");

    const Eigen::MatrixXd &C = problem.compliance;
    const Eigen::VectorXd &g = problem.gap;

    // Start from the cell of smallest gap: the first point the bodies touch.
    std::vector<bool> active(n, false);
    {
      Eigen::Index first;
      g.minCoeff(&first);
      active[first] = true;
    }

    std::set<std::vector<bool>> visited;
    std::ostringstream          history; // active-set sizes per iteration, for the diagnostic
    ContactSolution             s;
    s.pressure   = Eigen::VectorXd::Zero(n);
    s.loaded_gap = Eigen::VectorXd::Zero(n);

    for (unsigned int k = 1; k <= settings.max_iterations; ++k)
      {
        visited.insert(active);
        std::vector<Eigen::Index> idx;
        for (Eigen::Index i = 0; i < n; ++i)
          if (active[i])
            idx.push_back(i);
        const Eigen::Index m = static_cast<Eigen::Index>(idx.size());
        history << (k > 1 ? ", " : "") << m;

        // Bordered system of the active cells: C_AA p_A - delta 1 = -g_A,  A_A^T p_A = F.
        Eigen::MatrixXd M(m + 1, m + 1);
        Eigen::VectorXd rhs(m + 1);
        for (Eigen::Index b = 0; b < m; ++b)
          {
            for (Eigen::Index a = 0; a < m; ++a)
              M(a, b) = C(idx[a], idx[b]);
            M(m, b) = problem.area[idx[b]];
            M(b, m) = -1.0;
            rhs[b]  = -g[idx[b]];
          }
        M(m, m)  = 0.0;
        rhs[m]   = problem.load;
        const Eigen::VectorXd x = M.partialPivLu().solve(rhs);
        HG_REQUIRE_NUMERIC(x.allFinite(), "the active-set system of ", m,
                           " cells is singular (iteration ", k, ")");

        s.pressure.setZero();
        for (Eigen::Index a = 0; a < m; ++a)
          s.pressure[idx[a]] = x[a];
        s.approach = x[m];
        s.loaded_gap.noalias() = g + C(Eigen::all, idx) * x.head(m);
        s.loaded_gap.array() -= s.approach;

        // What counts as a penetration: round-off of the gap in the units of the problem.
        const double scale = std::max({std::abs(s.approach), g.cwiseAbs().maxCoeff(),
                                       (C(Eigen::all, idx) * x.head(m)).cwiseAbs().maxCoeff()});
        const double tolerance = 64.0 * std::numeric_limits<double>::epsilon() * scale;

        // Semismooth Newton update: keep active cells in compression, add penetrated ones.
        std::vector<bool> next(n, false);
        for (Eigen::Index i = 0; i < n; ++i)
          next[i] = active[i] ? s.pressure[i] > 0 : s.loaded_gap[i] < -tolerance;
        if (std::none_of(next.begin(), next.end(), [](bool b) { return b; }))
          {
            Eigen::Index first;
            s.loaded_gap.minCoeff(&first);
            next[first] = true;
          }

        if (next == active)
          {
            s.in_contact   = active;
            s.n_iterations = k;
            return s;
          }
        HG_REQUIRE_NUMERIC(visited.count(next) == 0,
                           "the contact active set cycles: iteration ", k, " returns to an earlier set "
                           "(active cells per iteration: ", history.str(), "); the compliance matrix may be "
                           "far from symmetric positive definite or the gap field inconsistent");
        active = std::move(next);
      }
    throw NumericalError(msg("the contact active set did not settle in ", settings.max_iterations,
                             " iterations (active cells per iteration: ", history.str(),
                             "); raise max_iterations or check the contact grid"));
  }
} // namespace hertzgear::contact
