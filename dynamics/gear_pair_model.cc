#include "dynamics/gear_pair_model.h"

#include "common/errors.h"
#include "common/names.h"

#include <algorithm>
#include <array>
#include <memory>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace hertzgear::dynamics
{
  namespace
  {
    double sign(const double v) { return (v > 0.0) - (v < 0.0); }

    const NameTable<HertzianLayer, 3> hertzian_layer_names = {
      {"dynamic", HertzianLayer::dynamic},
      {"quasi-static", HertzianLayer::quasi_static},
      {"off", HertzianLayer::off}};
    const NameTable<ContactDamping, 3> contact_damping_names = {
      {"hunt-crossley", ContactDamping::hunt_crossley},
      {"lankarani-nikravesh", ContactDamping::lankarani_nikravesh},
      {"viscous-only", ContactDamping::viscous_only}};
    const NameTable<MeshForceLawKind, 2> mesh_force_law_names = {
      {"serial-hertz", MeshForceLawKind::serial_hertz}, {"fe-map", MeshForceLawKind::fe_map}};
    // The phase coefficients of one law on one thread, by the models' phase key.
    struct LawPhaseStore
    {
      std::uint64_t                    law = 0; // the law's id; 0: unused
      std::unique_ptr<std::uint64_t[]> keys;
      std::unique_ptr<double[]>        frac;
      std::unique_ptr<double[]>        taylor; // unset until a phase fills its entry
    };

    // The store of `law` on this thread: the last few laws' stores are kept, most recently used
    // first (a comparison of laws alternates between two; a family shares one), so that the
    // models of a family, built at every speed or corrector step, find the phases their
    // predecessors filled. Entries hold the law's triples per phase only, so they serve every
    // model of the law.
    LawPhaseStore &law_phase_store(const MeshForceLaw &law, const unsigned per_entry,
                                   const std::size_t n)
    {
      constexpr std::size_t                        n_stores = 4;
      thread_local std::array<LawPhaseStore, n_stores> stores;
      if (stores[0].law == law.id())
        return stores[0];
      std::size_t i = 1;
      while (i < n_stores && stores[i].law != law.id())
        ++i;
      if (i == n_stores)
        {
          i                  = n_stores - 1;
          LawPhaseStore &s   = stores[i];
          s.law              = law.id();
          s.keys.reset(new std::uint64_t[n]);
          std::fill(s.keys.get(), s.keys.get() + n, ~std::uint64_t(0));
          s.frac.reset(new double[n]);
          s.taylor.reset(new double[std::size_t(n) * std::max(per_entry, 1u)]);
        }
      std::rotate(stores.begin(), stores.begin() + i, stores.begin() + i + 1);
      return stores[0];
    }
  } // namespace

  std::string Effects::describe() const
  {
    std::ostringstream os;
    os << "mesh_force_law=" << name_of(mesh_force_law, mesh_force_law_names)
       << " backlash=" << (backlash ? "on" : "off")
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

  MeshForceLawKind mesh_force_law_from_name(const std::string &name)
  {
    return from_name(name, mesh_force_law_names, "mesh_force_law");
  }

  std::string mesh_force_law_name(const MeshForceLawKind kind)
  {
    return name_of(kind, mesh_force_law_names);
  }

  std::shared_ptr<const MeshForceLaw> make_mesh_force_law(const GearPairParameters &p)
  {
    auto table = p.stiffness;
    if (!p.effects.mesh_stiffness_variation)
      table.k_hertz_N_per_m_pow_n = table.k_hertz_N_per_m_pow_n.constant_part();
    if (!p.effects.rest_stiffness_variation)
      table.k_rest_N_per_m = table.k_rest_N_per_m.constant_part();
    if (p.effects.mesh_force_law == MeshForceLawKind::fe_map)
      {
        // The ladder holds the two members apart: the law has no form without the layer.
        HG_REQUIRE_INPUT(p.effects.hertzian_layer != HertzianLayer::off && !p.rigid_structure,
                         "{mesh_force_law} = fe-map is the structural member in series with the "
                         "Hertzian layer: it needs {hertzian_layer} = dynamic or quasi-static");
        return fe_map_law(table, p.effects.rest_stiffness_variation,
                          p.effects.mesh_stiffness_variation);
      }
    return serial_hertz_law(table);
  }

  GearPairParameters with_shared_mesh_force_law(GearPairParameters p)
  {
    if (!p.shared_mesh_force_law)
      p.shared_mesh_force_law = make_mesh_force_law(p);
    return p;
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

    law = prm.shared_mesh_force_law ? prm.shared_mesh_force_law : make_mesh_force_law(prm);
    n_law_taylor = 3 * law->n_phase_coefficients();
    if (prm.effects.ste_excitation)
      ste_series = FourierEvaluator(prm.stiffness.unloaded_ste_m);
    phase_varies = law->varies_with_phase() || !ste_series.constant();

    store = PhaseStore(prm.effects.ste_excitation);
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

  double GearPairModel::forcing_period() const { return phase_varies ? mesh_period() : 0.0; }

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
    const unsigned slot = unsigned((key * 0x9E3779B97F4A7C15ull) >> (64 - cache_bits));
    LawPhaseStore &ls   = law_phase_store(*law, n_law_taylor, cache_size);
    double        *lt   = ls.taylor.get() + std::size_t(slot) * n_law_taylor;
    double         c1 = 1.0, s1 = 0.0;
    bool           have_angle = false;
    const auto     angle = [&] {
      if (phase_varies && !have_angle)
        {
          c1 = std::cos(2.0 * M_PI * frac);
          s1 = std::sin(2.0 * M_PI * frac);
        }
      have_angle = true;
    };
    if (ls.keys[slot] != key)
      {
        ls.keys[slot] = key;
        ls.frac[slot] = frac;
        angle();
        law->phase_coefficients(2.0 * M_PI * frac, c1, s1, lt);
      }
    Coefficients r;
    // The angle from the entry's phase (0 when this phase filled it; across 0 = 1 the short way).
    const auto angle_from = [&](const double entry_frac) {
      double d = frac - entry_frac;
      d        = d > 0.5 ? d - 1.0 : (d < -0.5 ? d + 1.0 : d);
      return 2.0 * M_PI * d;
    };
    r.law = MeshPhase{lt, angle_from(ls.frac[slot]), w};
    if (prm.effects.ste_excitation)
      {
        PhaseEntry &en = store.entries[slot];
        if (en.key != key)
          {
            en.key  = key;
            en.frac = frac;
            angle();
            ste_series.taylor(c1, s1, en.e);
          }
        const double dth = angle_from(en.frac);
        r.e              = en.e[0] + en.e[1] * dth;
        r.e_rate         = w * (en.e[1] + en.e[2] * dth);
      }
    return r;
  }

  double GearPairModel::excitation(const double t) const { return coefficients(t).e; }

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
    const double c = prm.damping_N_s_per_m;
    MeshLawForces &L = r.law;

    switch (prm.effects.hertzian_layer)
      {
        case HertzianLayer::off:
          {
            // Kahraman-Singh: the viscous part is kept, F may turn negative in contact.
            law->forces(co.law, r.f, 0.0, L, false);
            r.force        = L.structural + c * r.f_dot;
            r.u_dot        = r.f_dot;
            r.layer_closed = r.zone != 0;
            break;
          }
        case HertzianLayer::quasi_static:
          {
            const double d = law->quasi_static_penetration(co.law, r.f);
            law->evaluate(co.law, r.f - d, d, L);
            const double d_dot = (L.structural_du * r.f_dot + L.structural_dt - L.hertz_dt) /
                                 (L.structural_du + L.hertz_ddelta);
            r.penetration  = d;
            r.delta_dot    = d_dot;
            r.u_dot        = r.f_dot - d_dot;
            r.layer_closed = r.zone != 0;
            // The viscous part is kept when it makes F pull (Kahraman-Singh convention).
            r.force = r.layer_closed ? L.structural + c * r.u_dot : 0.0;
            break;
          }
        case HertzianLayer::dynamic:
          {
            if (prm.rigid_structure)
              {
                law->forces(co.law, 0.0, r.f, L, false);
                r.penetration  = r.f;
                r.delta_dot    = r.f_dot;
                r.layer_closed = r.zone != 0;
                r.force        = L.hertz + mu * L.damping_weight * r.f_dot;
                break;
              }
            const double d = y[2];
            law->forces(co.law, r.f - d, d, L, false);
            r.penetration  = d;
            r.layer_closed = r.zone != 0 && d * r.zone > 0.0;
            if (r.layer_closed)
              {
                const double D = c + mu * L.damping_weight;
                const double N = L.structural + c * r.f_dot - L.hertz;
                r.delta_dot    = D > 0.0 ? N / D : 0.0;
                // The layer opens when delta returns to 0 (an event). Before that, in a rebound
                // faster than 1/(1.5 alpha), the Hunt-Crossley term may make F pull briefly: it is
                // kept (Kahraman-Singh convention), which keeps the vector field continuous.
                r.force = L.hertz + mu * L.damping_weight * r.delta_dot;
              }
            if (!r.layer_closed)
              {
                // Open layer: the massless interface follows c (f' - delta') + k (f - delta) = 0.
                r.delta_dot = c > 0.0 ? r.f_dot + L.structural / c : 0.0;
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
    jacobian(evaluate(t, y), J);
  }

  void GearPairModel::rhs_and_jacobian(const double t, const double *y, double *y_dot, double *J)
  {
    const Forces r = evaluate(t, y);
    derivative(r, y, y_dot);
    jacobian(r, J);
  }

  void GearPairModel::jacobian(const Forces &r, double *J) const
  {
    const unsigned     n  = n_states();
    std::fill(J, J + n * n, 0.0);
    const double s = (r.zone != 0 || b_c == 0.0) ? 1.0 : 0.0; // df/dx = df'/dx'
    const MeshLawForces &L = r.law;
    const double k = L.structural_du, c = prm.damping_N_s_per_m, m = prm.equivalent_mass_kg;
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
            dF_dx = s * (L.hertz_ddelta + mu * L.damping_weight_slope * r.f_dot);
            dF_dv = s * mu * L.damping_weight;
          }
      }
    else
      {
        if (r.layer_closed)
          {
            const double D     = c + mu * L.damping_weight;
            const double dN_dd = -k - L.hertz_ddelta;
            const double ddot_dx = k * s / D, ddot_dv = c * s / D;
            const double ddot_dd = (dN_dd - r.delta_dot * mu * L.damping_weight_slope) / D;
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

  bool GearPairModel::root_seam(const double t, const double *y, const unsigned r) const
  {
    // The layer's root (the last) is zone * delta inside a contact zone and |p| - b_c outside:
    // where the teeth leave contact with the layer still compressed it jumps from delta > 0 to
    // 0- on the zone's surface, whose own root is the switching there; a second event there is
    // that seam (located a rounding apart, on either side). The layer's own switchings -- delta
    // through 0 inside a zone, and its closing as a contact begins with the layer relaxed -- take
    // place with delta at 0, and stay events.
    if (!has_delta_state || r + 1 != n_root_functions || b_c <= 0.0)
      return false;
    const double p         = y[0] - excitation(t);
    const double on_zone   = std::abs(std::abs(p) - b_c);
    const double delta_tol = 1e-6 * x_scale;
    return on_zone <= 1e-9 * x_scale && std::abs(y[2]) > delta_tol;
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
    const Forces         r = evaluate(t, y);
    const MeshLawForces &L = r.law; // at u = f - delta, delta = y[2]
    const double         c = prm.damping_N_s_per_m, d = y[2];
    const bool   closed = prm.damping_N_s_per_m > 0.0 ? r.layer_closed :
                                                        (r.zone != 0 && d * r.zone >= 0.0);
    double F = L.structural + c * (r.f_dot - y_dot[2]);
    if (closed)
      res[2] = (c + mu * L.damping_weight) * y_dot[2] - (L.structural + c * r.f_dot - L.hertz);
    else
      {
        res[2] = c * (y_dot[2] - r.f_dot) - L.structural;
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
        if (mu * r.law.damping_weight == 0.0 || r.zone == 0)
          y[2] = law->quasi_static_penetration(coefficients(t).law, r.f);
      }
    rhs(t, y, y_dot);
    if (has_delta_state && prm.damping_N_s_per_m == 0.0)
      {
        // rhs() took F from the layer; with c = 0 it is k (f - delta), equal when consistent.
        const Forces r = evaluate(t, y);
        y_dot[1] = (prm.static_force_N - r.law.structural * (r.zone != 0 ? 1.0 : 0.0)) /
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
    const double k_max = law->structural_stiffness_bound();
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

  MeshState GearPairModel::mesh_state(const double t, const double *y, const bool with_energy) const
  {
    const Forces r = evaluate(t, y);
    MeshState    s;
    s.dte_m            = y[0];
    s.dte_rate_m_per_s = y[1];
    s.penetration_m    = r.penetration;
    s.force_N          = r.force;
    s.contact          = r.layer_closed ? r.zone : 0;
    if (!with_energy)
      return s;
    const MeshPhase phase = coefficients(t).law;
    const double    c     = prm.damping_N_s_per_m;
    const double layer_closed = r.layer_closed ? 1.0 : 0.0;
    switch (prm.effects.hertzian_layer)
      {
        case HertzianLayer::off:
          s.elastic_energy_J = law->elastic_energy(phase, r.f, 0.0).structural;
          s.dissipation_W    = c * r.f_dot * r.f_dot;
          break;
        case HertzianLayer::quasi_static:
        case HertzianLayer::dynamic:
          {
            const double d = r.penetration;
            const double u = prm.rigid_structure ? 0.0 : r.f - d;
            const MeshLawEnergy energy = law->elastic_energy(phase, u, d);
            s.elastic_energy_J = energy.structural + layer_closed * energy.hertz;
            s.dissipation_W = (prm.rigid_structure ? 0.0 : c * r.u_dot * r.u_dot) +
                              layer_closed * mu * r.law.damping_weight * r.delta_dot * r.delta_dot;
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
    double u = 0.0, delta_layer = 0.0;
    law->static_compressions(F0, u, delta_layer);
    double delta = 0.0, f = u;
    if (prm.effects.hertzian_layer != HertzianLayer::off)
      {
        delta = delta_layer;
        f     = prm.rigid_structure ? delta : delta + u;
      }
    return state(e0 + b_c + f, 0.0, delta);
  }
} // namespace hertzgear::dynamics
