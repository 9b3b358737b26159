#pragma once
// The seam for the force law of the mesh (docs/dynamics.md, "The mesh force law"): the two
// elastic members of the serial mesh, the structural spring and the Hertzian layer, as functions
// of the mesh phase and of their own compressions. GearPairModel keeps the equations (the
// backlash, the viscous damper c across the structural member, the Hunt-Crossley term mu H(delta)
// delta' across the layer, the states and events) and asks a MeshForceLaw for the forces; a law is
// one file behind this interface.
//
// A law is evaluated in two parts, so that the model's right-hand side makes one call to it:
// - the coefficients that depend on the mesh phase only (n_phase_coefficients() of them, e.g.
//   k(theta) and k_h(theta) of the serial law), with their first two derivatives in the mesh angle
//   theta. The model computes them at a new phase only and keeps them by phase (an implicit
//   integrator and a periodic motion come back to the same phases);
// - the forces at the structural compression u and the Hertzian compression delta from those
//   coefficients, at every evaluation.
#include "table/stiffness_table.h"

#include <cstdint>
#include <limits>
#include <memory>

namespace hertzgear::dynamics
{
  // The phase coefficients of a law at one instant: from the stored Taylor triples (value, d/d
  // theta, d^2/d theta^2) of each coefficient at a nearby phase, the angle dth from there and the
  // mesh frequency w = d theta / dt.
  struct MeshPhase
  {
    const double *taylor = nullptr; // 3 per coefficient
    double        dth    = 0.0;     // [rad]
    double        w      = 0.0;     // [rad/s]

    // Coefficient i and its rate d/dt at this instant (exact to rounding for |dth| of the store's
    // resolution, 2^-36 of a period).
    double value(const unsigned i) const { return taylor[3 * i] + taylor[3 * i + 1] * dth; }
    double rate(const unsigned i) const
    {
      return w * (taylor[3 * i + 1] + taylor[3 * i + 2] * dth);
    }
  };

  // What a law gives at (phase, u, delta): each member's force, its derivative in its own
  // compression (the Jacobian) and in time at fixed compression (the quasi-static layer), and the
  // weight H(delta) of the Hunt-Crossley term mu H(delta) delta' with its derivative. Forces in N,
  // compressions in m; a compression and its force have the same sign (a law carries tension as
  // its odd extension; the model decides when a member is open).
  struct MeshLawForces
  {
    double structural          = 0.0; // K_r(u)
    double structural_du       = 0.0; // dK_r/du
    double structural_dt       = 0.0; // dK_r/dt at fixed u
    double hertz               = 0.0; // K_h(delta)
    double hertz_ddelta        = 0.0; // dK_h/ddelta
    double hertz_dt            = 0.0; // dK_h/dt at fixed delta
    double damping_weight      = 0.0; // H(delta) >= 0
    double damping_weight_slope = 0.0; // dH/ddelta
  };

  // Elastic energy stored in each member at (phase, u, delta) [J].
  struct MeshLawEnergy
  {
    double structural = 0.0;
    double hertz      = 0.0;
  };

  class MeshForceLaw
  {
  public:
    MeshForceLaw();
    virtual ~MeshForceLaw() = default;

    // A number that no other law object of the process has: the models keep a law's phase
    // coefficients per law and thread under it, shared by all models of that law (a family of
    // models over a parameter, built anew at every step, meets its phases again).
    std::uint64_t id() const { return id_; }

    // The coefficients that depend on the mesh phase only.
    virtual unsigned n_phase_coefficients() const = 0;
    // Whether any of them varies with the phase (else the law is autonomous).
    virtual bool varies_with_phase() const = 0;
    // The Taylor triples of every coefficient at the mesh angle theta in [0, 2 pi), given with
    // its cos(theta) and sin(theta), into taylor[3 i .. 3 i + 2].
    virtual void phase_coefficients(double theta, double cos_theta, double sin_theta,
                                    double *taylor) const = 0;

    // The forces at (phase, u, delta). Without `rates` the derivatives in time at fixed
    // compression (structural_dt, hertz_dt) are left 0: only the quasi-static layer needs them,
    // and a law may save their cost.
    virtual void forces(const MeshPhase &phase, double u, double delta, MeshLawForces &out,
                        bool rates) const = 0;
    void evaluate(const MeshPhase &phase, const double u, const double delta,
                  MeshLawForces &out) const
    {
      forces(phase, u, delta, out, true);
    }
    // The Hertzian compression delta of the massless serial mesh at the total compression f:
    // K_r(f - delta) = K_h(delta), sign(delta) = sign(f), |delta| <= |f|.
    virtual double quasi_static_penetration(const MeshPhase &phase, double f) const = 0;
    virtual MeshLawEnergy elastic_energy(const MeshPhase &phase, double u, double delta) const = 0;

    // The compressions (u, delta) that carry the force F >= 0 in forward contact with the
    // coefficients at their mean over the cycle (the static state the motion starts from).
    virtual void static_compressions(double force, double &u, double &delta) const = 0;
    // An upper bound of dK_r/du over the cycle at the loads the model sees (for state scales).
    virtual double structural_stiffness_bound() const = 0;
    // The largest force the law's data cover (N): above it the law extrapolates, and an analysis
    // that sees a larger mesh force says so. Infinite for a closed-form law.
    virtual double tabulated_force_limit() const
    {
      return std::numeric_limits<double>::infinity();
    }

  private:
    std::uint64_t id_;
  };

  // The paper's law (docs/dynamics.md): a structural spring linear in u with stiffness k(theta)
  // and the Hertzian layer K_h = k_h(theta) G(delta), G(delta) = sign(delta) |delta|^n, damping
  // weight H(delta) = |delta|^n, from the table's Fourier series and exponent n.
  std::shared_ptr<const MeshForceLaw> serial_hertz_law(const table::StiffnessTable &table);

  // The FE force law (docs/dynamics.md, "The FE force law"): the same serial mesh with each
  // member's force interpolated in the table's load ladder (structural part a - a_h, Hertzian
  // part a_h), monotone and C1 in the compression, the trigonometric interpolant of the
  // positions over the mesh cycle; H(delta) = |delta|^n as in the serial law. A member that does
  // not vary takes its secant coefficients' means over the cycle. Throws InputError for a table
  // without a ladder, or a ladder whose interpolant over the cycle does not grow with the load.
  std::shared_ptr<const MeshForceLaw> fe_map_law(const table::StiffnessTable &table,
                                                 bool structural_varies, bool hertz_varies);
} // namespace hertzgear::dynamics
