#pragma once
// The gear-pair model along the line of action (docs/dynamics.md), assembled from only the effects
// a scene asks for:
//   m_e x'' = F_0 - F,  F the mesh force through the structural spring K_r and damper c in series
//   with the Hertzian layer K_h(delta) + mu H(delta) delta'.
// The two springs are the mesh force law (dynamics/mesh_force_law.h; the paper's K_r = k(t) u,
// K_h = k_h(t) G(delta)); the model owns the rest of the equations.
// State (x, x') without a dynamic Hertzian layer, (x, x', delta) with one. SI units throughout.
#include "dynamics/mesh_force_law.h"
#include "dynamics/ode_system.h"
#include "table/stiffness_table.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  enum class HertzianLayer
  {
    dynamic,
    quasi_static,
    off
  };

  enum class ContactDamping
  {
    hunt_crossley,
    lankarani_nikravesh,
    viscous_only
  };

  // Which law gives the forces of the mesh's two springs (dynamics/mesh_force_law.h).
  enum class MeshForceLawKind
  {
    serial_hertz, // the paper's: k(t) u in series with k_h(t) G(delta)
    fe_map        // the FE load ladder of the stiffness table
  };

  struct Effects
  {
    MeshForceLawKind mesh_force_law         = MeshForceLawKind::serial_hertz;
    bool           backlash                 = true;
    HertzianLayer  hertzian_layer           = HertzianLayer::dynamic;
    ContactDamping contact_damping          = ContactDamping::hunt_crossley;
    bool           mesh_stiffness_variation = true;  // k_h(t) Fourier, else its mean
    bool           rest_stiffness_variation = false; // k(t) Fourier, else its mean
    bool           ste_excitation           = false; // unloaded STE e(t) from the table

    // "backlash=on hertzian_layer=dynamic ..." (the scene's words).
    std::string describe() const;
  };

  HertzianLayer  hertzian_layer_from_name(const std::string &name);
  ContactDamping contact_damping_from_name(const std::string &name);
  MeshForceLawKind mesh_force_law_from_name(const std::string &name);
  std::string      mesh_force_law_name(MeshForceLawKind kind);

  struct GearPairParameters
  {
    double         equivalent_mass_kg         = 0.0;
    double         static_force_N             = 0.0; // F_0 = T_1 / r_b1
    double         half_backlash_m            = 0.0; // b_c
    double         mesh_frequency_rad_per_s   = 0.0; // omega_m
    double         damping_N_s_per_m          = 0.0; // c of the structural mesh spring
    double         alpha_s_per_m              = 0.26; // Hunt-Crossley
    double         restitution_coefficient    = 0.9; // Lankarani-Nikravesh
    table::StiffnessTable stiffness;
    Effects        effects;
    // The force law of `stiffness` and `effects`, when already built: the models of one family
    // (the points of a sweep, the steps of a continuation), which differ in speed, load or
    // damping only, share it, since the FE law checks its interpolants when it is built.
    // Empty: the model builds it. with_shared_mesh_force_law() fills it.
    std::shared_ptr<const MeshForceLaw> shared_mesh_force_law;
    // Library option, not a scene effect: k -> infinity, i.e. the Hertzian layer alone
    // (delta = f(x), state (x, x')). Used to check a contact law in isolation.
    bool rigid_structure = false;
  };

  // The mesh force law of the parameters' stiffness table and effects (Effects::mesh_force_law;
  // a spring whose variation effect is off at its mean over the cycle). Throws InputError when
  // the table cannot serve the law.
  std::shared_ptr<const MeshForceLaw> make_mesh_force_law(const GearPairParameters &parameters);
  // The parameters with their force law built, for a family of models that share it.
  GearPairParameters with_shared_mesh_force_law(GearPairParameters parameters);

  // Equivalent mass along the line of action, m_e = I1 I2 / (I1 r_b2^2 + I2 r_b1^2).
  double equivalent_mass(double pinion_inertia_kg_m2, double gear_inertia_kg_m2,
                         double pinion_base_radius_m, double gear_base_radius_m);

  // Linearised mesh stiffness at the static load: k in series with the tangent Hertzian stiffness
  // n k_mh delta_s^(n-1), k_mh delta_s^n = F_0. Used for c = 2 zeta sqrt(k_eq m_e). With no load
  // and n > 1 the tangent Hertzian stiffness vanishes; then k alone is used.
  double equivalent_mesh_stiffness(const table::StiffnessTable &table, HertzianLayer layer,
                                   double static_force_N);

  // The mesh damping of a damping ratio zeta, c = 2 zeta sqrt(k_eq m_e), with k_eq the
  // equivalent mesh stiffness of `parameters` at their static force.
  double damping_of_ratio(const GearPairParameters &parameters, double damping_ratio);

  // Where the mesh is at one instant: all the derived quantities the analysis writes.
  struct MeshState
  {
    double dte_m         = 0.0; // x
    double dte_rate_m_per_s = 0.0;
    double penetration_m = 0.0; // delta (dynamic or quasi-static layer), f(x) when rigid, else 0
    double force_N       = 0.0; // F
    int    contact       = 0;   // 1 forward, 0 no force-carrying contact, -1 back side
    double dissipation_W = 0.0; // c u'^2 + mu H(delta) delta'^2 (>= 0); with_energy only
    double elastic_energy_J = 0.0; // k u^2 / 2 + k_h |delta|^(n+1) / (n+1) (serial law); with_energy only
  };

  class GearPairModel : public OdeSystem
  {
  public:
    explicit GearPairModel(GearPairParameters parameters);

    const GearPairParameters &parameters() const { return prm; }
    // The force law of the mesh's two springs (Effects::mesh_force_law).
    const MeshForceLaw &mesh_force_law() const { return *law; }

    unsigned n_states() const override { return has_delta_state ? 3 : 2; }
    void     rhs(double t, const double *y, double *y_dot) override;
    bool     has_jacobian() const override;
    void     jacobian(double t, const double *y, double *jac) const override;
    void     rhs_and_jacobian(double t, const double *y, double *y_dot, double *jac) override;
    // The mesh period when a stiffness or the STE varies in time, else 0 (autonomous).
    double   forcing_period() const override;
    unsigned n_roots() const override { return n_root_functions; }
    void     roots(double t, const double *y, double *g) const override;
    bool     handle_event(double t, double *y, const int *directions) override;
    bool     root_seam(double t, const double *y, unsigned r) const override;
    void     residual(double t, const double *y, const double *y_dot, double *r) override;
    std::vector<double> differential_components() const override;
    void consistent_initial_derivative(double t, double *y, double *y_dot) override;
    std::vector<double> absolute_tolerances(double displacement_tolerance) const override;
    std::string         describe_state(const double *y) const override;
    std::vector<double> blow_up_bounds() const override;
    // A characteristic size per state component: the characteristic displacement for x and
    // delta, and that times the highest natural frequency plus the mesh frequency for x'.
    std::vector<double> state_scales() const;

    // The energies (elastic_energy_J, dissipation_W) only when asked: an FE force law integrates
    // its energy numerically, far dearer than the forces the samples need.
    MeshState mesh_state(double t, const double *y, bool with_energy = false) const;

    // Static equilibrium under F_0 with the mean stiffness (forward contact; the middle of the
    // backlash when F_0 = 0).
    std::vector<double> static_equilibrium_state() const;
    // A state from x, x' and delta (delta ignored without a dynamic layer).
    std::vector<double> state(double x_m, double x_dot_m_per_s, double delta_m) const;

    // Mesh period 2 pi / omega_m [s].
    double mesh_period() const;
    // Unloaded STE excitation e(t) and its rate (0 when the effect is off).
    double excitation(double t) const;
    // Characteristic displacement b_c + F_0/k + |e| used for tolerances and bounds [m].
    double characteristic_displacement() const { return x_scale; }
    // The damping coefficient mu of the Hertzian layer now (N s / m^(n+1)).
    double contact_damping_coefficient() const { return mu; }

  private:
    struct Forces
    {
      int    zone      = 0; // sign of the backlash zone: +1 forward, -1 back, 0 separated
      double f         = 0; // f(p), p = x - e
      double f_dot     = 0;
      double delta_dot = 0;
      double force     = 0;
      double u_dot     = 0; // rate of the structural compression u = f - delta
      bool   layer_closed = false;
      double penetration  = 0;
      MeshLawForces law; // at u = f - delta and delta = penetration (u = f without a layer)
    };
    Forces evaluate(double t, const double *y) const;
    // Backlash zone of p = x - e: +1 forward contact, -1 back side, 0 in the backlash.
    int    zone_of(double p) const;
    // The coefficients that depend on time only: the force law's phase coefficients and the
    // excitation; one cos/sin pair of the mesh angle serves every series. They are kept by mesh
    // phase, since an implicit integrator evaluates the right-hand side at the same stage times
    // in every Newton iteration, and a periodic motion at the same phases in every period (which
    // is also why one model must not be shared between threads).
    struct Coefficients
    {
      MeshPhase law;
      double    e = 0, e_rate = 0;
    };
    Coefficients coefficients(double t) const;
    Forces       evaluate(const Coefficients &co, const double *y) const;
    // y' from the forces at y.
    void         derivative(const Forces &r, const double *y, double *y_dot) const;
    // df/dy at a state from the forces evaluated there.
    void         jacobian(const Forces &r, double *J) const;

    GearPairParameters prm;
    // Immutable once built, so copies of the model share it.
    std::shared_ptr<const MeshForceLaw> law;
    unsigned                            n_law_taylor = 0; // 3 per phase coefficient
    bool                                phase_varies = false; // the law or the excitation
    FourierEvaluator                    ste_series;
    bool               has_delta_state  = false;
    unsigned           n_root_functions = 0;
    double             b_c              = 0.0;
    double             mu               = 0.0; // current contact damping coefficient
    double             x_scale          = 0.0;
    // The stores of coefficients, direct-mapped on the mesh phase rounded to 2^-phase_bits of a
    // period (the key; all ones: empty). An entry keeps each series' value and first two
    // derivatives at the exact phase that filled it; another phase of the same key (at most
    // 2^-phase_bits of a period away) is served by the Taylor polynomial, exact to rounding at
    // that distance. A store holds several periods' worth of stage phases, so that a periodic
    // motion, whose steps repeat every period, finds them again. The law's coefficients depend
    // on the phase alone: they are kept per law and thread (gear_pair_model.cc), shared by every
    // model of that law on the thread, at any speed; the unloaded STE's here, per model.
    struct PhaseEntry
    {
      std::uint64_t key  = ~std::uint64_t(0);
      double        frac = 0.0; // phase in periods, [0, 1)
      double        e[3] = {};
    };
    static constexpr int      phase_bits = 36;
    static constexpr unsigned cache_bits = 12, cache_size = 1u << cache_bits;
    // The STE's entries (none without the STE excitation). A copy of the store is an empty
    // store of the same size: a copied model fills its own.
    struct PhaseStore
    {
      std::vector<PhaseEntry> entries;

      PhaseStore() = default;
      explicit PhaseStore(const bool used) : entries(used ? cache_size : 0) {}
      PhaseStore(const PhaseStore &other) : PhaseStore(!other.entries.empty()) {}
      PhaseStore(PhaseStore &&)            = default;
      PhaseStore &operator=(PhaseStore &&) = default;
      PhaseStore &operator=(const PhaseStore &other)
      {
        if (this != &other)
          *this = PhaseStore(!other.entries.empty());
        return *this;
      }
    };
    mutable PhaseStore store;
    double                          cycles_per_s = 0.0; // omega_m / 2 pi
  };
} // namespace hertzgear::dynamics
