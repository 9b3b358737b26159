// Stiffness source potential-energy: as hertz-analytic, with the structural stiffness of each pair
// at its contact point from both teeth's bending, shear, axial and fillet-foundation compliance
// (stiffness/potential_energy.h) and Yang & Lin's linear line contact on uncrowned flanks;
// 1/k_rest = 1/k_total,tangent - 1/k_h,tangent as in the FE source.
#include "meshing/pair_kinematics.h"
#include "stiffness/closed_form.h"
#include "stiffness/potential_energy.h"

#include <utility>

namespace hertzgear::stiffness
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    class PotentialEnergySource : public ClosedFormSource
    {
    public:
      PotentialEnergySource()
        : ClosedFormSource("potential-energy", "tooth beam and fillet foundation compliance with "
                                               "Hertz contact along the path of contact")
      {}

    protected:
      StiffnessResult tabulate(const StiffnessInput &input, ClosedFormPair &m) const override
      {
        const auto &pair = m.pair;
        // Both teeth's compliance at the contact point at roll distance s: the pinion at roll
        // angle s / r_b1, the gear at (L - s) / r_b2.
        const auto teeth = [&](const double roll_mm, const bool plane_strain) {
          const double u1 = roll_mm / pair.pinion().base_radius_mm();
          const double u2 = (pair.line_of_action_length_mm() - roll_mm) / pair.gear().base_radius_mm();
          const auto  &e1 = input.pinion_material, &e2 = input.gear_material;
          return std::pair{tooth_compliance(pair.pinion(), u1, e1.youngs_modulus_MPa,
                                            e1.poisson_ratio, plane_strain),
                           tooth_compliance(pair.gear(), u2, e2.youngs_modulus_MPa,
                                            e2.poisson_ratio, plane_strain)};
        };
        const auto pair_stiffness = [](const auto &t) {
          return 1.0 / (t.first.total_mm_per_N() + t.second.total_mm_per_N());
        };
        m.yang_lin   = true;
        m.structural = [=](const double roll_mm) { return pair_stiffness(teeth(roll_mm, false)); };

        StiffnessResult r = shared_load_cycle(input, m, true);
        // The single pair at the pitch point, each tooth's parts [N/m].
        const double s_C   = pair.point('C').roll_distance_mm;
        const auto   pitch = teeth(s_C, false);
        const auto   parts = [](const ToothCompliance &c) {
          return nlohmann::json{{"bending_N_per_m", 1e3 / c.bending_mm_per_N},
                                {"shear_N_per_m", 1e3 / c.shear_mm_per_N},
                                {"axial_N_per_m", 1e3 / c.axial_mm_per_N},
                                {"fillet_foundation_N_per_m", 1e3 / c.fillet_mm_per_N},
                                {"load_angle_deg", c.load_angle_rad * 180 / pi}};
        };
        r.notes["pitch_point_pinion_tooth"]            = parts(pitch.first);
        r.notes["pitch_point_gear_tooth"]              = parts(pitch.second);
        r.notes["pitch_point_pair_structural_N_per_m"] = pair_stiffness(pitch) * 1e3;
        r.notes["pitch_point_pair_N_per_m"] =
          m.load_N / m.pair_approach_mm(m.load_N, s_C, pair_stiffness(pitch)) * 1e3;
        r.notes["pitch_point_pair_structural_plane_strain_N_per_m"] =
          pair_stiffness(teeth(s_C, true)) * 1e3;
        r.table.source = "potential-energy: tooth bending, shear and axial compliance (Yang & Lin, "
                         "Tian), fillet foundation (Sainsot et al. 2004), Hertz contact per pair, "
                         "load sharing by compatibility";
        return r;
      }
    };
  } // namespace

  const StiffnessSource &potential_energy_source() { return the_source<PotentialEnergySource>(); }
} // namespace hertzgear::stiffness
