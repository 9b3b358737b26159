// Resolved FE contact (fem/resolved_contact): the primal-dual active set against a rigid plane
// reproduces the Hertz closed forms, and fails clearly on bad problems.
// Measured accuracy per level and the method: docs/validation-hertz.md.
#include "common/errors.h"
#include "contact/hertz.h"
#include "fem/resolved_contact.h"

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear;

namespace
{
  // The steel pair of both validation cases as one body against a rigid plane (E = 103 GPa,
  // nu = 0.3, R = 10 mm), 4 contact cells across the semi-axis on the first level.
  fem::ResolvedContactSettings steel_body(const unsigned int n_levels)
  {
    fem::ResolvedContactSettings s;
    s.youngs_modulus_MPa          = 103000;
    s.poisson_ratio               = 0.3;
    s.radius_x_mm                 = 10;
    s.initial_cells_per_semi_axis = 4;
    s.n_levels                    = n_levels;
    return s;
  }

  // The contact modulus E* = E / (1 - nu^2) of the body.
  double contact_modulus(const fem::ResolvedContactSettings &s)
  {
    return s.youngs_modulus_MPa / (1 - s.poisson_ratio * s.poisson_ratio);
  }

  // Hertz's answer for a sphere of the body's radius R_x.
  hertz::EllipticalContact sphere_hertz(const fem::ResolvedContactSettings &s)
  {
    return hertz::circular_contact(s.load, s.radius_x_mm, contact_modulus(s));
  }

  // The 2D cylinder case of data/scenes/validation/cylinder_2d.prm: 200 N/mm; block 10 x 10 mm
  // (67 half-widths).
  fem::ResolvedContactSettings cylinder_2d(const unsigned int n_levels)
  {
    auto s                  = steel_body(n_levels);
    s.radius_y_mm           = 0;
    s.load                  = 200;
    s.half_width_x_mm = s.depth_mm = 10;
    s.kelly_fraction        = 0.1;
    s.design_semi_axis_x_mm =
      hertz::line_contact(s.load, s.radius_x_mm, contact_modulus(s)).half_width;
    return s;
  }

  // The sphere case of data/scenes/validation/sphere.prm: 1 kN, block 16 mm (40 a).
  fem::ResolvedContactSettings sphere(const unsigned int n_levels)
  {
    auto s                  = steel_body(n_levels);
    s.radius_y_mm           = 10;
    s.load                  = 1000;
    s.half_width_x_mm = s.half_width_y_mm = s.depth_mm = 16;
    s.kelly_fraction        = 0.05;
    s.design_semi_axis_x_mm = s.design_semi_axis_y_mm = sphere_hertz(s).semi_major;
    return s;
  }

  double relative(const double fe, const double exact) { return (fe - exact) / exact; }
} // namespace

// Requirement: in plane strain the resolved FE contact shall give the Hertz half-width and peak
// pressure within 2 % (the acceptance bound) once the contact is resolved by about
// 30 cells per half-width, and both errors shall decrease with refinement.
TEST(ResolvedContact, CylinderPlaneStrainMatchesHertz)
{
  const auto   s      = cylinder_2d(5);
  const auto   hertz  = hertz::line_contact(s.load, s.radius_x_mm, contact_modulus(s));
  const auto   levels = fem::solve_resolved_contact<2>(s);
  ASSERT_EQ(levels.size(), 5u);
  const auto &last = levels.back();
  // Level 4 has contact cells of b/123 (measured -0.72 % in b, +0.52 % in p0, see
  // docs/validation-hertz.md); 2 % is the acceptance bound itself, not a fitted tolerance.
  EXPECT_LT(std::abs(relative(last.semi_axis_x_mm, hertz.half_width)), 0.02);
  EXPECT_LT(std::abs(relative(last.peak_pressure_MPa, hertz.peak_pressure)), 0.02);
  // Convergence: the error of the finest level is below that of the first.
  EXPECT_LT(std::abs(relative(last.semi_axis_x_mm, hertz.half_width)),
            std::abs(relative(levels.front().semi_axis_x_mm, hertz.half_width)));
  EXPECT_LT(std::abs(relative(last.peak_pressure_MPa, hertz.peak_pressure)),
            std::abs(relative(levels.front().peak_pressure_MPa, hertz.peak_pressure)));
}

// Requirement: the load control shall carry exactly the prescribed force: the approach is the
// unknown that makes the sum of the nodal contact forces equal F (round-off of the MUMPS solve).
TEST(ResolvedContact, LoadControlIsExact)
{
  const auto s      = cylinder_2d(2);
  const auto levels = fem::solve_resolved_contact<2>(s);
  for (const auto &l : levels)
    EXPECT_NEAR(l.total_force, s.load, 1e-9 * s.load);
}

