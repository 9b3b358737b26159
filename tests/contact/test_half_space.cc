// Boussinesq-Love half-space displacements (contact/half_space.h).
#include "contact/half_space.h"

#include "common/errors.h"

#include <boost/math/quadrature/gauss.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear;

namespace
{
  constexpr double pi = 3.14159265358979323846;
  constexpr double E = 206.0e9, nu = 0.3;

  // Boussinesq point-load displacement integrated over the rectangle by a tensor Gauss-Legendre
  // rule on an n_sub x n_sub split of the rectangle: an independent evaluation of the closed form.
  // For depth >= half the smaller side the integrand is analytic on each piece and 20 points
  // per piece reach round-off.
  double integrated_point_loads(const double x, const double y, const double depth, const double hx,
                                const double hy, const unsigned int n_sub)
  {
    using Rule   = boost::math::quadrature::gauss<double, 20>;
    double total = 0;
    for (unsigned int i = 0; i < n_sub; ++i)
      for (unsigned int j = 0; j < n_sub; ++j)
        {
          const double x0 = -hx + 2 * hx * i / n_sub, x1 = -hx + 2 * hx * (i + 1) / n_sub;
          const double y0 = -hy + 2 * hy * j / n_sub, y1 = -hy + 2 * hy * (j + 1) / n_sub;
          total += Rule::integrate(
            [&](const double xi) {
              return Rule::integrate(
                [&](const double eta) {
                  return half_space::point_load_displacement(std::hypot(x - xi, y - eta), depth, 1.0, E, nu);
                },
                y0, y1);
            },
            x0, x1);
        }
    return total;
  }
} // namespace

// The surface displacement at the centre and at a corner of a square of side 2a under pressure
// p shall equal Love's values (8/pi) ln(1 + sqrt 2) (1 - nu^2) p a / E and half of it
// (Love 1929; Johnson 1985, ch. 3); exact, so round-off tolerance.
TEST(HalfSpace, SquareCentreAndCornerMatchLove)
{
  const double a = 2.0e-4, p = 1.5e9;
  const double centre = 8.0 / pi * std::log(1 + std::sqrt(2.0)) * (1 - nu * nu) * p * a / E;
  EXPECT_NEAR(half_space::rectangle_surface_displacement(0, 0, a, a, p, E, nu), centre, 1e-13 * centre);
  EXPECT_NEAR(half_space::rectangle_surface_displacement(a, a, a, a, p, E, nu), centre / 2, 1e-13 * centre);
  EXPECT_NEAR(half_space::rectangle_surface_displacement(-a, a, a, a, p, E, nu), centre / 2, 1e-13 * centre);
}

// The displacement shall be even in x and y and the influence matrix of equal cells symmetric.
TEST(HalfSpace, SymmetryAndReciprocity)
{
  const double hx = 1e-4, hy = 3e-4;
  for (const double depth : {0.0, 2e-4})
    for (const auto &[x, y] : {std::pair{1.3e-4, 0.7e-4}, std::pair{5e-4, -2e-4}, std::pair{0.0, 1e-3}})
      {
        const double u = half_space::rectangle_displacement_at_depth(x, y, depth, hx, hy, 1.0, E, nu);
        EXPECT_NEAR(half_space::rectangle_displacement_at_depth(-x, y, depth, hx, hy, 1.0, E, nu), u, 1e-15 * u);
        EXPECT_NEAR(half_space::rectangle_displacement_at_depth(x, -y, depth, hx, hy, 1.0, E, nu), u, 1e-15 * u);
      }

  const auto            grid = half_space::ContactGrid::covering(-1e-3, 1e-3, -5e-4, 7e-4, 9, 5);
  const Eigen::MatrixXd C    = half_space::influence_matrix(grid, 0.0, E, nu);
  EXPECT_LT((C - C.transpose()).cwiseAbs().maxCoeff(), 1e-14 * C.cwiseAbs().maxCoeff());
  // The regular-grid shortcut shall equal the cell-by-cell builder.
  const Eigen::MatrixXd C_cells = half_space::influence_matrix(grid.cells(), 0.0, E, nu);
  EXPECT_LT((C - C_cells).cwiseAbs().maxCoeff(), 1e-14 * C.cwiseAbs().maxCoeff());
  // Diagonal dominance of the self-influence is what makes the contact problem well posed.
  EXPECT_TRUE((C.diagonal().array() > 0).all());
}

