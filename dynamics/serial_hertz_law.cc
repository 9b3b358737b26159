// The paper's serial mesh force law: the structural spring k(theta) u in series with the Hertzian
// layer k_h(theta) G(delta), both from the stiffness table's Fourier series (docs/dynamics.md).
#include "common/fourier_series.h"
#include "dynamics/mesh_force_law.h"
#include "dynamics/power_law.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace hertzgear::dynamics
{
  namespace
  {
    using power_law::G_prime;
    using power_law::H_prime;
    using power_law::power;
    using power_law::sign;

    // Phase coefficients: 0 the structural stiffness k [N/m], 1 the Hertzian stiffness k_h
    // [N/m^n].
    class SerialHertzLaw : public MeshForceLaw
    {
    public:
      explicit SerialHertzLaw(const table::StiffnessTable &table)
        : k_series(table.k_rest_N_per_m)
        , kh_series(table.k_hertz_N_per_m_pow_n)
        , n(table.hertz_exponent)
        , k_mean(table.k_rest_N_per_m.mean)
        , kh_mean(table.k_hertz_N_per_m_pow_n.mean)
        , k_bound(table.k_rest_N_per_m.mean + table.k_rest_N_per_m.amplitude_bound())
      {}

      unsigned n_phase_coefficients() const override { return 2; }
      bool     varies_with_phase() const override
      {
        return !(k_series.constant() && kh_series.constant());
      }
      void phase_coefficients(double, const double c1, const double s1, double *taylor) const override
      {
        k_series.taylor(c1, s1, taylor);
        kh_series.taylor(c1, s1, taylor + 3);
      }

      void forces(const MeshPhase &phase, const double u, const double d, MeshLawForces &out,
                  bool) const override
      {
        const double k = phase.value(0), kh = phase.value(1);
        const double Hd = power(std::abs(d), n), Gd = sign(d) * Hd;
        out.structural           = k * u;
        out.structural_du        = k;
        out.structural_dt        = phase.rate(0) * u;
        out.hertz                = kh * Gd;
        out.hertz_ddelta         = kh * G_prime(d, n);
        out.hertz_dt             = phase.rate(1) * Gd;
        out.damping_weight       = Hd;
        out.damping_weight_slope = H_prime(d, n);
      }

      double quasi_static_penetration(const MeshPhase &phase, const double f) const override
      {
        const double k = phase.value(0), kh = phase.value(1);
        // phi(d) = k (|f| - d) - kh d^n is strictly decreasing on [0, |f|] with phi(0) >= 0 >=
        // phi(|f|): one root, bracketed. Newton steps that leave the bracket are replaced by
        // bisection.
        const double a = std::abs(f);
        if (a == 0.0)
          return 0.0;
        if (n == 1.0)
          return sign(f) * k * a / (k + kh);
        double lo = 0.0, hi = a;
        double d  = std::min(a, std::pow(k * a / kh, 1.0 / n));
        for (int it = 0; it < 100; ++it)
          {
            const double phi = k * (a - d) - kh * std::pow(d, n);
            if (phi > 0.0)
              lo = d;
            else
              hi = d;
            const double dphi = -k - kh * n * std::pow(d, n - 1.0);
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

      MeshLawEnergy elastic_energy(const MeshPhase &phase, const double u,
                                   const double d) const override
      {
        const double k = phase.value(0), kh = phase.value(1);
        return {0.5 * k * u * u, kh * power(std::abs(d), n) * std::abs(d) / (n + 1.0)};
      }

      void static_compressions(const double F, double &u, double &delta) const override
      {
        u     = F / k_mean;
        delta = std::pow(F / kh_mean, 1.0 / n);
      }

      double structural_stiffness_bound() const override { return k_bound; }

    private:
      FourierEvaluator k_series, kh_series;
      double           n, k_mean, kh_mean, k_bound;
    };
  } // namespace

  MeshForceLaw::MeshForceLaw()
  {
    static std::atomic<std::uint64_t> next{1};
    id_ = next.fetch_add(1, std::memory_order_relaxed);
  }

  std::shared_ptr<const MeshForceLaw> serial_hertz_law(const table::StiffnessTable &table)
  {
    return std::make_shared<SerialHertzLaw>(table);
  }
} // namespace hertzgear::dynamics
