// Requirements on the potential-energy tooth compliance (stiffness/potential_energy.h): the beam
// integrals against closed forms of prismatic beams, the load angle of an involute against its
// closed form, and the physical trends a gear engineer relies on.
#include "common/errors.h"
#include "meshing/gear_geometry.h"
#include "stiffness/potential_energy.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear::meshing;
using namespace hertzgear::stiffness;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  // Closed form of the three beam energies of a prismatic cantilever of half-thickness h and
  // length d (from x = 0 to the load at x = d, y = y_P), width L:
  //   1/k_b = [c^2 d^3/3 - c s y_P d^2 + s^2 y_P^2 d] / (E I),  I = 2 h^3 L / 3
  //   1/k_s = 1.2 c^2 d / (G 2 h L),  1/k_a = s^2 d / (E 2 h L).
  ToothCompliance prismatic(const double h, const double d, const double y_P, const double a1,
                            const double E, const double G, const double L)
  {
    const double c = std::cos(a1), s = std::sin(a1), I = 2 * h * h * h * L / 3;
    ToothCompliance t;
    t.bending_mm_per_N = (c * c * d * d * d / 3 - c * s * y_P * d * d + s * s * y_P * y_P * d) / (E * I);
    t.shear_mm_per_N   = 1.2 * c * c * d / (G * 2 * h * L);
    t.axial_mm_per_N   = s * s * d / (E * 2 * h * L);
    return t;
  }

  GearParameters paper_pinion()
  {
    GearParameters g;
    g.teeth              = 23;
    g.module_mm          = 3;
    g.pressure_angle_rad = 20 * pi / 180;
    g.face_width_mm      = 20;
    g.bore_radius_mm     = 15;
    g.name               = "pinion";
    return g;
  }
} // namespace

TEST(PotentialEnergy, PrismaticBeamMatchesTheClosedForm)
{
  // Requirement: the bending, shear and axial integrals are those of the beam energies. For a
  // constant section they are polynomials in the length; the quadrature (relative tolerance
  // 1e-10) must reproduce them to 1e-9.
  const double E = 206000, G = E / 2.6, L = 20, h = 2.1, d = 5.3, y_P = 1.4, a1 = 0.31;
  const auto   c = beam_compliance([&](double) { return h; }, 0, d, y_P, a1, E, G, L);
  const auto   r = prismatic(h, d, y_P, a1, E, G, L);
  EXPECT_NEAR(c.bending_mm_per_N, r.bending_mm_per_N, 1e-9 * r.bending_mm_per_N);
  EXPECT_NEAR(c.shear_mm_per_N, r.shear_mm_per_N, 1e-9 * r.shear_mm_per_N);
  EXPECT_NEAR(c.axial_mm_per_N, r.axial_mm_per_N, 1e-9 * r.axial_mm_per_N);
}

TEST(PotentialEnergy, SteppedBeamIsSplitAtItsKink)
{
  // Requirement: a section that jumps (here from 3 mm to 1.5 mm half-thickness at x = 2 mm) is
  // integrated exactly when the jump is given as a kink: each part is a prismatic beam whose
  // bending moment is that of the whole cantilever. Closed form by splitting the bending
  // integral: int_0^2 m^2/(E I_1) + int_2^d m^2/(E I_2), m = c (d - x) - s y_P.
  const double E = 206000, G = E / 2.6, L = 20, d = 6, y_P = 1.2, a1 = 0.25, x_k = 2;
  const double h1 = 3, h2 = 1.5;
  const auto   y  = [&](const double x) { return x < x_k ? h1 : h2; };
  const auto   c  = beam_compliance(y, 0, d, y_P, a1, E, G, L, {x_k});
  const double ca = std::cos(a1), sa = std::sin(a1);
  // Antiderivative of m^2 in x: -(c (d - x) - s y_P)^3 / (3 c).
  const auto M2 = [&](const double x) { return -std::pow(ca * (d - x) - sa * y_P, 3) / (3 * ca); };
  const double I1 = 2 * h1 * h1 * h1 * L / 3, I2 = 2 * h2 * h2 * h2 * L / 3;
  const double bending = (M2(x_k) - M2(0)) / (E * I1) + (M2(d) - M2(x_k)) / (E * I2);
  const double inv_area = x_k / (2 * h1 * L) + (d - x_k) / (2 * h2 * L);
  EXPECT_NEAR(c.bending_mm_per_N, bending, 1e-9 * bending);
  EXPECT_NEAR(c.shear_mm_per_N, 1.2 * ca * ca / G * inv_area, 1e-9 * c.shear_mm_per_N);
  EXPECT_NEAR(c.axial_mm_per_N, sa * sa / E * inv_area, 1e-9 * c.axial_mm_per_N);
}