// Far from the rectangle the displacement shall tend to the point load F (1 - nu^2)/(pi E r)
// with F = p x area, on the surface and at depth. The leading error is the quadrupole term,
// relative size (side/r)^2 = 1e-6 here; the bound 1e-5 leaves a factor 10 for its coefficient.
TEST(HalfSpace, FarFieldIsThePointLoad)
{
  const double hx = 1e-4, hy = 2e-4, p = 1e9, F = p * 4 * hx * hy;
  const double r  = 1000 * 2 * hy;
  for (const double depth : {0.0, 0.3 * r})
    {
      const double u   = half_space::rectangle_displacement_at_depth(0.6 * r, 0.8 * r, depth, hx, hy, p, E, nu);
      const double ref = half_space::point_load_displacement(r, depth, F, E, nu);
      EXPECT_NEAR(u, ref, 1e-5 * ref) << "depth " << depth;
    }
  EXPECT_NEAR(half_space::point_load_displacement(r, 0, F, E, nu), F * (1 - nu * nu) / (pi * E * r), 1e-15);
}

// The closed form at depth shall equal the Boussinesq point load integrated numerically over the
// rectangle, below the centre, below an edge and off the rectangle; and shall tend to Love's
// surface value as depth -> 0. Tolerance 1e-10: the quadrature error of the reference.
TEST(HalfSpace, DepthClosedFormMatchesIntegratedPointLoads)
{
  const double hx = 1e-4, hy = 2.5e-4;
  for (const double depth : {1e-4, 3e-4, 1e-3})
    for (const auto &[x, y] : {std::pair{0.0, 0.0}, std::pair{1e-4, 1e-4}, std::pair{3e-4, -4e-4}})
      {
        const double u   = half_space::rectangle_displacement_at_depth(x, y, depth, hx, hy, 1.0, E, nu);
        const double ref = integrated_point_loads(x, y, depth, hx, hy, 8);
        EXPECT_NEAR(u, ref, 1e-10 * ref) << "depth " << depth << " at (" << x << ", " << y << ")";
      }
  const double surface = half_space::rectangle_surface_displacement(0.5e-4, 0, hx, hy, 1.0, E, nu);
  const double shallow = half_space::rectangle_displacement_at_depth(0.5e-4, 0, 1e-12, hx, hy, 1.0, E, nu);
  // The displacement decreases linearly from the surface (slope of order the pressure / E).
  EXPECT_NEAR(shallow, surface, 1e-7 * surface);
  EXPECT_LT(shallow, surface);
}

namespace
{
  // The smooth patch p = 3/(pi a^2) (1 - s^2)^2 integrated in Cartesian coordinates, y over the
  // chord at x = a sin(phi), then phi: independent of the polar rule under test. The substitution
  // makes the chord length a cos(phi) analytic (in x it has square-root ends, on which a plain
  // 40-point rule stops at 1e-10); the weight is a polynomial and the kernel analytic for
  // depth >= a, so 40 x 40 Gauss-Legendre points reach round-off.
  double cartesian_patch(const double r, const double depth, const double a)
  {
    using Rule = boost::math::quadrature::gauss<double, 40>;
    return Rule::integrate(
      [&](const double phi) {
        const double x = a * std::sin(phi), h = a * std::cos(phi);
        return h * Rule::integrate(
                     [&](const double y) {
                       const double s2 = (x * x + y * y) / (a * a);
                       const double p  = 3.0 / (pi * a * a) * (1 - s2) * (1 - s2);
                       return p * half_space::point_load_displacement(std::hypot(r - x, y), depth,
                                                                      1.0, E, nu);
                     },
                     -h, h);
      },
      -0.5 * pi, 0.5 * pi);
  }
} // namespace

