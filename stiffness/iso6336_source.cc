// Stiffness source iso6336: ISO 6336-1 method B mesh stiffness with Hertz at the pitch point,
// constant over the mesh cycle (docs/stiffness-closed-form.md).
#include "meshing/pair_kinematics.h"
#include "stiffness/closed_form.h"

#include <cmath>

namespace hertzgear::stiffness
{
  namespace
  {
    class Iso6336Source : public ClosedFormSource
    {
    public:
      Iso6336Source()
        : ClosedFormSource("iso6336", "ISO 6336-1 method B with Hertz closed forms")
      {}

    protected:
      // Constant series: ISO's mesh stiffness ratio c_gamma_alpha / c' applied to the pair's
      // rest stiffness, eps_alpha pairs' worth of Hertzian stiffness at the pitch point.
      StiffnessResult tabulate(const StiffnessInput &input, ClosedFormPair &m) const override
      {
        const auto  &pair = m.pair;
        const double F0_N = m.load_N, eps = pair.contact_ratio();
        const auto   c1    = m.contact(F0_N, pair.point('C').roll_distance_mm);
        const double k_h1  = F0_N / std::pow(c1.approach_mm, m.n);
        const double ratio = m.iso.c_gamma_alpha_N_per_mm_um / m.iso.c_prime_N_per_mm_um;

        StiffnessResult r;
        r.load_N         = F0_N;
        r.harmonics      = input.harmonics;
        r.notes_key      = "closed_form_model";
        r.notes          = m.notes();
        auto &t          = r.table;
        t.hertz_exponent = m.n;
        t.k_rest_N_per_m        = {m.k_r1_N_per_mm * ratio * 1e3, {}, {}, 0.0};
        t.k_hertz_N_per_m_pow_n = {eps * k_h1 * std::pow(1e3, m.n), {}, {}, 0.0};
        t.source = "iso6336: ISO 6336-1 method B mesh stiffness, Hertz at the pitch point";
        // STE of the series springs at F0 (pitch point, load shared as the mean stiffness says).
        const double delta_h = std::pow(F0_N / (eps * k_h1), 1.0 / m.n);
        const double ste_mm  = F0_N / (m.k_r1_N_per_mm * ratio) + delta_h;
        for (int i = 0; i < input.positions_per_cycle; ++i)
          {
            PositionRow row;
            row.mesh_phase            = double(i) / input.positions_per_cycle;
            row.ste_um                = ste_mm * 1e3;
            row.k_total_N_per_m       = F0_N / ste_mm * 1e3;
            row.k_hertz_N_per_m_pow_n = t.k_hertz_N_per_m_pow_n.mean;
            row.k_rest_N_per_m        = t.k_rest_N_per_m.mean;
            row.hertz_penetration_um  = delta_h * 1e3;
            row.contact_a_mm          = c1.a_mm;
            row.contact_b_mm          = c1.b_mm;
            row.peak_pressure_MPa     = c1.p0_MPa;
            r.rows.push_back(row);
            t.samples.mesh_phase.push_back(row.mesh_phase);
            t.samples.k_total_N_per_m.push_back(row.k_total_N_per_m);
            t.samples.k_hertz_N_per_m_pow_n.push_back(row.k_hertz_N_per_m_pow_n);
            t.samples.k_rest_N_per_m.push_back(row.k_rest_N_per_m);
            t.samples.ste_m.push_back(ste_mm * 1e-3);
          }
        return r;
      }
    };
  } // namespace

  const StiffnessSource &iso6336_source() { return the_source<Iso6336Source>(); }
} // namespace hertzgear::stiffness
