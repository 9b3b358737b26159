#pragma once
// Kinematics of a spur or helical pair and its unloaded tooth contact analysis (docs/geometry.md,
// "Pair kinematics", "Helical pairs: kinematics" and "Helical pairs: gaps").
//
// Pair frame (mm, rad): pinion centre O1 at the origin, gear centre O2 = (a_w, 0), z along both
// axes (0 = mid-face). The pinion drives counter-clockwise, the gear turns clockwise. Everything
// below lives in the transverse section (for a helical pair: transverse module, pressure angle,
// base radii and base pitch, ISO 21771): both bodies touch on their +theta flanks
// (GearGeometry's "drive" flank) along the transverse line of action from
// T1 = r_b1 (cos a_w, -sin a_w) (pinion base tangent point) in direction e = (sin a_w, cos a_w) to
// T2. A point of the line of action is given by its roll distance s = |T1 P|; s is also the
// transverse radius of curvature of the pinion flank there, and L - s that of the gear flank
// (L = |T1 T2| = a_w sin a_w).
//
// Mesh phase tau in [0, 1) is the pinion's turn in units of its angular pitch 2 pi / z1. Tooth
// pair j (j = 0, 1, ...) touches in the mid-face section z = 0, if at all, at
// s_j(tau) = s_A + (tau + j) p_b: pair 0 enters at A when tau = 0, pair 1 entered one base pitch
// earlier. A helical pair's contact line is inclined by the base helix angle beta_b in the plane
// of action: s_j(tau, z) = s_j(tau) + h_1 z tan(beta_b), h_1 = +1 for a right-hand pinion, -1 for
// a left-hand one (the pinion's section at z is turned by h_1 z tan(beta) / r_1 in its driving
// sense, FlankSurface); spur: s_j(tau, z) = s_j(tau).
#include "meshing/gear_geometry.h"
#include "meshing/gear_parameters.h"

#include <Eigen/Core>

