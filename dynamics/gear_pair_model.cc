#include "dynamics/gear_pair_model.h"

#include "common/errors.h"
#include "common/names.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace hertzgear::dynamics
{
  namespace
  {
    double sign(const double v) { return (v > 0.0) - (v < 0.0); }
    // a^p for a >= 0, with the exponents of line and point contact (1, 3/2 and their
    // derivatives' 0, 1/2) written out: the right-hand side evaluates them at every stage.
    double power(const double a, const double p)
    {
      if (p == 1.0)
        return a;
      if (p == 1.5)
        return a * std::sqrt(a);
      if (p == 0.5)
        return std::sqrt(a);
      if (p == 0.0)
        return 1.0;
      return std::pow(a, p);
    }
    // G(delta) = sign(delta)|delta|^n, H(delta) = |delta|^n and their derivatives.
    double G(const double d, const double n) { return sign(d) * power(std::abs(d), n); }
    double H(const double d, const double n) { return power(std::abs(d), n); }
    double G_prime(const double d, const double n)
    {
      return n == 1.0 ? 1.0 : n * power(std::abs(d), n - 1.0);
    }
    double H_prime(const double d, const double n)
    {
      return n == 1.0 ? sign(d) : n * sign(d) * power(std::abs(d), n - 1.0);
    }

    const NameTable<HertzianLayer, 3> hertzian_layer_names = {
      {"dynamic", HertzianLayer::dynamic},
      {"quasi-static", HertzianLayer::quasi_static},
      {"off", HertzianLayer::off}};
    const NameTable<ContactDamping, 3> contact_damping_names = {
      {"hunt-crossley", ContactDamping::hunt_crossley},
      {"lankarani-nikravesh", ContactDamping::lankarani_nikravesh},
      {"viscous-only", ContactDamping::viscous_only}};
  } // namespace

  std::string Effects::describe() const
  {
    std::ostringstream os;
    os << "backlash=" << (backlash ? "on" : "off")
       << " hertzian_layer=" << name_of(hertzian_layer, hertzian_layer_names)
       << " contact_damping=" << name_of(contact_damping, contact_damping_names)
       << " mesh_stiffness_variation=" << (mesh_stiffness_variation ? "fourier" : "constant")
       << " rest_stiffness_variation=" << (rest_stiffness_variation ? "fourier" : "constant")
       << " ste_excitation=" << (ste_excitation ? "table" : "off");
    return os.str();
  }

  HertzianLayer hertzian_layer_from_name(const std::string &name)
  {
    return from_name(name, hertzian_layer_names, "hertzian_layer");
  }

  ContactDamping contact_damping_from_name(const std::string &name)
  {
    return from_name(name, contact_damping_names, "contact_damping");
  }

  double equivalent_mass(const double I1, const double I2, const double rb1, const double rb2)
  {
    HG_REQUIRE_INPUT(I1 > 0.0 && I2 > 0.0 && rb1 > 0.0 && rb2 > 0.0,
                     "inertias and base radii must be positive (I1 = ", I1, " kg m^2, I2 = ", I2,
                     " kg m^2, r_b1 = ", rb1, " m, r_b2 = ", rb2, " m)");
    return I1 * I2 / (I1 * rb2 * rb2 + I2 * rb1 * rb1);
  }

  double equivalent_mesh_stiffness(const table::StiffnessTable &table, const HertzianLayer layer,
                                   const double F0)
  {
    const double k = table.k_rest_N_per_m.mean;
    const double n = table.hertz_exponent, kmh = table.k_hertz_N_per_m_pow_n.mean;
    if (layer == HertzianLayer::off || kmh <= 0.0)
      return k;
    double kh_tangent = 0.0;
    if (n == 1.0)
      kh_tangent = kmh;
    else if (F0 > 0.0)
      kh_tangent = n * kmh * std::pow(F0 / kmh, (n - 1.0) / n);
    if (kh_tangent <= 0.0)
      return k;
    return 1.0 / (1.0 / k + 1.0 / kh_tangent);
  }

  double damping_of_ratio(const GearPairParameters &p, const double zeta)
  {
    return 2.0 * zeta *
           std::sqrt(equivalent_mesh_stiffness(p.stiffness, p.effects.hertzian_layer,
                                               p.static_force_N) *
                     p.equivalent_mass_kg);
  }

  GearPairModel::GearPairModel(GearPairParameters parameters) : prm(std::move(parameters))
  {
    prm.stiffness.check();
    HG_REQUIRE_INPUT(prm.equivalent_mass_kg > 0.0, "equivalent mass must be positive, got ",
                     prm.equivalent_mass_kg, " kg");
    HG_REQUIRE_INPUT(prm.mesh_frequency_rad_per_s > 0.0, "mesh frequency must be positive");
    HG_REQUIRE_INPUT(prm.damping_N_s_per_m >= 0.0, "damping c must not be negative");
    HG_REQUIRE_INPUT(prm.half_backlash_m >= 0.0, "backlash must not be negative");
    if (prm.effects.hertzian_layer != HertzianLayer::off)
      HG_REQUIRE_INPUT(prm.stiffness.k_hertz_N_per_m_pow_n.mean > 0.0,
                       "a Hertzian layer needs k_mh > 0 ({k_hertz_mean} or the table's k_hertz_N_per_m_pow_n)");
    HG_REQUIRE_INPUT(!prm.effects.ste_excitation || prm.stiffness.has_unloaded_ste,
                     "{ste_excitation} = table needs an unloaded STE series in the stiffness "
                     "table (unloaded_ste_m)");
    // An effect that is off leaves the model: constant series instead of harmonic sums.
    if (!prm.effects.mesh_stiffness_variation)
      prm.stiffness.k_hertz_N_per_m_pow_n = prm.stiffness.k_hertz_N_per_m_pow_n.constant_part();
    if (!prm.effects.rest_stiffness_variation)
      prm.stiffness.k_rest_N_per_m = prm.stiffness.k_rest_N_per_m.constant_part();

    k_rest_series  = FourierEvaluator(prm.stiffness.k_rest_N_per_m);
    k_hertz_series = FourierEvaluator(prm.stiffness.k_hertz_N_per_m_pow_n);
    if (prm.effects.ste_excitation)
      ste_series = FourierEvaluator(prm.stiffness.unloaded_ste_m);

    n_exp           = prm.stiffness.hertz_exponent;
    cache.assign(cache_size, PhaseEntry{});
    cycles_per_s = prm.mesh_frequency_rad_per_s / (2.0 * M_PI);
    b_c             = prm.effects.backlash ? prm.half_backlash_m : 0.0;
    has_delta_state = prm.effects.hertzian_layer == HertzianLayer::dynamic && !prm.rigid_structure;
    if (prm.rigid_structure)
      HG_REQUIRE_INPUT(prm.effects.hertzian_layer == HertzianLayer::dynamic,
                       "a rigid structure needs the dynamic Hertzian layer");

    const bool nonlinear = b_c > 0.0 || prm.effects.hertzian_layer != HertzianLayer::off;
    n_root_functions     = (nonlinear ? (b_c > 0.0 ? 2 : 1) : 0) + (has_delta_state ? 1 : 0);

    const double kmh = prm.stiffness.k_hertz_N_per_m_pow_n.mean;
    switch (prm.effects.contact_damping)
      {
        case ContactDamping::hunt_crossley:
          // Until the first impact, Lankarani-Nikravesh uses the Hunt-Crossley value too.
        case ContactDamping::lankarani_nikravesh:
          mu = 1.5 * prm.alpha_s_per_m * kmh;
          break;
        case ContactDamping::viscous_only:
          mu = 0.0;
          break;
      }
    if (prm.effects.hertzian_layer == HertzianLayer::off)
      mu = 0.0;

    const double k_eq =
      equivalent_mesh_stiffness(prm.stiffness, prm.effects.hertzian_layer, prm.static_force_N);
    double scale = b_c + prm.static_force_N / k_eq;
    if (prm.effects.ste_excitation)
      scale += std::abs(prm.stiffness.unloaded_ste_m.mean) +
               prm.stiffness.unloaded_ste_m.amplitude_bound();
    // A floor for the unloaded, backlash-free case: 1 um, far below any gear tolerance.
    x_scale = std::max(scale, 1.0e-6);
  }

  double GearPairModel::mesh_period() const { return 2.0 * M_PI / prm.mesh_frequency_rad_per_s; }

  double GearPairModel::forcing_period() const
  {
    const bool varies = !(k_rest_series.constant() && k_hertz_series.constant()) ||
                        (prm.effects.ste_excitation && !ste_series.constant());
    return varies ? mesh_period() : 0.0;
  }

  int GearPairModel::zone_of(const double p) const
  {
    return b_c > 0.0 ? (p >= b_c ? 1 : (p <= -b_c ? -1 : 0)) : int(sign(p));
  }

  GearPairModel::Coefficients GearPairModel::coefficients(const double t) const
  {
    // The mesh phase in periods, frac in [0, 1), keyed by its rounding to 2^-36 (so that the
    // stage phases of a periodic motion, which differ from period to period only by the
    // rounding of t, find their entry again).
    const double   w      = prm.mesh_frequency_rad_per_s;
    const double   cycles = t * cycles_per_s;
    // floor(cycles) by truncation (one instruction; std::floor is a library call without SSE4.1).
    double whole = double(std::int64_t(cycles));
    whole        = whole > cycles ? whole - 1.0 : whole;
    const double frac = cycles - whole;
    constexpr auto one    = std::uint64_t(1) << phase_bits;
    const std::uint64_t key = std::uint64_t(frac * double(one) + 0.5) & (one - 1);
    PhaseEntry &en = cache[unsigned((key * 0x9E3779B97F4A7C15ull) >> (64 - cache_bits))];
    if (en.key != key)
      {
        en.key  = key;
        en.frac = frac;
        double c1 = 1.0, s1 = 0.0;
        if (!(k_rest_series.constant() && k_hertz_series.constant() && ste_series.constant()))
          {
            c1 = std::cos(2.0 * M_PI * frac);
            s1 = std::sin(2.0 * M_PI * frac);
          }
        k_rest_series.taylor(c1, s1, en.k);
        k_hertz_series.taylor(c1, s1, en.kh);
        if (prm.effects.ste_excitation)
          ste_series.taylor(c1, s1, en.e);
      }
    // The angle from the entry's phase (0 when this phase filled it; across 0 = 1 the short way).
    double d = frac - en.frac;
    d        = d > 0.5 ? d - 1.0 : (d < -0.5 ? d + 1.0 : d);
    const double dth = 2.0 * M_PI * d;
    Coefficients r;
    r.k       = en.k[0] + en.k[1] * dth;
    r.kh      = en.kh[0] + en.kh[1] * dth;
    r.e       = en.e[0] + en.e[1] * dth;
    r.k_rate  = w * (en.k[1] + en.k[2] * dth);
    r.kh_rate = w * (en.kh[1] + en.kh[2] * dth);
    r.e_rate  = w * (en.e[1] + en.e[2] * dth);
    return r;
  }

  double GearPairModel::excitation(const double t) const { return coefficients(t).e; }

  double GearPairModel::quasi_static_penetration(const double f, const double k,
                                                 const double kh) const
  {
    // phi(d) = k (|f| - d) - kh d^n is strictly decreasing on [0, |f|] with phi(0) >= 0 >=
    // phi(|f|): one root, bracketed. Newton steps that leave the bracket are replaced by bisection.
    const double a = std::abs(f);
    if (a == 0.0)
      return 0.0;
    if (n_exp == 1.0)
      return sign(f) * k * a / (k + kh);
    double lo = 0.0, hi = a;
    double d  = std::min(a, std::pow(k * a / kh, 1.0 / n_exp));
    for (int it = 0; it < 100; ++it)
      {
        const double phi = k * (a - d) - kh * std::pow(d, n_exp);
        if (phi > 0.0)
          lo = d;
        else
          hi = d;
        const double dphi = -k - kh * n_exp * std::pow(d, n_exp - 1.0);
        double       next = d - phi / dphi;
        if (!(next > lo && next < hi))
          next = 0.5 * (lo + hi);
        if (std::abs(next - d) <= 1.0e-15 * a)
          {
            d = next;
            break;
          }
        d = next;
      }
    return sign(f) * d;
  }

  GearPairModel::Forces GearPairModel::evaluate(const double t, const double *y) const
  {
    return evaluate(coefficients(t), y);
  }

  GearPairModel::Forces GearPairModel::evaluate(const Coefficients &co, const double *y) const
  {
    Forces       r;
    const double p     = y[0] - co.e;
    const double p_dot = y[1] - co.e_rate;
    r.zone = zone_of(p);
    if (r.zone != 0 || b_c == 0.0)
      {
        r.f     = p - r.zone * b_c;
        r.f_dot = p_dot;
      }
    const double k = co.k, c = prm.damping_N_s_per_m;

    switch (prm.effects.hertzian_layer)
      {
        case HertzianLayer::off:
          {
            // Kahraman-Singh: the viscous part is kept, F may turn negative in contact.
            r.force        = k * r.f + c * r.f_dot;
            r.u_dot        = r.f_dot;
            r.layer_closed = r.zone != 0;
            break;
          }
        case HertzianLayer::quasi_static:
          {
            const double kh = co.kh;
            const double d  = quasi_static_penetration(r.f, k, kh);
            const double d_dot =
              (k * r.f_dot + co.k_rate * (r.f - d) - co.kh_rate * G(d, n_exp)) /
              (k + kh * G_prime(d, n_exp));
            r.penetration  = d;
            r.delta_dot    = d_dot;
            r.u_dot        = r.f_dot - d_dot;
            r.layer_closed = r.zone != 0;
            // The viscous part is kept when it makes F pull (Kahraman-Singh convention).
            r.force = r.layer_closed ? k * (r.f - d) + c * r.u_dot : 0.0;
            break;
          }
        case HertzianLayer::dynamic:
          {
            const double kh = co.kh;
            if (prm.rigid_structure)
              {
                r.penetration  = r.f;
                r.delta_dot    = r.f_dot;
                r.layer_closed = r.zone != 0;
                r.force        = kh * G(r.f, n_exp) + mu * H(r.f, n_exp) * r.f_dot;
                break;
              }
            const double d = y[2];
            r.penetration  = d;
            r.layer_closed = r.zone != 0 && d * r.zone > 0.0;
            if (r.layer_closed)
              {
                const double Hd = H(d, n_exp), Gd = sign(d) * Hd;
                const double D  = c + mu * Hd;
                const double N  = k * (r.f - d) + c * r.f_dot - kh * Gd;
                r.delta_dot     = D > 0.0 ? N / D : 0.0;
                // The layer opens when delta returns to 0 (an event). Before that, in a rebound
                // faster than 1/(1.5 alpha), the Hunt-Crossley term may make F pull briefly: it is
                // kept (Kahraman-Singh convention), which keeps the vector field continuous.
                r.force = kh * Gd + mu * Hd * r.delta_dot;
              }
            if (!r.layer_closed)
              {
                // Open layer: the massless interface follows c (f' - delta') + k (f - delta) = 0.
                r.delta_dot = c > 0.0 ? r.f_dot + k * (r.f - d) / c : 0.0;
                r.force     = 0.0;
              }
            r.u_dot = r.f_dot - r.delta_dot;
            break;
          }
      }
    return r;
  }

  void GearPairModel::rhs(const double t, const double *y, double *y_dot)
  {
    derivative(evaluate(t, y), y, y_dot);
  }

  void GearPairModel::derivative(const Forces &r, const double *y, double *y_dot) const
  {
    y_dot[0] = y[1];
    y_dot[1] = (prm.static_force_N - r.force) / prm.equivalent_mass_kg;
    if (has_delta_state)
      y_dot[2] = r.delta_dot;
  }

  bool GearPairModel::has_jacobian() const
  {
    return prm.effects.hertzian_layer != HertzianLayer::quasi_static;
  }

  void GearPairModel::jacobian(const double t, const double *y, double *J) const
  {
    const Coefficients co = coefficients(t);
    jacobian(co, evaluate(co, y), y, J);
  }

  void GearPairModel::rhs_and_jacobian(const double t, const double *y, double *y_dot, double *J)
  {
    const Coefficients co = coefficients(t);
    const Forces       r  = evaluate(co, y);
    derivative(r, y, y_dot);
    jacobian(co, r, y, J);
  }

  void GearPairModel::jacobian(const Coefficients &co, const Forces &r, const double *y,
                               double *J) const
  {
    const unsigned     n  = n_states();
    std::fill(J, J + n * n, 0.0);
    const double s = (r.zone != 0 || b_c == 0.0) ? 1.0 : 0.0; // df/dx = df'/dx'
    const double k = co.k, c = prm.damping_N_s_per_m, m = prm.equivalent_mass_kg;
    double       dF_dx = 0.0, dF_dv = 0.0, dF_dd = 0.0;
    J[0 * n + 1] = 1.0;
    if (prm.effects.hertzian_layer == HertzianLayer::off)
      {
        dF_dx = k * s;
        dF_dv = c * s;
      }
    else if (prm.rigid_structure)
      {
        if (r.layer_closed)
          {
            const double kh = co.kh;
            dF_dx = s * (kh * G_prime(r.f, n_exp) + mu * H_prime(r.f, n_exp) * r.f_dot);
            dF_dv = s * mu * H(r.f, n_exp);
          }
      }
    else
      {
        const double d = y[2];
        if (r.layer_closed)
          {
            const double kh    = co.kh;
            const double D     = c + mu * H(d, n_exp);
            const double dN_dd = -k - kh * G_prime(d, n_exp);
            const double ddot_dx = k * s / D, ddot_dv = c * s / D;
            const double ddot_dd = (dN_dd - r.delta_dot * mu * H_prime(d, n_exp)) / D;
            J[2 * n + 0]        = ddot_dx;
            J[2 * n + 1]        = ddot_dv;
            J[2 * n + 2]        = ddot_dd;
            dF_dx               = k * s - c * ddot_dx;
            dF_dv               = c * s - c * ddot_dv;
            dF_dd               = -k - c * ddot_dd;
          }
        else if (c > 0.0)
          {
            J[2 * n + 0] = k * s / c;
            J[2 * n + 1] = s;
            J[2 * n + 2] = -k / c;
          }
      }
    J[1 * n + 0] = -dF_dx / m;
    J[1 * n + 1] = -dF_dv / m;
    if (has_delta_state)
      J[1 * n + 2] = -dF_dd / m;
  }

  void GearPairModel::roots(const double t, const double *y, double *g) const
  {
    const double p = y[0] - excitation(t);
    unsigned     i = 0;
    if (b_c > 0.0)
      {
        g[i++] = p - b_c;
        g[i++] = p + b_c;
      }
    else if (n_root_functions > (has_delta_state ? 1u : 0u))
      g[i++] = p;
    if (has_delta_state)
      {
        // The layer's own transition (it opens when delta returns to 0 in a rebound, closes when
        // delta leaves 0 in a contact zone) matters only inside a contact zone. In the backlash
        // the open layer relaxes to delta = 0 with the time constant c/k, and its rounding-level
        // sign changes are no events: there the function is |p| - b_c < 0 instead, which meets
        // delta (~0 after the relaxation) continuously at the zone boundary.
        const int zone = zone_of(p);
        g[i++]         = zone != 0 ? zone * y[2] : std::abs(p) - b_c;
      }
  }

  bool GearPairModel::handle_event(const double t, double *y, const int *directions)
  {
    if (prm.effects.contact_damping != ContactDamping::lankarani_nikravesh ||
        prm.effects.hertzian_layer != HertzianLayer::dynamic)
      return false;
    // Lankarani-Nikravesh: mu = 3 k_mh (1 - e^2) / (4 v_i) with the approach speed of this impact.
    const Forces r       = evaluate(t, y);
    bool         closing = false;
    for (unsigned i = 0; i < n_root_functions; ++i)
      closing = closing || directions[i] != 0;
    if (closing && r.zone != 0)
      {
        // Grazing contacts have no impact speed; a floor of 1e-3 omega_m x_scale keeps mu finite.
        const double v_i = std::max(std::abs(r.f_dot),
                                    1.0e-3 * prm.mesh_frequency_rad_per_s * x_scale);
        const double e   = prm.restitution_coefficient;
        mu = 3.0 * prm.stiffness.k_hertz_N_per_m_pow_n.mean * (1.0 - e * e) / (4.0 * v_i);
      }
    return false;
  }

  void GearPairModel::residual(const double t, const double *y, const double *y_dot, double *res)
  {
    if (!has_delta_state)
      {
        OdeSystem::residual(t, y, y_dot, res);
        return;
      }
    // (c + mu H(delta)) delta' = k (f - delta) + c f' - k_h G(delta) in contact, which is
    // algebraic where c + mu H vanishes (c = 0 at delta = 0); c (f' - delta') + k (f - delta) = 0
    // with the layer open.
    const Forces r = evaluate(t, y);
    const double k = k_rest(t), c = prm.damping_N_s_per_m, d = y[2];
    const bool   closed = prm.damping_N_s_per_m > 0.0 ? r.layer_closed :
                                                        (r.zone != 0 && d * r.zone >= 0.0);
    double F = k * (r.f - d) + c * (r.f_dot - y_dot[2]);
    if (closed)
      res[2] = (c + mu * H(d, n_exp)) * y_dot[2] -
               (k * (r.f - d) + c * r.f_dot - k_hertz(t) * G(d, n_exp));
    else
      {
        res[2] = c * (y_dot[2] - r.f_dot) - k * (r.f - d);
        F      = 0.0;
      }
    res[0] = y_dot[0] - y[1];
    res[1] = y_dot[1] - (prm.static_force_N - F) / prm.equivalent_mass_kg;
  }

  std::vector<double> GearPairModel::differential_components() const
  {
    std::vector<double> id(n_states(), 1.0);
    if (has_delta_state && prm.damping_N_s_per_m == 0.0 && mu == 0.0)
      id[2] = 0.0;
    return id;
  }

  void GearPairModel::consistent_initial_derivative(const double t, double *y, double *y_dot)
  {
    if (has_delta_state && prm.damping_N_s_per_m == 0.0)
      {
        // Without c the structural spring is in static balance with the layer whenever
        // c + mu H(delta) vanishes: put delta on that balance.
        const Forces r = evaluate(t, y);
        if (mu * H(y[2], n_exp) == 0.0 || r.zone == 0)
          y[2] = quasi_static_penetration(r.f, k_rest(t), k_hertz(t));
      }
    rhs(t, y, y_dot);
    if (has_delta_state && prm.damping_N_s_per_m == 0.0)
      {
        // rhs() took F from the layer; with c = 0 it is k (f - delta), equal when consistent.
        const Forces r = evaluate(t, y);
        y_dot[1] = (prm.static_force_N - k_rest(t) * (r.f - y[2]) * (r.zone != 0 ? 1.0 : 0.0)) /
                   prm.equivalent_mass_kg;
      }
  }

  std::vector<double> GearPairModel::absolute_tolerances(const double atol) const
  {
    std::vector<double> a(n_states(), atol);
    a[1] = atol * prm.mesh_frequency_rad_per_s;
    return a;
  }

  std::string GearPairModel::describe_state(const double *y) const
  {
    std::ostringstream os;
    os.precision(6);
    os << "x = " << y[0] * 1e6 << " um, x' = " << y[1] << " m/s";
    if (has_delta_state)
      os << ", delta = " << y[2] * 1e6 << " um";
    return os.str();
  }

  std::vector<double> GearPairModel::state_scales() const
  {
    const double k_max = prm.stiffness.k_rest_N_per_m.mean + prm.stiffness.k_rest_N_per_m.amplitude_bound();
    const double omega = std::sqrt(k_max / prm.equivalent_mass_kg) + prm.mesh_frequency_rad_per_s;
    std::vector<double> s(n_states(), x_scale);
    s[1] = x_scale * omega;
    return s;
  }

  std::vector<double> GearPairModel::blow_up_bounds() const
  {
    // 10^4 times the state's scale is far outside any physical response of the pair: a blow-up.
    std::vector<double> b = state_scales();
    for (double &v : b)
      v *= 1.0e4;
    return b;
  }

  MeshState GearPairModel::mesh_state(const double t, const double *y) const
  {
    const Forces r = evaluate(t, y);
    MeshState    s;
    s.dte_m            = y[0];
    s.dte_rate_m_per_s = y[1];
    s.penetration_m    = r.penetration;
    s.force_N          = r.force;
    s.contact          = r.layer_closed ? r.zone : 0;
    const double k = k_rest(t), c = prm.damping_N_s_per_m;
    const double layer_closed = r.layer_closed ? 1.0 : 0.0;
    switch (prm.effects.hertzian_layer)
      {
        case HertzianLayer::off:
          s.elastic_energy_J = 0.5 * k * r.f * r.f;
          s.dissipation_W    = c * r.f_dot * r.f_dot;
          break;
        case HertzianLayer::quasi_static:
        case HertzianLayer::dynamic:
          {
            const double kh = k_hertz(t), d = r.penetration;
            const double u  = prm.rigid_structure ? 0.0 : r.f - d;
            s.elastic_energy_J = 0.5 * k * u * u +
                                 layer_closed * kh * H(d, n_exp) * std::abs(d) / (n_exp + 1.0);
            s.dissipation_W = (prm.rigid_structure ? 0.0 : c * r.u_dot * r.u_dot) +
                              layer_closed * mu * H(d, n_exp) * r.delta_dot * r.delta_dot;
            break;
          }
      }
    return s;
  }

  std::vector<double> GearPairModel::state(const double x, const double x_dot,
                                           const double delta) const
  {
    std::vector<double> y{x, x_dot};
    if (has_delta_state)
      y.push_back(delta);
    return y;
  }

  std::vector<double> GearPairModel::static_equilibrium_state() const
  {
    const double F0 = prm.static_force_N;
    const double e0 = excitation(0.0);
    if (F0 <= 0.0)
      return state(e0, 0.0, 0.0);
    const double k = prm.stiffness.k_rest_N_per_m.mean;
    double       delta = 0.0, f = F0 / k;
    if (prm.effects.hertzian_layer != HertzianLayer::off)
      {
        delta = std::pow(F0 / prm.stiffness.k_hertz_N_per_m_pow_n.mean, 1.0 / n_exp);
        f     = prm.rigid_structure ? delta : delta + F0 / k;
      }
    return state(e0 + b_c + f, 0.0, delta);
  }
} // namespace hertzgear::dynamics
