#include "app/analytic_stiffness.h"

#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "common/errors.h"
#include "dynamics/stiffness_table.h"
#include "fem/hertz.h"
#include "meshing/iso6336.h"
#include "meshing/potential_energy.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>
#include <utility>

namespace hertzgear
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    // One tooth pair at a contact point: its Hertzian approach [mm] at load F [N] and the contact
    // semi-axes [mm] and peak pressure [MPa] that go with it.
    struct PairContact
    {
      double approach_mm = 0, a_mm = 0, b_mm = 0, p0_MPa = 0;
    };

    struct Model
    {
      explicit Model(const meshing::PairKinematics &kinematics) : pair(kinematics) {}

      const meshing::PairKinematics &pair;
      double E_star_MPa = 0, face_mm = 0, kappa_lead_per_mm = 0, n = 1, k_r1_N_per_mm = 0;
      // Uncrowned flanks: Yang & Lin's linear line contact (potential-energy source) instead of
      // Palmgren's.
      bool yang_lin = false;
      // Structural stiffness of one pair at a contact point [N/mm]; empty: k_r1 everywhere.
      std::function<double(double roll_mm)> structural;

      bool crowned() const { return kappa_lead_per_mm > 0; }

      double structural_N_per_mm(const double roll_mm) const
      {
        return structural ? structural(roll_mm) : k_r1_N_per_mm;
      }

      PairContact contact(const double load_N, const double roll_mm) const
      {
        PairContact c;
        if (load_N <= 0)
          return c;
        const double rho1 = pair.radius_of_curvature_pinion_mm(roll_mm);
        const double rho2 = pair.radius_of_curvature_gear_mm(roll_mm);
        const double kappa_profile = 1.0 / rho1 + 1.0 / rho2;
        if (crowned())
          {
            const auto e = hertz::elliptical_contact(load_N, kappa_profile, kappa_lead_per_mm, E_star_MPa);
            c.approach_mm = hertz::paper_approach(load_N, e.semi_major, e.eccentricity, E_star_MPa);
            c.a_mm        = e.major_axis_along_x ? e.semi_major : e.semi_minor; // across the profile
            c.b_mm        = e.major_axis_along_x ? e.semi_minor : e.semi_major; // along the face
            c.p0_MPa      = e.peak_pressure;
          }
        else
          {
            // Yang & Lin (1987): k_h = pi E L / (4 (1 - nu^2)) for equal materials, = pi L E* / 2.
            c.approach_mm = yang_lin ? 2 * load_N / (pi * face_mm * E_star_MPa) :
                                       hertz::line_approach_palmgren_mm(load_N, face_mm, E_star_MPa);
            const auto l  = hertz::line_contact(load_N / face_mm, 1.0 / kappa_profile, E_star_MPa);
            c.a_mm        = l.half_width;
            c.b_mm        = 0.5 * face_mm;
            c.p0_MPa      = l.peak_pressure;
          }
        return c;
      }

      // Approach of one pair (structural k_r [N/mm] + Hertzian) at load F [mm].
      double pair_approach_mm(const double load_N, const double roll_mm, const double k_r) const
      {
        return load_N / k_r + contact(load_N, roll_mm).approach_mm;
      }
    };

    // The pairs in contact sharing a total load so that their approaches agree.
    struct Sharing
    {
      double              approach_mm = 0; // the common approach (loaded STE)
      std::vector<double> loads_N;
    };

    Sharing share_load(const Model &m, const std::vector<double> &roll, const std::vector<double> &k_r,
                       const double F_N)
    {
      // Common approach: bisection on sum_i F_i(delta) = F, F_i from each pair's approach.
      const auto load_at = [&](const std::size_t j, const double delta) {
        double lo = 0, hi = F_N;
        while (m.pair_approach_mm(hi, roll[j], k_r[j]) < delta)
          hi *= 2;
        for (int it = 0; it < 100 && hi - lo > 1e-10 * F_N; ++it)
          {
            const double mid = 0.5 * (lo + hi);
            (m.pair_approach_mm(mid, roll[j], k_r[j]) < delta ? lo : hi) = mid;
          }
        return 0.5 * (lo + hi);
      };
      const auto total_at = [&](const double delta) {
        double f = 0;
        for (std::size_t j = 0; j < roll.size(); ++j)
          f += load_at(j, delta);
        return f;
      };
      double lo = 0, hi = m.pair_approach_mm(F_N, roll[0], k_r[0]);
      while (total_at(hi) < F_N)
        hi *= 2;
      for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it)
        {
          const double mid = 0.5 * (lo + hi);
          (total_at(mid) < F_N ? lo : hi) = mid;
        }
      Sharing s;
      s.approach_mm = 0.5 * (lo + hi);
      for (std::size_t j = 0; j < roll.size(); ++j)
        s.loads_N.push_back(load_at(j, s.approach_mm));
      return s;
    }

    std::string number(const double v)
    {
      std::ostringstream os;
      os << std::setprecision(10) << v;
      return os.str();
    }

    nlohmann::json series_json(const dynamics::FourierSeries &s)
    {
      return {{"mean", s.mean}, {"amplitudes", s.amplitudes}, {"phases_rad", s.phases_rad}};
    }
  } // namespace

  bool is_closed_form_source(const std::string &source)
  {
    return source == "iso6336" || source == "hertz-analytic" || source == "potential-energy";
  }

  AnalyticStiffness analytic_stiffness(const Scene &scene)
  {
    const auto &st = scene.stiffness;
    HG_REQUIRE_INPUT(is_closed_form_source(st.source),
                     "closed-form stiffness needs Stiffness/source = iso6336, hertz-analytic or "
                     "potential-energy, got ", st.source);
    HG_REQUIRE_INPUT(scene.operating.torque_Nm > 0, "Operating/torque_Nm = ", scene.operating.torque_Nm,
                     ": the closed-form stiffness is evaluated at the static load and needs a "
                     "positive torque");
    const meshing::PairKinematics pair = make_pair(scene);
    const auto   iso  = meshing::iso6336_method_b(pair, scene.operating.torque_Nm);
    const double b_mm = std::min(scene.pinion.face_width_mm, scene.gear.face_width_mm);
    const double F0_N = scene.operating.torque_Nm * 1e3 / pair.pinion().base_radius_mm();
    const double eps  = pair.contact_ratio();

    Model m(pair);
    m.E_star_MPa = hertz::contact_modulus(
      {scene.pinion_material.youngs_modulus_MPa, scene.pinion_material.poisson_ratio},
      {scene.gear_material.youngs_modulus_MPa, scene.gear_material.poisson_ratio});
    m.face_mm = b_mm;
    // Lead crowning Delta(z) = beta (2 z / b)^2 of each flank: curvature 8 beta / b^2.
    m.kappa_lead_per_mm = 8e-3 * (scene.pinion.crowning_um / std::pow(scene.pinion.face_width_mm, 2) +
                                  scene.gear.crowning_um / std::pow(scene.gear.face_width_mm, 2));
    m.n = st.hertz_exponent;

    // Structural stiffness of one pair: ISO's c' b without the line-contact Hertzian part it
    // contains (Palmgren, delta ~ F^0.9: tangent stiffness F / (0.9 delta) at the static load).
    const double c_prime_b_N_per_mm = iso.c_prime_N_per_mm_um * 1e3 * b_mm;
    const double line_tangent_N_per_mm =
      F0_N / (0.9 * hertz::line_approach_palmgren_mm(F0_N, b_mm, m.E_star_MPa));
    const double r1_compliance = 1.0 / c_prime_b_N_per_mm - 1.0 / line_tangent_N_per_mm;
    HG_REQUIRE_INPUT(r1_compliance > 0, "ISO 6336 single stiffness c' b = ", c_prime_b_N_per_mm,
                     " N/mm is stiffer than the line-contact Hertzian stiffness ",
                     line_tangent_N_per_mm,
                     " N/mm it contains: no positive structural stiffness is left (check "
                     "Operating/torque_Nm and the face widths)");
    m.k_r1_N_per_mm = 1.0 / r1_compliance;

    const int S = st.source == "iso6336" ? std::max(1, st.positions_per_cycle) : st.positions_per_cycle;
    const int H = st.harmonics;
    HG_REQUIRE_INPUT(S >= 2 * H + 1, "Stiffness/positions_per_cycle = ", S,
                     " is too few for Stiffness/harmonics = ", H, " (need at least ", 2 * H + 1, ")");
    const double si_n = std::pow(1e3, m.n); // N/mm^n -> N/m^n

    dynamics::StiffnessTable t;
    t.hertz_exponent = m.n;
    std::ostringstream csv;
    csv << std::setprecision(10);
    csv << "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,pairs_in_contact,"
           "load_share_1,load_share_2,hertz_penetration_um,contact_a_mm,contact_b_mm,"
           "peak_pressure_MPa\n";

    nlohmann::json model;
    model["iso6336_c_prime_N_per_mm_um"]           = iso.c_prime_N_per_mm_um;
    model["iso6336_c_gamma_alpha_N_per_mm_um"]     = iso.c_gamma_alpha_N_per_mm_um;
    model["line_contact_tangent_N_per_m"]          = line_tangent_N_per_mm * 1e3;
    model["pair_rest_stiffness_N_per_m"]           = m.k_r1_N_per_mm * 1e3;
    model["contact_ratio"]                         = eps;
    model["contact"]                               = m.crowned() ? "elliptical Hertz (crowned)" :
                                                                   "Palmgren line contact";
    model["lead_curvature_per_m"]                  = m.kappa_lead_per_mm * 1e3;

    if (st.source == "iso6336")
      {
        // Constant series: ISO's mesh stiffness ratio c_gamma_alpha / c' applied to the pair's
        // rest stiffness, eps_alpha pairs' worth of Hertzian stiffness at the pitch point.
        const double roll_C = pair.point('C').roll_distance_mm;
        const auto   c1     = m.contact(F0_N, roll_C);
        const double k_h1   = F0_N / std::pow(c1.approach_mm, m.n);
        const double ratio  = iso.c_gamma_alpha_N_per_mm_um / iso.c_prime_N_per_mm_um;
        t.k_rest_N_per_m        = {m.k_r1_N_per_mm * ratio * 1e3, {}, {}};
        t.k_hertz_N_per_m_pow_n = {eps * k_h1 * si_n, {}, {}};
        // STE of the series springs at F0 (pitch point, load shared as the mean stiffness says).
        const double delta_h = std::pow(F0_N / (eps * k_h1), 1.0 / m.n);
        const double ste_mm  = F0_N / (m.k_r1_N_per_mm * ratio) + delta_h;
        for (int i = 0; i < S; ++i)
          {
            t.samples.mesh_phase.push_back(double(i) / S);
            t.samples.k_total_N_per_m.push_back(F0_N / ste_mm * 1e3);
            t.samples.k_hertz_N_per_m_pow_n.push_back(t.k_hertz_N_per_m_pow_n.mean);
            t.samples.k_rest_N_per_m.push_back(t.k_rest_N_per_m.mean);
            t.samples.ste_m.push_back(ste_mm * 1e-3);
            csv << i << ',' << number(double(i) / S) << ',' << number(ste_mm * 1e3) << ','
                << number(F0_N / ste_mm * 1e3) << ',' << number(t.k_hertz_N_per_m_pow_n.mean) << ','
                << number(t.k_rest_N_per_m.mean) << ",,,," << number(delta_h * 1e3) << ','
                << number(c1.a_mm) << ',' << number(c1.b_mm) << ',' << number(c1.p0_MPa) << '\n';
          }
        t.source = "iso6336: ISO 6336-1 method B mesh stiffness, Hertz at the pitch point";
      }
    else
      {
        const bool pe = st.source == "potential-energy";
        if (pe)
          {
            // Both teeth's potential-energy compliance at the contact point at roll distance s
            // (meshing/potential_energy.h): the pinion at roll angle s / r_b1, the gear at
            // (L - s) / r_b2.
            const auto teeth = [&](const double roll_mm, const bool plane_strain) {
              const double u1 = roll_mm / pair.pinion().base_radius_mm();
              const double u2 = (pair.line_of_action_length_mm() - roll_mm) / pair.gear().base_radius_mm();
              return std::pair{meshing::tooth_compliance(pair.pinion(), u1,
                                                         scene.pinion_material.youngs_modulus_MPa,
                                                         scene.pinion_material.poisson_ratio, plane_strain),
                               meshing::tooth_compliance(pair.gear(), u2,
                                                         scene.gear_material.youngs_modulus_MPa,
                                                         scene.gear_material.poisson_ratio, plane_strain)};
            };
            const auto pair_stiffness = [](const auto &t) {
              return 1.0 / (t.first.total_mm_per_N() + t.second.total_mm_per_N());
            };
            m.yang_lin   = true;
            m.structural = [=](const double roll_mm) { return pair_stiffness(teeth(roll_mm, false)); };
            // The single pair at the pitch point, each tooth's parts [N/m].
            const double s_C   = pair.point('C').roll_distance_mm;
            const auto   pitch = teeth(s_C, false);
            const auto   parts = [](const meshing::ToothCompliance &c) {
              return nlohmann::json{{"bending_N_per_m", 1e3 / c.bending_mm_per_N},
                                    {"shear_N_per_m", 1e3 / c.shear_mm_per_N},
                                    {"axial_N_per_m", 1e3 / c.axial_mm_per_N},
                                    {"fillet_foundation_N_per_m", 1e3 / c.fillet_mm_per_N},
                                    {"load_angle_deg", c.load_angle_rad * 180 / pi}};
            };
            model["pitch_point_pinion_tooth"]            = parts(pitch.first);
            model["pitch_point_gear_tooth"]              = parts(pitch.second);
            model["pitch_point_pair_structural_N_per_m"] = pair_stiffness(pitch) * 1e3;
            model["pitch_point_pair_N_per_m"] =
              F0_N / m.pair_approach_mm(F0_N, s_C, pair_stiffness(pitch)) * 1e3;
            model["pitch_point_pair_structural_plane_strain_N_per_m"] =
              pair_stiffness(teeth(s_C, true)) * 1e3;
            model["contact"] = m.crowned() ? "elliptical Hertz (crowned)" : "Yang & Lin line contact";
          }
        std::vector<double> kh, kr, ste;
        for (int i = 0; i < S; ++i)
          {
            const double     phase = double(i) / S;
            std::vector<int> pairs = pair.pairs_in_contact(phase);
            HG_REQUIRE_INPUT(!pairs.empty(), "no tooth pair in contact at mesh phase ", phase,
                             " (contact ratio ", eps, ")");
            std::vector<double> roll, k_r;
            for (const int p : pairs)
              {
                roll.push_back(pair.contact_roll_distance_mm(p, phase));
                k_r.push_back(m.structural_N_per_mm(roll.back()));
              }
            const Sharing sh    = share_load(m, roll, k_r, F0_N);
            const double  delta = sh.approach_mm;
            double k_h = 0, k_h_tangent = 0, k_r_sum = 0, delta_h_max = 0;
            std::vector<double> share;
            PairContact         main;
            double              main_load = -1;
            for (std::size_t j = 0; j < roll.size(); ++j)
              {
                const double F = sh.loads_N[j];
                const auto   c = m.contact(F, roll[j]);
                k_h += F / std::pow(c.approach_mm, m.n);
                k_h_tangent += m.n * F / c.approach_mm;
                k_r_sum += k_r[j];
                share.push_back(F / F0_N);
                delta_h_max = std::max(delta_h_max, c.approach_mm);
                if (F > main_load)
                  main_load = F, main = c;
              }
            if (pe)
              {
                // As the FE stage: 1/k_rest = 1/k_total,tangent - 1/k_h,tangent, the tangent
                // total stiffness from +-2 % of the load (docs/theory-tca.md).
                const double eps_F     = 0.02;
                const double k_tangent = 2 * eps_F * F0_N /
                                         (share_load(m, roll, k_r, F0_N * (1 + eps_F)).approach_mm -
                                          share_load(m, roll, k_r, F0_N * (1 - eps_F)).approach_mm);
                const double rest = 1.0 / k_tangent - 1.0 / k_h_tangent;
                HG_REQUIRE_NUMERIC(rest > 0, "potential-energy stiffness at mesh phase ", phase,
                                    ": tangent total stiffness ", k_tangent,
                                    " N/mm is not below the Hertzian one ", k_h_tangent, " N/mm");
                kr.push_back(1e3 / rest);
              }
            else
              kr.push_back(k_r_sum * 1e3);
            kh.push_back(k_h * si_n);
            ste.push_back(delta * 1e-3);
            t.samples.mesh_phase.push_back(phase);
            t.samples.k_total_N_per_m.push_back(F0_N / delta * 1e3);
            t.samples.k_hertz_N_per_m_pow_n.push_back(kh.back());
            t.samples.k_rest_N_per_m.push_back(kr.back());
            t.samples.ste_m.push_back(ste.back());
            // Pair 1 is the pair that entered at phase 0 (pair index 0), pair 2 the one ahead.
            double s1 = 0, s2 = 0;
            for (std::size_t j = 0; j < pairs.size(); ++j)
              (pairs[j] == 0 ? s1 : s2) += share[j];
            csv << i << ',' << number(phase) << ',' << number(delta * 1e3) << ','
                << number(F0_N / delta * 1e3) << ',' << number(kh.back()) << ',' << number(kr.back())
                << ',' << pairs.size() << ',' << number(s1) << ',' << number(s2) << ','
                << number(delta_h_max * 1e3) << ',' << number(main.a_mm) << ','
                << number(main.b_mm) << ',' << number(main.p0_MPa) << '\n';
          }
        t.k_hertz_N_per_m_pow_n = dynamics::fit_fourier_series(kh, H);
        t.k_rest_N_per_m        = dynamics::fit_fourier_series(kr, H);
        t.source = pe ? "potential-energy: tooth bending, shear and axial compliance (Yang & Lin, "
                        "Tian), fillet foundation (Sainsot et al. 2004), Hertz contact per pair, "
                        "load sharing by compatibility" :
                        "hertz-analytic: Hertz closed forms per pair along the path of contact, "
                        "ISO 6336 structural stiffness, load sharing by compatibility";
      }
    t.check();

    AnalyticStiffness out;
    out.json = nlohmann::json::parse(dynamics::stiffness_table_to_json_text(t));
    const auto mean_of = [](const std::vector<double> &v) {
      double s = 0;
      for (const double x : v)
        s += x;
      return v.empty() ? 0.0 : s / v.size();
    };
    const auto &ks = t.samples;
    out.json["k_total_N_per_m"] = series_json(dynamics::fit_fourier_series(ks.k_total_N_per_m,
                                                                          S >= 2 * H + 1 ? H : 0));
    out.json["ste_m"] = series_json(dynamics::fit_fourier_series(ks.ste_m, S >= 2 * H + 1 ? H : 0));
    out.json["k_hertz_unit"]                 = "N/m^n";
    out.json["mean_k_total_N_per_m"]         = mean_of(ks.k_total_N_per_m);
    out.json["mean_k_hertz_N_per_m_pow_n"]   = t.k_hertz_N_per_m_pow_n.mean;
    out.json["mean_k_rest_N_per_m"]          = t.k_rest_N_per_m.mean;
    const auto [lo, hi] = std::minmax_element(ks.ste_m.begin(), ks.ste_m.end());
    out.json["ste_peak_to_peak_um"]          = (*hi - *lo) * 1e6;
    out.json["load_N"]                       = F0_N;
    out.json["harmonics"]                    = H;
    out.json["closed_form_model"]            = model;
    out.json.update(provenance(scene));
    out.csv = csv.str();
    return out;
  }
} // namespace hertzgear
