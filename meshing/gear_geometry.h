#pragma once
// Exact geometry of one spur gear cut by an ISO 53 basic rack (docs/geometry.md), and the
// transverse section of a helical one (its 3D flank: FlankSurface, meshing/flank_surface.h):
//   - the involute flank,   theta(r) = psi_b - inv(alpha_r),  cos(alpha_r) = r_b / r,
//   - the trochoidal fillet, the envelope of the round (radius rho_fP) of the cutting rack's tip
//     rolling on the reference circle (an equidistant of the trochoid of the round's centre),
//   - the root circle cut by the flat tip of the rack,
//   - lead crowning Delta(z) = beta (2z/b)^2 and linear/parabolic tip relief, both as material
//     removal normal to the flank.
// Points come from the analytic curves. The local frame of a tooth: gear centre at the origin,
// the tooth's centre line on the +x axis, the +theta (counter-clockwise) flank is the loaded one
// ("drive" flank in PairKinematics' convention), the -theta flank its mirror image.
#include "meshing/gear_parameters.h"

#include <Eigen/Core>

#include <vector>

namespace hertzgear::meshing
{
  // Transverse module m_t = m_n / cos(beta) and pressure angle tan(alpha_t) = tan(alpha_n) /
  // cos(beta) (ISO 21771:2007, 4.3). A spur gear (beta = 0) keeps m_n and alpha_n as they are,
  // not converted, so that its radii stay the same to the last bit.
  double transverse_module_mm(const GearParameters &p);
  double transverse_pressure_angle_rad(const GearParameters &p);
  // Base helix angle beta_b, sin(beta_b) = sin(beta) cos(alpha_n).
  double base_helix_angle_rad(const GearParameters &p);
  // The radii that follow from the parameters alone [mm], without the checks of GearGeometry (the
  // one formula of each; GearGeometry uses them): pitch r = m_t z / 2, base r_b = r cos(alpha_t),
  // root r_f = r + x m_n - h_fP of the generating rack.
  double pitch_radius_mm(const GearParameters &p);
  double base_radius_mm(const GearParameters &p);
  double root_radius_mm(const GearParameters &p);
  // Polar moment of inertia [kg m^2] of the gear body as a solid disc between the bore and the
  // root circle over the face width: I = rho b pi (r_f^4 - r_bore^4) / 2.
  double disc_inertia_kg_m2(const GearParameters &p, double density_kg_per_m3);

  class FlankSurface;

  // The transverse section of the gear (z = 0 of a helical gear): all radii, angles and thicknesses
  // below are transverse; module_mm() and pressure_angle_rad() are the rack's (normal) ones.
  class GearGeometry
  {
  public:
    // Builds the geometry and runs the single-gear checks; throws InputError for undercut, a
    // pointed tip, absurd dimensions, too large crowning or tip relief.
    explicit GearGeometry(const GearParameters &parameters);

    const GearParameters &parameters() const { return params; }
    int    n_teeth() const { return params.teeth; }
    double module_mm() const { return params.module_mm; }
    double pressure_angle_rad() const { return params.pressure_angle_rad; }
    double face_width_mm() const { return params.face_width_mm; }
    double helix_angle_rad() const { return params.helix_angle_rad; }
    double transverse_pressure_angle_rad() const { return alpha_t; }
    // The drive flank as a 3D surface (a view of this geometry, which must outlive it).
    FlankSurface flank() const;

    double reference_radius_mm() const { return r; }  // r = m_t z / 2
    double base_radius_mm() const { return r_b; }     // r_b = r cos(alpha_t)
    double tip_radius_mm() const { return r_a; }
    double root_radius_mm() const { return r_f; }     // r + x m - h_fP
    double form_radius_mm() const { return r_F; }     // where the fillet meets the involute
    double bore_radius_mm() const { return params.bore_radius_mm; }
    double angular_pitch_rad() const;                 // 2 pi / z
    double base_pitch_mm() const;                     // p_b = pi m_t cos(alpha_t)

