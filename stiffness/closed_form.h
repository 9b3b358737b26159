#pragma once
// What the closed-form sources (iso6336, hertz-analytic, potential-energy) share; the model is
// described in docs/stiffness-closed-form.md:
//  - structural (rest) stiffness of one tooth pair, k_r1 = 1 / (1/(c' b) - 1/k_line): ISO 6336-1
//    method B single stiffness c' over the face width b, minus the line-contact Hertzian part
//    that c' contains (Palmgren's steel line contact at the static load, tangent stiffness);
//  - Hertzian approach of one pair at its load F_i: elliptical Hertz contact (the paper's eq. 5)
//    when the flanks are crowned (profile curvature from the radii of curvature at the contact
//    point, lead curvature 8 beta / b^2 of both gears), Palmgren line contact otherwise (Yang &
//    Lin's linear line contact for the potential-energy source);
//  - load sharing by compatibility: the pairs in contact share the static load so that their
//    approaches agree (one routine for every source that shares load).
#include "meshing/pair_kinematics.h"
#include "stiffness/iso6336.h"
#include "stiffness/stiffness_source.h"

#include <functional>
#include <vector>

namespace hertzgear::stiffness
{
  // One tooth pair at a contact point: its Hertzian approach [mm] at load F [N], the contact
  // semi-axes [mm] and the peak pressure [MPa] that go with it.
  struct PairContact
  {
    double approach_mm = 0, a_mm = 0, b_mm = 0, p0_MPa = 0;
  };

  // The pairs in contact sharing a total load so that their approaches agree.
  struct LoadSharing
  {
    double              approach_mm = 0; // the common approach (loaded STE)
    std::vector<double> loads_N;
  };

  class ClosedFormPair
  {
  public:
    // Throws ParameterError when the closed forms leave no positive structural stiffness.
    ClosedFormPair(const StiffnessInput &input, const meshing::PairKinematics &pair);

    const meshing::PairKinematics &pair;
    Iso6336Stiffness               iso;
    double E_star_MPa = 0, face_mm = 0, kappa_lead_per_mm = 0, n = 1, load_N = 0;
    double k_r1_N_per_mm = 0;          // structural stiffness of one pair (ISO, without Hertz)
    double line_tangent_N_per_mm = 0;  // the line-contact part that ISO's c' b contains
    // Uncrowned flanks: Yang & Lin's linear line contact instead of Palmgren's.
    bool yang_lin = false;
    // Structural stiffness of one pair at a contact point [N/mm]; empty: k_r1 everywhere.
    std::function<double(double roll_mm)> structural;

    bool   crowned() const { return kappa_lead_per_mm > 0; }
    double structural_N_per_mm(double roll_mm) const;
    PairContact contact(double load_N, double roll_mm) const;
    // Approach of one pair (structural k_r [N/mm] in series with Hertz) at load F [N].
    double pair_approach_mm(double load_N, double roll_mm, double k_r) const;
    // The load F shared by the pairs at these roll distances with these structural stiffnesses.
    LoadSharing share_load(const std::vector<double> &roll_mm, const std::vector<double> &k_r,
                           double load_N) const;
    // The model's record for stiffness.json ("closed_form_model").
    nlohmann::json notes() const;
  };

  // The input checks every closed-form source makes (torque, positions against harmonics).
  void check_closed_form_input(const StiffnessInput &input);

  // A closed-form source: checked by check_closed_form_input; compute() builds the pair and its
  // closed-form model and lets the source tabulate the cycle (the table is then checked and its
  // rows summarised).
  class ClosedFormSource : public StiffnessSource
  {
  public:
    using StiffnessSource::StiffnessSource;
    void check(const StiffnessInput &input) const override { check_closed_form_input(input); }
    StiffnessResult compute(const StiffnessInput &input, PhaseTimer &timer) const final;

  protected:
    // The rows and the table of the source (SI), from the pair and its model.
    virtual StiffnessResult tabulate(const StiffnessInput &input, ClosedFormPair &model) const = 0;
  };

  // The mesh cycle along the path of contact with load sharing by compatibility (hertz-analytic
  // and potential-energy): S rows, the Fourier fits of k_h and k_rest. With `tangent_rest`,
  // 1/k_rest = 1/k_total,tangent - 1/k_h,tangent (as the FE source); else k_rest is the sum of
  // the pairs' structural stiffnesses.
  StiffnessResult shared_load_cycle(const StiffnessInput &input, const ClosedFormPair &model,
                                    bool tangent_rest);
} // namespace hertzgear::stiffness
