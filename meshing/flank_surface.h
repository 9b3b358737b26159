#pragma once
// The drive (+theta) flank of one gear as a surface in 3D: the involute helicoid (docs/geometry.md,
// "Flank surface"). A spur flank is its helix angle 0 case, the transverse involute extruded
// along the axis; every spur expression is reproduced bit for bit there (the turn of the
// section is skipped, cos(beta_b) is exactly 1 and the normal's axial component exactly 0).
//
// Coordinates on the flank: the roll distance xi [mm] of the transverse involute (distance from
// its base tangent point, xi = r_b u) and the face position z [mm] along the axis (0 = mid-face).
// The body frame is GearGeometry's tooth frame with z along the gear axis: the transverse section
// at z is the section at z = 0 turned by psi(z) = z tan(beta) / r about the axis (counter-clockwise
// as z grows for a right hand, clockwise for a left hand):
//   X(xi, z) = ( R(psi(z)) x_t(xi / r_b), z ),
//   N(xi, z) = ( cos(beta_b) R(psi(z)) n_t(xi / r_b), -h sin(beta_b) ),  h = +1 right, -1 left,
// with x_t, n_t the transverse involute point and outward normal (GearGeometry::involute_point,
// involute_normal) and sin(beta_b) = sin(beta) cos(alpha_n) (ISO 21771:2007, 4.3; Litvin &
// Fuentes, Gear Geometry and Applied Theory, 2nd ed., ch. 15).
//
// A view: it keeps a pointer to its GearGeometry, which must outlive it (obtain it by value from
// GearGeometry::flank() where it is used). Non-virtual; the functions called per pair of contact
// grid points are inline and free of trigonometry.
#include "meshing/flank_point.h"
#include "meshing/gear_geometry.h"

#include <Eigen/Core>

namespace hertzgear::meshing
{
  class FlankSurface
  {
  public:
    explicit FlankSurface(const GearGeometry &gear);

    double    helix_angle_rad() const { return beta; }      // beta at the reference circle
    HelixHand hand() const { return gear->parameters().hand; }
    // Base helix angle beta_b, sin(beta_b) = sin(beta) cos(alpha_n); exactly 0 for a spur gear.
    double base_helix_angle_rad() const { return beta_b; }
    double cos_base_helix() const { return cos_beta_b; }    // exactly 1 for a spur gear
    // Turn of the transverse section at face position z [rad], psi(z) = +-z tan(beta) / r (+ for
    // a right hand); exactly 0 for a spur gear.
    double section_angle_rad(const double z_mm) const { return turn_per_mm * z_mm; }

    // Nominal flank point of tooth 0 [mm] and unit outward normal (pointing out of the tooth).
    Eigen::Vector3d point(double roll_mm, double z_mm) const;
    Eigen::Vector3d normal(double roll_mm, double z_mm) const;
    // The modified flank: the nominal point moved by the micro-geometry's removal along the
    // inward normal.
    Eigen::Vector3d modified_point(double roll_mm, double z_mm) const;

    // Micro-geometry, material removed normal to the flank [mm]: GearGeometry's, unchanged.
    double modification_mm(const double roll_mm, const double z_mm) const
    {
      return gear->modification_mm(roll_mm, z_mm);
    }
    double lead_modification_mm(const double z_mm) const { return gear->lead_modification_mm(z_mm); }
    double profile_modification_mm(const double roll_mm) const
    {
      return gear->profile_modification_mm(roll_mm);
    }
    // The same removal measured in the transverse section, along the transverse normal (the
    // angle it turns the section's involute by, times r_b): Delta / cos(beta_b), since the
    // transverse normal makes the angle beta_b with the flank normal.
    double transverse_removal_mm(const double roll_mm, const double z_mm) const
    {
      return gear->modification_mm(roll_mm, z_mm) / cos_beta_b;
    }

    // Offset of flank point a from flank point b in the developed flank [mm], a plane whose
    // Euclidean distances are the flank's arc lengths to first order. With U = xi^2 / (2 r_b)
    // (the involute's arc length from the base circle) the metric of the helicoid is
    //   ds^2 = dU^2 + 2 g12 dU dz + g22 dz^2,  g12 = -h tan(beta_b) xi / r_b,
    //   g22 = 1 + tan^2(beta_b) (1 + xi^2 / r_b^2),  det = 1 / cos^2(beta_b),
    // i.e. ds^2 = (dU + g12 dz)^2 + (dz / cos(beta_b))^2; g12 is taken at the mean roll of the
    // two points. Spur: (dU, dz), the cylinder's development.
    Eigen::Vector2d developed_offset_mm(const FlankPoint &a, const FlankPoint &b) const
    {
      const double du = (a.roll_mm * a.roll_mm - b.roll_mm * b.roll_mm) / (2.0 * r_b);
      const double dz = a.z_mm - b.z_mm;
      // -h tan(beta_b) / r_b = -h tan(beta) / r = -turn_per_mm: exactly 0 (a sum with +-0) spur.
      return {du - turn_per_mm * (0.5 * (a.roll_mm + b.roll_mm)) * dz, dz * inv_cos_beta_b};
    }

  private:
    const GearGeometry *gear = nullptr;
    double r_b = 0, beta = 0, beta_b = 0, cos_beta_b = 1, inv_cos_beta_b = 1;
    double turn_per_mm = 0; // h tan(beta) / r [rad/mm]
    double normal_z    = 0; // -h sin(beta_b)
  };
} // namespace hertzgear::meshing