    // Half the angular tooth thickness on the base circle, psi_b = s/(2r) + inv(alpha), with s
    // the (thinned) circular tooth thickness on the reference circle.
    double half_base_thickness_angle_rad() const { return psi_b; }
    double reference_tooth_thickness_mm() const { return s_ref; }
    // Circular tooth thickness on the involute at radius (r_b <= radius <= r_a).
    double tooth_thickness_mm(double radius) const;
    double top_land_mm() const { return tooth_thickness_mm(r_a); }

    // Roll angle u = tan(alpha_r) of the involute point at radius (>= r_b); the roll length
    // (distance to the base tangent point, = radius of curvature) is r_b u.
    double roll_angle_at_radius(double radius) const;
    double form_roll_angle() const { return u_F; }
    double tip_roll_angle() const { return u_a; }

    // Polar angle of the +theta flank at radius (involute part, r >= r_b).
    double flank_polar_angle_rad(double radius) const;
    // +theta flank point and unit outward normal (pointing out of the tooth) at roll angle u.
    Eigen::Vector2d involute_point(double roll_angle) const;
    Eigen::Vector2d involute_normal(double roll_angle) const;

    // +theta fillet point for t in [0, 1]: t = 0 on the root circle (bottom of the round),
    // t = 1 at the form point where the involute starts. Exact envelope of the rack tip round.
    Eigen::Vector2d fillet_point(double t) const;
    // Polar angle of the bottom of the fillet (start of the root arc of the +theta side).
    double root_fillet_angle_rad() const;

    // Material removed normal to the flank [mm] at face position z (0 = mid-face) and roll
    // length xi = r_b u (distance from the base tangent point): crowning + tip relief.
    double crowning_mm(double z_mm) const;
    double tip_relief_mm(double roll_length_mm) const;
    // Along the face: crowning, helix slope deviation and lead end relief.
    double lead_modification_mm(double z_mm) const;
    // Across the profile: tip relief, profile crowning and root relief.
    double profile_modification_mm(double roll_length_mm) const;
    double modification_mm(double roll_length_mm, double z_mm) const
    {
      return lead_modification_mm(z_mm) + profile_modification_mm(roll_length_mm);
    }
    // Face positions where the lead modification changes its formula (the lead end relief
    // knees); between them it is a quadratic in z.
    std::vector<double> lead_breakpoints_mm() const;
    // Radius of the crowning parabola, R = b^2 / (8 beta); infinity when uncrowned.
    double crowning_radius_mm() const;

    // The whole +theta half-profile of the tooth centred on the x axis, from the space centre
    // on the root circle to the tip corner, sampled from the analytic curves.
    struct HalfProfile
    {
      std::vector<Eigen::Vector2d> root_arc; // space centre -> bottom of the fillet
      std::vector<Eigen::Vector2d> fillet;   // bottom of the fillet -> form point
      std::vector<Eigen::Vector2d> flank;    // form point -> tip corner
    };
    HalfProfile half_profile(unsigned int n_root, unsigned int n_fillet, unsigned int n_flank) const;

    // Rotation that takes the generation frame (tooth space on +y) to the tooth frame.
    static Eigen::Vector2d rotate(const Eigen::Vector2d &p, double angle);

  private:
    GearParameters params;
    double m_t = 0, alpha_t = 0; // transverse module and pressure angle
    double r = 0, r_b = 0, r_a = 0, r_f = 0, r_F = 0;
    double s_ref = 0, psi_b = 0, u_F = 0, u_a = 0;
    // Generating rack: centre of its tip round (x_c, y_c) in the generation frame, rolling
    // parameters of the fillet's ends.
    double x_c = 0, y_c = 0, rho = 0, phi_root = 0, phi_form = 0;

    Eigen::Vector2d fillet_point_generation_frame(double phi) const;
    void            check() const;
  };

  // Radius of curvature of an involute at roll length xi is xi itself; kept for readability.
  inline double involute_radius_of_curvature_mm(const double roll_length_mm)
  {
    return roll_length_mm;
  }
} // namespace hertzgear::meshing
