#pragma once
// Resolved finite-element contact: an elastic block pressed against a rigid plane, frictionless,
// solved with a primal-dual active set (semismooth Newton; Hintermueller, Ito & Kunisch 2002, the
// method of deal.II's step-41/42) on the deal.II system, with adaptive refinement driven by the
// contact zone and Kelly's error estimator. PETSc (MUMPS) and MPI (parallel::distributed).
// It is the reference against which the Hertz closed forms (contact/hertz) and the hybrid local
// compliance of the TCA (contact/mesh_cycle) are checked: docs/validation-hertz.md.
//
// The Hertz problem of two elastic bodies equals one body of contact modulus E* = E/(1 - nu^2)
// against a rigid plane with the initial gap g(x, y) = x^2/(2 R_x) + y^2/(2 R_y) (Johnson 1985,
// ch. 4). Geometry, one symmetric part of the block (half in 2D plane strain, quarter in 3D):
//
//        z = 0  contact face: u_z <= g(x, y), pressure p >= 0, p (u_z - g) = 0
//   x = 0 +----------------------------+ x = X (free)      y = 0: roller (3D)
//  roller |                            |                   y = Y: free (the end of a roller
//   u_x=0 |        elastic block       |                          or the flank's face edge)
//         +----------------------------+ z = -H: u_z = delta (rigid approach), tangentially free
//
// (2D: y plays the role of z.) Load control: for a given active set the solution is
// u = u_g + delta u_1 (u_g: gap on the active set, bottom fixed; u_1: active set fixed, bottom
// moved by 1), so delta follows from the total contact force F exactly; both fields share one
// MUMPS factorisation. Units: mm, N, MPa.
#include <deal.II/base/point.h>

#include <functional>
#include <string>
#include <vector>

namespace hertzgear
{
  namespace fem
  {
    struct ResolvedContactSettings
    {
      // The equivalent body: E/(1 - nu^2) = E* of the pair.
      double youngs_modulus_MPa = 103000;
      double poisson_ratio      = 0.3;
      // Radii of the gap g = x^2/(2 R_x) + y^2/(2 R_y); radius_y_mm = 0: no curvature along y
      // (line contact, 3D only).
      double radius_x_mm = 10;
      double radius_y_mm = 10;
      // 3D: total force on the whole body [N]; 2D: force per unit length [N/mm].
      double load = 100;
      // Block: 0 <= x <= X, 0 <= y <= Y (3D), -H <= z <= 0.
      double half_width_x_mm = 10;
      double half_width_y_mm = 10;
      double depth_mm        = 10;
      // True when the contact is meant to reach y = Y (a roller or a flank that ends there):
      // otherwise an active node at y = Y means the contact left the modelled surface.
      bool contact_may_reach_y_end = false;
      // > 0 (3D line contact): the rigid body ends at y = this (a roller shorter than the block,
      // i.e. on a wider elastic raceway); beyond it there is no contact.
      double rigid_end_y_mm = 0;

      // Target contact semi-axes (mesh design only: the size of the first zoomed cells and the
      // region refined before the first solve; the results do not use them).
      double design_semi_axis_x_mm = 1;
      double design_semi_axis_y_mm = 1;
      unsigned int initial_cells_per_semi_axis = 2; // across the smaller design semi-axis, level 0
      unsigned int n_levels       = 4;   // adaptive levels solved and reported
      double       kelly_fraction = 0.1; // of the cells refined by Kelly's estimator per level
      unsigned int max_active_set_iterations = 40;

      // Depths below the contact centre at which the approach is read.
      std::vector<double> reading_depths_mm;
    };

    // One point of a pressure profile along an axis of the contact face.
    struct ProfilePoint
    {
      double coordinate_mm = 0;
      double pressure_MPa  = 0;
    };

    struct ResolvedContactLevel
    {
      unsigned int level        = 0;
      unsigned long long n_dofs = 0;
      unsigned int n_cells      = 0;
      unsigned int n_active     = 0;  // active contact nodes of the modelled part
      unsigned int n_iterations = 0;  // of the active set at this level
      double       wall_time_s  = 0;  // cumulative, from the start of the run
      double       contact_cell_mm = 0; // edge length of the finest contact-face cells

      double approach_mm   = 0; // delta: displacement of the face z = -H
      double peak_pressure_MPa = 0;   // nodal force / lumped area at the centre node
      // Semi-axes from the second moments of the nodal contact forces: for the Hertz pressure
      // sum P x^2 / sum P = a^2/5 (elliptical) or b^2/4 (line contact, per slice).
      double semi_axis_x_mm = 0;
      double semi_axis_y_mm = 0; // 3D elliptical only
      // The same from the active set: midway between the last active and the first free node on
      // each axis (resolution +- half a cell).
      double active_semi_axis_x_mm = 0;
      double active_semi_axis_y_mm = 0;
      // Compression between the contact centre and points at reading_depths_mm below it:
      // u_z(0, 0, -d) - u_z(0, 0, 0).
      std::vector<double> depth_approach_mm;
      double total_force = 0; // check: the load of the whole body (both symmetric parts)
      std::vector<ProfilePoint> profile_x, profile_y;
    };

    // Solves the levels in turn; `report` is called after each. Throws InputError for bad
    // settings and NumericalError when the active set cycles, does not settle within the
    // iteration cap, or the contact reaches the edge of the modelled surface.
    template <int dim>
    std::vector<ResolvedContactLevel>
    solve_resolved_contact(const ResolvedContactSettings &settings,
                           const std::function<void(const ResolvedContactLevel &)> &report = {});
  } // namespace fem
} // namespace hertzgear