// The displacement at depth d under the smooth unit patch of radius a (the FE table's load) shall
// equal the point load integrated over the disc by an independent Cartesian rule, below the
// centre, the rim and outside, for d = 2a (the table's split) and d = a (the smallest allowed).
// Tolerance 1e-12 relative: both rules converge exponentially and agree to round-off (about 1e-15
// measured); 1e-12 leaves room for the round-off of 1600-term sums.
TEST(HalfSpace, PatchLoadMatchesTheIntegratedPointLoad)
{
  const double a = 0.5e-3;
  for (const double depth : {2 * a, a})
    for (const double r : {0.0, 0.5 * a, a, 3 * a, 20 * a})
      {
        const double u   = half_space::patch_load_displacement(r, depth, a, E, nu);
        const double ref = cartesian_patch(r, depth, a);
        EXPECT_NEAR(u, ref, 1e-12 * ref) << "depth " << depth << ", r " << r;
      }
  // Far from the patch it is the point load, to the patch's second moment: the relative
  // difference is O((a / r)^2), here (1/100)^2 times a factor of order one.
  const double far = 100 * a;
  EXPECT_NEAR(half_space::patch_load_displacement(far, 2 * a, a, E, nu),
              half_space::point_load_displacement(far, 2 * a, 1.0, E, nu),
              1e-4 * half_space::point_load_displacement(far, 2 * a, 1.0, E, nu));
}

// The tabulated kernel shall reproduce the quadrature everywhere, inside the spline's range
// (r <= 64 a) to 1e-7 of the peak value (cubic spline at spacing a/16 on a function whose scale
// is the depth 2a: error ~ (1/32)^4 ~ 1e-6 times a constant below one, measured 3.4e-8), and
// exactly beyond; it is even in r.
TEST(HalfSpace, PatchLoadKernelReproducesTheQuadrature)
{
  const double                     a = 0.54, depth = 1.08, E_mpa = 206000;
  const half_space::PatchLoadKernel kernel(depth, a, E_mpa, nu);
  const double peak = half_space::patch_load_displacement(0, depth, a, E_mpa, nu);
  double       worst = 0;
  for (unsigned int k = 0; k <= 997; ++k)
    {
      const double r = 70 * a * k / 997.0;
      worst = std::max(worst, std::abs(kernel(r) - half_space::patch_load_displacement(r, depth, a, E_mpa, nu)));
    }
  EXPECT_LT(worst, 1e-7 * peak);
  EXPECT_DOUBLE_EQ(kernel(-1.3), kernel(1.3));
  EXPECT_EQ(kernel(80 * a), half_space::patch_load_displacement(80 * a, depth, a, E_mpa, nu));
}

// Bad input shall be refused with an InputError.
TEST(HalfSpace, RejectsBadInput)
{
  EXPECT_THROW(half_space::rectangle_displacement_at_depth(0, 0, -1e-3, 1e-4, 1e-4, 1, E, nu), InputError);
  EXPECT_THROW(half_space::rectangle_surface_displacement(0, 0, 0, 1e-4, 1, E, nu), InputError);
  EXPECT_THROW(half_space::ContactGrid::covering(0, -1, 0, 1, 4, 4), InputError);
  // The patch kernel is smooth only where the reading lies at least a radius deep.
  EXPECT_THROW(half_space::patch_load_displacement(0, 0.5e-3, 1e-3, E, nu), InputError);
  EXPECT_THROW(half_space::patch_load_displacement(0, 1e-3, 0, E, nu), InputError);
}
