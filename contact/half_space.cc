#include "contact/half_space.h"

#include "common/errors.h"

#include <boost/math/quadrature/gauss.hpp>

#include <boost/math/quadrature/gauss.hpp>

#include <cmath>

namespace hertzgear
{
  namespace half_space
  {
    namespace
    {
      constexpr double pi = 3.14159265358979323846;

      void check_material(const double E, const double nu)
      {
        HG_REQUIRE_INPUT(E > 0, "Young's modulus must be positive, got ", E);
        HG_REQUIRE_INPUT(nu > -1.0 && nu < 0.5, "Poisson ratio must lie in (-1, 0.5), got ", nu);
      }

      // asinh(s / t), set to 0 at t = 0: t vanishes only where the factor in front of it does.
      double asinh_of_ratio(const double s, const double t)
      {
        return t == 0 ? 0.0 : std::asinh(s / t);
      }

      // Double primitives over the tangent plane (X = x - xi, Y = y - eta), odd in X and in Y so
      // that one expression holds in every quadrant; d^2/dXdY gives the integrand:
      //   Q1(X, Y) -> 1/rho,          rho = sqrt(X^2 + Y^2 + d^2),
      //   Q3(X, Y) -> d^2/rho^3 = d * d/dXdY atan(X Y / (d rho)).
      double primitive_inverse_distance(const double X, const double Y, const double d)
      {
        const double rho = std::sqrt(X * X + Y * Y + d * d);
        double       q   = X * asinh_of_ratio(Y, std::sqrt(X * X + d * d)) + Y * asinh_of_ratio(X, std::sqrt(Y * Y + d * d));
        if (d > 0)
          q -= d * std::atan(X * Y / (d * rho));
        return q;
      }

      double primitive_depth_term(const double X, const double Y, const double d)
      {
        if (d == 0)
          return 0.0;
        const double rho = std::sqrt(X * X + Y * Y + d * d);
        return d * std::atan(X * Y / (d * rho));
      }

      template <typename Primitive>
      double over_rectangle(const Primitive &P, const double x, const double y, const double half_x,
                            const double half_y, const double d)
      {
        return P(x + half_x, y + half_y, d) - P(x + half_x, y - half_y, d) -
               P(x - half_x, y + half_y, d) + P(x - half_x, y - half_y, d);
      }
    } // namespace

    ContactGrid ContactGrid::covering(const double x_min, const double x_max, const double y_min,
                                      const double y_max, const unsigned int n_x, const unsigned int n_y)
    {
      HG_REQUIRE_INPUT(x_max > x_min && y_max > y_min && n_x > 0 && n_y > 0,
                       "a contact grid needs a non-empty rectangle and at least one cell per direction");
      ContactGrid g;
      g.x_min = x_min;
      g.y_min = y_min;
      g.n_x   = n_x;
      g.n_y   = n_y;
      g.dx    = (x_max - x_min) / n_x;
      g.dy    = (y_max - y_min) / n_y;
      return g;
    }

    Eigen::Vector2d ContactGrid::centre(const unsigned int k) const
    {
      const unsigned int i = k % n_x, j = k / n_x;
      return {x_min + (i + 0.5) * dx, y_min + (j + 0.5) * dy};
    }

    std::vector<Cell> ContactGrid::cells() const
    {
      std::vector<Cell> result(n_cells());
      for (unsigned int k = 0; k < n_cells(); ++k)
        result[k] = Cell{centre(k), Eigen::Vector2d(0.5 * dx, 0.5 * dy)};
      return result;
    }

    double rectangle_surface_displacement(const double x, const double y, const double half_x,
                                          const double half_y, const double pressure,
                                          const double youngs_modulus, const double poisson_ratio)
    {
      return rectangle_displacement_at_depth(x, y, 0.0, half_x, half_y, pressure, youngs_modulus,
                                             poisson_ratio);
    }