// Requirement: in 3D the resolved FE contact shall give the Hertz radius (both semi-axes) and
// peak pressure of the sphere within 2 % at its third level (contact cells of a/26), and the
// circular contact shall come out circular.
TEST(ResolvedContact, SphereMatchesHertz)
{
  const auto   s      = sphere(3);
  const auto   hertz  = sphere_hertz(s);
  const auto   levels = fem::solve_resolved_contact<3>(s);
  const auto  &last   = levels.back();
  // 2 %: the acceptance bound (measured on this level: -0.46 % in a, +0.28 % in p0).
  EXPECT_LT(std::abs(relative(last.semi_axis_x_mm, hertz.semi_major)), 0.02);
  EXPECT_LT(std::abs(relative(last.semi_axis_y_mm, hertz.semi_major)), 0.02);
  EXPECT_LT(std::abs(relative(last.peak_pressure_MPa, hertz.peak_pressure)), 0.02);
  // The quarter model is symmetric under x <-> y: the semi-axes agree to the solver's round-off.
  EXPECT_NEAR(last.semi_axis_x_mm, last.semi_axis_y_mm, 1e-9 * last.semi_axis_x_mm);
  EXPECT_NEAR(last.total_force, s.load, 1e-9 * s.load);
}

// Requirement: a load so high that the contact zone reaches the edge of the modelled surface
// shall end with a NumericalError (exit code 3) that says so.
TEST(ResolvedContact, ContactLeavingTheSurfaceIsANumericalError)
{
  auto s            = cylinder_2d(1);
  s.half_width_x_mm = 0.3; // Hertz b = 0.15 mm at 200 N/mm; at 2000 N/mm b = 0.47 mm > 0.3 mm
  s.depth_mm        = 2;
  s.load            = 2000;
  try
    {
      fem::solve_resolved_contact<2>(s);
      FAIL() << "expected a NumericalError";
    }
  catch (const NumericalError &e)
    {
      EXPECT_NE(std::string(e.what()).find("edge of the modelled surface"), std::string::npos)
        << e.what();
    }
}

// Requirement: an active set that does not settle within the iteration cap shall end with a
// NumericalError (exit code 3) that lists the active-set history.
TEST(ResolvedContact, IterationCapIsANumericalError)
{
  auto s                      = cylinder_2d(1);
  s.max_active_set_iterations = 1; // the first level needs 6 iterations from a single node
  try
    {
      fem::solve_resolved_contact<2>(s);
      FAIL() << "expected a NumericalError";
    }
  catch (const NumericalError &e)
    {
      EXPECT_NE(std::string(e.what()).find("did not settle"), std::string::npos) << e.what();
    }
}

// Requirement: bad settings shall be rejected as InputError (exit code 2) naming the value.
TEST(ResolvedContact, BadSettingsAreInputErrors)
{
  auto s = cylinder_2d(1);
  s.poisson_ratio = 0.5;
  EXPECT_THROW(fem::solve_resolved_contact<2>(s), InputError);
  s                   = cylinder_2d(1);
  s.reading_depths_mm = {20.0}; // below the 10 mm block
  EXPECT_THROW(fem::solve_resolved_contact<2>(s), InputError);
}

// Requirement (also run on 2 ranks by ctest fem.resolved_contact_mpi2): distributed over MPI
// ranks the solver shall solve the same discrete problem: exact load balance, a circular contact,
// and the sphere's radius and peak pressure within the 2 % acceptance bound at level 1.
TEST(ResolvedContactMpi, DistributedSphereIsConsistent)
{
  const auto   s      = sphere(2);
  const auto   hertz  = sphere_hertz(s);
  const auto   levels = fem::solve_resolved_contact<3>(s);
  const auto  &last   = levels.back();
  EXPECT_NEAR(last.total_force, s.load, 1e-9 * s.load);
  EXPECT_NEAR(last.semi_axis_x_mm, last.semi_axis_y_mm, 1e-9 * last.semi_axis_x_mm);
  // Level 1 (contact cells a/13): measured -0.89 % in a and +1.71 % in p0 serially; the
  // distributed run solves the same discrete problem, so the same 2 % bound holds.
  EXPECT_LT(std::abs(relative(last.semi_axis_x_mm, hertz.semi_major)), 0.02);
  EXPECT_LT(std::abs(relative(last.peak_pressure_MPa, hertz.peak_pressure)), 0.02);
  if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "ranks " << dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) << ": a "
              << last.semi_axis_x_mm << " mm, p0 " << last.peak_pressure_MPa << " MPa, approach "
              << last.approach_mm << " mm, " << last.n_dofs << " dofs" << std::endl;
}
