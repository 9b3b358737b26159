// The discrete contact problem (contact/contact_solver.h) on half-space compliance against Hertz.
#include "contact/contact_solver.h"

#include "common/errors.h"
#include "contact/half_space.h"
#include "contact/hertz.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace hertzgear;
using namespace hertzgear::contact;

namespace
{
  constexpr double pi     = 3.14159265358979323846;
  constexpr double E_star = 1.13e11; // Pa, steel on steel

  // Two paraboloids g = x^2/(2 Rx) + y^2/(2 Ry) on a grid of n_x x n_y cells covering
  // [-c a, c a] x [-c b, c b] around the Hertz ellipse (a along x), half-space compliance of both
  // bodies through E*.
  struct PointContactCase
  {
    half_space::ContactGrid        grid;
    ContactProblem                 problem;
    hertz::EllipticalContact       hertz;
  };

  PointContactCase point_contact(const double Rx, const double Ry, const double F, const unsigned int n_x,
                                 const unsigned int n_y, const double cover = 1.2)
  {
    PointContactCase c;
    c.hertz          = hertz::elliptical_contact(F, 1 / Rx, 1 / Ry, E_star);
    const double ax  = c.hertz.major_axis_along_x ? c.hertz.semi_major : c.hertz.semi_minor;
    const double ay  = c.hertz.major_axis_along_x ? c.hertz.semi_minor : c.hertz.semi_major;
    c.grid           = half_space::ContactGrid::covering(-cover * ax, cover * ax, -cover * ay, cover * ay, n_x, n_y);
    const unsigned n = c.grid.n_cells();
    c.problem.compliance = half_space::influence_matrix(c.grid, 0.0, E_star, 0.0);
    c.problem.gap.resize(n);
    for (unsigned int k = 0; k < n; ++k)
      {
        const Eigen::Vector2d x = c.grid.centre(k);
        c.problem.gap[k]        = x.x() * x.x() / (2 * Rx) + x.y() * x.y() / (2 * Ry);
      }
    c.problem.area = Eigen::VectorXd::Constant(n, c.grid.cell_area());
    c.problem.load = F;
    return c;
  }

  // The conditions of the discrete problem, to round-off: p >= 0, h >= 0, p h = 0 (h = 0 on the
  // contact cells up to the round-off of the bordered solve), sum p A = F.
  void expect_solution_satisfies_conditions(const ContactProblem &problem, const ContactSolution &s)
  {
    const double h_scale = problem.gap.cwiseAbs().maxCoeff() + std::abs(s.approach);
    const double h_tol   = 1e-12 * h_scale; // bordered LU residual, relative to the gap scale
    for (Eigen::Index i = 0; i < problem.gap.size(); ++i)
      {
        EXPECT_GE(s.pressure[i], 0.0);
        if (s.in_contact[i])
          EXPECT_LE(std::abs(s.loaded_gap[i]), h_tol) << "cell " << i;
        else
          {
            EXPECT_EQ(s.pressure[i], 0.0);
            EXPECT_GE(s.loaded_gap[i], -h_tol) << "cell " << i;
          }
      }
    const double total = s.pressure.dot(problem.area);
    EXPECT_NEAR(total, problem.load, 1e-10 * problem.load);
  }

  // Semi-axis from the second moment of the pressure along x: for the Hertz distribution
  // p0 sqrt(1 - x^2/a^2 - y^2/b^2), <x^2>_p = a^2/5.
  double moment_semi_axis(const half_space::ContactGrid &grid, const Eigen::VectorXd &p, const bool along_x)
  {
    double m0 = 0, m2 = 0;
    for (unsigned int k = 0; k < grid.n_cells(); ++k)
      {
        const double x = along_x ? grid.centre(k).x() : grid.centre(k).y();
        const double h = along_x ? grid.dx : grid.dy;
        m0 += p[k];
        m2 += p[k] * (x * x + h * h / 12); // exact second moment of a uniform cell
      }
    return std::sqrt(5 * m2 / m0);
  }

