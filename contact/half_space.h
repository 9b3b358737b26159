#pragma once
// Boussinesq-Love: normal displacement of an elastic half-space under uniform pressure on a
// rectangle, on the surface (Love 1929) and at a depth below it, under a point load and a smooth
// disc patch, and the influence-coefficient matrices of a contact grid built from them. Plain
// C++, Eigen and Boost.Math, any consistent units.
// Equations and sources: docs/theory-contact.md.
//
// Frame: the half-space is z >= 0 (z = depth), the load presses along +z, and the displacement
// returned is the component along +z (into the body) of the point (x, y, depth).
#include "contact/hertz.h"

#include <Eigen/Dense>
#include <boost/math/interpolators/cardinal_cubic_b_spline.hpp>

#include <vector>

namespace hertzgear
{
  namespace half_space
  {
    // One rectangular cell of a contact grid: centre and half side lengths in the tangent plane.
    struct Cell
    {
      Eigen::Vector2d centre;
      Eigen::Vector2d half_size;
      double area() const { return 4.0 * half_size.x() * half_size.y(); }
    };

    // A regular n_x x n_y grid of equal cells; cell k = i + n_x j has centre
    // (x_min + (i + 1/2) dx, y_min + (j + 1/2) dy).
    struct ContactGrid
    {
      double       x_min = 0, y_min = 0;
      double       dx = 0, dy = 0;
      unsigned int n_x = 0, n_y = 0;

      // The grid of n_x x n_y cells covering [x_min, x_max] x [y_min, y_max].
      static ContactGrid covering(const double x_min, const double x_max, const double y_min,
                                  const double y_max, const unsigned int n_x, const unsigned int n_y);
      unsigned int       n_cells() const { return n_x * n_y; }
      double             cell_area() const { return dx * dy; }
      Eigen::Vector2d    centre(const unsigned int k) const;
      std::vector<Cell>  cells() const;
    };

    // Surface normal displacement at (x, y) due to pressure p on |xi| <= half_x, |eta| <= half_y
    // (Love 1929; Johnson 1985, ch. 3): exact closed form.
    double rectangle_surface_displacement(const double x, const double y, const double half_x,
                                          const double half_y, const double pressure,
                                          const double youngs_modulus, const double poisson_ratio);

    // Normal displacement at (x, y) and depth d >= 0: Boussinesq's point-load displacement
    //   u_z = F (1 + nu)/(2 pi E) [2 (1 - nu)/rho + d^2/rho^3]
    // integrated over the rectangle in closed form (exact; reduces to Love's formula at d = 0).
    double rectangle_displacement_at_depth(const double x, const double y, const double depth,
                                           const double half_x, const double half_y,
                                           const double pressure, const double youngs_modulus,
                                           const double poisson_ratio);

    // Boussinesq point load F at the origin, displacement at horizontal distance r and depth d.
    double point_load_displacement(const double r, const double depth, const double load,
                                   const double youngs_modulus, const double poisson_ratio);

    // Displacement at horizontal distance r and depth d under a unit force spread over a disc of
    // radius a with the pressure 3 / (pi a^2) (1 - s^2)^2, s = distance / a: the patch load of
    // fem::ElasticBody. Boussinesq's point-load displacement integrated over the disc by
    // Gauss-Legendre quadrature in radius and angle (20 x 20 points); needs d >= a, where the
    // integrand is smooth (relative quadrature error below 1e-12, tested against 40 x 40 points).
    double patch_load_displacement(double r, double depth, double radius, double youngs_modulus,
                                   double poisson_ratio);

    // patch_load_displacement for one depth, radius and material, tabulated once in r for many
    // evaluations: a cardinal cubic B-spline through the quadrature at spacing radius / 16 up to
    // r = 64 radii (interpolation error 3.4e-8 of the value at r = 0 for d = 2a), the quadrature
    // beyond.
    class PatchLoadKernel
    {
    public:
      PatchLoadKernel(double depth, double radius, double youngs_modulus, double poisson_ratio);
      double operator()(double r) const;

    private:
      double depth, radius, E, nu, r_max;
      boost::math::interpolators::cardinal_cubic_b_spline<double> spline;
    };

    // C(i, j) = displacement at (centre_i, depth) per unit pressure on cell j, one body.
    // For the surface of two bodies in contact (depth = 0) the compliances add: pass
    // youngs_modulus = E*, poisson_ratio = 0, since (1 - 0^2)/E* = sum_i (1 - nu_i^2)/E_i.
    // At depth each body needs its own E and nu.
    Eigen::MatrixXd influence_matrix(const std::vector<Cell> &cells, const double depth,
                                     const double youngs_modulus, const double poisson_ratio);

    // The same for a regular grid, using that C depends only on the cell offset: one evaluation
    // per offset, (2 n_x - 1)(2 n_y - 1) instead of n_cells^2.
    Eigen::MatrixXd influence_matrix(const ContactGrid &grid, const double depth,
                                     const double youngs_modulus, const double poisson_ratio);

    // Hybrid FE / half-space compliance of a contact grid (per unit pressure):
    //   C_ij = A_j C_FE(i*, j) + sum_k [C_B,k(i, j) - C_B,k(i*, j)],
    // i* the point at `depth` below cell centre i. fe_force_compliance(i, j) is the closing
    // displacement at i* per unit force at cell j, already summed over both bodies (the FE model
    // is too coarse to resolve the Hertzian zone but exact enough at the depth); the half-space
    // terms of each body k add the local displacement between the surface and the depth.
    Eigen::MatrixXd hybrid_compliance(const Eigen::MatrixXd &            fe_force_compliance,
                                      const std::vector<Cell> &          cells,
                                      const double                       depth,
                                      const std::vector<Material> &bodies);

    // Displacement (into the body) on the axis at depth d of a half-space of modulus E, Poisson's
    // ratio nu, under the Hertz pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2): Boussinesq's point load
    // integrated numerically (x = a r cos t, y = b r sin t, r = sin s makes the integrand smooth;
    // 64-point Gauss-Legendre in s, the periodic trapezoidal rule in t with 256 points).
    double hertz_pressure_displacement_at_depth(double p0, double a, double b, double depth,
                                                double youngs_modulus, double poisson_ratio);
  } // namespace half_space
} // namespace hertzgear
