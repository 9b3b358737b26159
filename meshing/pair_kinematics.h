#pragma once
// Kinematics of a spur pair and its unloaded tooth contact analysis (docs/geometry.md).
//
// Pair frame (mm, rad): pinion centre O1 at the origin, gear centre O2 = (a_w, 0). The pinion
// drives counter-clockwise, the gear turns clockwise. Both bodies touch on their +theta flanks
// (GearGeometry's "drive" flank) along the line of action from T1 = r_b1 (cos a_w, -sin a_w)
// (pinion base tangent point) in direction e = (sin a_w, cos a_w) to T2. A point of the line of
// action is given by its roll distance s = |T1 P|; s is also the radius of curvature of the
// pinion flank there, and L - s that of the gear flank (L = |T1 T2| = a_w sin a_w).
//
// Mesh phase tau in [0, 1) is the pinion's turn in units of its angular pitch 2 pi / z1. Tooth
// pair j (j = 0, 1, ...) touches, if at all, at s_j(tau) = s_A + (tau + j) p_b: pair 0 enters at
// A when tau = 0, pair 1 entered one base pitch earlier.
#include "meshing/gear_geometry.h"
#include "meshing/gear_parameters.h"

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace hertzgear::meshing
{
  // A characteristic point of the path of contact.
  struct LineOfActionPoint
  {
    double roll_distance_mm = 0; // from T1
    double rho_pinion_mm    = 0; // radius of curvature of the pinion flank
    double rho_gear_mm      = 0;
    double radius_pinion_mm = 0; // where on each flank
    double radius_gear_mm   = 0;
  };

  // Placement of a body mesh (built in its own frame: centre at the origin, sector centred on
  // the +x axis with tooth k at polar angle (k - central) 2 pi / z) in the pair frame at a mesh
  // phase: x_pair = centre + R(rotation) x_body.
  struct BodyPlacement
  {
    Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
    double          rotation_rad = 0;
  };

  class PairKinematics
  {
  public:
    // Resolves the operating centre distance and the backlash (thinning the teeth when the
    // centre distance is not given), builds both gears and runs the pair checks: jamming centre
    // distance, involute interference, contact ratio below 1, tip relief beyond the active
    // profile. Throws InputError.
    explicit PairKinematics(const PairParameters &parameters);

    const GearGeometry &pinion() const { return gears[0]; }
    const GearGeometry &gear() const { return gears[1]; }
    const GearGeometry &body(unsigned int i) const { return gears[i]; }

    double center_distance_mm() const { return a_w; }
    double reference_center_distance_mm() const; // (z1 + z2) m / 2
    double tight_mesh_center_distance_mm() const { return a_tight; }
    double operating_pressure_angle_rad() const { return alpha_w; }
    double operating_pitch_radius_mm(unsigned int body) const;
    double base_pitch_mm() const { return p_b; }
    double line_of_action_length_mm() const { return L; } // |T1 T2|
    double path_of_contact_mm() const { return s_E - s_A; }
    double contact_ratio() const { return (s_E - s_A) / p_b; }
    // Total backlash along the line of action j_bn (from the centre distance and the thinning).
    double backlash_loa_mm() const { return j_bn; }
    double gear_ratio() const;

    // A: start of contact (gear tip), B: lowest point of single tooth contact on the pinion,
    // C: pitch point, D: highest point of single tooth contact, E: end (pinion tip).
    LineOfActionPoint point(char name) const;
    LineOfActionPoint point_at(double roll_distance_mm) const;
    double            radius_of_curvature_pinion_mm(double roll_distance_mm) const;
    double            radius_of_curvature_gear_mm(double roll_distance_mm) const;
    // Where the active profile of a body (0 pinion, 1 gear) starts, the radius its flank carries
    // contact from: point A on the pinion, point E on the gear.
    double active_profile_start_radius_mm(unsigned int body) const;

    // Contact position s_j(tau) of pair j, and the pairs with s_A <= s_j <= s_E.
    double           contact_roll_distance_mm(int pair, double mesh_phase) const;
    std::vector<int> pairs_in_contact(double mesh_phase) const;
    // Point of the line of action in the pair frame.
    Eigen::Vector2d line_of_action_point(double roll_distance_mm) const;
    Eigen::Vector2d line_of_action_direction() const;

    // Placement of the body meshes at a mesh phase, for a sector with `central_tooth` on the
    // +x axis of the body frame (GearBodyMesher's central_tooth()): the pinion's central tooth
    // and the gear's central tooth form pair 0. Pair j uses pinion tooth central + j and gear
    // tooth central - j.
    BodyPlacement placement(unsigned int body, double mesh_phase) const;
    static int    sector_tooth_of_pair(unsigned int body, int central_tooth, int pair);

    // Unloaded gap [mm] of tooth pair `pair` at mesh phase tau, between the pinion flank point
    // at roll distance `pinion_roll_mm` (its radius is sqrt(r_b1^2 + s^2); s = s_j is the
    // contact line) and the gear flank, measured along the line of action, at face position
    // z (0 = mid-face), including crowning and tip relief of both flanks, minus the rigid
    // approach: the smallest gap over the contact lines of all pairs in contact is 0.
    // Rigid bodies in the unloaded position; this is the FE contact stage's gap input.
    double unloaded_gap_mm(int pair, double mesh_phase, double pinion_roll_mm, double z_mm) const;
    // Without the rigid approach (the separation of the nominal flanks plus modifications).
    double separation_mm(int pair, double mesh_phase, double pinion_roll_mm, double z_mm) const;
    // The rigid approach at tau: min over the pairs in contact and over z of the modifications
    // and the misalignment at the contact lines (exact: the lead part is piecewise quadratic).
    double rigid_approach_mm(double mesh_phase) const;
    // Shaft misalignment along the line of action over the face width, f_eq = f_ma + f_Sd
    // sin(alpha_w) + f_Sb cos(alpha_w) [mm], and its gap contribution f_eq z / b.
    double misalignment_mm() const;
    double misalignment_gap_mm(double z_mm) const;
    // The common face width b = min(b_1, b_2) [mm] (the contact grid's).
    double face_width_mm() const;
    // The z-dependent part of the separation: lead modifications of both flanks plus the
    // misalignment, and where over the face it is smallest (z, value) [mm].
    double                    lead_gap_mm(double z_mm) const;
    std::pair<double, double> smallest_lead_gap_mm() const;
    // Gear flank point hit along e from the pinion flank point: its roll distance from T2.
    double gear_roll_at_mm(int pair, double mesh_phase, double pinion_roll_mm) const;

  private:
    PairParameters params;
    std::vector<GearGeometry> gears;
    double a_w = 0, a_tight = 0, alpha_w = 0, p_b = 0, L = 0, s_A = 0, s_E = 0, j_bn = 0;

    // Polar angle of the centre line of the pinion (gear) tooth whose drive flank touches the
    // line of action at roll distance s.
    double pinion_tooth_angle(double s) const;
    double gear_tooth_angle(double s) const;
    void   check() const;
  };
} // namespace hertzgear::meshing