  // Half-extent of the contact cells along the axis through the centre, to the outer cell edge.
  double support_semi_axis(const half_space::ContactGrid &grid, const ContactSolution &s, const bool along_x)
  {
    double extent = 0;
    for (unsigned int k = 0; k < grid.n_cells(); ++k)
      if (s.in_contact[k])
        {
          const Eigen::Vector2d x = grid.centre(k);
          if (along_x && std::abs(x.y()) < grid.dy)
            extent = std::max(extent, std::abs(x.x()) + grid.dx / 2);
          if (!along_x && std::abs(x.x()) < grid.dx)
            extent = std::max(extent, std::abs(x.y()) + grid.dy / 2);
        }
    return extent;
  }

  struct Errors
  {
    double a, b, p0, delta;
  };

  Errors hertz_errors(const PointContactCase &c, const ContactSolution &s, const bool print)
  {
    const bool   x_major = c.hertz.major_axis_along_x;
    const double a       = moment_semi_axis(c.grid, s.pressure, x_major);
    const double b       = moment_semi_axis(c.grid, s.pressure, !x_major);
    Errors       e;
    e.a     = a / c.hertz.semi_major - 1;
    e.b     = b / c.hertz.semi_minor - 1;
    e.p0    = s.pressure.maxCoeff() / c.hertz.peak_pressure - 1;
    e.delta = s.approach / c.hertz.approach - 1;
    if (print)
      std::cout << "    grid " << c.grid.n_x << " x " << c.grid.n_y << ", " << s.n_active()
                << " contact cells, " << s.n_iterations << " active-set iterations; relative errors a "
                << e.a << ", b " << e.b << ", p0 " << e.p0 << ", delta " << e.delta << "\n";
    return e;
  }

  // Both semi-axes, the peak pressure and the approach within `bound` of Hertz's (relative).
  void expect_all_within(const Errors &e, const double bound)
  {
    EXPECT_LT(std::abs(e.a), bound);
    EXPECT_LT(std::abs(e.b), bound);
    EXPECT_LT(std::abs(e.p0), bound);
    EXPECT_LT(std::abs(e.delta), bound);
  }
} // namespace

// The contact solver shall reproduce Hertz's sphere (a, p0, delta) within 3 % (the TCA's
// acceptance bound for an isolated contact) on a grid of 40 x 40 cells over 1.2 a on each side
// (about 17 cells per radius), and satisfy the discrete conditions to round-off. Measured
// (printed): errors below 0.1 % on 40 x 40 and below 0.3 % on 20 x 20 (8 cells per radius), falling
// with refinement (asserted for p0 and delta). a is read from the second moment of the pressure,
// which is exact for a Hertz distribution; the contact set itself is checked to one cell.
TEST(ContactSolver, ReproducesHertzSphere)
{
  const double R = 0.01, F = 200.0;
  const auto   fine   = point_contact(R, R, F, 40, 40);
  const auto   s_fine = ContactSolver().solve(fine.problem);
  expect_solution_satisfies_conditions(fine.problem, s_fine);
  const Errors e = hertz_errors(fine, s_fine, true);
  expect_all_within(e, 0.03);
  // The contact set itself is resolved to one cell.
  EXPECT_NEAR(support_semi_axis(fine.grid, s_fine, true), fine.hertz.semi_major, fine.grid.dx);

  const auto   coarse   = point_contact(R, R, F, 20, 20);
  const auto   s_coarse = ContactSolver().solve(coarse.problem);
  const Errors e_coarse = hertz_errors(coarse, s_coarse, true);
  EXPECT_LT(std::abs(e.delta), std::abs(e_coarse.delta));
  EXPECT_LT(std::abs(e.p0), std::abs(e_coarse.p0));
}

// The contact solver shall reproduce an elongated Hertz ellipse (Ry/Rx = 8, b/a about 0.26) within
// 3 % in both semi-axes, p0 and delta, on a grid with about 17 cells per semi-axis in each direction.
TEST(ContactSolver, ReproducesHertzEllipse)
{
  const double Rx = 0.04, Ry = 0.005, F = 500.0; // major axis along x (smaller curvature)
  const auto   c = point_contact(Rx, Ry, F, 40, 40);
  EXPECT_TRUE(c.hertz.major_axis_along_x);
  const auto s = ContactSolver().solve(c.problem);
  expect_solution_satisfies_conditions(c.problem, s);
  const Errors e = hertz_errors(c, s, true);
  expect_all_within(e, 0.03);
}

