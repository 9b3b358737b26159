// The FE force law (docs/dynamics.md, "The FE force law"): the paper's serial mesh, a structural
// member in series with the Hertzian layer, with each member's force taken from the stiffness
// table's load ladder instead of a power law fitted at one load.
//
// A member (structural: exponent p = 1; Hertzian: p = n of the table) at rung j of load F_j has
// the compression a_j(theta) at the mesh angle theta. Across the mesh cycle its secant coefficient
// c_j = F_j / a_j^p is the trigonometric interpolant of its S positions (exactly the series of a
// ladder made from Fourier coefficients). Across the load, log F is the quintic spline of log a
// through the rungs (X_j = log a_j, Y_j = log F_j; C4, so that an integrator's error estimate does
// not see the rungs the motion crosses, and exact on a power law), its curvature and third
// derivative zero at the top, where it continues as the power law of its end slope (an
// extrapolation the analyses count, docs/dynamics.md). At the lowest rung the structural member's
// slope is 1 and its curvature 0 (linear below it down to first touch); the Hertzian member's
// spline is natural there too (curvature and third derivative 0) and continues below as the
// power law of its slope m_0 there, the FE's own exponent at light load, unless m_0 < 1 at some
// phase (a softening contact), when it is clamped to n. The spline is checked to grow at every
// phase (a ladder whose spline does not is refused).
//
// The coefficients X_j(theta) and the spline's slopes m_j(theta) and curvatures kappa_j(theta) of
// each member that varies over the cycle are computed exactly on N nodes over the cycle at
// construction; an evaluation interpolates the few it needs by the quintic Hermite polynomial of
// its cell (GridPhase), N doubled until that is exact to 1e-12 (docs/dynamics.md, "What an
// evaluation costs"). A member that does not vary keeps its coefficients at the cycle's mean
// (ConstantPhase). An evaluation without rates (the dynamic layer's) keeps what it found at a
// phase, the cell and each member's interval with its quintic (LadderMember::Segment, PhaseSlot),
// for the next evaluation at that phase: an implicit integrator comes back to each of its stage
// times once per Newton iteration.
#include "common/errors.h"
#include "common/fourier_series.h"
#include "dynamics/mesh_force_law.h"
#include "dynamics/power_law.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
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
        // The interval of constant_x at the left edge of each of `buckets` equal cells over
        // [x_0, x_{J-1}] (at least 2 rungs: the ladder's check), so that an evaluation finds its
        // interval's neighbourhood with one multiplication.
        double widest = 0.0;
        for (std::size_t j = 0; j + 1 < constant_x.size(); ++j)
          widest = std::max(widest, constant_x[j + 1] - constant_x[j]);
        kappa_weight = 0.01728 * widest * widest;
        bucket_scale = double(buckets) / (constant_x.back() - constant_x.front());
        for (unsigned b = 0; b < buckets; ++b)
          bucket_interval[b] = static_cast<int>(
            std::upper_bound(constant_x.begin(), constant_x.end(),
                             constant_x.front() + double(b) / bucket_scale) - constant_x.begin() - 1);
      }

      std::size_t n_rungs() const { return Y.size(); }
      // What an error in a curvature kappa_j does to log F at most, per unit: the largest
      // |H(t)| = t^2 (1 - t)^3 / 2 of its basis function (at t = 2/5) times D^2, D the widest
      // rung interval in X (at the cycle's mean).
      double curvature_weight() const { return kappa_weight; }
      // Phase coefficients of the member: X_j, m_j and kappa_j.
      unsigned n_phase_coefficients() const { return 3 * static_cast<unsigned>(Y.size()); }
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
        spline(taylor);
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
        spline(taylor);
      }

    private:
      // The quintic of interval i in t = (X - X_i) / D, D = X_{i+1} - X_i:
      // Y(t) = Y_i + t (c1 + t (c2 + t (c3 + t (c4 + t c5)))), the Hermite quintic of the values,
      // slopes s = D m and curvatures w = D^2 kappa (in t) at both ends.
      struct Piece
      {
        double Y0, c1, c2, c3, c4, c5;
        double m0, m1, k0, k1; // the data in X, for the rates
        double value(const double t) const
        {
          return Y0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))));
        }
        double slope(const double t) const // dY/dt
        {
          return c1 + t * (2.0 * c2 + t * (3.0 * c3 + t * (4.0 * c4 + 5.0 * t * c5)));
        }
      };

    public:
      // The force at the compression a > 0 with its derivatives in a and in time at fixed a
      // (without `rates` that in time is left 0).
      template <class Phase>
      MemberForce force(const Phase &ph, const double a, const bool rates = true) const
      {
        return rates ? force<true>(ph, a) : force<false>(ph, a);
      }
      template <bool rates, class Phase>
      MemberForce force(const Phase &ph, const double a) const
      {
        const double X = std::log(a);
        double       xk = 0.0, xk1 = 0.0;
        const long   k = interval(ph, X, xk, xk1);
        if constexpr (!rates)
          {
            Segment s;
            segment(ph, k, xk, xk1, s);
            return force(s, X, a);
          }
        const long J  = static_cast<long>(Y.size());
        double     Yv = 0, dY_dX = 0, dY_dt = 0;
        if (k < 0)
          {
            // Below the lowest rung: the power law of the spline's lowest slope m_0 (p when the
            // end is clamped).
            const double m  = lowest_slope(ph);
            const double dX = X - xk1;
            Yv              = Y[0] + m * dX;
            dY_dX           = m;
            if constexpr (rates)
              dY_dt = (natural_low ? ph.rate(slope_index(0)) * dX : 0.0) - m * xr(ph, 0);
          }
        else if (k == J - 1)
          {
            // Above the top: the power law of the spline's end slope.
            const double m  = ph.value(slope_index(std::size_t(J - 1)));
            const double dX = X - xk;
            Yv              = Y[J - 1] + m * dX;
            dY_dX           = m;
            if constexpr (rates)
              dY_dt = ph.rate(slope_index(std::size_t(J - 1))) * dX - m * xr(ph, std::size_t(J - 1));
          }
        else
          {
            const std::size_t i     = std::size_t(k);
            const double      D     = xk1 - xk;
            const double      inv_D = 1.0 / D;
            const double      t     = (X - xk) * inv_D;
            const Piece       q     = piece(ph, i, D);
            Yv                      = q.value(t);
            const double Yt         = q.slope(t); // dY/dt
            dY_dX                   = Yt * inv_D;
            if constexpr (rates)
              {
                // At fixed X the phase moves t (through x_i, x_{i+1}) and the piece's data
                // s = D m and w = D^2 kappa at both ends.
                const double r0 = xr(ph, i), Dr = xr(ph, i + 1) - r0;
                const double tr = -(r0 + t * Dr) * inv_D;
                const auto   H  = quintic_basis(t);
                const double s0r = Dr * q.m0 + D * ph.rate(slope_index(i)),
                             s1r = Dr * q.m1 + D * ph.rate(slope_index(i + 1));
                const double w0r = D * (2.0 * Dr * q.k0 + D * ph.rate(curvature_index(i))),
                             w1r = D * (2.0 * Dr * q.k1 + D * ph.rate(curvature_index(i + 1)));
                dY_dt = Yt * tr + H[0] * s0r + H[1] * w0r + H[2] * s1r + H[3] * w1r;
              }
          }
        const double F = std::exp(Yv);
        return {F, F * dY_dX / a, F * dY_dt};
      }

      // The force's law on one interval of X = log a at one phase: what force<false> finds there
      // (the interval and the quintic of its piece, or the power law beyond the ladder) before it
      // evaluates at X. An evaluation at a phase and in an interval met before starts from it and
      // skips the search, the six coefficients interpolated over the cycle, the piece and its
      // division (an implicit integrator's Newton iterations evaluate at the same stage times; a
      // member that does not vary has one per interval for every phase). Its force is that of
      // force<false> to the bit: the same operations on the same numbers.
      struct Segment
      {
        // It holds for lo <= X < hi (-inf and inf beyond the ladder; none before it is found).
        double lo = std::numeric_limits<double>::infinity(),
               hi = -std::numeric_limits<double>::infinity();
        bool   inside = false; // between two rungs: the quintic q in t = (X - x0) inv_D
        double x0 = 0, inv_D = 0;
        double m  = 0; // beyond the ladder: log F = q.Y0 + m (X - x0)
        Piece  q{};
        bool   holds(const double X) const { return X >= lo && X < hi; }
        void   clear()
        {
          lo = std::numeric_limits<double>::infinity();
          hi = -lo;
        }
      };
      // The segment s of the interval of X at the phase `ph`.
      template <class Phase>
      void find_segment(const Phase &ph, const double X, Segment &s) const
      {
        double     xk = 0.0, xk1 = 0.0;
        const long k = interval(ph, X, xk, xk1);
        segment(ph, k, xk, xk1, s);
      }
      // The force at X = log a > 0 on the segment that holds X (in time at fixed a: 0).
      MemberForce force(const Segment &s, const double X, const double a) const
      {
        double Yv, dY_dX;
        if (s.inside)
          {
            const double t = (X - s.x0) * s.inv_D;
            Yv             = s.q.value(t);
            dY_dX          = s.q.slope(t) * s.inv_D;
          }
        else
          {
            Yv    = s.q.Y0 + s.m * (X - s.x0);
            dY_dX = s.m;
          }
        const double F = std::exp(Yv);
        return {F, F * dY_dX / a, 0.0};
      }
      // The member's segments at the cycle's mean coefficients `ph` (a member that does not vary),
      // one per interval, and the one that holds X among them (found as interval() does).
      template <class Phase>
      void keep_mean_segments(const Phase &ph)
      {
        const long J = static_cast<long>(Y.size());
        mean_segments.clear();
        mean_segments.resize(std::size_t(J + 1));
        for (long k = -1; k < J; ++k)
          segment(ph, k, k >= 0 ? x(ph, std::size_t(k)) : 0.0,
                  k + 1 < J ? x(ph, std::size_t(k + 1)) : 0.0, mean_segments[std::size_t(k + 1)]);
      }
      const Segment &mean_segment(const double X) const
      {
        const long J = static_cast<long>(Y.size());
        long       k = bucket(X);
        for (long it = 0; it <= J; ++it)
          {
            const Segment &s = mean_segments[std::size_t(k + 1)];
            if (k >= 0 && X < s.lo)
              --k;
            else if (k + 1 < J && X >= s.hi)
              ++k;
            else
              break;
          }
        return mean_segments[std::size_t(k + 1)];
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
        const Piece  q  = piece(ph, k, D);
        // The quintic Y(t) on [0, 1], increasing (checked at construction): Newton steps kept
        // inside a shrinking bracket.
        double lo = 0.0, hi = 1.0, t = (Yt - Y[k]) / (Y[k + 1] - Y[k]);
        for (int it = 0; it < 100; ++it)
          {
            const double r  = q.value(t) - Yt;
            const double dr = q.slope(t);
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
      // The interval k of X (x_k <= X < x_{k+1}; -1 below the ladder, J - 1 above it) with x_k
      // and x_{k+1} there (those that exist): near the one among the x_j at the cycle's mean
      // (their bucket), then found with the phase's values.
      long bucket(const double X) const
      {
        const long   J = static_cast<long>(Y.size());
        const double b = (X - constant_x.front()) * bucket_scale;
        return !(b >= 0.0) ? -1 : (b >= double(buckets) ? J - 1 : bucket_interval[std::size_t(b)]);
      }
      template <class Phase>
      long interval(const Phase &ph, const double X, double &xk, double &xk1) const
      {
        const long J = static_cast<long>(Y.size());
        long       k = bucket(X);
        for (long it = 0; it <= J; ++it)
          {
            if (k >= 0 && X < (xk = x(ph, std::size_t(k))))
              --k;
            else if (k + 1 < J && X >= (xk1 = x(ph, std::size_t(k + 1))))
              ++k;
            else
              break;
          }
        return k;
      }
      // The segment s of the interval k, with x_k and x_{k+1} there, at the phase `ph`.
      template <class Phase>
      void segment(const Phase &ph, const long k, const double xk, const double xk1,
                   Segment &s) const
      {
        const long J = static_cast<long>(Y.size());
        s.inside     = false;
        s.lo = k < 0 ? -std::numeric_limits<double>::infinity() : xk;
        s.hi = k + 1 < J ? xk1 : std::numeric_limits<double>::infinity();
        if (k < 0)
          {
            // Below the lowest rung: the power law of the spline's lowest slope m_0 (p when the
            // end is clamped).
            s.m    = lowest_slope(ph);
            s.x0   = xk1;
            s.q.Y0 = Y[0];
          }
        else if (k == J - 1)
          {
            // Above the top: the power law of the spline's end slope.
            s.m    = ph.value(slope_index(std::size_t(J - 1)));
            s.x0   = xk;
            s.q.Y0 = Y[J - 1];
          }
        else
          {
            const double D = xk1 - xk;
            s.inside       = true;
            s.x0           = xk;
            s.inv_D        = 1.0 / D;
            piece(ph, std::size_t(k), D, s.q);
          }
      }

      // The Hermite slope at rung k and its rate.
      template <class Phase>
      Slope slope(const Phase &ph, const std::size_t k) const
      {
        const unsigned i = slope_index(k);
        return {ph.value(i), ph.rate(i)};
      }
      // Where X_j, m_j and kappa_j lie among the member's coefficients.
      static unsigned x_index(const std::size_t j) { return static_cast<unsigned>(3 * j); }
      static unsigned slope_index(const std::size_t k) { return static_cast<unsigned>(3 * k + 1); }
      static unsigned curvature_index(const std::size_t k) { return static_cast<unsigned>(3 * k + 2); }

      template <class Phase>
      Piece piece(const Phase &ph, const std::size_t i, const double D) const
      {
        Piece q;
        piece(ph, i, D, q);
        return q;
      }
      template <class Phase>
      void piece(const Phase &ph, const std::size_t i, const double D, Piece &q) const
      {
        q.m0 = ph.value(slope_index(i));
        q.m1 = ph.value(slope_index(i + 1));
        q.k0 = ph.value(curvature_index(i));
        q.k1 = ph.value(curvature_index(i + 1));
        const double dY = Y[i + 1] - Y[i], s0 = D * q.m0, s1 = D * q.m1, w0 = D * D * q.k0,
                     w1 = D * D * q.k1;
        q.Y0 = Y[i];
        q.c1 = s0;
        q.c2 = 0.5 * w0;
        q.c3 = 10.0 * dY - 6.0 * s0 - 4.0 * s1 - 1.5 * w0 + 0.5 * w1;
        q.c4 = -15.0 * dY + 8.0 * s0 + 7.0 * s1 + 1.5 * w0 - w1;
        q.c5 = 6.0 * dY - 3.0 * (s0 + s1) - 0.5 * (w0 - w1);
      }
      // The quintic Hermite basis functions of s0, w0, s1, w1 (those of the slopes and
      // curvatures; the values' do not move with the phase).
      static std::array<double, 4> quintic_basis(const double t)
      {
        const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
        return {t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5, 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5),
                -4.0 * t3 + 7.0 * t4 - 3.0 * t5, 0.5 * (t3 - 2.0 * t4 + t5)};
      }
      // The slope of the power law below the lowest rung.
      template <class Phase>
      double lowest_slope(const Phase &ph) const
      {
        return natural_low ? ph.value(slope_index(0)) : p;
      }
      // A Taylor triple (value, first and second derivative in the mesh angle).
      struct T3
      {
        double v = 0, d = 0, dd = 0;
        T3     operator+(const T3 &o) const { return {v + o.v, d + o.d, dd + o.dd}; }
        T3     operator-(const T3 &o) const { return {v - o.v, d - o.d, dd - o.dd}; }
        T3     operator*(const T3 &o) const
        {
          return {v * o.v, d * o.v + v * o.d, dd * o.v + 2.0 * d * o.d + v * o.dd};
        }
        friend T3 operator*(const double c, const T3 &a) { return {c * a.v, c * a.d, c * a.dd}; }
      };

      // The Taylor triples of the slopes m_j and curvatures kappa_j of the quintic spline in
      // (X, Y) through the rungs, from those of X_j. The spline is C4: at an interior rung, with
      // g = 1 / (X_{i+1} - X_i) of the intervals left (L) and right (R) of it and dY their rises,
      // the third and fourth derivatives of the two quintics agree:
      //   -8 gL^2 m_{j-1} - gL k_{j-1} + 12 (gR^2 - gL^2) m_j + 3 (gL + gR) k_j + 8 gR^2 m_{j+1}
      //     - gR k_{j+1} = 20 (dY_R gR^3 - dY_L gL^3),
      //   -14 gL^3 m_{j-1} - 2 gL^2 k_{j-1} - 16 (gL^3 + gR^3) m_j + 3 (gL^2 - gR^2) k_j
      //     - 14 gR^3 m_{j+1} + 2 gR^2 k_{j+1} = -30 (dY_L gL^4 + dY_R gR^4).
      // At the top kappa = 0 and Y''' = 0 (C3 into the straight line above it):
      //   -8 g^2 m_{J-2} - g k_{J-2} - 12 g^2 m_{J-1} + 3 g k_{J-1} = -20 dY g^3;
      // at the lowest rung kappa = 0 and either Y''' = 0 too (natural: C3 into the power law of
      // its slope below it), -12 g^2 m_0 - 3 g k_0 - 8 g^2 m_1 + g k_1 = -20 dY g^3, or m_0 = p
      // (clamped). On a power law (Y linear in X) m = p and kappa = 0 solve it. The derivatives
      // in the angle solve A z' = r' - A' z and A z'' = r'' - A'' z - 2 A' z' with the same
      // factors.
      void spline(double *taylor) const
      {
        const std::size_t J = Y.size();
        std::vector<T3>   g(J - 1);
        for (std::size_t i = 0; i + 1 < J; ++i)
          {
            const double *lo = taylor + 3 * x_index(i), *hi = taylor + 3 * x_index(i + 1);
            const double  h = hi[0] - lo[0], h1 = hi[1] - lo[1], h2 = hi[2] - lo[2];
            const double  g0 = 1.0 / h;
            g[i]             = {g0, -h1 * g0 * g0, (2.0 * h1 * h1 * g0 - h2) * g0 * g0};
          }
        // The matrix as 2 x 2 blocks (rows of rung j: its two equations; columns of rung i: m_i,
        // kappa_i): B[o][j][0, 1, 2] couple rung j to rungs j - 1, j, j + 1; derivative order o.
        using Blocks = std::vector<std::array<Eigen::Matrix2d, 3>>;
        std::array<Blocks, 3>                       B;
        std::array<std::vector<Eigen::Vector2d>, 3> r;
        for (int o = 0; o < 3; ++o)
          {
            B[o].assign(J, {Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero()});
            r[o].assign(J, Eigen::Vector2d::Zero());
          }
        // Equation e (0, 1) of rung j: the coefficient of m (kappa) of rung j + d, d = -1, 0, 1.
        const auto set_m = [&](const std::size_t j, const int e, const int d, const T3 &v) {
          B[0][j][d + 1](e, 0) = v.v;
          B[1][j][d + 1](e, 0) = v.d;
          B[2][j][d + 1](e, 0) = v.dd;
        };
        const auto set_k = [&](const std::size_t j, const int e, const int d, const T3 &v) {
          B[0][j][d + 1](e, 1) = v.v;
          B[1][j][d + 1](e, 1) = v.d;
          B[2][j][d + 1](e, 1) = v.dd;
        };
        const auto rhs = [&](const std::size_t j, const int e, const T3 &v) {
          r[0][j](e) = v.v;
          r[1][j](e) = v.d;
          r[2][j](e) = v.dd;
        };
        const T3 one{1.0, 0.0, 0.0};
        // Lowest rung: kappa_0 = 0; natural Y''' = 0 or clamped m_0 = p.
        set_k(0, 0, 0, one);
        if (natural_low)
          {
            const T3 g1 = g[0], g2 = g1 * g1, g3 = g2 * g1;
            set_m(0, 1, 0, -12.0 * g2);
            set_k(0, 1, 0, -3.0 * g1);
            set_m(0, 1, 1, -8.0 * g2);
            set_k(0, 1, 1, g1);
            rhs(0, 1, -20.0 * (Y[1] - Y[0]) * g3);
          }
        else
          {
            set_m(0, 1, 0, one);
            rhs(0, 1, p * one);
          }
        for (std::size_t j = 1; j + 1 < J; ++j)
          {
            const T3 gL = g[j - 1], gR = g[j], gL2 = gL * gL, gR2 = gR * gR, gL3 = gL2 * gL,
                     gR3 = gR2 * gR;
            const double dL = Y[j] - Y[j - 1], dR = Y[j + 1] - Y[j];
            set_m(j, 0, -1, -8.0 * gL2);
            set_k(j, 0, -1, -1.0 * gL);
            set_m(j, 0, 0, 12.0 * (gR2 - gL2));
            set_k(j, 0, 0, 3.0 * (gL + gR));
            set_m(j, 0, 1, 8.0 * gR2);
            set_k(j, 0, 1, -1.0 * gR);
            rhs(j, 0, 20.0 * (dR * gR3 - dL * gL3));
            set_m(j, 1, -1, -14.0 * gL3);
            set_k(j, 1, -1, -2.0 * gL2);
            set_m(j, 1, 0, -16.0 * (gL3 + gR3));
            set_k(j, 1, 0, 3.0 * (gL2 - gR2));
            set_m(j, 1, 1, -14.0 * gR3);
            set_k(j, 1, 1, 2.0 * gR2);
            rhs(j, 1, -30.0 * (dL * (gL3 * gL) + dR * (gR3 * gR)));
          }
        // Top: kappa = 0 and Y''' = 0.
        const std::size_t top = J - 1;
        const T3          g1 = g[top - 1], g2 = g1 * g1, g3 = g2 * g1;
        set_k(top, 0, 0, one);
        set_m(top, 1, -1, -8.0 * g2);
        set_k(top, 1, -1, -1.0 * g1);
        set_m(top, 1, 0, -12.0 * g2);
        set_k(top, 1, 0, 3.0 * g1);
        rhs(top, 1, -20.0 * (Y[top] - Y[top - 1]) * g3);

        // (A_o z)_j, from the blocks.
        using Vec = std::vector<Eigen::Vector2d>;
        const auto apply = [&](const int o, const Vec &z, const std::size_t j) {
          Eigen::Vector2d v = B[o][j][1] * z[j];
          if (j > 0)
            v += B[o][j][0] * z[j - 1];
          if (j + 1 < J)
            v += B[o][j][2] * z[j + 1];
          return v;
        };
        // Block elimination (block LU without pivoting between rungs), checked by the residual
        // of its solution; where that is not at the rounding of the data (a block pivot too
        // small), a dense LU with partial pivoting.
        std::vector<Eigen::Matrix2d> pivot_inverse(J), multiplier(J);
        pivot_inverse[0] = B[0][0][1].inverse();
        for (std::size_t j = 1; j < J; ++j)
          {
            multiplier[j]    = B[0][j][0] * pivot_inverse[j - 1];
            pivot_inverse[j] = (B[0][j][1] - multiplier[j] * B[0][j - 1][2]).inverse();
          }
        const auto block_solve = [&](Vec y) {
          for (std::size_t j = 1; j < J; ++j)
            y[j] -= multiplier[j] * y[j - 1];
          for (std::size_t j = J; j-- > 0;)
            y[j] = pivot_inverse[j] * (j + 1 < J ? Eigen::Vector2d(y[j] - B[0][j][2] * y[j + 1]) : y[j]);
          return y;
        };
        Vec    z0 = block_solve(r[0]);
        double residual = 0.0, size = 0.0;
        for (std::size_t j = 0; j < J; ++j)
          {
            residual = std::max(residual, (apply(0, z0, j) - r[0][j]).cwiseAbs().maxCoeff());
            size     = std::max(size, r[0][j].cwiseAbs().maxCoeff() +
                                      (B[0][j][0].cwiseAbs() + B[0][j][1].cwiseAbs() + B[0][j][2].cwiseAbs()).maxCoeff() *
                                        z0[j].cwiseAbs().maxCoeff());
          }
        const bool blocks = std::isfinite(residual) && residual <= 1e-13 * size;
        Eigen::PartialPivLU<Eigen::MatrixXd> lu;
        Eigen::VectorXd                      row_scale;
        const auto dense_solve = [&](const Vec &b) {
          Eigen::VectorXd v(2 * J);
          for (std::size_t j = 0; j < J; ++j)
            v.segment<2>(2 * j) = b[j];
          v = lu.solve(row_scale.asDiagonal() * v);
          Vec y(J);
          for (std::size_t j = 0; j < J; ++j)
            y[j] = v.segment<2>(2 * j);
          return y;
        };
        if (!blocks)
          {
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * J, 2 * J);
            for (std::size_t j = 0; j < J; ++j)
              for (int d = -1; d <= 1; ++d)
                if (long(j) + d >= 0 && long(j) + d < long(J))
                  A.block<2, 2>(2 * j, 2 * (j + d)) = B[0][j][d + 1];
            // Rows equilibrated (their powers of g differ by up to g^4).
            row_scale = A.cwiseAbs().rowwise().maxCoeff().cwiseInverse();
            lu.compute(row_scale.asDiagonal() * A);
            z0 = dense_solve(r[0]);
          }
        const auto solve = [&](const Vec &b) { return blocks ? block_solve(b) : dense_solve(b); };
        Vec b1(J), b2(J);
        for (std::size_t j = 0; j < J; ++j)
          b1[j] = r[1][j] - apply(1, z0, j);
        const Vec z1 = solve(b1);
        for (std::size_t j = 0; j < J; ++j)
          b2[j] = r[2][j] - apply(2, z0, j) - 2.0 * apply(1, z1, j);
        const Vec z2 = solve(b2);
        for (std::size_t j = 0; j < J; ++j)
          {
            double *slope_out = taylor + 3 * slope_index(j), *curvature_out = taylor + 3 * curvature_index(j);
            slope_out[0]      = z0[j](0);
            slope_out[1]      = z1[j](0);
            slope_out[2]      = z2[j](0);
            curvature_out[0]  = z0[j](1);
            curvature_out[1]  = z1[j](1);
            curvature_out[2]  = z2[j](1);
          }
      }

    public:
      // Where the interpolant does not grow with the compression at the phase of `taylor`: the
      // interval k (between rungs k and k + 1; J - 1 for the straight line above the top) whose
      // slope dY/dt, a quartic in t, is not positive somewhere on [0, 1], or -1. The quartic's
      // Bernstein coefficients bound it from below; where they do not prove it positive its
      // halves are examined (de Casteljau), and one still unproven on 2^-30 of the interval
      // counts as not growing.
      long not_monotone(const std::vector<double> &taylor) const
      {
        const MeshPhase   ph{taylor.data(), 0.0, 0.0};
        const std::size_t J = Y.size();
        for (std::size_t k = 0; k + 1 < J; ++k)
          {
            const Piece  q    = piece(ph, k, x(ph, k + 1) - x(ph, k));
            const double a[5] = {q.c1, 2.0 * q.c2, 3.0 * q.c3, 4.0 * q.c4, 5.0 * q.c5};
            // Bernstein coefficients of degree 4: b_i = sum_{j <= i} C(i, j) / C(4, j) a_j.
            static constexpr double C[5][5] = {{1, 0, 0, 0, 0},
                                               {1, 0.25, 0, 0, 0},
                                               {1, 0.5, 1.0 / 6.0, 0, 0},
                                               {1, 0.75, 0.5, 0.25, 0},
                                               {1, 1, 1, 1, 1}};
            std::array<double, 5> bernstein{};
            for (int i = 0; i < 5; ++i)
              for (int j = 0; j <= i; ++j)
                bernstein[i] += C[i][j] * a[j];
            if (!positive(bernstein, 0))
              return static_cast<long>(k);
          }
        return slope(ph, J - 1).m > 0.0 ? -1 : static_cast<long>(J - 1);
      }

    private:
      // Whether the quartic of Bernstein coefficients b is positive on its interval.
      static bool positive(const std::array<double, 5> &b, const int depth)
      {
        if (!(b[0] > 0.0 && b[4] > 0.0))
          return false; // its values at the ends
        if (*std::min_element(b.begin(), b.end()) > 0.0)
          return true;
        if (depth == 30)
          return false;
        // Its halves (de Casteljau at 1/2).
        std::array<double, 5> left{}, right{}, w = b;
        for (int level = 0; level < 5; ++level)
          {
            left[level]      = w[0];
            right[4 - level] = w[4 - level];
            for (int i = 0; i + level < 4; ++i)
              w[i] = 0.5 * (w[i] + w[i + 1]);
          }
        return positive(left, depth + 1) && positive(right, depth + 1);
      }

      // Positions per cycle the law takes (the interpolant's harmonics are at most half of them).
      static constexpr unsigned max_harmonics = 512;

      std::vector<double>        Y;           // log F_j
      std::vector<double>        mean_secant; // their means over the cycle
      std::vector<double>        cos_coefficient, sin_coefficient; // a_jh, b_jh
      std::vector<double>        constant_x;  // X_j at the mean coefficients
      std::vector<Segment>       mean_segments; // at the mean coefficients, interval k at k + 1
      static constexpr unsigned  buckets = 4 * max_rungs;
      std::array<int, buckets>   bucket_interval{}; // of constant_x, at each bucket's left edge
      double                     bucket_scale = 0; // buckets per unit of X
      double                     kappa_weight = 0; // curvature_weight()
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
      GridCell() = default;
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
      double      b[6] = {}, db[6] = {};
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
      [[gnu::always_inline]] double value(const unsigned c) const
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

    // What an evaluation without rates keeps of a phase on its thread (FeMapLaw::values): the
    // cell of its angle and, per member that varies, the segment it last evaluated there. An
    // implicit integrator evaluates the right-hand side at each stage time of a step once per
    // Newton iteration and its Jacobian at the step's start, the last stage time of the step
    // before: up to 10 phases (9 stages and the step's start) come back. The slots are filled in
    // turn and found by a hash of the angle's bits (an index of 256 entries, so that the phases of
    // a step rarely share one: one that loses its entry is filled again, the same to the bit).
    // Keyed by the law's id and the angle itself (not the model's 2^-36 phase key), a slot gives
    // what the law would compute there; per thread, as the models' phase store, nothing is shared.
    struct PhaseSlot
    {
      std::uint64_t         law = 0, theta = 0; // the law's id (0: empty) and the angle's bits
      GridCell              cell;
      LadderMember::Segment segment[2]; // structural, Hertzian
    };
    struct PhaseSlots
    {
      static constexpr unsigned n = 16;
      PhaseSlot                 slot[n];
      std::uint8_t              index[256] = {}; // by hash: the slot last filled with that hash
      unsigned                  next = 0;        // the slot filled next
    };
    thread_local PhaseSlots phase_slots;

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
                                 " does not grow with the compression: the smooth interpolant "
                                 "through its rungs cannot follow its stiffness there (a kink of "
                                 "the FE's stiffness in the load, as where a crowned contact "
                                 "crosses the contact grid's cells, which "
                                 "Stiffness/contact_grid_face_extent = load avoids, or rungs too "
                                 "far apart where it changes fast)");
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
        structural.keep_mean_segments(ConstantPhase{structural_mean.data()});
        hertz.keep_mean_segments(ConstantPhase{hertz_mean.data()});
        tabulate();
      }

      // One phase coefficient: the mesh angle theta (its Taylor triple theta, 1, 0 is exact).
      unsigned n_phase_coefficients() const override { return 1; }
      bool     varies_with_phase() const override { return structural.varies() || hertz.varies(); }
      void     phase_coefficients(const double theta, double, double, double *taylor) const override
      {
        const double period = 2.0 * M_PI;
        taylor[0] = theta >= 0.0 && theta < period ? theta : theta - period * std::floor(theta / period);
        taylor[1]          = 1.0;
        taylor[2]          = 0.0;
      }

      void forces(const MeshPhase &phase, const double u, const double d, MeshLawForces &out,
                  const bool rates) const override
      {
        if (rates)
          forces<true>(phase, u, d, out);
        else
          values(phase, u, d, out);
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
      // The forces at (phase, u, d) from the phase's coefficients, with rates for the quasi-static
      // layer (without them values() gives the same to the bit). Not inlined into forces(): it
      // would widen the frame of the path without rates, the common one.
      template <bool rates>
      [[gnu::noinline]] void forces(const MeshPhase &phase, const double u, const double d,
                                    MeshLawForces &out) const
      {
        const auto member = [&](const LadderMember &m, const auto &ph, const double a,
                                const double p, double &F, double &dF_da, double &dF_dt) {
          if (a == 0.0)
            {
              // F = c_0 a^p near zero: slope c_0 for p = 1, else 0.
              F     = 0.0;
              dF_dt = 0.0;
              dF_da = p == 1.0 ? m.template force<false>(ph, 1.0e-30).dF_da : 0.0;
              return;
            }
          const double        s = sign(a);
          const MemberForce   f = m.template force<rates>(ph, s * a);
          F                     = s * f.F;
          dF_da                 = f.dF_da;
          dF_dt                 = s * f.dF_dt;
        };
        with_phases(phase, rates, [&](const auto &structural_phase, const auto &hertz_phase) {
          member(structural, structural_phase, u, 1.0, out.structural, out.structural_du,
                 out.structural_dt);
          member(hertz, hertz_phase, d, n, out.hertz, out.hertz_ddelta, out.hertz_dt);
        });
        out.damping_weight       = power_law::H(d, n);
        out.damping_weight_slope = power_law::H_prime(d, n);
      }

      // forces<false> by segments (LadderMember::Segment): those of the members that vary kept by
      // phase on the thread (PhaseSlot), those of a member that does not vary made at
      // construction. The same forces to the bit.
      void values(const MeshPhase &phase, const double u, const double d, MeshLawForces &out) const
      {
        PhaseSlot *const slot = varies_with_phase() ? &phase_slot(phase.value(0)) : nullptr;
        value(structural, slot, 0, u, 1.0, out.structural, out.structural_du, out.structural_dt);
        value(hertz, slot, 1, d, n, out.hertz, out.hertz_ddelta, out.hertz_dt);
        if (n == 1.5)
          {
            // Point contact: H and H' of power_law with their one square root shared.
            const double r           = std::sqrt(std::abs(d));
            out.damping_weight       = std::abs(d) * r;
            out.damping_weight_slope = n * sign(d) * r;
          }
        else
          {
            out.damping_weight       = power_law::H(d, n);
            out.damping_weight_slope = power_law::H_prime(d, n);
          }
      }
      // One member's part of values() at its compression a (p its exponent).
      void value(const LadderMember &m, PhaseSlot *const slot, const unsigned which, const double a,
                 const double p, double &F, double &dF_da, double &dF_dt) const
      {
        if (a == 0.0)
          {
            // F = c_0 a^p near zero: slope c_0 for p = 1, else 0.
            F     = 0.0;
            dF_dt = 0.0;
            dF_da = p == 1.0 ? value(m, slot, which, 1.0e-30).dF_da : 0.0;
            return;
          }
        // The odd extension (as forces<false>: a sign of -1 negates, exactly).
        const bool        tension = a < 0.0;
        const MemberForce f       = value(m, slot, which, tension ? -a : a);
        F                         = tension ? -f.F : f.F;
        dF_da                     = f.dF_da;
        dF_dt                     = tension ? -f.dF_dt : f.dF_dt;
      }
      // The force of a member at a > 0 without rates: on its segment kept in the phase's slot if
      // it varies (found anew when X has left it), else on its segment at the mean.
      MemberForce value(const LadderMember &m, PhaseSlot *const slot, const unsigned which,
                        const double a) const
      {
        const double X = std::log(a);
        if (!m.varies())
          return m.force(m.mean_segment(X), X, a);
        LadderMember::Segment &s = slot->segment[which];
        if (!s.holds(X))
          find_segment(m, *slot, which, X);
        return m.force(s, X, a);
      }
      // Out of the common path (an evaluation at a phase and in an interval met before): the
      // search and the piece of a segment, the cell of a new phase.
      [[gnu::noinline]] void find_segment(const LadderMember &m, PhaseSlot &slot,
                                          const unsigned which, const double X) const
      {
        m.find_segment(GridPhase(which == 0 ? structural_grid : hertz_grid, per_member(), slot.cell),
                       X, slot.segment[which]);
      }

      // The slot of the mesh angle theta on this thread, filled (its cell, no segments) if it
      // holds another.
      PhaseSlot &phase_slot(const double theta) const
      {
        std::uint64_t bits;
        std::memcpy(&bits, &theta, sizeof bits);
        PhaseSlots        &slots = phase_slots;
        const std::uint8_t hash  = std::uint8_t((bits * 0x9E3779B97F4A7C15ull) >> 56);
        PhaseSlot         &found = slots.slot[slots.index[hash]];
        if (found.theta == bits && found.law == id())
          return found;
        return fill_slot(theta, bits, hash);
      }
      [[gnu::noinline]] PhaseSlot &fill_slot(const double theta, const std::uint64_t bits,
                                             const std::uint8_t hash) const
      {
        PhaseSlots    &slots = phase_slots;
        const unsigned j     = slots.next;
        slots.next           = j + 1 == PhaseSlots::n ? 0 : j + 1;
        slots.index[hash]    = std::uint8_t(j);
        PhaseSlot &slot      = slots.slot[j];
        slot.law             = id();
        slot.theta           = bits;
        slot.cell            = GridCell(n_nodes, theta, 0.0, false);
        slot.segment[0].clear();
        slot.segment[1].clear();
        return slot;
      }

      static std::vector<std::vector<double>> structural_part(const table::LoadLadder &l)
      {
        auto u = l.approach_m;
        for (std::size_t j = 0; j < u.size(); ++j)
          for (std::size_t s = 0; s < u[j].size(); ++s)
            u[j][s] -= l.hertz_approach_m[j][s];
        return u;
      }

      // Coefficients per member (Taylor triples of X_j, m_j and kappa_j).
      unsigned per_member() const { return 3 * 3 * J; }

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
      // (X_j: of the logarithm, so relative in the compression; m_j: of the slope, ~1; kappa_j:
      // its effect on log F, at most max|H| D^2 times its error, LadderMember::curvature_weight)
      // and its rate within 1e-10 per radian or the rounding floor of the rate, whichever is
      // larger.
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
                        // c = 3 j + 0, 1, 2: X_j, m_j, kappa_j.
                        const double weight = c % 3 == 2 ? m->curvature_weight() : 1.0;
                        value_error = std::max(value_error, weight * std::abs(g.value(c) - exact[3 * c]));
                        rate_error  = std::max(rate_error, weight * std::abs(g.rate(c) - exact[3 * c + 1]));
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
