#pragma once
#include "contact/half_space.h"
#include "contact/mesh_cycle.h"
#include "meshing/flank_surface.h"

namespace hertzgear::contact
{
  // A body whose structural compliance at the reference depth is the half-space's: the
  // displacement at depth d below flank point `reading` of a unit force spread uniformly over
  // the TCA grid cell centred at flank point `load` (Boussinesq-Love, exact), at their offset
  // in the developed flank (FlankSurface::developed_offset_mm). The cell's half-sides are those
  // on the flank: du / 2 across the profile and, along the face, dz / (2 cos(beta_b)) for a
  // helical flank (dz / 2 spur), so that the rectangle has the cell's area du dz / cos(beta_b).
  // `flank` views a GearGeometry that must outlive this body.
  class HalfSpaceFlankCompliance : public FlankCompliance
  {
  public:
    HalfSpaceFlankCompliance(const Material &material, const double depth_mm,
                             const meshing::FlankSurface &flank, const double half_cell_u_mm,
                             const double half_cell_z_mm)
      : material(material), depth(depth_mm), flank(flank), hu(half_cell_u_mm)
      , hz(half_cell_z_mm)
    {}
    double compliance_mm_per_N(const FlankPoint &reading, const FlankPoint &load) const override
    {
      if (reading.tooth != load.tooth)
        return 0.0;
      const Eigen::Vector2d offset = flank.developed_offset_mm(reading, load);
      return half_space::rectangle_displacement_at_depth(offset.x(), offset.y(), depth, hu, hz,
                                                         1.0 / (4.0 * hu * hz),
                                                         material.youngs_modulus_MPa,
                                                         material.poisson_ratio);
    }
    double reference_depth_mm() const override { return depth; }

  private:
    Material              material;
    double                depth;
    meshing::FlankSurface flank;
    double                hu, hz;
  };
} // namespace hertzgear::contact
