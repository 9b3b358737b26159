#include "stiffness/closed_form.h"

#include "common/errors.h"
#include "contact/hertz.h"

#include <algorithm>
#include <cmath>

namespace hertzgear::stiffness
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  } // namespace

  ClosedFormPair::ClosedFormPair(const StiffnessInput &input, const meshing::PairKinematics &kinematics)
    : pair(kinematics)
  {
    const auto &p1 = input.pair.pinion, &p2 = input.pair.gear;
    iso        = iso6336_method_b(pair, input.torque_Nm);
    face_mm    = std::min(p1.face_width_mm, p2.face_width_mm);
    load_N     = input.torque_Nm * 1e3 / pair.pinion().base_radius_mm();
    E_star_MPa = hertz::contact_modulus(input.pinion_material, input.gear_material);
    // Lead crowning Delta(z) = beta (2 z / b)^2 of each flank: curvature 8 beta / b^2.
    kappa_lead_per_mm = 8.0 * (p1.crowning_mm / std::pow(p1.face_width_mm, 2) +
                               p2.crowning_mm / std::pow(p2.face_width_mm, 2));
    n = input.hertz_exponent;

    // Structural stiffness of one pair: ISO's c' b without the line-contact Hertzian part it
    // contains (Palmgren, delta ~ F^0.9: tangent stiffness F / (0.9 delta) at the static load).
    const double c_prime_b_N_per_mm = iso.c_prime_N_per_mm_um * 1e3 * face_mm;
    line_tangent_N_per_mm =
      load_N / (0.9 * hertz::line_approach_palmgren_mm(load_N, face_mm, E_star_MPa));
    const double r1_compliance = 1.0 / c_prime_b_N_per_mm - 1.0 / line_tangent_N_per_mm;
    if (!(r1_compliance > 0))
      throw ParameterError("torque_Nm",
                           msg(input.torque_Nm, ": ISO 6336 single stiffness c' b = ",
                               c_prime_b_N_per_mm,
                               " N/mm is stiffer than the line-contact Hertzian stiffness ",
                               line_tangent_N_per_mm,
                               " N/mm it contains, so no positive structural stiffness is left "
                               "(check the torque and the face widths)"));
    k_r1_N_per_mm = 1.0 / r1_compliance;
  }

  double ClosedFormPair::structural_N_per_mm(const double roll_mm) const
  {
    return structural ? structural(roll_mm) : k_r1_N_per_mm;
  }

  PairContact ClosedFormPair::contact(const double F, const double roll_mm) const
  {
    PairContact c;
    if (F <= 0)
      return c;
    const double rho1          = pair.radius_of_curvature_pinion_mm(roll_mm);
    const double rho2          = pair.radius_of_curvature_gear_mm(roll_mm);
    const double kappa_profile = 1.0 / rho1 + 1.0 / rho2;
    if (crowned())
      {
        const auto e  = hertz::elliptical_contact(F, kappa_profile, kappa_lead_per_mm, E_star_MPa);
        c.approach_mm = hertz::paper_approach(F, e.semi_major, e.eccentricity, E_star_MPa);
        c.a_mm        = e.major_axis_along_x ? e.semi_major : e.semi_minor; // across the profile
        c.b_mm        = e.major_axis_along_x ? e.semi_minor : e.semi_major; // along the face
        c.p0_MPa      = e.peak_pressure;
      }
    else
      {
        // Yang & Lin (1987): k_h = pi E L / (4 (1 - nu^2)) for equal materials, = pi L E* / 2.
        c.approach_mm = yang_lin ? 2 * F / (pi * face_mm * E_star_MPa) :
                                   hertz::line_approach_palmgren_mm(F, face_mm, E_star_MPa);
        const auto l = hertz::line_contact(F / face_mm, 1.0 / kappa_profile, E_star_MPa);
        c.a_mm       = l.half_width;
        c.b_mm       = 0.5 * face_mm;
        c.p0_MPa     = l.peak_pressure;
      }
    return c;
  }

  double ClosedFormPair::pair_approach_mm(const double F, const double roll_mm, const double k_r) const
  {
    return F / k_r + contact(F, roll_mm).approach_mm;
  }

  LoadSharing ClosedFormPair::share_load(const std::vector<double> &roll, const std::vector<double> &k_r,
                                         const double F_N) const
  {
    // Common approach: bisection on sum_i F_i(delta) = F, F_i from each pair's approach.
    const auto load_at = [&](const std::size_t j, const double delta) {
      double lo = 0, hi = F_N;
      while (pair_approach_mm(hi, roll[j], k_r[j]) < delta)
        hi *= 2;
      for (int it = 0; it < 100 && hi - lo > 1e-10 * F_N; ++it)
        {
          const double mid = 0.5 * (lo + hi);
          (pair_approach_mm(mid, roll[j], k_r[j]) < delta ? lo : hi) = mid;
        }
      return 0.5 * (lo + hi);
    };
    const auto total_at = [&](const double delta) {
      double f = 0;
      for (std::size_t j = 0; j < roll.size(); ++j)
        f += load_at(j, delta);
      return f;
    };
    double lo = 0, hi = pair_approach_mm(F_N, roll[0], k_r[0]);
    while (total_at(hi) < F_N)
      hi *= 2;
    for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (total_at(mid) < F_N ? lo : hi) = mid;
      }
    LoadSharing s;
    s.approach_mm = 0.5 * (lo + hi);
    for (std::size_t j = 0; j < roll.size(); ++j)
      s.loads_N.push_back(load_at(j, s.approach_mm));
    return s;
  }

  nlohmann::json ClosedFormPair::notes() const
  {
    return {{"iso6336_c_prime_N_per_mm_um", iso.c_prime_N_per_mm_um},
            {"iso6336_c_gamma_alpha_N_per_mm_um", iso.c_gamma_alpha_N_per_mm_um},
            {"line_contact_tangent_N_per_m", line_tangent_N_per_mm * 1e3},
            {"pair_rest_stiffness_N_per_m", k_r1_N_per_mm * 1e3},
            {"contact_ratio", pair.contact_ratio()},
            {"contact", crowned() ? "elliptical Hertz (crowned)" :
                        yang_lin  ? "Yang & Lin line contact" :
                                    "Palmgren line contact"},
            {"lead_curvature_per_m", kappa_lead_per_mm * 1e3}};
  }

  StiffnessResult ClosedFormSource::compute(const StiffnessInput &input, PhaseTimer &timer) const
  {
    check(input);
    PhaseTimer::Scope             scope(timer, "closed-form stiffness");
    const meshing::PairKinematics pair(input.pair);
    ClosedFormPair                model(input, pair);
    StiffnessResult               r = tabulate(input, model);
    r.table.check();
    summarise_rows(r);
    return r;
  }

  void check_closed_form_input(const StiffnessInput &input)
  {
    meshing::require_spur_pair(input.pair.pinion, input.pair.gear,
                               "the closed-form stiffness sources");
    if (!(input.torque_Nm > 0))
      throw ParameterError("torque_Nm", msg(input.torque_Nm,
                                            ": the closed-form stiffness is evaluated at the "
                                            "static load and needs a positive torque"));
    const int S = input.positions_per_cycle, H = input.harmonics;
    if (S < 2 * H + 1)
      throw ParameterError("positions_per_cycle",
                           msg(S, " is too few for ", H, " harmonics (need at least ", 2 * H + 1, ")"));
  }

  StiffnessResult shared_load_cycle(const StiffnessInput &input, const ClosedFormPair &m,
                                    const bool tangent_rest)
  {
    const int    S    = input.positions_per_cycle;
    const double F0_N = m.load_N;
    const double si_n = std::pow(1e3, m.n); // N/mm^n -> N/m^n
    StiffnessResult r;
    r.load_N    = F0_N;
    r.harmonics = input.harmonics;
    auto &t          = r.table;
    t.hertz_exponent = m.n;
    for (int i = 0; i < S; ++i)
      {
        const double     phase = double(i) / S;
        std::vector<int> pairs = m.pair.pairs_in_contact(phase);
        if (pairs.empty())
          throw InputError(msg("no tooth pair in contact at mesh phase ", phase, " (contact ratio ",
                               m.pair.contact_ratio(), ")"));
        std::vector<double> roll, k_r;
        for (const int p : pairs)
          {
            roll.push_back(m.pair.contact_roll_distance_mm(p, phase));
            k_r.push_back(m.structural_N_per_mm(roll.back()));
          }
        const LoadSharing sh    = m.share_load(roll, k_r, F0_N);
        const double      delta = sh.approach_mm;
        double k_h = 0, k_h_tangent = 0, k_r_sum = 0, delta_h_max = 0, main_load = -1;
        PairContact main;
        PositionRow row;
        row.load_share_1 = 0.0;
        row.load_share_2 = 0.0;
        for (std::size_t j = 0; j < roll.size(); ++j)
          {
            const double F = sh.loads_N[j];
            const auto   c = m.contact(F, roll[j]);
            k_h += F / std::pow(c.approach_mm, m.n);
            k_h_tangent += m.n * F / c.approach_mm;
            k_r_sum += k_r[j];
            delta_h_max = std::max(delta_h_max, c.approach_mm);
            // Pair 1 is the pair that entered at phase 0 (pair index 0), pair 2 the one ahead.
            *(pairs[j] == 0 ? row.load_share_1 : row.load_share_2) += F / F0_N;
            if (F > main_load)
              main_load = F, main = c;
          }
        double k_rest_N_per_mm = k_r_sum;
        if (tangent_rest)
          {
            // As the FE source: 1/k_rest = 1/k_total,tangent - 1/k_h,tangent, the tangent total
            // stiffness from +-2 % of the load (docs/theory-tca.md).
            const double eps_F     = 0.02;
            const double k_tangent = 2 * eps_F * F0_N /
                                     (m.share_load(roll, k_r, F0_N * (1 + eps_F)).approach_mm -
                                      m.share_load(roll, k_r, F0_N * (1 - eps_F)).approach_mm);
            const double rest = 1.0 / k_tangent - 1.0 / k_h_tangent;
            HG_REQUIRE_NUMERIC(rest > 0, "closed-form stiffness at mesh phase ", phase,
                               ": tangent total stiffness ", k_tangent,
                               " N/mm is not below the Hertzian one ", k_h_tangent, " N/mm");
            k_rest_N_per_mm = 1.0 / rest;
          }
        row.mesh_phase            = phase;
        row.ste_um                = delta * 1e3;
        row.k_total_N_per_m       = F0_N / delta * 1e3;
        row.k_hertz_N_per_m_pow_n = k_h * si_n;
        row.k_rest_N_per_m        = k_rest_N_per_mm * 1e3;
        row.pairs_in_contact      = static_cast<int>(pairs.size());
        row.hertz_penetration_um  = delta_h_max * 1e3;
        row.contact_a_mm          = main.a_mm;
        row.contact_b_mm          = main.b_mm;
        row.peak_pressure_MPa     = main.p0_MPa;
        r.rows.push_back(row);
        t.samples.mesh_phase.push_back(phase);
        t.samples.k_total_N_per_m.push_back(row.k_total_N_per_m);
        t.samples.k_hertz_N_per_m_pow_n.push_back(row.k_hertz_N_per_m_pow_n);
        t.samples.k_rest_N_per_m.push_back(row.k_rest_N_per_m);
        t.samples.ste_m.push_back(delta * 1e-3);
      }
    t.k_hertz_N_per_m_pow_n = fit_fourier_series(t.samples.k_hertz_N_per_m_pow_n, input.harmonics);
    t.k_rest_N_per_m        = fit_fourier_series(t.samples.k_rest_N_per_m, input.harmonics);
    r.notes_key = "closed_form_model";
    r.notes     = m.notes();
    return r;
  }
} // namespace hertzgear::stiffness