    double rectangle_displacement_at_depth(const double x, const double y, const double depth,
                                           const double half_x, const double half_y,
                                           const double pressure, const double youngs_modulus,
                                           const double poisson_ratio)
    {
      check_material(youngs_modulus, poisson_ratio);
      HG_REQUIRE_INPUT(depth >= 0 && half_x > 0 && half_y > 0,
                       "depth must be >= 0 and the rectangle non-empty");
      const double nu = poisson_ratio;
      const double I1 = over_rectangle(primitive_inverse_distance, x, y, half_x, half_y, depth);
      const double I3 = over_rectangle(primitive_depth_term, x, y, half_x, half_y, depth);
      return pressure * (1.0 + nu) / (2.0 * pi * youngs_modulus) * (2.0 * (1.0 - nu) * I1 + I3);
    }

    double point_load_displacement(const double r, const double depth, const double load,
                                   const double youngs_modulus, const double poisson_ratio)
    {
      check_material(youngs_modulus, poisson_ratio);
      const double rho = std::sqrt(r * r + depth * depth);
      HG_REQUIRE_INPUT(rho > 0, "the point-load displacement is singular at the load point");
      const double nu = poisson_ratio;
      return load * (1.0 + nu) / (2.0 * pi * youngs_modulus) *
             (2.0 * (1.0 - nu) / rho + depth * depth / (rho * rho * rho));
    }

    double patch_load_displacement(const double r, const double depth, const double radius,
                                   const double youngs_modulus, const double poisson_ratio)
    {
      check_material(youngs_modulus, poisson_ratio);
      HG_REQUIRE_INPUT(radius > 0 && depth >= radius && r >= 0,
                       "the patch-load displacement needs a radius > 0, a depth >= the radius and "
                       "r >= 0 (radius ", radius, ", depth ", depth, ", r ", r, ")");
      using Gauss = boost::math::quadrature::gauss<double, 20>;
      // p(s) = 3 / (pi a^2) (1 - s^2)^2: the unit force over the disc, in polar coordinates
      // (s a, theta) with area element a^2 s ds dtheta; the two half discs theta in [0, pi] and
      // [pi, 2 pi] are mirror images about the line through the reading point.
      const double nu     = poisson_ratio;
      const double factor = (1.0 + nu) / (2.0 * pi * youngs_modulus);
      const auto   ring   = [&](const double s) {
        const auto kernel = [&](const double theta) {
          const double x    = r - s * radius * std::cos(theta);
          const double y    = s * radius * std::sin(theta);
          const double rho2 = x * x + y * y + depth * depth;
          const double rho  = std::sqrt(rho2);
          return 2.0 * (1.0 - nu) / rho + depth * depth / (rho2 * rho);
        };
        const double w = (1.0 - s * s) * (1.0 - s * s);
        return 2.0 * Gauss::integrate(kernel, 0.0, pi) * w * s;
      };
      return factor * 3.0 / pi * Gauss::integrate(ring, 0.0, 1.0);
    }

    PatchLoadKernel::PatchLoadKernel(const double depth, const double radius,
                                     const double youngs_modulus, const double poisson_ratio)
      : depth(depth), radius(radius), E(youngs_modulus), nu(poisson_ratio), r_max(64 * radius)
    {
      const double        step = radius / 16;
      std::vector<double> values;
      for (unsigned int k = 0; k <= 64 * 16; ++k)
        values.push_back(patch_load_displacement(k * step, depth, radius, E, nu));
      // Even in r: zero slope at r = 0; the slope at r_max from the quadrature by a central
      // difference (its own error is of the order of the spline's).
      const double slope = (patch_load_displacement(r_max + step, depth, radius, E, nu) -
                            patch_load_displacement(r_max - step, depth, radius, E, nu)) /
                           (2 * step);
      spline = boost::math::interpolators::cardinal_cubic_b_spline<double>(
        values.data(), values.size(), 0.0, step, 0.0, slope);
    }

    double PatchLoadKernel::operator()(const double r) const
    {
      const double a = std::abs(r);
      return a <= r_max ? spline(a) : patch_load_displacement(a, depth, radius, E, nu);
    }

