// The FE force law (docs/dynamics.md, "The FE force law"): the paper's serial mesh, a structural
// member in series with the Hertzian layer, with each member's force taken from the stiffness
// table's load ladder instead of a power law fitted at one load.
//
// A member (structural: exponent p = 1; Hertzian: p = n of the table) at rung j of load F_j has
// the compression a_j(theta) at the mesh angle theta. Across the mesh cycle its secant coefficient
// c_j = F_j / a_j^p is the trigonometric interpolant of its S positions (exactly the series of a
// ladder made from Fourier coefficients). Across the load, log F is the cubic spline of log a
// through the rungs (X_j = log a_j, Y_j = log F_j; C2, so that an integrator's steps do not
// shrink where the motion crosses a rung, and exact on a power law), its curvature zero at the
// top, where it continues as the power law of its end slope (an extrapolation the analyses count,
// docs/dynamics.md). At the lowest rung the structural member's slope is 1 (linear below it down
// to first touch); the Hertzian member's spline is natural there too and continues below as the
// power law of its slope m_0 there, the FE's own exponent at light load, unless m_0 < 1 at some
// phase (a softening contact), when it is clamped to n. The spline is checked to grow
// at every phase (a ladder whose spline does not is refused).
//
// The coefficients X_j(theta) and the spline's slopes m_j(theta) of each member that varies over
// the cycle are computed exactly on N nodes over the cycle at construction; an evaluation
// interpolates the few it needs by the quintic Hermite polynomial of its cell (GridPhase), N
// doubled until that is exact to 1e-12 (docs/dynamics.md, "What an evaluation costs"). A member
// that does not vary keeps its coefficients at the cycle's mean (ConstantPhase).
#include "common/errors.h"
#include "common/fourier_series.h"
#include "dynamics/mesh_force_law.h"
#include "dynamics/power_law.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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

    // The largest number of rungs the law takes.
    constexpr std::size_t max_rungs = 64;

    // One member of the serial mesh on the ladder. Its phase coefficients are, per rung j =
    // 0..J-1, X_j(theta) = log a_j(theta) and the Hermite slope m_j(theta) there (so that an
    // evaluation at a compression finds them without a division, and the four it needs lie side by
    // side).
    class LadderMember
    {
    public:
      LadderMember(const std::vector<double> &loads, const std::vector<std::vector<double>> &a,
                   const double p, const bool varies, const bool natural_lower_end)
        : p(p)
        , natural_low(natural_lower_end)
      {
        std::vector<FourierSeries> secants; // c_j(theta)
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
            secants.push_back(series);
            harmonics = std::max(harmonics, series.n_harmonics());
          }
        // The series as cosine and sine coefficients, rung-major, `harmonics` per rung.
        for (const auto &series : secants)
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
      // Phase coefficients of the member: X_j and m_j.
      unsigned n_phase_coefficients() const { return 2 * static_cast<unsigned>(Y.size()); }
      bool     varies() const { return harmonics > 0; }

      // The Taylor triples of X_j from those of c_j, X = (Y - log c) / p, then of the slopes.
      // The harmonics of the angle are computed once for all rungs (recurrence as in
      // FourierEvaluator).
      void phase_coefficients(const double c1, const double s1, double *taylor) const
      {
        if (harmonics == 0)
          {
            mean_coefficients(taylor);
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
            double *x = taylor + 3 * x_index(j);
            x[0]      = (Y[j] - std::log(v)) / p;
            x[1]      = -d1 / (p * v);
            x[2]      = -(d2 * v - d1 * d1) / (p * v * v);
          }
        slopes(taylor);
      }
      // The same at the cycle's mean coefficients (no rates).
      void mean_coefficients(double *taylor) const
      {
        for (std::size_t j = 0; j < Y.size(); ++j)
          {
            double *x = taylor + 3 * x_index(j);
            x[0]      = constant_x[j];
            x[1] = x[2] = 0.0;
          }
        slopes(taylor);
      }

      // The force at the compression a > 0 with its derivatives in a and in time at fixed a.
      template <class Phase>
      MemberForce force(const Phase &ph, const double a, const bool rates = true) const
      {
        const long   J = static_cast<long>(Y.size());
        const double X = std::log(a);
        // The interval k (x_k <= X < x_{k+1}; -1 below the ladder, J - 1 above it): found among
        // the x_j at the cycle's mean (a plain array), then corrected with the phase's values.
        long k = static_cast<long>(std::upper_bound(constant_x.begin(), constant_x.end(), X) -
                                   constant_x.begin()) - 1;
        double xk = 0.0, xk1 = 0.0;
        for (long it = 0; it <= J; ++it)
          {
            if (k >= 0 && X < (xk = x(ph, std::size_t(k))))
              --k;
            else if (k + 1 < J && X >= (xk1 = x(ph, std::size_t(k + 1))))
              ++k;
            else
              break;
          }
        double Yv = 0, dY_dX = 0, dY_dt = 0;
        if (k < 0)
          {
            // Below the lowest rung: the power law of the spline's lowest slope m_0 (p when the
            // end is clamped).
            const double m  = lowest_slope(ph);
            const double dX = X - xk1;
            Yv              = Y[0] + m * dX;
            dY_dX           = m;
            if (rates)
              dY_dt = (natural_low ? ph.rate(slope_index(0)) * dX : 0.0) - m * xr(ph, 0);
          }
        else if (k == J - 1)
          {
            // Above the top: the power law of the spline's end slope.
            const double m  = ph.value(slope_index(std::size_t(J - 1)));
            const double dX = X - xk;
            Yv              = Y[J - 1] + m * dX;
            dY_dX           = m;
            if (rates)
              dY_dt = ph.rate(slope_index(std::size_t(J - 1))) * dX - m * xr(ph, std::size_t(J - 1));
          }
        else
          {
            const std::size_t i     = std::size_t(k);
            const double      D     = xk1 - xk;
            const double      inv_D = 1.0 / D;
            const double      t     = (X - xk) * inv_D;
            const double      m0 = ph.value(slope_index(i)), m1 = ph.value(slope_index(i + 1));
            // The cubic in t in Horner form: Y_i + t (D m0 + t (c2 + t c3)).
            const double dY = Y[i + 1] - Y[i], s0 = D * m0, s1 = D * m1;
            const double c2 = 3.0 * dY - 2.0 * s0 - s1, c3 = s0 + s1 - 2.0 * dY;
            Yv              = Y[i] + t * (s0 + t * (c2 + t * c3));
            const double Yt = s0 + t * (2.0 * c2 + 3.0 * t * c3); // dY/dt
            dY_dX           = Yt * inv_D;
            if (rates)
              {
                const auto   h  = hermite(t);
                const double r0 = xr(ph, i), Dr = xr(ph, i + 1) - r0;
                const double tr = -(r0 + t * Dr) * inv_D;
                dY_dt = Yt * tr + Dr * (h[1] * m0 + h[3] * m1) +
                        D * (h[1] * ph.rate(slope_index(i)) + h[3] * ph.rate(slope_index(i + 1)));
              }
          }
        const double F = std::exp(Yv);
        return {F, F * dY_dX / a, F * dY_dt};
      }

      // The compression that carries the force F > 0.
      template <class Phase>
      double compression(const Phase &ph, const double F) const
      {
        const std::size_t J  = Y.size();
        const double      Yt = std::log(F);
        if (Yt <= Y[0])
          return std::exp(x(ph, 0) + (Yt - Y[0]) / lowest_slope(ph));
        if (Yt >= Y[J - 1])
          return std::exp(x(ph, J - 1) + (Yt - Y[J - 1]) / slope(ph, J - 1).m);
        const std::size_t k = static_cast<std::size_t>(
          std::upper_bound(Y.begin(), Y.end(), Yt) - Y.begin() - 1);
        const double xk = x(ph, k), D = x(ph, k + 1) - xk;
        const double m0 = slope(ph, k).m, m1 = slope(ph, k + 1).m;
        // The cubic Y(t) on [0, 1], increasing (checked at construction): Newton steps kept
        // inside a shrinking bracket.
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
      template <class Phase>
      double energy(const Phase &ph, const double a) const
      {
        const std::size_t J = Y.size();
        const double      X = std::log(a);
        const auto        F_at = [&](const double Xq) { return force(ph, std::exp(Xq), false).F; };
        // Below the lowest rung F = c a^m0: int = F a / (m0 + 1).
        const double X0 = x(ph, 0), m0 = lowest_slope(ph);
        if (X <= X0)
          return F_at(X) * a / (m0 + 1.0);
        double E = std::exp(Y[0] + X0) / (m0 + 1.0);
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
          E += (F_at(X) * a - std::exp(Y[J - 1] + Xt)) / (slope(ph, J - 1).m + 1.0);
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

      // Whether the spline's lowest end is natural (else clamped to p), and the switch to the
      // clamped end.
      bool natural_lower_end() const { return natural_low; }
      void clamp_lower_end() { natural_low = false; }
      // The spline's slope at the lowest rung at the phase of `taylor`.
      double lowest_slope(const std::vector<double> &taylor) const
      {
        return taylor[3 * slope_index(0)];
      }

    private:
      struct Slope
      {
        double m = 0, rate = 0;
      };

      template <class Phase>
      double x(const Phase &ph, const std::size_t j) const
      {
        return ph.value(x_index(j));
      }
      template <class Phase>
      double xr(const Phase &ph, const std::size_t j) const
      {
        return ph.rate(x_index(j));
      }
      // The Hermite slope at rung k and its rate.
      template <class Phase>
      Slope slope(const Phase &ph, const std::size_t k) const
      {
        const unsigned i = slope_index(k);
        return {ph.value(i), ph.rate(i)};
      }
      // Where X_j and m_j lie among the member's coefficients.
      static unsigned x_index(const std::size_t j) { return static_cast<unsigned>(2 * j); }
      static unsigned slope_index(const std::size_t k) { return static_cast<unsigned>(2 * k + 1); }
      // The slope of the power law below the lowest rung.
      template <class Phase>
      double lowest_slope(const Phase &ph) const
      {
        return natural_low ? ph.value(slope_index(0)) : p;
      }
      // The Taylor triples of the Hermite slopes m_j in (X, Y) from those of X_j: the cubic
      // spline through the rungs (C2), its curvature at the top zero (natural: C2 into the
      // straight-line extrapolation above) and at the lowest rung either zero too (natural) or its
      // slope p (clamped). With g_i = 1 / (X_{i+1} - X_i) the slopes solve the tridiagonal
      //   g_{i-1} m_{i-1} + 2 (g_{i-1} + g_i) m_i + g_i m_{i+1} = 3 (dY_{i-1} g_{i-1}^2 + dY_i g_i^2),
      // 2 g_0 m_0 + g_0 m_1 = 3 dY_0 g_0^2 (natural) or m_0 = p (clamped), and
      // g_{J-2} m_{J-2} + 2 g_{J-2} m_{J-1} = 3 dY_{J-2} g_{J-2}^2; their derivatives
      // in the mesh angle solve A m' = r' - A' m and A m'' = r'' - A'' m - 2 A' m' with the same
      // matrix.
      void slopes(double *taylor) const
      {
        const std::size_t J = Y.size();
        // g_i and g_i^2 with their first two derivatives, from those of X.
        std::array<double, max_rungs> g[3], G[3];
        for (std::size_t i = 0; i + 1 < J; ++i)
          {
            const double *lo = taylor + 3 * x_index(i), *hi = taylor + 3 * x_index(i + 1);
            const double  h = hi[0] - lo[0], h1 = hi[1] - lo[1], h2 = hi[2] - lo[2];
            g[0][i]         = 1.0 / h;
            g[1][i]         = -h1 * g[0][i] * g[0][i];
            g[2][i]         = (2.0 * h1 * h1 * g[0][i] - h2) * g[0][i] * g[0][i];
            G[0][i]         = g[0][i] * g[0][i];
            G[1][i]         = 2.0 * g[0][i] * g[1][i];
            G[2][i]         = 2.0 * (g[1][i] * g[1][i] + g[0][i] * g[2][i]);
          }
        // Row i: lower l[i] m_{i-1} + diagonal d[i] m_i + upper u[i] m_{i+1} = r[i], and the
        // same rows' derivatives (index 1, 2).
        std::array<double, max_rungs> l[3], d[3], u[3], r[3];
        for (int o = 0; o < 3; ++o)
          {
            if (natural_low && J > 1)
              {
                // 2 g_0 m_0 + g_0 m_1 = 3 dY_0 g_0^2.
                l[o][0] = 0.0;
                d[o][0] = 2.0 * g[o][0];
                u[o][0] = g[o][0];
                r[o][0] = 3.0 * (Y[1] - Y[0]) * G[o][0];
              }
            else
              {
                l[o][0] = u[o][0] = 0.0;
                d[o][0]           = o == 0 ? 1.0 : 0.0;
                r[o][0]           = o == 0 ? p : 0.0;
              }
            for (std::size_t i = 1; i < J; ++i)
              {
                const bool last = i + 1 == J;
                l[o][i]         = g[o][i - 1];
                u[o][i]         = last ? 0.0 : g[o][i];
                d[o][i]         = 2.0 * (g[o][i - 1] + (last ? 0.0 : g[o][i]));
                r[o][i] = 3.0 * ((Y[i] - Y[i - 1]) * G[o][i - 1] + (last ? 0.0 : (Y[i + 1] - Y[i]) * G[o][i]));
              }
          }
        // The Thomas algorithm on A = (l[0], d[0], u[0]): the forward sweep once, then three
        // right-hand sides.
        std::array<double, max_rungs> pivot, factor;
        pivot[0] = d[0][0];
        for (std::size_t i = 1; i < J; ++i)
          {
            factor[i] = l[0][i] / pivot[i - 1];
            pivot[i]  = d[0][i] - factor[i] * u[0][i - 1];
          }
        const auto solve = [&](std::array<double, max_rungs> &x) {
          for (std::size_t i = 1; i < J; ++i)
            x[i] -= factor[i] * x[i - 1];
          x[J - 1] /= pivot[J - 1];
          for (std::size_t i = J - 1; i-- > 0;)
            x[i] = (x[i] - u[0][i] * x[i + 1]) / pivot[i];
        };
        // (A^(o) v)_i.
        const auto apply = [&](const int o, const std::array<double, max_rungs> &v, const std::size_t i) {
          return (i > 0 ? l[o][i] * v[i - 1] : 0.0) + d[o][i] * v[i] +
                 (i + 1 < J ? u[o][i] * v[i + 1] : 0.0);
        };
        std::array<double, max_rungs> m0 = r[0], m1{}, m2{};
        solve(m0);
        for (std::size_t i = 0; i < J; ++i)
          m1[i] = r[1][i] - apply(1, m0, i);
        solve(m1);
        for (std::size_t i = 0; i < J; ++i)
          m2[i] = r[2][i] - apply(2, m0, i) - 2.0 * apply(1, m1, i);
        solve(m2);
        for (std::size_t k = 0; k < J; ++k)
          {
            double *out = taylor + 3 * slope_index(k);
            out[0]      = m0[k];
            out[1]      = m1[k];
            out[2]      = m2[k];
          }
      }

    public:
      // Where the interpolant does not grow with the compression at the phase of `taylor`: the
      // interval k (between rungs k and k + 1; J - 1 for the straight line above the top) whose
      // slope dY/dX = 6 d t (1 - t) + m_k (3t^2 - 4t + 1) + m_{k+1} (3t^2 - 2t), d its secant,
      // is not positive somewhere on [0, 1], or -1.
      long not_monotone(const std::vector<double> &taylor) const
      {
        const MeshPhase   ph{taylor.data(), 0.0, 0.0};
        const std::size_t J = Y.size();
        for (std::size_t k = 0; k + 1 < J; ++k)
          {
            const double dk = (Y[k + 1] - Y[k]) / (x(ph, k + 1) - x(ph, k));
            const double m0 = slope(ph, k).m, m1 = slope(ph, k + 1).m;
            const double qa = -6.0 * dk + 3.0 * m0 + 3.0 * m1, qb = 6.0 * dk - 4.0 * m0 - 2.0 * m1;
            double       low = std::min(m0, m1);
            if (qa > 0.0 && -qb > 0.0 && -qb < 2.0 * qa)
              low = std::min(low, m0 - qb * qb / (4.0 * qa));
            if (!(low > 0.0))
              return static_cast<long>(k);
          }
        return slope(ph, J - 1).m > 0.0 ? -1 : static_cast<long>(J - 1);
      }

    private:
      // The rung interval k with X_k <= X < X_{k+1} (X inside the ladder).
      template <class Phase>
      std::size_t interval(const Phase &ph, const double X) const
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
      bool                       natural_low; // the spline's lowest end natural, else clamped to p
    };

    // The interpolation over the mesh cycle: N nodes theta_i = i h, h = 2 pi / N, at each the
    // value, h d/dtheta and h^2 d^2/dtheta^2 of every coefficient of a member that varies, and the
    // quintic Hermite polynomial through the two nodes of the angle's cell (exact for a quintic;
    // error ~ (h/2)^6 f^(6) / 720). The cell and its basis are found once per evaluation
    // (GridCell), each member reads its own table there (GridPhase); values and rates are computed
    // per coefficient, when the force asks for it.
    struct GridCell
    {
      GridCell(const unsigned n_nodes, const double theta, const double w, const bool rates)
      {
        double u = theta * (double(n_nodes) / (2.0 * M_PI));
        // floor(u) by truncation (std::floor is a library call without SSE4.1); u >= -1 here.
        double c = double(std::int64_t(u));
        c        = c > u ? c - 1.0 : c;
        const double t = u - c;
        long i   = static_cast<long>(c); // in -1 .. N
        i        = i < 0 ? i + long(n_nodes) : (i >= long(n_nodes) ? i - long(n_nodes) : i);
        node0    = std::size_t(i);
        node1    = std::size_t(i + 1 == long(n_nodes) ? 0 : i + 1);
        const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
        b[0]            = 1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5;
        b[1]            = t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5;
        b[2]            = 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5);
        b[3]            = 10.0 * t3 - 15.0 * t4 + 6.0 * t5;
        b[4]            = -4.0 * t3 + 7.0 * t4 - 3.0 * t5;
        b[5]            = 0.5 * (t3 - 2.0 * t4 + t5);
        if (!rates)
          return; // rate() is not called
        // d/dt of the same, times d t/d time = w N / 2 pi.
        const double r = w * (double(n_nodes) / (2.0 * M_PI));
        db[0]          = r * (-30.0 * t2 + 60.0 * t3 - 30.0 * t4);
        db[1]          = r * (1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4);
        db[2]          = r * 0.5 * (2.0 * t - 9.0 * t2 + 12.0 * t3 - 5.0 * t4);
        db[3]          = -db[0];
        db[4]          = r * (-12.0 * t2 + 28.0 * t3 - 15.0 * t4);
        db[5]          = r * 0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4);
      }
      std::size_t node0 = 0, node1 = 0;
      double      b[6], db[6] = {};
    };

    // A member's coefficients at the cell's angle, from its table over the cycle.
    class GridPhase
    {
    public:
      GridPhase(const std::vector<double> &grid, const unsigned per_node, const GridCell &cell)
        : n0(grid.data() + cell.node0 * per_node)
        , n1(grid.data() + cell.node1 * per_node)
        , cell(cell)
      {}
      double value(const unsigned c) const
      {
        const double *p = n0 + 3 * c, *q = n1 + 3 * c;
        const double *b = cell.b;
        return b[0] * p[0] + b[1] * p[1] + b[2] * p[2] + b[3] * q[0] + b[4] * q[1] + b[5] * q[2];
      }
      double rate(const unsigned c) const
      {
        const double *p = n0 + 3 * c, *q = n1 + 3 * c;
        const double *db = cell.db;
        return db[0] * p[0] + db[1] * p[1] + db[2] * p[2] + db[3] * q[0] + db[4] * q[1] +
               db[5] * q[2];
      }

    private:
      const double   *n0, *n1;
      const GridCell &cell;
    };

    // The coefficients of a member that does not vary over the cycle: their values, rates 0.
    struct ConstantPhase
    {
      const double *taylor;
      double        value(const unsigned c) const { return taylor[3 * c]; }
      double        rate(unsigned) const { return 0.0; }
    };

    // The law's coefficients: X_j and m_j of each member, computed exactly at a phase
    // (LadderMember::phase_coefficients) to make their table over the cycle for a member that
    // varies, once at the cycle's mean for one that does not; the model's phase coefficient is the
    // mesh angle itself, from which an evaluation interpolates the few coefficients it needs.
    class FeMapLaw : public MeshForceLaw
    {
    public:
      FeMapLaw(const table::StiffnessTable &table, const bool structural_varies,
               const bool hertz_varies)
        : n(table.hertz_exponent)
        , J(static_cast<unsigned>(table.ladder.n_rungs()))
        , structural(table.ladder.load_N, structural_part(table.ladder), 1.0, structural_varies,
                     false)
        , hertz(table.ladder.load_N, table.ladder.hertz_approach_m, table.hertz_exponent,
                hertz_varies, true)
        , top(table.ladder.load_N.back())
      {
        // The interpolants between positions must keep every rung's compression growing with
        // the load: checked at 8 phases per position (the interpolants' harmonics are at most
        // S / 2, so this samples each at 16 points per period of the highest).
        const std::size_t   S = table.ladder.n_positions(), n_check = 8 * S;
        std::vector<double> taylor(per_member());
        // The Hertzian spline's lowest end is natural when its slope there, the exponent the
        // layer continues with down to first touch, is at least 1 at every phase (a contact
        // that does not soften); else it is clamped to n.
        for (std::size_t i = 0; i < n_check && hertz.natural_lower_end(); ++i)
          {
            const double theta = 2.0 * M_PI * double(i) / n_check;
            hertz.phase_coefficients(std::cos(theta), std::sin(theta), taylor.data());
            if (!(hertz.lowest_slope(taylor) >= 1.0))
              hertz.clamp_lower_end();
          }
        for (const auto *m : {&structural, &hertz})
          {
            const char *member = m == &structural ? "structural" : "Hertzian";
            std::vector<std::vector<double>> taylors;
            for (std::size_t i = 0; i < n_check; ++i)
              {
                const double theta = 2.0 * M_PI * double(i) / n_check;
                m->phase_coefficients(std::cos(theta), std::sin(theta), taylor.data());
                const long j = m->not_increasing(taylor);
                HG_REQUIRE_INPUT(j < 0, "stiffness table: load_ladder: between its positions, at "
                                        "mesh phase ", double(i) / n_check, ", the ", member,
                                 " approach interpolated over the cycle does not grow from ",
                                 table.ladder.load_N[j], " N to ", table.ladder.load_N[j + 1],
                                 " N: the ladder needs more positions per cycle or rungs further "
                                 "apart");
                const long k = m->not_monotone(taylor);
                HG_REQUIRE_INPUT(k < 0, "stiffness table: load_ladder: at mesh phase ",
                                 double(i) / n_check, " the ", member, " force interpolated ",
                                 k + 1 < long(J) ? "between the rungs of " : "above the top rung of ",
                                 table.ladder.load_N[std::min<long>(k, J - 1)], " N",
                                 k + 1 < long(J) ? " and " + std::to_string(table.ladder.load_N[k + 1]) + " N" : std::string(),
                                 " does not grow with the compression: the ladder needs rungs "
                                 "closer together where its stiffness changes fast");
                if (i % 8 == 0)
                  taylors.push_back(taylor);
              }
            if (m == &structural)
              k_bound = structural.stiffness_bound(taylors);
          }
        structural_mean.assign(per_member(), 0.0);
        hertz_mean.assign(per_member(), 0.0);
        structural.mean_coefficients(structural_mean.data());
        hertz.mean_coefficients(hertz_mean.data());
        tabulate();
      }

      // One phase coefficient: the mesh angle theta (its Taylor triple theta, 1, 0 is exact).
      unsigned n_phase_coefficients() const override { return 1; }
      bool     varies_with_phase() const override { return structural.varies() || hertz.varies(); }
      void     phase_coefficients(const double c1, const double s1, double *taylor) const override
      {
        const double theta = std::atan2(s1, c1);
        taylor[0]          = theta < 0.0 ? theta + 2.0 * M_PI : theta;
        taylor[1]          = 1.0;
        taylor[2]          = 0.0;
      }

      void forces(const MeshPhase &phase, const double u, const double d, MeshLawForces &out,
                  const bool rates) const override
      {
        const auto member = [&](const LadderMember &m, const auto &ph, const double a,
                                const double p, double &F, double &dF_da, double &dF_dt) {
          if (a == 0.0)
            {
              // F = c_0 a^p near zero: slope c_0 for p = 1, else 0.
              F     = 0.0;
              dF_dt = 0.0;
              dF_da = p == 1.0 ? m.force(ph, 1.0e-30, false).dF_da : 0.0;
              return;
            }
          const MemberForce f = m.force(ph, std::abs(a), rates);
          F                   = sign(a) * f.F;
          dF_da               = f.dF_da;
          dF_dt               = sign(a) * f.dF_dt;
        };
        with_phases(phase, rates, [&](const auto &structural_phase, const auto &hertz_phase) {
          member(structural, structural_phase, u, 1.0, out.structural, out.structural_du,
                 out.structural_dt);
          member(hertz, hertz_phase, d, n, out.hertz, out.hertz_ddelta, out.hertz_dt);
        });
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
        double d = 0.5 * a;
        with_phases(phase, false, [&](const auto &structural_phase, const auto &hertz_phase) {
          double lo = 0.0, hi = a;
          for (int it = 0; it < 200; ++it)
            {
              const MemberForce r = structural.force(structural_phase, a - d, false),
                                h = hertz.force(hertz_phase, d, false);
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
        });
        return sign(f) * d;
      }

      MeshLawEnergy elastic_energy(const MeshPhase &phase, const double u,
                                   const double d) const override
      {
        MeshLawEnergy e;
        with_phases(phase, false, [&](const auto &structural_phase, const auto &hertz_phase) {
          e = {u == 0.0 ? 0.0 : structural.energy(structural_phase, std::abs(u)),
               d == 0.0 ? 0.0 : hertz.energy(hertz_phase, std::abs(d))};
        });
        return e;
      }

      void static_compressions(const double F, double &u, double &delta) const override
      {
        const ConstantPhase s{structural_mean.data()}, h{hertz_mean.data()};
        u     = F > 0.0 ? structural.compression(s, F) : 0.0;
        delta = F > 0.0 ? hertz.compression(h, F) : 0.0;
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

      // Coefficients per member (Taylor triples of X_j and m_j).
      unsigned per_member() const { return 3 * 2 * J; }

      // Calls f(structural phase, Hertzian phase) with each member's coefficients at the mesh
      // angle of `phase`: its table over the cycle (GridPhase) if it varies, else its constant
      // coefficients (ConstantPhase).
      template <class F>
      void with_phases(const MeshPhase &phase, const bool rates, F &&f) const
      {
        const ConstantPhase s{structural_mean.data()}, h{hertz_mean.data()};
        if (!varies_with_phase())
          return f(s, h);
        const GridCell cell(n_nodes, phase.value(0), phase.w, rates);
        const GridPhase sg(structural_grid, per_member(), cell), hg(hertz_grid, per_member(), cell);
        if (!structural.varies())
          return f(s, hg);
        if (!hertz.varies())
          return f(sg, h);
        f(sg, hg);
      }

      // The tables over the cycle of the members that vary: N = 2^k nodes, from 64 up, doubled
      // until the quintic reproduces every coefficient at every cell's midpoint within 1e-12
      // (X_j: of the logarithm, so relative in the compression; m_j: of the slope, ~1) and its
      // rate within 1e-10 per radian or the rounding floor of the rate, whichever is larger.
      void tabulate()
      {
        if (!varies_with_phase())
          return;
        const unsigned      per = per_member();
        std::vector<double> exact(per);
        double              previous_rate_error = std::numeric_limits<double>::infinity();
        for (n_nodes = 64;; n_nodes *= 2)
          {
            const double h = 2.0 * M_PI / n_nodes;
            double value_error = 0.0, rate_error = 0.0;
            for (const auto &[m, grid] : {std::pair{&structural, &structural_grid},
                                          std::pair{&hertz, &hertz_grid}})
              {
                if (!m->varies())
                  continue;
                grid->assign(std::size_t(n_nodes) * per, 0.0);
                for (unsigned i = 0; i < n_nodes; ++i)
                  {
                    double *node = grid->data() + std::size_t(i) * per;
                    m->phase_coefficients(std::cos(i * h), std::sin(i * h), node);
                    for (unsigned c = 0; c < per; c += 3)
                      {
                        node[c + 1] *= h;
                        node[c + 2] *= h * h;
                      }
                  }
                for (unsigned i = 0; i < n_nodes; ++i)
                  {
                    const double theta = (i + 0.5) * h;
                    m->phase_coefficients(std::cos(theta), std::sin(theta), exact.data());
                    const GridCell  cell(n_nodes, theta, 1.0, true);
                    const GridPhase g(*grid, per, cell);
                    for (unsigned c = 0; 3 * c < per; ++c)
                      {
                        value_error = std::max(value_error, std::abs(g.value(c) - exact[3 * c]));
                        rate_error  = std::max(rate_error, std::abs(g.rate(c) - exact[3 * c + 1]));
                      }
                  }
              }
            // The rate's error falls like h^5 until the rounding of the values (~1e-15 of log a,
            // times N / 2 pi) takes over and it grows with N: where it no longer falls it is at
            // that floor, and more nodes would not help (crowned pair, 17 positions: 8.7e-11,
            // 1.1e-10, 2.7e-10 at N = 1024, 2048, 4096).
            const bool rate_floor = rate_error > 0.25 * previous_rate_error;
            previous_rate_error   = rate_error;
            const bool converged  = value_error <= 1e-12 && (rate_error <= 1e-10 || rate_floor);
            HG_REQUIRE_INPUT(n_nodes < max_nodes || converged,
                             "stiffness table: load_ladder: its phase variation is too rough to "
                             "tabulate over the cycle: ", max_nodes, " nodes leave an error of ",
                             value_error, " in the logarithm of the compression (at most 1e-12) "
                             "and of ", rate_error, " in its derivative in the mesh angle (at "
                             "most 1e-10 per radian)");
            if (converged)
              return;
          }
      }

      // The most nodes of the table over the cycle.
      static constexpr unsigned max_nodes = 16384;

      double              n;
      unsigned            J;
      LadderMember        structural, hertz;
      double              top;
      double              k_bound = 0.0;
      std::vector<double> structural_mean, hertz_mean; // coefficients at the cycle's mean
      std::vector<double> structural_grid, hertz_grid; // tables over the cycle (members that vary)
      unsigned            n_nodes = 1;
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
    HG_REQUIRE_INPUT(table.ladder.n_rungs() <= max_rungs, "stiffness table: load_ladder: ",
                     table.ladder.n_rungs(), " loads; the FE force law takes at most ", max_rungs);
    HG_REQUIRE_INPUT(table.ladder.n_positions() <= 1024, "stiffness table: load_ladder: ",
                     table.ladder.n_positions(), " positions per cycle; the FE force law takes at "
                     "most 1024");
    return std::make_shared<FeMapLaw>(table, structural_varies, hertz_varies);
  }
} // namespace hertzgear::dynamics