TEST(PotentialEnergy, LoadAngleOfTheInvoluteIsRollAngleMinusHalfBaseThickness)
{
  // Requirement: the load acts along the involute's normal, the base tangent at polar angle
  // psi_b - u; its angle to the perpendicular of the tooth's centre line is a1 = u - psi_b
  // (positive: the load compresses the tooth). Closed form, to rounding.
  const GearGeometry g(paper_pinion());
  for (const double f : {0.0, 0.3, 0.7, 1.0})
    {
      const double u = g.form_roll_angle() + f * (g.tip_roll_angle() - g.form_roll_angle());
      const auto   c = tooth_compliance(g, u, 206000, 0.3);
      EXPECT_NEAR(c.load_angle_rad, u - g.half_base_thickness_angle_rad(), 1e-12) << "u = " << u;
    }
}

TEST(PotentialEnergy, ALoadFurtherUpTheToothIsCarriedMoreCompliantly)
{
  // Requirement: moving the load from the start of the active flank to the tip lengthens the
  // lever arm, so the bending and the total compliance of the tooth grow monotonically (every
  // published potential-energy curve of a single tooth does). Bending dominates at the tip.
  const GearGeometry g(paper_pinion());
  double             previous_bending = 0, previous_total = 0;
  for (int i = 0; i <= 10; ++i)
    {
      const double u = g.form_roll_angle() + 0.1 * i * (g.tip_roll_angle() - g.form_roll_angle());
      const auto   c = tooth_compliance(g, u, 206000, 0.3);
      EXPECT_GT(c.bending_mm_per_N, previous_bending) << "u = " << u;
      EXPECT_GT(c.total_mm_per_N(), previous_total) << "u = " << u;
      EXPECT_GT(c.shear_mm_per_N, 0.0);
      EXPECT_GT(c.fillet_mm_per_N, 0.0);
      previous_bending = c.bending_mm_per_N;
      previous_total   = c.total_mm_per_N();
    }
  const auto tip = tooth_compliance(g, g.tip_roll_angle(), 206000, 0.3);
  EXPECT_GT(tip.bending_mm_per_N, tip.shear_mm_per_N + tip.axial_mm_per_N);
}

TEST(PotentialEnergy, PlaneStrainScalesTheNormalStressPartsByOneMinusNuSquared)
{
  // Requirement: plane strain replaces E by E/(1 - nu^2) in the bending, axial and fillet parts
  // and leaves the shear part (G) alone, so the ratios are exactly 1 - nu^2 and 1 (to rounding
  // and quadrature tolerance 1e-10).
  const GearGeometry g(paper_pinion());
  const double       nu = 0.3, u = 0.5 * (g.form_roll_angle() + g.tip_roll_angle());
  const auto         ps = tooth_compliance(g, u, 206000, nu, false);
  const auto         pe = tooth_compliance(g, u, 206000, nu, true);
  EXPECT_NEAR(pe.bending_mm_per_N / ps.bending_mm_per_N, 1 - nu * nu, 1e-9);
  EXPECT_NEAR(pe.axial_mm_per_N / ps.axial_mm_per_N, 1 - nu * nu, 1e-9);
  EXPECT_NEAR(pe.fillet_mm_per_N / ps.fillet_mm_per_N, 1 - nu * nu, 1e-12);
  EXPECT_NEAR(pe.shear_mm_per_N / ps.shear_mm_per_N, 1.0, 1e-12);
}

TEST(PotentialEnergy, AGearWithoutBoreOrALoadOffTheFlankIsAnInputError)
{
  // Requirement: the fillet foundation needs r_f / r_bore, so a gear without a bore is named;
  // a roll angle outside the involute is named with the valid range.
  auto p           = paper_pinion();
  p.bore_radius_mm = 0;
  const GearGeometry solid(p);
  EXPECT_THROW(tooth_compliance(solid, 0.5 * (solid.form_roll_angle() + solid.tip_roll_angle()),
                                206000, 0.3),
               hertzgear::InputError);
  const GearGeometry g(paper_pinion());
  EXPECT_THROW(tooth_compliance(g, 1.1 * g.tip_roll_angle(), 206000, 0.3), hertzgear::InputError);
}