// Two separate contact zones (two tooth pairs, no elastic coupling between them in this test)
// shall share the load so that both see the same rigid approach: equal shares without offset;
// with a gap offset e on zone 2, zone k alone under its own share gives delta_k = delta - e_k to
// round-off; zone 2 carries nothing once e exceeds the approach.
TEST(ContactSolver, TwoZonesShareTheLoad)
{
  const double R = 0.01, F = 200.0;
  const auto   zone = point_contact(R, R, F / 2, 20, 20);
  const auto   n    = zone.grid.n_cells();

  const auto two_zones = [&](const double offset) {
    ContactProblem p;
    p.compliance = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    p.compliance.topLeftCorner(n, n)     = zone.problem.compliance;
    p.compliance.bottomRightCorner(n, n) = zone.problem.compliance;
    p.gap.resize(2 * n);
    p.gap << zone.problem.gap, zone.problem.gap.array() + offset;
    p.area.resize(2 * n);
    p.area << zone.problem.area, zone.problem.area;
    p.load = F;
    return p;
  };
  std::vector<bool> first(2 * n, false);
  std::fill(first.begin(), first.begin() + n, true);
  std::vector<bool> second(2 * n, true);
  std::fill(second.begin(), second.begin() + n, false);

  {
    const ContactProblem  p = two_zones(0.0);
    const ContactSolution s = ContactSolver().solve(p);
    expect_solution_satisfies_conditions(p, s);
    EXPECT_NEAR(s.force(p.area, first), F / 2, 1e-10 * F);
    EXPECT_NEAR(s.force(p.area, second), F / 2, 1e-10 * F);
  }
  {
    const double          offset = 0.3 * zone.hertz.approach;
    const ContactProblem  p      = two_zones(offset);
    const ContactSolution s      = ContactSolver().solve(p);
    expect_solution_satisfies_conditions(p, s);
    const double F1 = s.force(p.area, first), F2 = s.force(p.area, second);
    EXPECT_NEAR(F1 + F2, F, 1e-10 * F);
    EXPECT_GT(F1, F2);
    ContactProblem alone = zone.problem;
    alone.load           = F1;
    EXPECT_NEAR(ContactSolver().solve(alone).approach, s.approach, 1e-10 * s.approach);
    alone.load = F2;
    EXPECT_NEAR(ContactSolver().solve(alone).approach, s.approach - offset, 1e-10 * s.approach);
    // Against Hertz: F = K delta^1.5 + K (delta - e)^1.5 with K = (4/3) E* sqrt(R) (R is the
    // effective radius of the gap). The discrete zone on this grid reproduces delta(F) within
    // 0.1 % (sphere test), which moves the shares by less than 0.5 %.
    const double K = 4.0 / 3.0 * E_star * std::sqrt(R);
    double       lo = offset, hi = 10 * offset + zone.hertz.approach * 4;
    for (int it = 0; it < 200; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (K * (std::pow(mid, 1.5) + std::pow(mid - offset, 1.5)) > F ? hi : lo) = mid;
      }
    const double F2_hertz = K * std::pow(0.5 * (lo + hi) - offset, 1.5);
    std::cout << "    shares " << F1 / F << " / " << F2 / F << ", Hertz " << 1 - F2_hertz / F << " / "
              << F2_hertz / F << "\n";
    EXPECT_NEAR(F2 / F, F2_hertz / F, 0.005 * F2_hertz / F);
  }
  {
    const ContactProblem  p = two_zones(10 * zone.hertz.approach);
    const ContactSolution s = ContactSolver().solve(p);
    expect_solution_satisfies_conditions(p, s);
    EXPECT_EQ(s.force(p.area, second), 0.0);
  }
}

// A solve that cannot settle within the iteration cap shall end in a NumericalError that says so;
// bad input shall end in an InputError.
TEST(ContactSolver, ReportsNonConvergenceAndBadInput)
{
  const auto c = point_contact(0.01, 0.01, 200.0, 20, 20);
  ContactSettings settings;
  settings.max_iterations = 2;
  try
    {
      ContactSolver(settings).solve(c.problem);
      FAIL() << "expected a NumericalError";
    }
  catch (const NumericalError &e)
    {
      EXPECT_NE(std::string(e.what()).find("did not settle in 2 iterations"), std::string::npos) << e.what();
    }
  ContactProblem bad = c.problem;
  bad.load           = -1;
  EXPECT_THROW(ContactSolver().solve(bad), InputError);
  bad      = c.problem;
  bad.area = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(ContactSolver().solve(bad), InputError);
}