#include <string>
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

  // Refuses a helical pair (either gear with a helix angle) in a stage that handles spur pairs
  // only: InputError "helical pairs are not supported by <stage> yet" naming the helix angle.
  void require_spur_pair(const GearParameters &pinion, const GearParameters &gear,
                         const std::string &stage);

  class PairKinematics
  {
  public:
    // Resolves the operating centre distance and the backlash (thinning the teeth when the
    // centre distance is not given), builds both gears and runs the pair checks: equal modules,
    // pressure angles and helix angles, opposite hands of a helical pair, jamming centre
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
    double contact_ratio() const { return (s_E - s_A) / p_b; } // transverse, eps_alpha
    // Helix angle beta at the reference circle and base helix angle beta_b (both 0 for spur).
    double helix_angle_rad() const { return beta; }
    double base_helix_angle_rad() const { return beta_b; }
    // Face (overlap) contact ratio eps_beta = b sin(beta) / (pi m_n), b the common face width,
    // and the total contact ratio eps_gamma = eps_alpha + eps_beta (ISO 21771:2007, 5.5).
    double face_contact_ratio() const;
    double total_contact_ratio() const { return contact_ratio() + face_contact_ratio(); }
    // Total backlash along the (transverse) line of action j_bn, from the centre distance and the
    // thinning; for a helical pair the backlash normal to the flanks is j_bn cos(beta_b).
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

    // Contact position s_j(tau) of pair j in the mid-face section, and s_j(tau, z) at face
    // position z: s_j(tau) + contact_line_slope() z.
    double contact_roll_distance_mm(int pair, double mesh_phase) const;
    double contact_roll_distance_mm(int pair, double mesh_phase, double z_mm) const;
    // ds/dz of a contact line in the plane of action: h_1 tan(beta_b) (0 for spur).
    double contact_line_slope() const { return roll_per_face; }
    // The pairs whose contact line meets the path of contact, s_A <= s_j(tau, z) <= s_E, somewhere
    // on the face |z| <= b/2 (spur: s_A <= s_j <= s_E), in increasing order of j.
    std::vector<int> pairs_in_contact(double mesh_phase) const;
    // Total length [mm] of the contact lines inside the field of action (s_A <= s <= s_E,
    // |z| <= b/2) at mesh phase tau: each line's extent in z there, divided by cos(beta_b).
    // Exact (the lines are clipped analytically); spur: b times the number of pairs in contact.
    double contact_line_length_mm(double mesh_phase) const;
    // Point of the line of action in the pair frame.
    Eigen::Vector2d line_of_action_point(double roll_distance_mm) const;
    Eigen::Vector2d line_of_action_direction() const;

    // Placement of the body meshes at a mesh phase, for a sector with `central_tooth` on the
    // +x axis of the body frame (GearBodyMesher's central_tooth()): the pinion's central tooth
    // and the gear's central tooth form pair 0. Pair j uses pinion tooth central + j and gear
    // tooth central - j. A rotation about the axis: for a helical pair it places the whole
    // helicoids (their mid-face sections touch at s_j(tau)).
    BodyPlacement placement(unsigned int body, double mesh_phase) const;
    static int    sector_tooth_of_pair(unsigned int body, int central_tooth, int pair);

    // Unloaded gap [mm] of tooth pair `pair` at mesh phase tau between the pinion flank point at
    // roll distance `pinion_roll_mm` and face position z (0 = mid-face) and the gear flank, minus
    // the rigid approach: the smallest gap over the contact lines of all pairs in contact is 0.
    // Rigid bodies in the unloaded position; this is the contact stage's gap input.
    //
    // Measured normal to the flanks (docs/geometry.md, "Helical pairs: gaps"): the transverse
    // section at z is the mid-face section of a spur pair advanced along the line of action by
    // contact_line_slope() z, so from the pinion point a line parallel to the transverse line of
    // action e is intersected with the gear flank in that section (the gear roll at
    // gear_roll_at_mm); that transverse distance times cos(beta_b) is the distance along the
    // flank normal, to which the micro-geometry of both flanks (removed normal to the flank,
    // FlankSurface::modification_mm) and the misalignment gap are added. Spur: cos(beta_b) = 1
    // exactly, the normal and the line of action coincide.
    double unloaded_gap_mm(int pair, double mesh_phase, double pinion_roll_mm, double z_mm) const;
    // Without the rigid approach (the separation of the nominal flanks plus modifications),
    // normal to the flanks.
    double separation_mm(int pair, double mesh_phase, double pinion_roll_mm, double z_mm) const;
    // The rigid approach at tau, normal to the flanks: min over the pairs in contact and over their
    // contact lines inside the field of action of the modifications and the misalignment there
    // (exact: piecewise quadratic along each line). Along the transverse line of action it is
    // this divided by cos(beta_b) (the kinematic transmission error).
    double rigid_approach_mm(double mesh_phase) const;
    // cos(beta_b): a distance normal to the flanks per distance along the transverse line of
    // action (exactly 1 for a spur pair).
    double cos_base_helix() const { return cos_beta_b; }
    // Shaft misalignment along the line of action over the face width, f_eq = f_ma + f_Sd
    // sin(alpha_w) + f_Sb cos(alpha_w) [mm], and its gap contribution f_eq z / b (added to the
    // gaps as a removal normal to the flanks, spur or helical).
    double misalignment_mm() const;
    double misalignment_gap_mm(double z_mm) const;
    // The common face width b = min(b_1, b_2) [mm] (the contact grid's).
    double face_width_mm() const;
    // The z-dependent part of the separation: lead modifications of both flanks plus the
    // misalignment, and where over the face it is smallest (z, value) [mm].
    double                    lead_gap_mm(double z_mm) const;
    std::pair<double, double> smallest_lead_gap_mm() const;
    // Gear flank point hit along e from the pinion flank point in the transverse section at face
    // position z: its roll distance from T2. Without z: the mid-face section (spur: every one).
    double gear_roll_at_mm(int pair, double mesh_phase, double pinion_roll_mm, double z_mm) const;
    double gear_roll_at_mm(int pair, double mesh_phase, double pinion_roll_mm) const;

  private:
    PairParameters params;
    std::vector<GearGeometry> gears;
    double a_w = 0, a_tight = 0, alpha_w = 0, p_b = 0, L = 0, s_A = 0, s_E = 0, j_bn = 0;
    // Helical: beta, beta_b, cos(beta_b) and h_1 tan(beta_b); spur: 0, 0, 1, 0 exactly.
    double beta = 0, beta_b = 0, cos_beta_b = 1, roll_per_face = 0;

    // Polar angle of the centre line of the pinion (gear) tooth whose drive flank touches the
    // line of action at roll distance s.
    double pinion_tooth_angle(double s) const;
    double gear_tooth_angle(double s) const;
    void   check() const;
    // The nominal flanks' distance along e in the transverse section at z (no modifications).
    double transverse_separation_mm(int pair, double mesh_phase, double pinion_roll_mm,
                                    double z_mm) const;
  };
} // namespace hertzgear::meshing