    Eigen::MatrixXd influence_matrix(const std::vector<Cell> &cells, const double depth,
                                     const double youngs_modulus, const double poisson_ratio)
    {
      const Eigen::Index n = static_cast<Eigen::Index>(cells.size());
      Eigen::MatrixXd    C(n, n);
      for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
          {
            const Eigen::Vector2d r = cells[i].centre - cells[j].centre;
            C(i, j) = rectangle_displacement_at_depth(r.x(), r.y(), depth, cells[j].half_size.x(),
                                                      cells[j].half_size.y(), 1.0, youngs_modulus,
                                                      poisson_ratio);
          }
      return C;
    }

    Eigen::MatrixXd influence_matrix(const ContactGrid &grid, const double depth,
                                     const double youngs_modulus, const double poisson_ratio)
    {
      const int       n_x = grid.n_x, n_y = grid.n_y;
      // u(di, dj) for offsets di in (-n_x, n_x), dj in (-n_y, n_y).
      Eigen::MatrixXd u(2 * n_x - 1, 2 * n_y - 1);
      for (int dj = -(n_y - 1); dj <= n_y - 1; ++dj)
        for (int di = -(n_x - 1); di <= n_x - 1; ++di)
          u(di + n_x - 1, dj + n_y - 1) =
            rectangle_displacement_at_depth(di * grid.dx, dj * grid.dy, depth, 0.5 * grid.dx,
                                            0.5 * grid.dy, 1.0, youngs_modulus, poisson_ratio);

      const Eigen::Index n = grid.n_cells();
      Eigen::MatrixXd    C(n, n);
      for (int jj = 0; jj < n_y; ++jj)
        for (int ji = 0; ji < n_x; ++ji)
          for (int ij = 0; ij < n_y; ++ij)
            for (int ii = 0; ii < n_x; ++ii)
              C(ii + n_x * ij, ji + n_x * jj) = u(ii - ji + n_x - 1, ij - jj + n_y - 1);
      return C;
    }

    Eigen::MatrixXd hybrid_compliance(const Eigen::MatrixXd &             fe_force_compliance,
                                      const std::vector<Cell> &           cells,
                                      const double                        depth,
                                      const std::vector<Material> &bodies)
    {
      const Eigen::Index n = static_cast<Eigen::Index>(cells.size());
      HG_REQUIRE_INPUT(fe_force_compliance.rows() == n && fe_force_compliance.cols() == n,
                       "the FE compliance is ", fe_force_compliance.rows(), " x ", fe_force_compliance.cols(),
                       " but the contact grid has ", n, " cells");
      HG_REQUIRE_INPUT(depth > 0, "the hybrid split needs a positive reference depth, got ", depth);
      HG_REQUIRE_INPUT(!bodies.empty(), "the hybrid split needs the materials of the bodies");
      Eigen::MatrixXd C = fe_force_compliance;
      for (Eigen::Index j = 0; j < n; ++j)
        C.col(j) *= cells[j].area();
      for (const auto &body : bodies)
        C += influence_matrix(cells, 0.0, body.youngs_modulus_MPa, body.poisson_ratio) -
             influence_matrix(cells, depth, body.youngs_modulus_MPa, body.poisson_ratio);
      return C;
    }

    double hertz_pressure_displacement_at_depth(const double p0, const double a, const double b,
                                                const double depth, const double E, const double nu)
    {
      const unsigned int n_t = 256;
      const auto         ring = [&](const double s) {
        const double r = std::sin(s), dr = std::cos(s), p = p0 * std::cos(s);
        double       u = 0;
        for (unsigned int k = 0; k < n_t; ++k)
          {
            const double t = 2.0 * pi * (k + 0.5) / n_t;
            const double x = a * r * std::cos(t), y = b * r * std::sin(t);
            u += p * a * b * r * dr * (2.0 * pi / n_t) *
                 point_load_displacement(std::hypot(x, y), depth, 1.0, E, nu);
          }
        return u;
      };
      return boost::math::quadrature::gauss<double, 64>::integrate(ring, 0.0, 0.5 * pi);
    }
  } // namespace half_space
} // namespace hertzgear
