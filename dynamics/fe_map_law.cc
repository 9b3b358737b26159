// The FE force law (docs/dynamics.md, "The FE force law"): the paper's serial mesh, a structural
// member in series with the Hertzian layer, with each member's force taken from the stiffness
// table's load ladder instead of a power law fitted at one load.
//
// A member (structural: exponent p = 1; Hertzian: p = n of the table) at rung j of load F_j has
// the compression a_j(theta) at the mesh angle theta. Across the mesh cycle its secant coefficient
// c_j = F_j / a_j^p is the trigonometric interpolant of its S positions (exactly the series of a
// ladder made from Fourier coefficients). Across the load, log F is a monotone cubic Hermite
// function of log a through the rungs (X_j = log a_j, Y_j = log F_j): slopes the harmonic mean of
// the neighbouring secants inside (Fritsch-Butland: monotone, C1, exact on a power law), p at the
// lowest rung, where the law continues below as F = c_0 a^p (the contact's own exponent down to
// first touch), and the last secant at the top, where it continues as the power law of that
// exponent (an extrapolation the analyses count, docs/dynamics.md).
#include "common/errors.h"
#include "common/fourier_series.h"
#include "dynamics/mesh_force_law.h"
#include "dynamics/power_law.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  namespace
  {
    using power_law::sign;

    // A member's force and its derivatives at one compression a > 0.
    struct MemberForce
    {
      double F = 0, dF_da = 0, dF_dt = 0;
    };

    // One member of the serial mesh on the ladder. Its phase coefficients are X_j(theta) = log
    // a_j(theta), j = 0..J-1, from `first` on.
    class LadderMember
    {
    public:
      LadderMember(const std::vector<double> &loads, const std::vector<std::vector<double>> &a,
                   const double p, const bool varies, const unsigned first)
        : p(p), first(first)
      {
        std::vector<FourierSeries> secant; // c_j(theta)
        for (std::size_t j = 0; j < loads.size(); ++j)
          {
            Y.push_back(std::log(loads[j]));
            std::vector<double> c(a[j].size());
            for (std::size_t s = 0; s < c.size(); ++s)
              c[s] = loads[j] / std::pow(a[j][s], p);
            FourierSeries series = interpolate_fourier_series(c);
            if (!varies)
              series = series.constant_part();
            mean_secant.push_back(series.mean);
            secant.push_back(series);
            harmonics = std::max(harmonics, series.n_harmonics());
          }
        // The series as cosine and sine coefficients, rung-major, `harmonics` per rung.
        for (const auto &series : secant)
          for (unsigned h = 0; h < harmonics; ++h)
            {
              const bool has = h < series.n_harmonics();
              cos_coefficient.push_back(has ? series.amplitudes[h] * std::cos(series.phases_rad[h]) : 0.0);
              sin_coefficient.push_back(has ? series.amplitudes[h] * std::sin(series.phases_rad[h]) : 0.0);
            }
        for (std::size_t j = 0; j < Y.size(); ++j)
          constant_x.push_back((Y[j] - std::log(mean_secant[j])) / p);
      }

      std::size_t n_rungs() const { return Y.size(); }
      bool        varies() const { return harmonics > 0; }

      // The Taylor triples of X_j from those of c_j: X = (Y - log c) / p. The harmonics of the
      // angle are computed once for all rungs (recurrence as in FourierEvaluator).
      void phase_coefficients(const double c1, const double s1, double *taylor) const
      {
        double *x0 = taylor + 3 * first;
        if (harmonics == 0)
          {
            for (std::size_t j = 0; j < Y.size(); ++j)
              {
                x0[3 * j]     = constant_x[j];
                x0[3 * j + 1] = x0[3 * j + 2] = 0.0;
              }
            return;
          }
        double ch[max_harmonics], sh[max_harmonics];
        ch[0] = c1;
        sh[0] = s1;
        for (unsigned h = 1; h < harmonics; ++h)
          {
            ch[h] = ch[h - 1] * c1 - sh[h - 1] * s1;
            sh[h] = sh[h - 1] * c1 + ch[h - 1] * s1;
          }
        for (std::size_t j = 0; j < Y.size(); ++j)
          {
            const double *a = cos_coefficient.data() + j * harmonics;
            const double *b = sin_coefficient.data() + j * harmonics;
            double        v = mean_secant[j], d1 = 0.0, d2 = 0.0;
            for (unsigned h = 0; h < harmonics; ++h)
              {
                const double order = double(h + 1), term = a[h] * ch[h] + b[h] * sh[h];
                v += term;
                d1 += order * (b[h] * ch[h] - a[h] * sh[h]);
                d2 -= order * order * term;
              }
            double *x = x0 + 3 * j;
            x[0]      = (Y[j] - std::log(v)) / p;
            x[1]      = -d1 / (p * v);
            x[2]      = -(d2 * v - d1 * d1) / (p * v * v);
          }
      }
      // The same at the cycle's mean coefficients (no rates).
      void mean_coefficients(double *taylor) const
      {
        for (std::size_t j = 0; j < Y.size(); ++j)
          {
            double *x = taylor + 3 * (first + j);
            x[0]      = constant_x[j];
            x[1] = x[2] = 0.0;
          }
      }

      // The force at the compression a > 0 with its derivatives in a and in time at fixed a.
      MemberForce force(const MeshPhase &ph, const double a) const
      {
        const std::size_t J = Y.size();
        const double      X = std::log(a);
        double            Yv = 0, dY_dX = 0, dY_dt = 0;
        if (X <= x(ph, 0))
          {
            Yv    = Y[0] + p * (X - x(ph, 0));
            dY_dX = p;
            dY_dt = -p * xr(ph, 0);
          }
        else if (X >= x(ph, J - 1))
          {
            const Slope  m  = top_slope(ph);
            const double dX = X - x(ph, J - 1);
            Yv              = Y[J - 1] + m.m * dX;
            dY_dX           = m.m;
            dY_dt           = m.rate * dX - m.m * xr(ph, J - 1);
          }
        else
          {
            const std::size_t k  = interval(ph, X);
            const double      xk = x(ph, k), D = x(ph, k + 1) - xk;
            const double      Dr = xr(ph, k + 1) - xr(ph, k);
            const double      t  = (X - xk) / D;
            const Slope       dk = secant_of(ph, k);
            const Slope       m0 = k == 0 ? lowest_slope(dk) : harmonic(secant_of(ph, k - 1), dk);
            const Slope       m1 = k + 2 == J ? dk : harmonic(dk, secant_of(ph, k + 1));
            const auto        h  = hermite(t);
            Yv    = h[0] * Y[k] + h[2] * Y[k + 1] + D * (h[1] * m0.m + h[3] * m1.m);
            const double Yt = h[4] * Y[k] + h[6] * Y[k + 1] + D * (h[5] * m0.m + h[7] * m1.m);
            dY_dX           = Yt / D;
            const double tr = -(xr(ph, k) + t * Dr) / D;
            dY_dt = Yt * tr + Dr * (h[1] * m0.m + h[3] * m1.m) + D * (h[1] * m0.rate + h[3] * m1.rate);
          }
        const double F = std::exp(Yv);
        return {F, F * dY_dX / a, F * dY_dt};
      }

      // The compression that carries the force F > 0.
      double compression(const MeshPhase &ph, const double F) const
      {
        const std::size_t J  = Y.size();
        const double      Yt = std::log(F);
        if (Yt <= Y[0])
          return std::exp(x(ph, 0) + (Yt - Y[0]) / p);
        if (Yt >= Y[J - 1])
          return std::exp(x(ph, J - 1) + (Yt - Y[J - 1]) / top_slope(ph).m);
        const std::size_t k = static_cast<std::size_t>(
          std::upper_bound(Y.begin(), Y.end(), Yt) - Y.begin() - 1);
        const double xk = x(ph, k), D = x(ph, k + 1) - xk;
        const double m0 = slope(ph, k).m, m1 = slope(ph, k + 1).m;
        // The monotone cubic Y(t) on [0, 1]: Newton steps kept inside a shrinking bracket.
        double lo = 0.0, hi = 1.0, t = (Yt - Y[k]) / (Y[k + 1] - Y[k]);
        for (int it = 0; it < 100; ++it)
          {
            const auto   h  = hermite(t);
            const double r  = h[0] * Y[k] + h[2] * Y[k + 1] + D * (h[1] * m0 + h[3] * m1) - Yt;
            const double dr = h[4] * Y[k] + h[6] * Y[k + 1] + D * (h[5] * m0 + h[7] * m1);
            (r < 0.0 ? lo : hi) = t;
            double next = dr > 0.0 ? t - r / dr : 0.5 * (lo + hi);
            if (!(next > lo && next < hi))
              next = 0.5 * (lo + hi);
            const bool done = std::abs(next - t) <= 1e-15;
            t               = next;
            if (done)
              break;
          }
        return std::exp(xk + t * D);
      }

      // The elastic energy int_0^a F da' stored at the compression a > 0.
      double energy(const MeshPhase &ph, const double a) const
      {
        const std::size_t J = Y.size();
        const double      X = std::log(a);
        const auto        F_at = [&](const double Xq) { return force(ph, std::exp(Xq)).F; };
        // Below the lowest rung F = c a^p: int = F a / (p + 1).
        const double X0 = x(ph, 0);
        if (X <= X0)
          return F_at(X) * a / (p + 1.0);
        double E = std::exp(Y[0] + X0) / (p + 1.0);
        // Each rung interval in X (int F da = int F e^X dX), 5-point Gauss-Legendre.
        static constexpr std::array<double, 5> gx{-0.9061798459386640, -0.5384693101056831, 0.0,
                                                  0.5384693101056831, 0.9061798459386640};
        static constexpr std::array<double, 5> gw{0.2369268850561891, 0.4786286704993665,
                                                  0.5688888888888889, 0.4786286704993665,
                                                  0.2369268850561891};
        for (std::size_t k = 0; k + 1 < J; ++k)
          {
            const double lo = x(ph, k), hi = std::min(X, x(ph, k + 1));
            if (hi <= lo)
              break;
            const double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
            for (std::size_t q = 0; q < 5; ++q)
              {
                const double Xq = mid + half * gx[q];
                E += half * gw[q] * F_at(Xq) * std::exp(Xq);
              }
          }
        // Above the top F = F_top (a / a_top)^m: int = (F a - F_top a_top) / (m + 1).
        const double Xt = x(ph, J - 1);
        if (X > Xt)
          E += (F_at(X) * a - std::exp(Y[J - 1] + Xt)) / (top_slope(ph).m + 1.0);
        return E;
      }

      // The largest dF/da at the rungs over the cycle's phases `taylors` (for state scales).
      double stiffness_bound(const std::vector<std::vector<double>> &taylors) const
      {
        double bound = 0.0;
        for (const auto &taylor : taylors)
          {
            const MeshPhase ph{taylor.data(), 0.0, 0.0};
            for (std::size_t j = 0; j < Y.size(); ++j)
              bound = std::max(bound, force(ph, std::exp(x(ph, j))).dF_da);
          }
        return bound;
      }

      // Where the interpolated rungs do not grow with the load (or a secant is not positive):
      // the index j of the pair (j, j + 1), or -1.
      long not_increasing(const std::vector<double> &taylor) const
      {
        const MeshPhase ph{taylor.data(), 0.0, 0.0};
        for (std::size_t j = 0; j < Y.size(); ++j)
          if (!std::isfinite(x(ph, j)) || (j > 0 && !(x(ph, j) > x(ph, j - 1))))
            return static_cast<long>(j == 0 ? 0 : j - 1);
        return -1;
      }

    private:
      struct Slope
      {
        double m = 0, rate = 0;
      };

      double x(const MeshPhase &ph, const std::size_t j) const
      {
        return ph.value(static_cast<unsigned>(first + j));
      }
      double xr(const MeshPhase &ph, const std::size_t j) const
      {
        return ph.rate(static_cast<unsigned>(first + j));
      }
      // The secant of interval i in (X, Y) and its rate.
      Slope secant_of(const MeshPhase &ph, const std::size_t i) const
      {
        const double D = x(ph, i + 1) - x(ph, i);
        const double d = (Y[i + 1] - Y[i]) / D;
        return {d, -d * (xr(ph, i + 1) - xr(ph, i)) / D};
      }
      Slope top_slope(const MeshPhase &ph) const { return secant_of(ph, Y.size() - 2); }
      // The Hermite slope at the lowest rung from the first secant d: p, kept inside the
      // monotone region (at most 3 d).
      Slope lowest_slope(const Slope &d) const
      {
        return p <= 3.0 * d.m ? Slope{p, 0.0} : Slope{3.0 * d.m, 3.0 * d.rate};
      }
      // The Hermite slope at an inner rung from the secants a below and b above it.
      static Slope harmonic(const Slope &a, const Slope &b)
      {
        const double s = a.m + b.m;
        return {2.0 * a.m * b.m / s, 2.0 * (b.m * b.m * a.rate + a.m * a.m * b.rate) / (s * s)};
      }
      // The Hermite slope at rung k.
      Slope slope(const MeshPhase &ph, const std::size_t k) const
      {
        if (k == 0)
          return lowest_slope(secant_of(ph, 0));
        if (k == Y.size() - 1)
          return top_slope(ph);
        return harmonic(secant_of(ph, k - 1), secant_of(ph, k));
      }
      // The rung interval k with X_k <= X < X_{k+1} (X inside the ladder).
      std::size_t interval(const MeshPhase &ph, const double X) const
      {
        std::size_t lo = 0, hi = Y.size() - 1;
        while (hi - lo > 1)
          {
            const std::size_t mid = (lo + hi) / 2;
            (x(ph, mid) <= X ? lo : hi) = mid;
          }
        return lo;
      }
      // h00, h10, h01, h11 and their derivatives in t.
      static std::array<double, 8> hermite(const double t)
      {
        const double t2 = t * t, t3 = t2 * t;
        return {2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2,
                6 * t2 - 6 * t,      3 * t2 - 4 * t + 1, -6 * t2 + 6 * t, 3 * t2 - 2 * t};
      }

      // Positions per cycle the law takes (the interpolant's harmonics are at most half of them).
      static constexpr unsigned max_harmonics = 512;

      std::vector<double>        Y;           // log F_j
      std::vector<double>        mean_secant; // their means over the cycle
      std::vector<double>        cos_coefficient, sin_coefficient; // a_jh, b_jh
      std::vector<double>        constant_x;  // X_j at the mean coefficients
      unsigned                   harmonics = 0;
      double                     p;
      unsigned                   first;
    };

    // Phase coefficients: X_j of the structural member (j = 0..J-1), then of the Hertzian one.
    class FeMapLaw : public MeshForceLaw
    {
    public:
      FeMapLaw(const table::StiffnessTable &table, const bool structural_varies,
               const bool hertz_varies)
        : n(table.hertz_exponent)
        , J(static_cast<unsigned>(table.ladder.n_rungs()))
        , structural(table.ladder.load_N, structural_part(table.ladder), 1.0, structural_varies, 0)
        , hertz(table.ladder.load_N, table.ladder.hertz_approach_m, table.hertz_exponent,
                hertz_varies, J)
        , top(table.ladder.load_N.back())
      {
        // The interpolants between positions must keep every rung's compression growing with
        // the load: checked at 8 phases per position (the interpolants' harmonics are at most
        // S / 2, so this samples each at 16 points per period of the highest).
        const std::size_t   S = table.ladder.n_positions(), n_check = 8 * S;
        std::vector<double> taylor(3 * n_phase_coefficients());
        std::vector<std::vector<double>> taylors;
        for (std::size_t i = 0; i < n_check; ++i)
          {
            const double theta = 2.0 * M_PI * double(i) / n_check;
            phase_coefficients(std::cos(theta), std::sin(theta), taylor.data());
            for (const auto *m : {&structural, &hertz})
              {
                const long j = m->not_increasing(taylor);
                HG_REQUIRE_INPUT(j < 0, "stiffness table: load_ladder: between its positions, at "
                                        "mesh phase ", double(i) / n_check, ", the ",
                                 m == &structural ? "structural" : "Hertzian",
                                 " approach interpolated over the cycle does not grow from ",
                                 table.ladder.load_N[j], " N to ", table.ladder.load_N[j + 1],
                                 " N: the ladder needs more positions per cycle or rungs further "
                                 "apart");
              }
            if (i % 8 == 0)
              taylors.push_back(taylor);
          }
        k_bound = structural.stiffness_bound(taylors);
        mean_taylor.assign(3 * n_phase_coefficients(), 0.0);
        structural.mean_coefficients(mean_taylor.data());
        hertz.mean_coefficients(mean_taylor.data());
      }

      unsigned n_phase_coefficients() const override { return 2 * J; }
      bool     varies_with_phase() const override { return structural.varies() || hertz.varies(); }
      void     phase_coefficients(const double c1, const double s1, double *taylor) const override
      {
        structural.phase_coefficients(c1, s1, taylor);
        hertz.phase_coefficients(c1, s1, taylor);
      }

      void evaluate(const MeshPhase &phase, const double u, const double d,
                    MeshLawForces &out) const override
      {
        const auto member = [&](const LadderMember &m, const double a, const double p, double &F,
                                double &dF_da, double &dF_dt) {
          if (a == 0.0)
            {
              // F = c_0 a^p near zero: slope c_0 for p = 1, else 0.
              F     = 0.0;
              dF_dt = 0.0;
              dF_da = p == 1.0 ? m.force(phase, 1.0e-30).dF_da : 0.0;
              return;
            }
          const MemberForce f = m.force(phase, std::abs(a));
          F                   = sign(a) * f.F;
          dF_da               = f.dF_da;
          dF_dt               = sign(a) * f.dF_dt;
        };
        member(structural, u, 1.0, out.structural, out.structural_du, out.structural_dt);
        member(hertz, d, n, out.hertz, out.hertz_ddelta, out.hertz_dt);
        out.damping_weight       = power_law::H(d, n);
        out.damping_weight_slope = power_law::H_prime(d, n);
      }

      double quasi_static_penetration(const MeshPhase &phase, const double f) const override
      {
        // phi(d) = K_r(|f| - d) - K_h(d) decreases strictly on [0, |f|] from K_r(|f|) > 0 to
        // -K_h(|f|) < 0: one root, bracketed; Newton steps that leave the bracket bisect.
        const double a = std::abs(f);
        if (a == 0.0)
          return 0.0;
        double lo = 0.0, hi = a, d = 0.5 * a;
        for (int it = 0; it < 200; ++it)
          {
            const MemberForce r = structural.force(phase, a - d), h = hertz.force(phase, d);
            const double      phi = r.F - h.F;
            (phi > 0.0 ? lo : hi) = d;
            const double dphi = -r.dF_da - h.dF_da;
            double       next = d - phi / dphi;
            if (!(next > lo && next < hi))
              next = 0.5 * (lo + hi);
            const bool done = std::abs(next - d) <= 1.0e-15 * a;
            d               = next;
            if (done)
              break;
          }
        return sign(f) * d;
      }

      MeshLawEnergy elastic_energy(const MeshPhase &phase, const double u,
                                   const double d) const override
      {
        return {u == 0.0 ? 0.0 : structural.energy(phase, std::abs(u)),
                d == 0.0 ? 0.0 : hertz.energy(phase, std::abs(d))};
      }

      void static_compressions(const double F, double &u, double &delta) const override
      {
        const MeshPhase mean{mean_taylor.data(), 0.0, 0.0};
        u     = F > 0.0 ? structural.compression(mean, F) : 0.0;
        delta = F > 0.0 ? hertz.compression(mean, F) : 0.0;
      }

      double structural_stiffness_bound() const override { return k_bound; }
      double tabulated_force_limit() const override { return top; }

    private:
      static std::vector<std::vector<double>> structural_part(const table::LoadLadder &l)
      {
        auto u = l.approach_m;
        for (std::size_t j = 0; j < u.size(); ++j)
          for (std::size_t s = 0; s < u[j].size(); ++s)
            u[j][s] -= l.hertz_approach_m[j][s];
        return u;
      }

      double              n;
      unsigned            J;
      LadderMember        structural, hertz;
      double              top;
      double              k_bound = 0.0;
      std::vector<double> mean_taylor;
    };
  } // namespace

  std::shared_ptr<const MeshForceLaw> fe_map_law(const table::StiffnessTable &table,
                                                 const bool structural_varies,
                                                 const bool hertz_varies)
  {
    HG_REQUIRE_INPUT(!table.ladder.empty(),
                     "the FE force law needs a stiffness table with a load ladder (load_ladder): "
                     "Stiffness/source = fem makes one");
    table.ladder.check("stiffness table: load_ladder");
    HG_REQUIRE_INPUT(table.ladder.n_positions() <= 1024, "stiffness table: load_ladder: ",
                     table.ladder.n_positions(), " positions per cycle; the FE force law takes at "
                     "most 1024");
    return std::make_shared<FeMapLaw>(table, structural_varies, hertz_varies);
  }
} // namespace hertzgear::dynamics
