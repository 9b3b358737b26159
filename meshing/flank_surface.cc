#include "meshing/flank_surface.h"

#include <cmath>

namespace hertzgear::meshing
{
  FlankSurface GearGeometry::flank() const
  {
    return FlankSurface(*this);
  }

  FlankSurface::FlankSurface(const GearGeometry &gear)
    : gear(&gear), r_b(gear.base_radius_mm()), beta(gear.helix_angle_rad())
  {
    if (beta == 0)
      return; // spur: beta_b = 0, cos(beta_b) = 1, no turn, normal_z = 0 exactly
    const double h = gear.parameters().hand == HelixHand::right ? 1.0 : -1.0;
    beta_b         = meshing::base_helix_angle_rad(gear.parameters());
    cos_beta_b     = std::cos(beta_b);
    inv_cos_beta_b = 1 / cos_beta_b;
    turn_per_mm    = h * std::tan(beta) / gear.reference_radius_mm();
    normal_z       = -h * std::sin(beta_b);
  }

  Eigen::Vector3d FlankSurface::point(const double roll_mm, const double z_mm) const
  {
    const Eigen::Vector2d p = gear->involute_point(roll_mm / r_b);
    if (turn_per_mm == 0)
      return {p.x(), p.y(), z_mm};
    const Eigen::Vector2d q = GearGeometry::rotate(p, turn_per_mm * z_mm);
    return {q.x(), q.y(), z_mm};
  }

  Eigen::Vector3d FlankSurface::normal(const double roll_mm, const double z_mm) const
  {
    const Eigen::Vector2d n = gear->involute_normal(roll_mm / r_b);
    if (turn_per_mm == 0)
      return {n.x(), n.y(), normal_z};
    const Eigen::Vector2d q = GearGeometry::rotate(n, turn_per_mm * z_mm);
    return {cos_beta_b * q.x(), cos_beta_b * q.y(), normal_z};
  }

  Eigen::Vector3d FlankSurface::modified_point(const double roll_mm, const double z_mm) const
  {
    return point(roll_mm, z_mm) - modification_mm(roll_mm, z_mm) * normal(roll_mm, z_mm);
  }
} // namespace hertzgear::meshing
