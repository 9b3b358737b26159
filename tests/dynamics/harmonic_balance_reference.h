#pragma once
// Independent multi-harmonic harmonic-balance (HB) reference for the dimensionless backlash
// oscillator of Kahraman & Singh (1990) in the variant hertzgear uses (damping in contact only):
//   p'' + 2 zeta c(p) p' + f(p) = F_m + F_a cos(Omega t),
//   f(p) = p - 1 (p > 1), p + 1 (p < -1), 0 otherwise;  c(p) = 1 for |p| >= 1, 0 in the backlash.
// It does not use the library; see tests/dynamics/test_kahraman_singh.cc for the two-term version.
//
// Method.
//  * Harmonic balance (Galerkin projection on 1, cos k tau, sin k tau, k = 1..H, tau = Omega t) of
//      Omega^2 p'' + 2 zeta Omega c(p) p' + f(p) = F_m + F_a cos(tau + psi),
//    the multi-harmonic extension of the mean + first-harmonic balance of Comparin & Singh (1989)
//    (J. Sound Vib. 134(2)) used by Kahraman & Singh (1990) (J. Sound Vib. 142(1)); see Krack &
//    Gross (2019), "Harmonic Balance for Nonlinear Vibration Problems", Springer, ch. 2-4.
//    The time origin is fixed by b_1 = 0 and the forcing phase psi is an unknown: the unknowns are
//    (a_0, a_1, a_2, b_2, ..., a_H, b_H, psi, Omega), 2H + 2 of them for 2H + 1 equations.
//  * Nonlinear force: alternating frequency/time scheme (Cameron & Griffin 1989, J. Appl. Mech.
//    56(1)) with exact segment integration. p is sampled on max(N, 256) equidistant times; there the
//    contact switches |p| = 1 are bracketed and then refined as roots of the trigonometric polynomial
//    p (safeguarded Newton). On a contact interval the force g = p -+ 1 + 2 zeta Omega p' is itself a
//    trigonometric polynomial, so its Fourier coefficients are integrated in closed form. This
//    removes the O(1/N) error of plain sampled AFT, which c(p) p' (discontinuous at every switch)
//    would otherwise cause, and makes the residual smooth so Newton converges quadratically.
//    Measured: the plain-AFT residual at the exact-segment fold state decays only like 1/N, with
//    erratic sign; its first-order effect on Omega_down is 3.9e-3 / 1.3e-3 (H = 16, N = 8H / 16H),
//    1.2e-3 / 9e-5 (H = 32) and 1e-4 (H = 64), and Newton on the discontinuous plain-AFT residual
//    stalls at the level of its jumps. For N -> infinity it tends to the exact-segment residual.
//  * Analytic Jacobian. The moving switches tau* contribute -+ (zeta Omega / pi) (dp/dy)(tau*)
//    e^{-ik tau*} (g jumps by 2 zeta Omega p' there and dtau*/dy = -(dp/dy) / p'). Checked against
//    central differences: agreement to 1e-10.
//  * Continuation: pseudo-arclength in all unknowns (predictor along the tangent, chord-Newton
//    corrector), started from the contact-linear solution (no separation) on the lower branch at
//    Omega = 0.5 and on the resonant branch at Omega = 1.3, in the direction of growing amplitude.
//    The first fold met from each start is located as the root of the Omega component of the
//    tangent (Illinois regula falsi on the arclength, |t_Omega| < 1e-12): the upper fold Omega_up
//    (local maximum of Omega on the lower branch: the up-sweep jump) and the lower fold Omega_down
//    (minimum of Omega on the resonant branch: the down-sweep jump).
//
// Measured (zeta = 0.05, F_m = 0.1, F_a = 0.02; results identical for N = 8H and 16H, since the
// quadrature is exact and N only serves to bracket the switches):
//      H     Omega_up        Omega_down      a1_down      hp2p_down   time (g++ -O2)
//      1     0.9085044944    0.4009126810    1.2576000    1.2576000   (the two-term values)
//      4     0.9090341184    0.3973323790    1.2622600    1.3563226
//      8     0.9090755258    0.3951411249    1.2590872    1.3681817
//     16     0.9090755137    0.3948392252    1.2590344    1.3676853
//     32     0.9090755737    0.3948118049    1.2590189    1.3676260   0.03 s
//     64     0.9090755829    0.3948082857    1.2590197    1.3676325   0.1 s
//    128     0.9090755836    0.3948078111    1.2590197    1.3676329   0.7 s
//    256     0.9090755837    0.3948077514    1.2590196    1.3676329   3.7 s
//    512     0.9090755837    0.3948077440    1.2590196    1.3676329    35 s
// The lower fold converges as H^-3 (successive differences shrink by 7.4-8.0 per doubling of H:
// f has kinks and c(p) p' jumps at the switches, so p'' is discontinuous and the Fourier
// coefficients of p decay like k^-3). Richardson limit Omega_down = 0.3948077429; error at
// H = 32: 4.1e-6 (1.0e-5 relative), H = 64: 5.4e-7 (1.4e-6 relative), H = 128: 6.8e-8.
// Omega_up (barely any separation there) = 0.9090755837, error < 1e-7 from H = 16 on.
// Checked against RK4 time integration with the contact switches located (20000 steps per period,
// 400 periods). Half peak-to-peak on the resonant branch: at Omega = 0.7, 0.376408590 (HB, H = 64:
// 0.376408612); at Omega = 0.45, 1.032931476 (HB, H = 64: 1.032932321; H = 128: 1.032931629).
// Started on the HB branch (4000 steps per period, 6000 periods), the integration stays on the
// lower branch at Omega_up - 1e-5 and jumps up at Omega_up + 1e-5. It stays on the resonant
// branch at Omega_down + 1e-5 and jumps at Omega_down - 1e-5.
// Recommended for a unit test: H = 64, N = 8H (0.1 s with -O2, 3-4 s at -O0, 1.4 s with ASan/UBSan).
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace hertzgear::dynamics::testing
{
  struct HbFold
  {
    double omega;                    // frequency of the fold (extremum of Omega along the curve)
    double amplitude_first_harmonic; // sqrt(a_1^2 + b_1^2) of p at the fold
    double half_peak_to_peak;        // (max p - min p) / 2 at the fold
  };

  // Periodic HB solution p(tau) = mean + sum_k a_k cos(k tau) + b_k sin(k tau), tau = Omega t,
  // forced by F_m + F_a cos(tau + forcing_phase) (b_1 = 0 by the choice of the time origin).
  struct HbSolution
  {
    double          omega = 0, forcing_phase = 0, mean = 0;
    Eigen::VectorXd a, b; // a(k-1), b(k-1) for k = 1..H
    double          amplitude_first_harmonic = 0, half_peak_to_peak = 0, p_max = 0, p_min = 0;

    double p(const double tau) const
    {
      double s = mean;
      for (int k = 1; k <= a.size(); ++k)
        s += a(k - 1) * std::cos(k * tau) + b(k - 1) * std::sin(k * tau);
      return s;
    }
  };

  enum class HbBranch
  {
    lower,   // from small Omega up to the upper fold (stable; an up-sweep follows it)
    resonant // from large Omega down to the lower fold (stable; a down-sweep follows it)
  };

  namespace hb_detail
  {
    using Vec = Eigen::VectorXd;
    using Mat = Eigen::MatrixXd;
    using cplx = std::complex<double>;

    // The dimensionless backlash oscillator with damping in contact only, in tau = Omega t:
    //   Omega^2 p'' + 2 zeta Omega c(p) p' + f(p) = F_m + F_a cos(tau + psi).
    // Unknowns y (2H + 2): [a_0, a_1, a_2, b_2, ..., a_H, b_H, psi, Omega] (b_1 = 0).
    // Equations (2H + 1): [R_0, R_1c, R_1s, ..., R_Hc, R_Hs].
    class KahramanSinghHb
    {
    public:
      KahramanSinghHb(const double zeta, const double F_m, const double F_a, const int H, const int N)
        : zeta_(zeta), F_m_(F_m), F_a_(F_a), H_(H)
      {
        if (H < 1 || N < 4)
          throw std::invalid_argument("harmonic balance: H >= 1 and N >= 4 required");
        if (!(zeta > 0 && F_m > 0 && F_a > 0 && 2 * F_a < F_m))
          throw std::invalid_argument("harmonic balance: needs zeta, F_m, F_a > 0 and F_a < F_m / 2 "
                                      "(contact-linear starts of the continuation)");
        // Time grid on which the contact switches are bracketed (at least 256 samples).
        M_ = std::max(N, 256);
        cos_.resize(M_, H_);
        sin_.resize(M_, H_);
        for (int n = 0; n < M_; ++n)
          for (int k = 1; k <= H_; ++k)
            {
              const double th = 2 * M_PI * double(n) * k / M_;
              cos_(n, k - 1)  = std::cos(th);
              sin_(n, k - 1)  = std::sin(th);
            }
      }

      int    H() const { return H_; }
      int    n_unknowns() const { return 2 * H_ + 2; }
      int    n_equations() const { return 2 * H_ + 1; }
      int    omega_index() const { return 2 * H_ + 1; }
      int    phase_index() const { return 2 * H_; }
      double zeta() const { return zeta_; }
      static constexpr double step_tolerance = 1e-12, residual_tolerance = 1e-12; // Newton

      void split(const Vec &y, double &a0, Vec &a, Vec &b) const
      {
        a0 = y(0);
        a.setZero(H_);
        b.setZero(H_);
        a(0) = y(1);
        for (int k = 2; k <= H_; ++k)
          {
            a(k - 1) = y(2 * k - 2);
            b(k - 1) = y(2 * k - 1);
          }
      }

      // p, p', p'' at tau.
      void eval(const double a0, const Vec &a, const Vec &b, const double tau, double &p, double &dp,
                double &ddp) const
      {
        p = a0;
        dp = ddp = 0;
        const cplx z(std::cos(tau), std::sin(tau));
        cplx       zk(1, 0);
        for (int k = 1; k <= H_; ++k)
          {
            zk *= z;
            if (k % 16 == 0)
              zk = cplx(std::cos(k * tau), std::sin(k * tau)); // limit the round-off drift
            const double c = zk.real(), s = zk.imag();
            p += a(k - 1) * c + b(k - 1) * s;
            dp += k * (-a(k - 1) * s + b(k - 1) * c);
            ddp -= double(k) * k * (a(k - 1) * c + b(k - 1) * s);
          }
      }

      int ia(const int m) const { return m == 0 ? 0 : (m == 1 ? 1 : 2 * m - 2); } // index of a_m in y
      int ib(const int m) const { return m == 1 ? -1 : 2 * m - 1; }               // index of b_m (b_1 = 0)

      // Residual; with J != nullptr also its analytic Jacobian.
      Vec residual(const Vec &y, Mat *J = nullptr) const
      {
        double a0;
        Vec    a, b;
        split(y, a0, a, b);
        const double      psi = y(phase_index()), W = y(omega_index());
        std::vector<cplx> G(H_ + 1); // G_k = (1/2pi) int g e^{-ik tau}: g_kc = 2 Re G_k, g_ks = -2 Im G_k
        Eigen::MatrixXcd  dG;
        force_exact(a0, a, b, W, G, J ? &dG : nullptr);
        Vec r(n_equations());
        r(0) = G[0].real() - F_m_;
        for (int k = 1; k <= H_; ++k)
          {
            r(2 * k - 1) = -W * W * k * k * a(k - 1) + 2 * G[k].real();
            r(2 * k)     = -W * W * k * k * b(k - 1) - 2 * G[k].imag();
          }
        r(1) -= F_a_ * std::cos(psi);
        r(2) += F_a_ * std::sin(psi);
        if (J)
          {
            J->setZero(n_equations(), n_unknowns());
            J->row(0) = dG.row(0).real();
            for (int k = 1; k <= H_; ++k)
              {
                J->row(2 * k - 1) = 2 * dG.row(k).real();
                J->row(2 * k)     = -2 * dG.row(k).imag();
                (*J)(2 * k - 1, ia(k)) -= W * W * k * k;
                if (k > 1)
                  (*J)(2 * k, ib(k)) -= W * W * k * k;
                (*J)(2 * k - 1, omega_index()) -= 2 * W * k * k * a(k - 1);
                (*J)(2 * k, omega_index()) -= 2 * W * k * k * b(k - 1);
              }
            (*J)(1, phase_index()) += F_a_ * std::sin(psi);
            (*J)(2, phase_index()) += F_a_ * std::cos(psi);
          }
        return r;
      }

      Mat jacobian(const Vec &y) const
      {
        Mat J;
        residual(y, &J);
        return J;
      }

      // Central-difference Jacobian, to check the analytic one.
      Mat jacobian_fd(const Vec &y, const double h = 1e-6) const
      {
        Mat J(n_equations(), n_unknowns());
        for (int j = 0; j < n_unknowns(); ++j)
          {
            Vec yp = y, ym = y;
            yp(j) += h;
            ym(j) -= h;
            J.col(j) = (residual(yp) - residual(ym)) / (2 * h);
          }
        return J;
      }

      // Max and min of p over the period (grid search refined by Newton on p' = 0).
      void extrema(const Vec &y, double &pmax, double &pmin) const
      {
        double a0;
        Vec    a, b;
        split(y, a0, a, b);
        const int grid = std::max(M_, 64 * H_);
        pmax           = -std::numeric_limits<double>::infinity();
        pmin           = std::numeric_limits<double>::infinity();
        std::vector<double> v(grid);
        for (int n = 0; n < grid; ++n)
          {
            double dp, ddp;
            eval(a0, a, b, 2 * M_PI * n / grid, v[n], dp, ddp);
          }
        for (int n = 0; n < grid; ++n)
          {
            const double l = v[(n + grid - 1) % grid], c = v[n], r = v[(n + 1) % grid];
            const bool   is_max = c >= l && c >= r, is_min = c <= l && c <= r;
            if (!is_max && !is_min)
              continue;
            double       tau = 2 * M_PI * n / grid, p, dp, ddp;
            const double h = 2 * M_PI / grid;
            double       best = c;
            for (int it = 0; it < 20; ++it)
              {
                eval(a0, a, b, tau, p, dp, ddp);
                if (is_max ? p > best : p < best)
                  best = p;
                if (ddp == 0)
                  break;
                const double step = -dp / ddp;
                if (std::abs(step) > h)
                  break; // stay in the grid cell
                tau += step;
                if (std::abs(step) < 1e-15)
                  break;
              }
            eval(a0, a, b, tau, p, dp, ddp);
            if (is_max ? p > best : p < best)
              best = p;
            if (is_max)
              pmax = std::max(pmax, best);
            if (is_min)
              pmin = std::min(pmin, best);
          }
      }

      HbSolution solution(const Vec &y) const
      {
        HbSolution s;
        split(y, s.mean, s.a, s.b);
        s.omega                    = y(omega_index());
        s.forcing_phase            = y(phase_index());
        s.amplitude_first_harmonic = std::hypot(s.a(0), s.b(0));
        extrema(y, s.p_max, s.p_min);
        s.half_peak_to_peak = 0.5 * (s.p_max - s.p_min);
        return s;
      }

    private:
      static double f(const double p) { return p > 1 ? p - 1 : (p < -1 ? p + 1 : 0.0); }

      // Root of p(tau) - level in (tl, tr] where p - level changes sign (dl: its value at tl).
      double root(const double a0, const Vec &a, const Vec &b, const double level, double tl, double tr,
                  const double dl) const
      {
        double t = 0.5 * (tl + tr);
        for (int it = 0; it < 100; ++it)
          {
            double p, dp, ddp;
            eval(a0, a, b, t, p, dp, ddp);
            const double d = p - level;
            if ((d > 0) == (dl > 0))
              tl = t;
            else
              tr = t;
            double tn = dp != 0 ? t - d / dp : 0.5 * (tl + tr);
            if (!(tn > tl && tn < tr))
              tn = 0.5 * (tl + tr);
            if (std::abs(tn - t) < 1e-15 || tr - tl < 1e-15)
              return tn;
            t = tn;
          }
        return t;
      }

      // Contact intervals {p >= 1} (upper) or {p <= -1}, as [start, end] with end > start; the
      // switches are appended to `switches` as (tau, +1 for a start, -1 for an end).
      void intervals(const double a0, const Vec &a, const Vec &b, const Vec &pg, const bool upper,
                     std::vector<std::pair<double, double>> &out,
                     std::vector<std::pair<double, double>> &switches) const
      {
        const double        level = upper ? 1.0 : -1.0;
        std::vector<double> roots;
        std::vector<bool>   entering;
        for (int n = 0; n < M_; ++n)
          {
            const double dl = pg(n) - level, dr = pg((n + 1) % M_) - level;
            if ((dl > 0) != (dr > 0))
              {
                roots.push_back(root(a0, a, b, level, 2 * M_PI * n / M_, 2 * M_PI * (n + 1) / M_, dl));
                entering.push_back(upper ? dr > 0 : dr <= 0);
              }
          }
        if (roots.empty())
          {
            if (upper ? pg(0) > level : pg(0) <= level)
              out.emplace_back(0.0, 2 * M_PI);
            return;
          }
        const std::size_t m = roots.size();
        for (std::size_t i = 0; i < m; ++i)
          if (entering[i])
            {
              const double end = i + 1 < m ? roots[i + 1] : roots[0] + 2 * M_PI;
              out.emplace_back(roots[i], end);
              switches.emplace_back(roots[i], 1.0);
              switches.emplace_back(end, -1.0);
            }
      }

      // Exact Fourier coefficients of g = chi_contact (p + 2 zeta W p') - chi_upper + chi_lower, and
      // optionally their derivatives dG (H+1 x n_unknowns). In dG, the motion of a contact switch
      // tau* contributes -+ (zeta W / pi) dp/dy(tau*) e^{-ik tau*} (g jumps by 2 zeta W p' there
      // and dtau*/dy = -(dp/dy) / p').
      void force_exact(const double a0, const Vec &a, const Vec &b, const double W, std::vector<cplx> &G,
                       Eigen::MatrixXcd *dG) const
      {
        const Vec                              pg = (cos_ * a + sin_ * b).array() + a0;
        std::vector<std::pair<double, double>> up, lo, switches;
        intervals(a0, a, b, pg, true, up, switches);
        intervals(a0, a, b, pg, false, lo, switches);
        // E_m = (1/2pi) int_I e^{i m tau} dtau, m = 0..2H (E_{-m} = conj E_m).
        const int         L = 2 * H_;
        std::vector<cplx> Eu(L + 1, 0.0), El(L + 1, 0.0), Ec(2 * L + 1);
        auto              accumulate = [&](const std::vector<std::pair<double, double>> &iv,
                                  std::vector<cplx> &E) {
          for (const auto &[s, e] : iv)
            {
              E[0] += (e - s) / (2 * M_PI);
              const cplx zs(std::cos(s), std::sin(s)), ze(std::cos(e), std::sin(e));
              cplx       ps(1, 0), pe(1, 0);
              for (int m = 1; m <= L; ++m)
                {
                  ps *= zs;
                  pe *= ze;
                  if (m % 16 == 0)
                    {
                      ps = cplx(std::cos(m * s), std::sin(m * s));
                      pe = cplx(std::cos(m * e), std::sin(m * e));
                    }
                  E[m] += (pe - ps) / cplx(0, 2 * M_PI * m);
                }
            }
        };
        accumulate(up, Eu);
        accumulate(lo, El);
        for (int m = 0; m <= L; ++m)
          {
            Ec[L + m] = Eu[m] + El[m];
            Ec[L - m] = std::conj(Ec[L + m]);
          }
        auto E  = [](const std::vector<cplx> &v, const int m) { return m >= 0 ? v[m] : std::conj(v[-m]); };
        auto EC = [&](const int m) { return Ec[L + m]; };
        // P_j, Q_j: complex coefficients of p and of q = p + 2 zeta W p', j = -H..H.
        std::vector<cplx> P(2 * H_ + 1), Q(2 * H_ + 1);
        P[H_] = Q[H_] = a0;
        for (int j = 1; j <= H_; ++j)
          {
            P[H_ + j] = 0.5 * cplx(a(j - 1), -b(j - 1));
            P[H_ - j] = std::conj(P[H_ + j]);
            Q[H_ + j] = P[H_ + j] * cplx(1.0, 2 * zeta_ * W * j);
            Q[H_ - j] = std::conj(Q[H_ + j]);
          }
        for (int k = 0; k <= H_; ++k)
          {
            cplx g = -E(Eu, -k) + E(El, -k);
            for (int j = -H_; j <= H_; ++j)
              g += Q[H_ + j] * EC(j - k);
            G[k] = g;
          }
        if (!dG)
          return;
        dG->setZero(H_ + 1, n_unknowns());
        for (int k = 0; k <= H_; ++k)
          {
            (*dG)(k, 0) += EC(-k);
            cplx dw = 0;
            for (int m = 1; m <= H_; ++m)
              {
                const cplx qa = 0.5 * cplx(1.0, 2 * zeta_ * W * m); // dQ_m / da_m; dQ_-m = conj
                const cplx qb = cplx(0, -1) * qa;                    // dQ_m / db_m
                (*dG)(k, ia(m)) += qa * EC(m - k) + std::conj(qa) * EC(-m - k);
                if (m > 1)
                  (*dG)(k, ib(m)) += qb * EC(m - k) + std::conj(qb) * EC(-m - k);
                const cplx dq = P[H_ + m] * cplx(0, 2 * zeta_ * m); // dQ_m / dW
                dw += dq * EC(m - k) + std::conj(dq) * EC(-m - k);
              }
            (*dG)(k, omega_index()) += dw;
          }
        std::vector<double> cm(H_ + 1), sm(H_ + 1);
        for (const auto &[t, sign] : switches)
          {
            const double c = sign * zeta_ * W / M_PI;
            for (int m = 0; m <= H_; ++m)
              {
                cm[m] = std::cos(m * t);
                sm[m] = std::sin(m * t);
              }
            for (int k = 0; k <= H_; ++k)
              {
                const cplx ek = c * cplx(cm[k], -sm[k]);
                (*dG)(k, 0) += ek;
                for (int m = 1; m <= H_; ++m)
                  {
                    (*dG)(k, ia(m)) += ek * cm[m];
                    if (m > 1)
                      (*dG)(k, ib(m)) += ek * sm[m];
                  }
              }
          }
      }

      double       zeta_, F_m_, F_a_;
      int          H_, M_;
      Mat          cos_, sin_;
    };

    // Newton on R(y) = 0 plus the scalar constraint c^T (y - y_ref) = s. With `J_frozen` (the
    // Jacobian at a nearby point) chord iterations, otherwise a fresh Jacobian per iteration.
    inline bool correct(const KahramanSinghHb &hb, Vec &y, const Vec &c, const Vec &y_ref, const double s,
                        int &iterations, const int max_iterations, const Mat *J_frozen = nullptr)
    {
      const int                  n = hb.n_unknowns();
      Mat                        A(n, n);
      Eigen::PartialPivLU<Mat>   lu;
      if (J_frozen)
        {
          A.topRows(n - 1) = *J_frozen;
          A.row(n - 1)     = c.transpose();
          lu.compute(A);
        }
      for (iterations = 1; iterations <= max_iterations; ++iterations)
        {
          Mat       J;
          const Vec r = J_frozen ? hb.residual(y) : hb.residual(y, &J);
          if (!r.allFinite())
            return false;
          Vec rhs(n);
          rhs.head(n - 1) = -r;
          rhs(n - 1)      = -(c.dot(y - y_ref) - s);
          if (!J_frozen)
            {
              A.topRows(n - 1) = J;
              A.row(n - 1)     = c.transpose();
              lu.compute(A);
            }
          const Vec dy = lu.solve(rhs);
          if (!dy.allFinite())
            return false;
          y += dy;
          if (dy.norm() < KahramanSinghHb::step_tolerance * (1 + y.norm()))
            return hb.residual(y).norm() < KahramanSinghHb::residual_tolerance;
        }
      return false;
    }

    // Unit tangent of the solution curve from the Jacobian J at y, oriented along `orientation`.
    inline Vec tangent(const Mat &J, const Vec &orientation)
    {
      const int n = int(J.cols());
      Mat       A(n, n);
      A.topRows(n - 1) = J;
      A.row(n - 1)     = orientation.transpose();
      Vec rhs          = Vec::Zero(n);
      rhs(n - 1)       = 1;
      Vec t            = A.partialPivLu().solve(rhs);
      t.normalize();
      if (t.dot(orientation) < 0)
        t = -t;
      return t;
    }

    struct CurvePoint
    {
      Vec y, t;
      Mat J;
    };

    // Fold between p0 and p1 (the Omega component of the tangent changes sign): root of t_Omega(s),
    // s the arclength along p0.t, by the Illinois variant of regula falsi.
    inline Vec refine_fold(const KahramanSinghHb &hb, const CurvePoint &p0, const CurvePoint &p1)
    {
      const int  iw = hb.omega_index();
      const Vec &c  = p0.t;
      double     sl = 0, sr = c.dot(p1.y - p0.y);
      double     fl = p0.t(iw), fr = p1.t(iw);
      Vec        yl = p0.y, yr = p1.y, best = std::abs(fl) < std::abs(fr) ? yl : yr;
      int        side = 0;
      for (int it = 0; it < 60; ++it)
        {
          double s = (sl * fr - sr * fl) / (fr - fl);
          if (!(s > sl && s < sr))
            s = 0.5 * (sl + sr);
          Vec y = yl + (s - sl) / (sr - sl) * (yr - yl);
          int its;
          if (!correct(hb, y, c, p0.y, s, its, 20))
            throw std::runtime_error("harmonic balance: fold refinement failed");
          const double fs = tangent(hb.jacobian(y), c)(iw);
          best            = y;
          if (std::abs(fs) < 1e-12 || sr - sl < 1e-12)
            break;
          if ((fs > 0) == (fl > 0))
            {
              sl = s, fl = fs, yl = y;
              if (side == -1)
                fr *= 0.5;
              side = -1;
            }
          else
            {
              sr = s, fr = fs, yr = y;
              if (side == 1)
                fl *= 0.5;
              side = 1;
            }
        }
      return best;
    }

    struct Trace
    {
      std::vector<Vec> path; // the continuation points
      bool             fold_found = false, target_found = false;
      Vec              fold, target;
    };

    // Pseudo-arclength continuation from the contact-linear solution at omega_start, in the direction
    // of increasing first-harmonic amplitude, up to the first Omega fold (which is refined), or up to
    // omega_target if that comes first (then the solution there is returned).
    inline Trace trace(const KahramanSinghHb &hb, const double F_m, const double F_a, const double omega_start,
                       const double omega_target = std::numeric_limits<double>::quiet_NaN())
    {
      const int n  = hb.n_unknowns();
      const int iw = hb.omega_index(), ip = hb.phase_index();
      Vec       y  = Vec::Zero(n);
      // Permanent contact (needs |1 - W^2| > F_a / F_m): p = 1 + F_m + A cos tau with
      // (1 - W^2) A = F_a cos psi, 2 zeta W A = F_a sin psi.
      {
        const double W = omega_start, re = 1 - W * W, im = 2 * hb.zeta() * W;
        y(0)           = 1 + F_m;
        y(1)           = F_a / std::hypot(re, im);
        y(ip)          = std::atan2(im, re);
        y(iw)          = W;
      }
      Vec e = Vec::Zero(n);
      e(iw) = 1;
      auto at_omega = [&](Vec &z, const double W) {
        Vec zref = z;
        zref(iw) = W;
        int its;
        return correct(hb, z, e, zref, 0.0, its, 30);
      };
      if (!at_omega(y, omega_start))
        throw std::runtime_error("harmonic balance: no start solution");
      Vec up = Vec::Zero(n);
      up(1)  = 1;
      Trace      tr;
      CurvePoint p0{y, Vec(), hb.jacobian(y)};
      p0.t = tangent(p0.J, up);
      tr.path.push_back(y);
      double       ds = 0.01;
      const double ds_min = 1e-8, ds_max = 0.1;
      for (int step = 0; step < 100000; ++step)
        {
          Vec              y1 = p0.y + ds * p0.t;
          int              its;
          bool             ok = correct(hb, y1, p0.t, p0.y, ds, its, 15, &p0.J);
          CurvePoint       p1;
          if (ok)
            {
              p1.y = y1;
              p1.J = hb.jacobian(y1);
              p1.t = tangent(p1.J, p0.t);
              ok   = p1.t.dot(p0.t) > 0.95; // no sharp turn (or branch jump) within the step
            }
          if (!ok)
            {
              ds *= 0.5;
              if (ds < ds_min)
                throw std::runtime_error("harmonic balance: continuation step too small");
              continue;
            }
          tr.path.push_back(p1.y);
          // Up to the first fold, Omega is monotonic: the target lies between p0 and p1, or between
          // p0 and the fold if there is one in this step.
          const bool fold = (p0.t(iw) > 0) != (p1.t(iw) > 0);
          if (fold)
            {
              tr.fold_found = true;
              tr.fold       = refine_fold(hb, p0, p1);
            }
          const Vec &end = fold ? tr.fold : p1.y;
          if (!std::isnan(omega_target) && (p0.y(iw) - omega_target) * (end(iw) - omega_target) <= 0)
            {
              const double w = (omega_target - p0.y(iw)) / (end(iw) - p0.y(iw));
              Vec          z = p0.y + w * (end - p0.y);
              if (!at_omega(z, omega_target))
                throw std::runtime_error("harmonic balance: no solution at the target frequency");
              tr.target_found = true;
              tr.target       = z;
              return tr;
            }
          if (fold)
            return tr;
          if (p1.y(iw) > 5.0 || p1.y(iw) < 0.02)
            return tr;
          p0 = std::move(p1);
          if (its <= 6)
            ds = std::min(ds_max, 1.5 * ds);
        }
      return tr;
    }

    // Starts of the two stable branches: contact-linear (amplitude F_a / |1 - W^2| < F_m).
    inline double lower_start(const double F_m, const double F_a, const double omega)
    {
      const double w_max = std::sqrt(std::max(0.0, 1 - 2 * F_a / F_m)); // amplitude < F_m / 2
      return std::min({0.5, 0.5 * omega, 0.9 * w_max});
    }
    inline double resonant_start(const double F_m, const double F_a, const double omega)
    {
      const double w_min = std::sqrt(1 + 2 * F_a / F_m);
      return std::max({1.3, 1.1 * w_min, omega + 0.05});
    }
  } // namespace hb_detail

  // {upper fold, lower fold} of the HB response curve with H harmonics. The upper fold is the first
  // fold met when following the lower (non-resonant) branch from small Omega: the local maximum of
  // Omega where an up-sweep jumps up. The lower fold is the first fold met when following the
  // resonant branch from large Omega: the minimum of Omega on it, where a down-sweep jumps down.
  inline std::pair<HbFold, HbFold> kahraman_singh_folds(const double zeta, const double F_m, const double F_a,
                                                         const int H, const int N)
  {
    using namespace hb_detail;
    const KahramanSinghHb hb(zeta, F_m, F_a, H, N);
    const Trace           left  = trace(hb, F_m, F_a, lower_start(F_m, F_a, 1.0));
    const Trace           right = trace(hb, F_m, F_a, resonant_start(F_m, F_a, 0.0));
    if (!left.fold_found || !right.fold_found)
      throw std::runtime_error("harmonic balance: fold not found");
    auto fold = [&](const Vec &y) {
      const HbSolution s = hb.solution(y);
      return HbFold{s.omega, s.amplitude_first_harmonic, s.half_peak_to_peak};
    };
    return {fold(left.fold), fold(right.fold)};
  }

  // HB periodic solution at `omega` on the lower or the resonant branch (throws if that branch
  // folds before reaching omega).
  inline HbSolution kahraman_singh_periodic(const double zeta, const double F_m, const double F_a, const int H,
                                            const int N, const double omega, const HbBranch branch)
  {
    using namespace hb_detail;
    const KahramanSinghHb hb(zeta, F_m, F_a, H, N);
    const double          start =
      branch == HbBranch::lower ? lower_start(F_m, F_a, omega) : resonant_start(F_m, F_a, omega);
    const Trace tr = trace(hb, F_m, F_a, start, omega);
    if (!tr.target_found)
      throw std::runtime_error("harmonic balance: the branch does not reach this frequency");
    return hb.solution(tr.target);
  }
} // namespace hertzgear::dynamics::testing
