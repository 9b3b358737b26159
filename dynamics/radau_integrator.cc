// Radau IIA collocation of high order (s = 3, 5, 7 or 9 stages, order 2s - 1) with step-size
// control, for the small stiff systems of the dynamics stage. The method and its implementation
// follow Hairer & Wanner, Solving Ordinary Differential Equations II, 2nd ed., Sec. IV.5 and IV.8
// (the codes RADAU5 and RADAU); the tableau is computed here for any odd s.
//
// Why hertzgear has it (docs/accuracy-dynamics.md): the steady response of a gear pair at low speed
// is a smooth, quasi-static periodic function, while the structural mesh mode (a few kHz, damping
// ratio ~0.015) and the Hertzian layer (~1e5 1/s) make the system stiff and oscillatory. BDF of
// orders 3-5 is unstable near the imaginary axis and falls back to orders 1-2; the explicit and
// order-5 implicit methods need 300-2000 steps per mesh period at rtol 1e-8. Radau IIA is
// L-stable at every order (it damps the unexcited stiff modes instead of resolving them) and its
// order 2s - 1 makes steps of a few hundredths of a mesh period accurate to 1e-8.
//
// One step of size h from (t0, y0): stage increments Z_i = Y_i - y0 solve
//   Z_i = h sum_j a_ij f(t0 + c_j h, y0 + Z_j),  y1 = y0 + Z_s  (c_s = 1, stiffly accurate),
// by simplified Newton iterations with J = df/dy at the middle of the step on the predicted solution
// (at (t0, y0) without a prediction). With A^-1 = V Lambda V^-1 the Newton
// matrix I - h A (x) J decouples into s complex n x n systems (lambda_k / h - J) dW_k = R_k.
// Error estimate: the embedded formula y^ = y0 + h (g0 f(t0, y0) + sum_i b^_i f(Y_i)) of order s
// with g0 = 1 / lambda_real (the real eigenvalue of A^-1), filtered for stiff components:
//   err = (I - h g0 J)^-1 (g0 h f(t0, y0) + sum_i e_i Z_i),  e = A^-T (b^ - b).
// Because the estimate has order s and the solution order 2s - 1, the relative tolerance is
// transformed as in RADAU5, rtol' = 0.1 rtol^((s+1)/(2s)), so that the solution's error, not the
// estimate's, is of the size the user asks for. The absolute tolerance is not (RADAU5 scales it
// by rtol'/rtol): it governs components near zero, and in this model those are the penetration
// delta where the Hertzian layer opens and closes, where |delta|^n (n = 3/2) has a singular
// second derivative and the solution is not smooth enough for the error to be of order 2s - 1.
// There the error is as large as its estimate, and an absolute tolerance scaled by rtol'/rtol
// (which grows as rtol falls, by 1e4 at rtol 1e-12 and s = 7) let it through unchecked
// (docs/dynamics.md). The Newton iterations stop on the untransformed tolerance.
//
// Starting values: the extrapolated collocation polynomial of the last step, or, for a system
// with a forcing period T (OdeSystem::forcing_period), the stages of the stored steps over
// [t - T, t - T + h], whichever came nearer the last solution. In a periodic steady state the
// latter are within the Newton tolerance, so that a step takes one iteration instead of two or
// three, and it reuses that step's Jacobian and factorisations (a fresh Jacobian when the
// iteration then fails). Only the starting values and the Newton matrix change, never the
// stopping test, so the accuracy is that of the extrapolated start.
//
// Newton convergence: the first iteration of a solve is accepted on the contraction rate of an
// earlier solve, raised to the power 0.8 on every solve that does not measure it again (RADAU5),
// and reset at every event, where the vector field changes (docs/dynamics.md).
//
// Output and events: a step never straddles an output time. After every accepted step the root
// functions are compared with their values at the step's start; a sign change is located on the
// collocation polynomial (the dense output through y0 and the stages) by the Illinois method, the
// step is redone up to just past the root, the root located again on the redone step's own
// polynomial until it lies at the step's end, and the system handles the event there.
#include "common/errors.h"
#include "dynamics/integrator.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <type_traits>

namespace hertzgear::dynamics
{
  namespace
  {
    constexpr int n_max = 12; // largest state dimension handled (the gear pair has 2 or 3, 12 with
                              // its sensitivities, periodic_orbit.h)
    constexpr int s_max = 9; // largest number of stages

    using cplx  = std::complex<double>;
    using SVec  = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, s_max, 1>;
    using SMat  = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, s_max, s_max>;
    using SCMat = Eigen::Matrix<cplx, Eigen::Dynamic, Eigen::Dynamic, 0, s_max, s_max>;

    // The Radau IIA tableau with s stages and what the implementation derives from it.
    struct Tableau
    {
      int   s = 0;
      SVec  c, b, e;       // nodes, weights, error weights e = A^-T (b^ - b)
      SMat  A, A_inv;
      SCMat V, V_inv;      // A^-1 = V diag(lambda) V^-1
      Eigen::Matrix<cplx, Eigen::Dynamic, 1, 0, s_max, 1> lambda;
      int    real_index = 0; // the real eigenvalue of A^-1 (s odd)
      double g0         = 0.0; // 1 / lambda_real
      // One eigenvalue of each conjugate pair (and the real one) with its weight in
      // dZ_i = sum_k V_ik W_k: 2 Re(V_ik W_k) for a pair, Re(V_ik W_k) for the real one.
      std::vector<int>    reps;
      std::vector<double> rep_weight;
    };

    // LU with partial pivoting of shift I - J for a small n x n Jacobian (real or complex shift),
    // written out: the gear pair has n = 2 or 3, where a general dense LU costs more than the
    // arithmetic. N > 0 fixes n at compile time; N = 0 takes it at run time (n <= n_max).
    // Products written out: std::complex's operator* also handles infinities and NaNs (C99 Annex
    // G), which the Newton iterations do not need (a non-finite stage is a failed iteration).
    inline double mul(const double a, const double b) { return a * b; }
    inline cplx   mul(const cplx a, const cplx b)
    {
      return cplx(a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real());
    }

    template <typename T, int N>
    struct SmallLU
    {
      static constexpr int NM = N > 0 ? N : n_max;
      int n_rt = N;
      int block = 0; // > 0: shift I - J is block diagonal with equal blocks of this size
      T   a[NM][NM];
      T   inv_pivot[NM];
      int perm[NM];

      int dim() const
      {
        if constexpr (N > 0)
          return N;
        else
          return n_rt;
      }

      static double magnitude(const T &x)
      {
        if constexpr (std::is_same_v<T, double>)
          return std::abs(x);
        else
          return std::norm(x);
      }

      static T inverse(const T &x)
      {
        if constexpr (std::is_same_v<T, double>)
          return x != 0.0 ? 1.0 / x : 0.0;
        else
          {
            const double nn = std::norm(x);
            return nn > 0.0 ? std::conj(x) / nn : T(0.0);
          }
      }

      // J is row-major with leading dimension NM.
      // With block_size > 0 only the first block of J is read and factorised (OdeSystem::
      // jacobian_block_size), and solve() applies it to every block.
      void factor(const double (&J)[NM][NM], const int n, const T shift, const int block_size = 0)
      {
        n_rt  = n;
        block = block_size > 0 && block_size < dim() && dim() % block_size == 0 ? block_size : 0;
        const int m = block > 0 ? block : dim();
        for (int i = 0; i < m; ++i)
          for (int j = 0; j < m; ++j)
            a[i][j] = (i == j ? shift : T(0.0)) - J[i][j];
        for (int i = 0; i < m; ++i)
          perm[i] = i;
        for (int k = 0; k < m; ++k)
          {
            int    p    = k;
            double best = magnitude(a[k][k]);
            for (int i = k + 1; i < m; ++i)
              if (magnitude(a[i][k]) > best)
                {
                  best = magnitude(a[i][k]);
                  p    = i;
                }
            if (p != k)
              {
                for (int j = 0; j < m; ++j)
                  std::swap(a[k][j], a[p][j]);
                std::swap(perm[k], perm[p]);
              }
            inv_pivot[k] = inverse(a[k][k]);
            for (int i = k + 1; i < m; ++i)
              {
                const T l = mul(a[i][k], inv_pivot[k]);
                a[i][k]   = l;
                for (int j = k + 1; j < m; ++j)
                  a[i][j] -= mul(l, a[k][j]);
              }
          }
      }

      // x = (shift I - J)^-1 b, in place.
      void solve(T *b) const
      {
        if (block == 0)
          {
            solve_block(b, dim());
            return;
          }
        if constexpr (NM >= 6) // the pair with a dynamic layer and its sensitivities: unrolled
          if (block == 3)
            {
              for (int s0 = 0; s0 < dim(); s0 += 3)
                solve_block<3>(b + s0, 3);
              return;
            }
        for (int s0 = 0; s0 < dim(); s0 += block)
          solve_block(b + s0, block);
      }

      // M > 0: the block size known at compile time (m == M).
      template <int M = 0>
      void solve_block(T *b, const int m_rt) const
      {
        const int m = M > 0 ? M : m_rt;
        T x[NM];
        for (int i = 0; i < m; ++i)
          x[i] = b[perm[i]];
        for (int i = 1; i < m; ++i)
          for (int j = 0; j < i; ++j)
            x[i] -= mul(a[i][j], x[j]);
        for (int i = m - 1; i >= 0; --i)
          {
            for (int j = i + 1; j < m; ++j)
              x[i] -= mul(a[i][j], x[j]);
            x[i] = mul(x[i], inv_pivot[i]);
          }
        for (int i = 0; i < m; ++i)
          b[i] = x[i];
      }
    };

    // Radau IIA nodes: the roots of P_s(2c - 1) - P_{s-1}(2c - 1) on (0, 1], c_s = 1
    // (Hairer & Wanner II, Sec. IV.5, Table 5.5 for s <= 3). The s - 1 interior roots are
    // bracketed on a fine grid and bisected to machine precision.
    Tableau make_tableau(const int s)
    {
      HG_REQUIRE_INPUT(s >= 3 && s <= s_max && s % 2 == 1,
                       "radau-iia needs an odd number of stages between 3 and ", s_max, ", got ", s);
      const auto radau_poly = [s](const double c) {
        return std::legendre(unsigned(s), 2.0 * c - 1.0) - std::legendre(unsigned(s - 1), 2.0 * c - 1.0);
      };
      std::vector<double> nodes;
      const int           grid = 4000;
      for (int g = 0; g < grid - 1; ++g)
        {
          double a = double(g) / grid, b = double(g + 1) / grid;
          double fa = radau_poly(a), fb = radau_poly(b);
          if (fa == 0.0)
            {
              nodes.push_back(a);
              continue;
            }
          if (fa * fb > 0.0)
            continue;
          for (int it = 0; it < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon(); ++it)
            {
              const double m  = 0.5 * (a + b);
              const double fm = radau_poly(m);
              if (fa * fm <= 0.0)
                b = m;
              else
                {
                  a  = m;
                  fa = fm;
                }
            }
          nodes.push_back(0.5 * (a + b));
        }
      HG_REQUIRE_INPUT(int(nodes.size()) == s - 1, "radau-iia: found ", nodes.size(),
                       " interior Radau nodes for s = ", s, " (expected ", s - 1, ")");
      nodes.push_back(1.0);

      Tableau T;
      T.s = s;
      T.c.resize(s);
      for (int i = 0; i < s; ++i)
        T.c[i] = nodes[i];
      // a_ij = int_0^{c_i} l_j, with the Lagrange basis l_j(x) = sum_k L_kj x^k, L = Vandermonde^-1.
      using LMat = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
      LMat Vd(s, s);
      for (int i = 0; i < s; ++i)
        for (int k = 0; k < s; ++k)
          Vd(i, k) = std::pow((long double)T.c[i], k);
      const LMat L = Vd.fullPivLu().inverse();
      T.A.resize(s, s);
      for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j)
          {
            long double a = 0.0L;
            for (int k = 0; k < s; ++k)
              a += L(k, j) * std::pow((long double)T.c[i], k + 1) / (k + 1);
            T.A(i, j) = double(a);
          }
      T.b     = T.A.row(s - 1).transpose();
      T.A_inv = T.A.inverse();

      // Eigenvectors in conjugate pairs (columns k and k + 1 conjugate), so that the Newton
      // solves need only one eigenvalue of each pair.
      Eigen::EigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(T.A_inv));
      T.lambda.resize(s);
      T.V.resize(s, s);
      T.real_index = -1;
      {
        int col = 0;
        for (int k = 0; k < s; ++k)
          {
            const cplx l = eig.eigenvalues()[k];
            if (std::abs(l.imag()) < 1e-9 * std::abs(l))
              {
                T.real_index = col;
                T.lambda[col] = l.real();
                T.V.col(col)  = eig.eigenvectors().col(k).real().cast<cplx>();
                T.reps.push_back(col);
                T.rep_weight.push_back(1.0);
                ++col;
              }
            else if (l.imag() > 0.0)
              {
                T.lambda[col]     = l;
                T.lambda[col + 1] = std::conj(l);
                T.V.col(col)      = eig.eigenvectors().col(k);
                T.V.col(col + 1)  = eig.eigenvectors().col(k).conjugate();
                T.reps.push_back(col);
                T.rep_weight.push_back(2.0);
                col += 2;
              }
          }
        HG_REQUIRE_INPUT(col == s && T.real_index >= 0,
                         "radau-iia: unexpected eigenvalues of A^-1 for s = ", s);
      }
      T.V_inv = T.V.inverse();
      T.g0 = 1.0 / T.lambda[T.real_index].real();

      // Embedded weights b^ of order s: g0 [q == 1] + sum_i b^_i c_i^(q-1) = 1/q, q = 1..s, a
      // system with the transposed Vandermonde matrix: b^ = L^T rhs.
      Eigen::Matrix<long double, Eigen::Dynamic, 1> rhs(s);
      for (int q = 1; q <= s; ++q)
        rhs[q - 1] = 1.0L / q - (q == 1 ? (long double)T.g0 : 0.0L);
      const Eigen::Matrix<long double, Eigen::Dynamic, 1> b_hat = L.transpose() * rhs;
      SVec d(s);
      for (int i = 0; i < s; ++i)
        d[i] = double(b_hat[i]) - T.b[i];
      T.e = T.A_inv.transpose() * d;
      return T;
    }

    // The tableau of s stages, built once per process for every admissible s (each build
    // bisects the nodes on a fine grid, which would otherwise cost as much as a few hundred steps
    // for every integrator made, such as one per Newton iteration of the shooting method).
    const Tableau &tableau(const int s)
    {
      HG_REQUIRE_INPUT(s >= 3 && s <= s_max && s % 2 == 1,
                       "radau-iia needs an odd number of stages between 3 and ", s_max, ", got ", s);
      static const std::vector<Tableau> all = [] {
        std::vector<Tableau> t;
        for (int k = 3; k <= s_max; k += 2)
          t.push_back(make_tableau(k));
        return t;
      }();
      return all[std::size_t((s - 3) / 2)];
    }

    // The integrator proper for a state of dimension N (0: at run time, <= n_max) and S stages,
    // both fixed at compile time for the gear pair (n = 2 or 3, s = 3, 5, 7 or 9) so that the
    // loops over states and stages unroll; a step costs a few microseconds, of which the
    // right-hand side is a third.
    class RadauCoreBase
    {
    public:
      virtual ~RadauCoreBase() = default;
      virtual void integrate(OdeSystem &system, double t0, std::vector<double> &y0,
                             double output_interval, long n_outputs, const Observer &observer,
                             const StepObserver &step_observer) = 0;
    };

    template <int N, int S>
    class RadauCore final : public RadauCoreBase
    {
      static constexpr int NM = N > 0 ? N : n_max;
      static constexpr int R  = (S + 1) / 2; // one real eigenvalue and (S - 1) / 2 pairs
      using V      = std::array<double, NM>;
      using Stages = std::array<V, S>; // Stages[i] is stage i

    public:
      RadauCore(const IntegratorSettings &st, const Tableau &tab, IntegratorStats &stats,
                const int n_states)
        : settings(st)
        , statistics(stats)
        , n_rt(n_states)
      {
        for (int i = 0; i < S; ++i)
          {
            c[i] = tab.c[i];
            e[i] = tab.e[i];
            for (int j = 0; j < S; ++j)
              A_inv[i][j] = tab.A_inv(i, j);
            // l_i(tau) = tau prod_{j != i} (tau - c_j) / (c_i prod_{j != i} (c_i - c_j)).
            double d = tab.c[i];
            for (int j = 0; j < S; ++j)
              if (j != i)
                d *= tab.c[i] - tab.c[j];
            lagrange_weight[i] = 1.0 / d;
          }
        g0 = tab.g0;
        // The real eigenvalue first, then one of each conjugate pair.
        int q = 0;
        for (std::size_t r = 0; r < tab.reps.size(); ++r)
          {
            const int k   = tab.reps[r];
            const int dst = k == tab.real_index ? 0 : ++q;
            HG_REQUIRE_INPUT(dst < R, "radau-iia: unexpected eigen-decomposition for s = ", S);
            lambda[dst] = tab.lambda[k];
            weight[dst] = tab.rep_weight[r];
            for (int i = 0; i < S; ++i)
              {
                V_col[dst][i]  = tab.V(i, k);
                V_inv_row[dst][i] = tab.V_inv(k, i);
              }
          }
        HG_REQUIRE_INPUT(q == R - 1, "radau-iia: unexpected eigen-decomposition for s = ", S);
        const double rtol = settings.relative_tolerance;
        rtol_est          = 0.1 * std::pow(rtol, (S + 1.0) / (2.0 * S));
        en_max_growth     = std::pow(0.9 / 6.0, S + 1.0);
      }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer, const StepObserver &step_observer) override
      {
        const int n = dim();
        sys         = &system;
        {
          const auto a = system.absolute_tolerances(settings.absolute_tolerance);
          for (int i = 0; i < n; ++i)
            atol[i] = a[i];
        }
        n_roots = system.n_roots();
        g_start.assign(n_roots, 0.0);
        g_new.assign(n_roots, 0.0);
        g_mid.assign(n_roots, 0.0);
        sign_old.assign(n_roots, 0);
        directions.assign(n_roots, 0);
        have_predictor = false;
        // The periodic starting values need the history of this very trajectory.
        const double T = settings.periodic_start ? system.forcing_period() : 0.0;
        if (T != period || t0 != t_end || &system != history_system)
          clear_history();
        period         = T;
        history_system = &system;

        V y{};
        for (int i = 0; i < n; ++i)
          y[i] = y0[i];
        double t = t0;
        if (H <= 0.0) // first call: a conservative first step, the control takes over
          H = std::min(output_interval, settings.max_step > 0 ? settings.max_step : output_interval) * 1e-2;
        if (n_roots)
          {
            system.roots(t, y.data(), g_start.data());
            update_signs(g_start);
          }

        if (observer)
          observer(t, y.data());
        const std::string remedy =
          "check that the scene is physical (positive stiffness and damping), or relax "
          "{relative_tolerance}, or use {integrator} = cvode-bdf";
        const std::vector<double> bounds = system.blow_up_bounds();
        for (long out = 1; out <= n_outputs; ++out)
          {
            const double tout  = t0 + out * output_interval;
            long         steps = 0;
            while (t < tout)
              {
                if (++steps > settings.max_steps_per_output)
                  throw NumericalError(msg("radau-iia took more than ", settings.max_steps_per_output,
                                           " steps before t = ", tout, " s, at t = ", t, " s (step ", H,
                                           " s): ", system.describe_state(y.data()), ". Remedy: ",
                                           remedy));
                double h_max = tout - t;
                if (settings.max_step > 0.0)
                  h_max = std::min(h_max, settings.max_step);
                // Hit the output time exactly when the step would end just short of it.
                const double h_try  = H >= h_max * (1.0 - 1e-10) ? h_max : std::min(H, h_max);
                const bool   to_end = h_try == tout - t;
                const double h_done = step(t, y, h_try, remedy);
                const double t_next = (to_end && h_done == h_try) ? tout : t + h_done;
                if (step_observer)
                  // The collocation polynomial of the kept step (up to the event, if any).
                  step_observer(t, t_next, [&](const double tt, double *u) {
                    const V v = dense(y, Z_dense, (tt - t) / h_dense);
                    std::copy(v.begin(), v.begin() + n, u);
                  });
                t = t_next;
                y                   = y_next;
                check_state(system, bounds, t, y.data(), "radau-iia", remedy);
              }
            if (observer)
              observer(tout, y.data());
          }
        for (int i = 0; i < n; ++i)
          y0[i] = y[i];
        t_end = t;
      }

    private:
      int dim() const
      {
        if constexpr (N > 0)
          return N;
        else
          return n_rt;
      }

      // Weighted RMS norm of e with the scale atol + rtol max(|a|, |b|).
      double error_norm(const V &err, const V &a, const V &b, const double rtol) const
      {
        const int n   = dim();
        double    sum = 0.0;
        for (int i = 0; i < n; ++i)
          {
            const double sc = atol[i] + rtol * std::max(std::abs(a[i]), std::abs(b[i]));
            sum += (err[i] / sc) * (err[i] / sc);
          }
        return std::sqrt(sum / n);
      }

      // The same over all stages (scale from y0 + Z_i and y0).
      double stage_norm(const V &y, const Stages &dZ) const
      {
        const int    n    = dim();
        const double rtol = settings.relative_tolerance;
        double       sum  = 0.0;
        for (int i = 0; i < S; ++i)
          for (int r = 0; r < n; ++r)
            {
              const double sc = atol[r] + rtol * std::max(std::abs(y[r]), std::abs(y[r] + Z[i][r]));
              sum += (dZ[i][r] / sc) * (dZ[i][r] / sc);
            }
        return std::sqrt(sum / (n * S));
      }

      // f0 = f(t, y) and J = df/dy at (tj, yj): the middle of the coming step on the predicted
      // solution when there is a prediction (the stiff eigenvalue follows k_h(t), and a Jacobian
      // from the step's middle halves what the simplified Newton iteration has to make up).
      void linearise(const double t, const V &y, const double tj, const V &yj)
      {
        const int n = dim();
        sys->rhs(t, y.data(), f0.data());
        ++statistics.rhs_evals;
        if (sys->has_jacobian())
          {
            double jac[NM * NM];
            sys->jacobian(tj, yj.data(), jac);
            for (int i = 0; i < n; ++i)
              for (int j = 0; j < n; ++j)
                J[i][j] = jac[i * n + j];
          }
        else
          {
            V yp = yj, fp{}, fj{};
            sys->rhs(tj, yj.data(), fj.data());
            for (int j = 0; j < n; ++j)
              {
                const double dy = std::sqrt(std::numeric_limits<double>::epsilon()) *
                                  std::max(std::abs(yj[j]), atol[j] / settings.relative_tolerance);
                yp[j] = yj[j] + dy;
                sys->rhs(tj, yp.data(), fp.data());
                for (int i = 0; i < n; ++i)
                  J[i][j] = (fp[i] - fj[i]) / dy;
                yp[j] = yj[j];
              }
            statistics.rhs_evals += n + 1;
          }
        ++statistics.jacobian_evals;
        lu_valid = false;
      }

      // The collocation polynomial of a solve at tau = (t - t0) / h: Lagrange form through
      // (0, y0) and (c_i, y0 + Z_i); since the basis sums to one,
      // u(tau) = y0 + sum_i Z_i l_i(tau).
      V dense(const V &y, const Stages &Zs, const double tau) const
      {
        const int n = dim();
        double    l[S];
        for (int i = 0; i < S; ++i)
          {
            double p = tau * lagrange_weight[i];
            for (int j = 0; j < S; ++j)
              if (j != i)
                p *= tau - c[j];
            l[i] = p;
          }
        V u = y;
        for (int i = 0; i < S; ++i)
          for (int r = 0; r < n; ++r)
            u[r] += l[i] * Zs[i][r];
        return u;
      }

      // Solves the collocation equations for a step of size h from (t, y), with J and f0 from
      // linearise(t, y). On success Z holds the stage increments and y_next = y + Z_s.
      bool solve(const double t, const V &y, const double h)
      {
        const int n = dim();
        // LU of lambda_k / h - J for one eigenvalue of each conjugate pair of A^-1; kept while
        // neither J nor h changed.
        if (!lu_valid || h != h_lu)
          {
            const int block = int(sys->jacobian_block_size());
            lu_real.factor(J, n, lambda[0].real() / h, block);
            for (int q = 1; q < R; ++q)
              lu_cplx[q].factor(J, n, lambda[q] / h, block);
            lu_valid = true;
            h_lu     = h;
          }
        solve_ok          = false;
        have_periodic     = periodic_start(t, h);
        // The extrapolation is skipped while the periodic values came within the Newton
        // tolerance's order of the last solution (it could not do better).
        have_extrapolated = have_predictor && !(have_periodic && use_periodic && periodic_distance < 1.0);
        if (have_extrapolated)
          {
            // Extrapolate the previous collocation polynomial (Hairer & Wanner's starting values).
            for (int i = 0; i < S; ++i)
              {
                const V u = dense(y_prev, Z_prev, 1.0 + c[i] * h / h_prev);
                for (int r = 0; r < n; ++r)
                  Z_extrapolated[i][r] = u[r] - y[r];
              }
          }
        if (have_periodic && (use_periodic || !have_extrapolated))
          Z = Z_periodic;
        else if (have_extrapolated)
          Z = Z_extrapolated;
        else
          Z = Stages{};
        Stages       F{}, dZ{};
        double       Rr[S][NM];
        double       dn_old = 0.0;
        const double kappa  = 0.05;
        const double h_inv  = 1.0 / h;
        for (int it = 0; it < max_newton; ++it)
          {
            for (int i = 0; i < S; ++i)
              {
                V Y;
                for (int r = 0; r < n; ++r)
                  Y[r] = y[r] + Z[i][r];
                sys->rhs(t + c[i] * h, Y.data(), F[i].data());
              }
            statistics.rhs_evals += S;
            // R_i = f_i - sum_j Ainv_ij Z_j / h.
            for (int i = 0; i < S; ++i)
              {
                double acc[NM] = {};
                for (int j = 0; j < S; ++j)
                  for (int r = 0; r < n; ++r)
                    acc[r] += A_inv[i][j] * Z[j][r];
                for (int r = 0; r < n; ++r)
                  Rr[i][r] = F[i][r] - acc[r] * h_inv;
              }
            // W_k = sum_i Vinv_ki R_i, (lambda_k / h - J) W_k = W_k, dZ_i = sum_k V_ik W_k.
            {
              // The real eigenvalue: real arithmetic.
              double w[NM];
              for (int r = 0; r < n; ++r)
                {
                  double acc = 0.0;
                  for (int i = 0; i < S; ++i)
                    acc += V_inv_row[0][i].real() * Rr[i][r];
                  w[r] = acc;
                }
              lu_real.solve(w);
              for (int i = 0; i < S; ++i)
                {
                  const double v = weight[0] * V_col[0][i].real();
                  for (int r = 0; r < n; ++r)
                    dZ[i][r] = v * w[r];
                }
            }
            for (int q = 1; q < R; ++q)
              {
                cplx w[NM];
                for (int r = 0; r < n; ++r)
                  {
                    double re = 0.0, im = 0.0;
                    for (int i = 0; i < S; ++i)
                      {
                        re += V_inv_row[q][i].real() * Rr[i][r];
                        im += V_inv_row[q][i].imag() * Rr[i][r];
                      }
                    w[r] = cplx(re, im);
                  }
                lu_cplx[q].solve(w);
                for (int i = 0; i < S; ++i)
                  {
                    const double vr = weight[q] * V_col[q][i].real(),
                                 vi = weight[q] * V_col[q][i].imag();
                    for (int r = 0; r < n; ++r)
                      dZ[i][r] += vr * w[r].real() - vi * w[r].imag();
                  }
              }
            bool finite = true;
            for (int i = 0; i < S; ++i)
              for (int r = 0; r < n; ++r)
                {
                  Z[i][r] += dZ[i][r];
                  finite = finite && std::isfinite(Z[i][r]);
                }
            if (!finite)
              return false;
            const double dn = stage_norm(y, dZ);
            if (it == 0)
              {
                // The contraction measured on an earlier solve stands in for the first
                // iteration's, weakened by the power 0.8 on every solve that does not measure it
                // again (RADAU5's FACCON = max(FACCON, uround)^0.8): a rate measured on a short
                // step or in a linear stretch (0 there) must not let the first iteration of
                // every later, longer or nonlinear step pass untested. After at most a few such
                // solves the test asks for a second iteration, which measures the rate anew.
                eta_newton = std::pow(std::max(eta_newton, std::numeric_limits<double>::epsilon()), 0.8);
                if (eta_newton * dn <= kappa)
                  return solve_ok = true;
              }
            else
              {
                const double theta = dn / std::max(dn_old, 1e-300);
                if (theta >= 0.99)
                  return false;
                eta_newton = theta / (1.0 - theta);
                if (eta_newton * dn <= kappa)
                  return solve_ok = true;
                // Not converging within the remaining iterations at this rate.
                double theta_rest = 1.0;
                for (int k = it + 1; k < max_newton; ++k)
                  theta_rest *= theta;
                if (eta_newton * dn * theta_rest > kappa * 1e3)
                  return false;
              }
            if (dn == 0.0)
              return solve_ok = true;
            dn_old = dn;
          }
        return false;
      }

      // err = scale (lambda_real / h - J)^-1 raw.
      void filter(const V &raw, const double scale, V &err) const
      {
        const int n = dim();
        double    w[NM];
        for (int r = 0; r < n; ++r)
          w[r] = raw[r];
        lu_real.solve(w);
        for (int r = 0; r < n; ++r)
          err[r] = scale * w[r];
      }

      // raw = g0 h f + sum_i e_i Z_i.
      V raw_estimate(const V &f, const double h) const
      {
        const int n = dim();
        V         raw{};
        for (int r = 0; r < n; ++r)
          {
            double acc = g0 * h * f[r];
            for (int i = 0; i < S; ++i)
              acc += e[i] * Z[i][r];
            raw[r] = acc;
          }
        return raw;
      }

      // Filtered error estimate of the step just solved, in the transformed norm.
      double estimate(const double t, const V &y, const double h, const bool refine)
      {
        const int    n     = dim();
        const double scale = lambda[0].real() / h; // (I - h g0 J)^-1 = scale (scale - J)^-1
        V            err{};
        filter(raw_estimate(f0, h), scale, err);
        V y1{};
        for (int r = 0; r < n; ++r)
          y1[r] = y[r] + Z[S - 1][r];
        double en = error_norm(err, y, y1, rtol_est);
        if (en > 1.0 && refine)
          {
            // Hairer & Wanner IV.8 (8.21): one more filter with f at y0 + err.
            V yp{}, fp{};
            for (int r = 0; r < n; ++r)
              yp[r] = y[r] + err[r];
            sys->rhs(t, yp.data(), fp.data());
            ++statistics.rhs_evals;
            filter(raw_estimate(fp, h), scale, err);
            en = error_norm(err, y, y1, rtol_est);
          }
        return en;
      }

      // Periodic starting values. A periodically forced system settles into a motion that repeats
      // with the forcing period T (or a multiple); its stages then repeat the stages of one
      // period earlier, which the extrapolated collocation polynomial of the last step matches
      // only to its interpolation error. The steps of the last period are kept (a ring of
      // (t, h, y, Z)); the starting increments are those of the stored solution over
      // [t - T, t - T + h]. Which of the two starting values the solve takes follows which one
      // was nearer the solution of the last step, so that transients, period-k and aperiodic
      // motions keep the extrapolation. While the periodic values are in use, the stored step
      // also lends its Jacobian and factorisations (periodic_jacobian). The stopping test of the
      // Newton iteration is the same either way.
      struct PastStep
      {
        double t, h;
        V      y;
        Stages Z;
        double J[NM][NM];
        double             h_lu; // the step size of the factorisations (0: none)
        SmallLU<double, N> lu_real;
        SmallLU<cplx, N>   lu_cplx[R];
      };

      PastStep &past_at(const std::size_t k) { return past[(past_first + k) & (past.size() - 1)]; }

      void clear_history()
      {
        past_first = past_n = 0;
        use_periodic = have_periodic = false;
      }

      // Stores the accepted step [t, t + h] (stages in Z) and updates the choice of starting
      // values from how near each candidate came to the solution.
      void remember(const double t, const V &y, const double h)
      {
        if (period <= 0.0)
          return;
        if (have_periodic)
          {
            periodic_distance = stage_distance(y, Z_periodic);
            if (have_extrapolated)
              use_periodic = periodic_distance < stage_distance(y, Z_extrapolated);
          }
        if (past_n == past.size())
          {
            if (past.size() >= max_history)
              {
                past_first = (past_first + 1) & (past.size() - 1);
                --past_n;
              }
            else
              {
                std::vector<PastStep> grown(std::max<std::size_t>(2 * past.size(), 256));
                for (std::size_t k = 0; k < past_n; ++k)
                  grown[k] = past_at(k);
                past.swap(grown);
                past_first = 0;
              }
          }
        PastStep &p = past_at(past_n++);
        p.t         = t;
        p.h         = h;
        p.y         = y;
        p.Z         = Z;
        std::copy(&J[0][0], &J[0][0] + NM * NM, &p.J[0][0]);
        p.h_lu    = lu_valid ? h_lu : 0.0;
        p.lu_real = lu_real;
        for (int q = 1; q < R; ++q)
          p.lu_cplx[q] = lu_cplx[q];
      }

      // The step of one period earlier that began at t - T with the same size h (within 1e-9 h),
      // after prune_history(t); else nullptr. It is the first or second stored step then.
      const PastStep *aligned_step(const double t, const double h)
      {
        const double t_back = t - period;
        for (std::size_t j = 0; j < std::min<std::size_t>(past_n, 2); ++j)
          {
            const PastStep &p = past_at(j);
            if (std::abs(p.t - t_back) <= 1e-9 * h && std::abs(p.h - h) <= 1e-9 * h)
              return &p;
          }
        return nullptr;
      }

      // The aligned step of one period earlier, while the periodic starting values are in use
      // and came near the last solution; else nullptr.
      const PastStep *periodic_jacobian(const double t, const double h)
      {
        if (!(use_periodic && periodic_distance < 1.0) || !prune_history(t))
          return nullptr;
        return aligned_step(t, h);
      }

      // Drops the stored steps that end before t - T; false when none is left.
      bool prune_history(const double t)
      {
        const double t_back = t - period;
        while (past_n > 0 && past_at(0).t + past_at(0).h < t_back - 1e-9 * past_at(0).h)
          {
            past_first = (past_first + 1) & (past.size() - 1);
            --past_n;
          }
        return past_n > 0;
      }

      // Weighted distance of starting values from the stages in Z (Newton norm).
      double stage_distance(const V &y, const Stages &start) const
      {
        Stages d;
        for (int i = 0; i < S; ++i)
          for (int r = 0; r < dim(); ++r)
            d[i][r] = start[i][r] - Z[i][r];
        return stage_norm(y, d);
      }

      // Z_periodic for a step [t, t + h] from the stored solution over [t - T, t - T + h]; false
      // when the history does not cover it.
      bool periodic_start(const double t, const double h)
      {
        if (period <= 0.0)
          return false;
        const double t_back = t - period;
        const double slack  = 1e-9 * h;
        if (!prune_history(t) || past_at(0).t > t_back + slack)
          return false;
        // The common case: a stored step of this size began at t - T; its stages are the values.
        if (const PastStep *p = aligned_step(t, h))
          {
            Z_periodic = p->Z;
            return true;
          }
        std::size_t k = 0;
        auto at_time = [&](const double tau, V &u) {
          while (k + 1 < past_n && past_at(k).t + past_at(k).h < tau)
            ++k;
          const PastStep &p = past_at(k);
          if (p.t + p.h < tau - slack || p.t > tau + slack)
            return false;
          // At a node (the steps of the last period usually match the coming ones), the stored
          // stage itself.
          const double frac = (tau - p.t) / p.h;
          if (std::abs(frac) < 1e-9)
            {
              u = p.y;
              return true;
            }
          for (int j = 0; j < S; ++j)
            if (std::abs(frac - c[j]) < 1e-9)
              {
                for (int r = 0; r < dim(); ++r)
                  u[r] = p.y[r] + p.Z[j][r];
                return true;
              }
          u = dense(p.y, p.Z, frac);
          return true;
        };
        V u0;
        if (!at_time(t_back, u0))
          return false;
        const int n = dim();
        for (int i = 0; i < S; ++i)
          {
            V u;
            if (!at_time(t_back + c[i] * h, u))
              return false;
            for (int r = 0; r < n; ++r)
              Z_periodic[i][r] = u[r] - u0[r];
          }
        return true;
      }

      void set_next(const V &y)
      {
        for (int r = 0; r < dim(); ++r)
          y_next[r] = y[r] + Z[S - 1][r];
      }

      // x^(-1/(S+1)), the step-size controller's power (without pow for the common orders).
      static double inverse_root(const double x)
      {
        if constexpr (S == 3)
          return 1.0 / std::sqrt(std::sqrt(x));
        else if constexpr (S == 5)
          return 1.0 / std::sqrt(std::cbrt(x));
        else
          return std::pow(x, -1.0 / (S + 1.0));
      }

      // Takes one accepted step from (t, y) of at most h_try; the result is in y_next and the
      // step actually taken is returned (shorter than h_try when an event was located).
      double step(const double t, const V &y, double h_try, const std::string &remedy)
      {
        const auto fresh_jacobian = [&]() {
          if (have_predictor)
            linearise(t, y, t + 0.5 * h_try, dense(y_prev, Z_prev, 1.0 + 0.5 * h_try / h_prev));
          else
            linearise(t, y, t, y);
        };
        bool from_history = false;
        if (const PastStep *p = periodic_jacobian(t, h_try))
          {
            // A periodic motion: the Jacobian of the same step one period earlier, and its
            // factorisations when they were made for this step size.
            sys->rhs(t, y.data(), f0.data());
            ++statistics.rhs_evals;
            std::copy(&p->J[0][0], &p->J[0][0] + NM * NM, &J[0][0]);
            lu_valid = std::abs(p->h_lu - h_try) <= 1e-9 * h_try;
            if (lu_valid)
              {
                lu_real = p->lu_real;
                for (int q = 1; q < R; ++q)
                  lu_cplx[q] = p->lu_cplx[q];
                h_lu = h_try;
              }
            from_history = true;
          }
        else
          fresh_jacobian();
        const double H_in         = H;
        int          rejections   = 0;
        bool         was_rejected = false;
        for (;;)
          {
            if (solve(t, y, h_try))
              {
                const double en = estimate(t, y, h_try, was_rejected || first_step);
                // 0.9 en^(-1/(S+1)) clamped to [0.2, 6]; the largest factor without the power
                // when en is below (0.9 / 6)^(S+1).
                const double fac =
                  en <= en_max_growth
                    ? 6.0
                    : std::clamp(0.9 * inverse_root(std::max(en, 1e-10)), 0.2, 6.0);
                if (en <= 1.0)
                  {
                    first_step = false;
                    ++statistics.steps;
                    set_next(y);
                    Z_dense      = Z;
                    h_dense      = h_try;
                    double taken = h_try;
                    if (n_roots)
                      taken = locate_event(t, y, h_try);
                    if (solve_ok)
                      remember(t, y, taken);
                    double h_new = h_try * fac;
                    if (was_rejected)
                      h_new = std::min(h_new, h_try);
                    // A step shortened by the output grid or by an event keeps the proposal it had.
                    if (taken == h_try)
                      H = (h_try < H_in && !was_rejected) ? std::max(H_in, h_new) : h_new;
                    if (taken == h_try && !event_now)
                      {
                        // Starting values for the next step.
                        have_predictor = true;
                        y_prev         = y;
                        Z_prev         = Z;
                        h_prev         = h_try;
                      }
                    else
                      have_predictor = false;
                    return taken;
                  }
                h_try *= std::min(fac, 0.9);
              }
            else if (from_history)
              {
                // The motion is no longer that of one period earlier: a Jacobian of its own, and
                // the same step again.
                fresh_jacobian();
                from_history = false;
              }
            else
              {
                h_try *= 0.5;
              }
            ++statistics.rejected_steps;
            was_rejected = true;
            H            = h_try;
            if (++rejections > 50)
              throw NumericalError(msg("radau-iia: 50 rejected steps in a row at t = ", t,
                                       " s (step ", h_try, " s): ", sys->describe_state(y.data()),
                                       ". Remedy: ", remedy));
          }
      }

      // Sign of the root functions before the step: the last nonzero sign each had (0 while a
      // function has been exactly zero from the start). A function that stays at zero is
      // therefore no event, as in CVODE.
      void update_signs(const std::vector<double> &g)
      {
        for (unsigned r = 0; r < n_roots; ++r)
          if (g[r] != 0.0)
            sign_old[r] = g[r] > 0.0 ? 1 : -1;
      }

      // Whether g_r has left its sign (reaching zero counts).
      bool changed(const std::vector<double> &g, const unsigned r) const
      {
        return sign_old[r] != 0 && g[r] * sign_old[r] <= 0.0;
      }

      // The earliest root on the collocation polynomial of the step [t, t + h] from y with
      // increments Zs, given the root functions at its ends (g_hi changed sign): Illinois over
      // [a, b] = [0, 1] (fractions of the step), bisection when a bracket value is zero. Returns
      // b, the upper end of the final bracket (just past the root), and g_hi there.
      double earliest_root(const double t, const V &y, const Stages &Zs, const double h,
                           std::vector<double> g_lo, std::vector<double> &g_hi)
      {
        double       a = 0.0, b = 1.0;
        const double s_tol = 100.0 * std::numeric_limits<double>::epsilon() * (std::abs(t) + h) / h;
        int          last_moved = 0; // +1: b moved last, -1: a moved last
        double       w_lo = 1.0, w_hi = 1.0;
        while (b - a > s_tol)
          {
            double sp = b;
            for (unsigned r = 0; r < n_roots; ++r)
              if (changed(g_hi, r))
                {
                  if (g_lo[r] == 0.0 || g_hi[r] == 0.0 || g_lo[r] * g_hi[r] > 0.0)
                    sp = std::min(sp, 0.5 * (a + b));
                  else
                    sp = std::min(sp, a + (b - a) * (w_lo * g_lo[r]) / (w_lo * g_lo[r] - w_hi * g_hi[r]));
                }
            sp = std::clamp(sp, a + 0.5 * s_tol, b - 0.5 * s_tol);
            const V u = dense(y, Zs, sp);
            sys->roots(t + sp * h, u.data(), g_mid.data());
            ++statistics.root_evals;
            bool left = false;
            for (unsigned r = 0; r < n_roots; ++r)
              left = left || changed(g_mid, r);
            if (left)
              {
                b          = sp;
                g_hi       = g_mid;
                w_lo       = last_moved == 1 ? 0.5 * w_lo : 1.0;
                w_hi       = 1.0;
                last_moved = 1;
              }
            else
              {
                a          = sp;
                g_lo       = g_mid;
                w_hi       = last_moved == -1 ? 0.5 * w_hi : 1.0;
                w_lo       = 1.0;
                last_moved = -1;
              }
          }
        return b;
      }

      // After an accepted step of size h (result in y_next, stages in Z), find the first root
      // function that changed its sign. If one did, the step is redone up to just past the
      // root, the system handles the event there, and the step to the root is returned.
      //
      // The root is first located on the polynomial of the accepted step, which crosses the
      // switch: across the kink of the vector field that polynomial is a poor approximation, so
      // the root it shows may lie past the true one. The step redone up to that point then
      // still crosses the switch by the difference, with the vector field of the other side
      // over its last stages and no error test of its own. Hence the root is located again on
      // the polynomial of each redone step, and the step redone up to it, until the root lies at
      // the step's end within the root tolerance: the step that is kept ends at the switch and
      // never integrates across it.
      double locate_event(const double t, const V &y, const double h)
      {
        event_now = false;
        sys->roots(t + h, y_next.data(), g_new.data());
        ++statistics.root_evals;
        bool any = false;
        for (unsigned r = 0; r < n_roots; ++r)
          any = any || (sign_old[r] != 0 && g_new[r] * sign_old[r] < 0.0);
        if (!any)
          {
            update_signs(g_new);
            g_start = g_new;
            return h;
          }
        std::vector<double> g_hi = g_new;
        double              b    = earliest_root(t, y, Z, h, g_start, g_hi);
        double              h_root = b * h;
        const double        t_tol  = 100.0 * std::numeric_limits<double>::epsilon() * (std::abs(t) + h);
        for (int pass = 0; b < 1.0 && pass < max_relocations; ++pass)
          {
            const Stages Zs = Z; // the polynomial the root was located on
            if (!solve(t, y, h_root))
              {
                // No convergence on the shorter step (rare): the dense output there, which
                // stays the step's polynomial.
                y_next = dense(y, Zs, b);
                sys->roots(t + h_root, y_next.data(), g_hi.data());
                ++statistics.root_evals;
                break;
              }
            set_next(y);
            Z_dense = Z;
            h_dense = h_root;
            sys->roots(t + h_root, y_next.data(), g_hi.data());
            ++statistics.root_evals;
            bool confirmed = false;
            for (unsigned r = 0; r < n_roots; ++r)
              confirmed = confirmed || changed(g_hi, r);
            if (!confirmed)
              {
                if (unconfirmed_last)
                  break;
                // The accurate step ends just short of the root: accept it without an event;
                // the next step, from much closer, locates it again.
                unconfirmed_last = true;
                update_signs(g_hi);
                g_start = g_hi;
                return h_root;
              }
            // The redone step crosses the switch too: the root on its own polynomial.
            std::vector<double> g_end = g_hi;
            b = earliest_root(t, y, Z, h_root, g_start, g_end);
            if ((1.0 - b) * h_root <= t_tol)
              break;
            h_root *= b;
          }
        unconfirmed_last = false;
        event_now        = true;
        // A restart: the vector field past the switch is another one. The contraction rate of
        // the Newton iterations measured before it says nothing about the iterations after it
        // (in the free flight through the backlash the equations are linear and one iteration
        // is exact, a rate of 0, which would let the first iteration of every later step pass
        // untested). The next solve measures the rate afresh, and its error estimate is
        // refined as on a first step.
        eta_newton = 1.0;
        first_step = true;
        for (unsigned r = 0; r < n_roots; ++r)
          directions[r] = changed(g_hi, r) ? -sign_old[r] : 0;
        ++statistics.events;
        sys->handle_event(t + h_root, y_next.data(), directions.data());
        sys->roots(t + h_root, y_next.data(), g_new.data());
        ++statistics.root_evals;
        // Past the root: the new sign. A function that sits exactly at zero there has no sign
        // until it leaves zero, so that it cannot trigger the same event again.
        for (unsigned r = 0; r < n_roots; ++r)
          if (directions[r] != 0)
            sign_old[r] = 0;
        update_signs(g_new);
        g_start = g_new;
        return h_root;
      }

      static constexpr int         max_newton  = 10;
      // Redone steps per located event (locate_event); one or two suffice in practice.
      static constexpr int         max_relocations = 8;
      // Steps kept for the periodic starting values: a power of 2, at most about 32 MB.
      static constexpr std::size_t max_history = []() {
        std::size_t m = 1;
        while (2 * m * sizeof(PastStep) <= (std::size_t(32) << 20))
          m *= 2;
        return m;
      }();

      const IntegratorSettings &settings;
      IntegratorStats          &statistics;
      int                       n_rt;
      // The tableau, in the order the Newton solve uses it (eigenvalue 0 is the real one).
      double               c[S], e[S], A_inv[S][S], lagrange_weight[S], g0 = 0.0;
      cplx                 lambda[R], V_col[R][S], V_inv_row[R][S];
      double               weight[R];
      double               rtol_est = 0.0; // transformed relative tolerance of the estimate
      double               en_max_growth = 0.0; // error norm below which the step grows 6-fold
      OdeSystem           *sys      = nullptr;
      unsigned             n_roots  = 0;
      V                    atol{}, f0{}, y_next{}, y_prev{};
      double               J[NM][NM] = {};
      Stages               Z{}, Z_prev{};
      // The polynomial of the last kept step: its stages and the step size they were solved for
      // (at least the step kept; longer when the step was cut at an event on that polynomial).
      Stages               Z_dense{};
      double               h_dense = 0.0;
      SmallLU<double, N>   lu_real;
      SmallLU<cplx, N>     lu_cplx[R];
      bool                 lu_valid = false;
      double               h_lu = 0.0, eta_newton = 1.0;
      bool                 have_predictor = false, first_step = true, event_now = false,
                           unconfirmed_last = false;
      double               h_prev = 0.0;
      std::vector<double>  g_start, g_new, g_mid; // root functions at the step's start, end, inside
      std::vector<int>     sign_old;
      std::vector<int>     directions;
      double               H = 0.0; // proposed next step
      bool                 solve_ok = false; // the last solve converged (Z is its solution)
      // Periodic starting values (periodic_start): period, history, candidates and choice.
      double                period = 0.0, t_end = std::numeric_limits<double>::quiet_NaN();
      const OdeSystem      *history_system = nullptr;
      std::vector<PastStep> past;
      std::size_t           past_first = 0, past_n = 0;
      Stages                Z_periodic{}, Z_extrapolated{};
      bool                  have_periodic = false, have_extrapolated = false, use_periodic = false;
      double                periodic_distance = 0.0; // of the periodic values from the last solution
    };

    template <int S>
    std::unique_ptr<RadauCoreBase> make_core(const IntegratorSettings &st, const Tableau &tab,
                                             IntegratorStats &stats, const int n)
    {
      if (n == 2)
        return std::make_unique<RadauCore<2, S>>(st, tab, stats, n);
      if (n == 3)
        return std::make_unique<RadauCore<3, S>>(st, tab, stats, n);
      // The gear pair with its sensitivities (periodic_orbit.h): 2 + 4 and 3 + 9 states.
      if (n == 6)
        return std::make_unique<RadauCore<6, S>>(st, tab, stats, n);
      if (n == 12)
        return std::make_unique<RadauCore<12, S>>(st, tab, stats, n);
      return std::make_unique<RadauCore<0, S>>(st, tab, stats, n);
    }

    class RadauIIA : public Integrator
    {
    public:
      explicit RadauIIA(const IntegratorSettings &st)
        : settings(st)
        , tab(tableau(st.stages > 0 ? st.stages : default_stages(st.relative_tolerance)))
      {
        statistics.name = "radau-iia";
      }

      // Stages by tolerance: the cheapest order that takes steps of a few hundredths of a mesh
      // period (measured in docs/accuracy-dynamics.md).
      static int default_stages(const double rtol)
      {
        if (rtol >= 1e-5)
          return 3;
        if (rtol >= 1e-10)
          return 5;
        return 7;
      }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto start = std::chrono::steady_clock::now();
        const int  n     = int(system.n_states());
        HG_REQUIRE_INPUT(n >= 1 && n <= n_max, "the radau-iia integrator handles up to ", n_max,
                         " states, the system has ", n);
        // The core keeps the step size and Newton rate from one call to the next.
        if (!core || n != core_n)
          {
            switch (tab.s)
              {
                case 3:
                  core = make_core<3>(settings, tab, statistics, n);
                  break;
                case 5:
                  core = make_core<5>(settings, tab, statistics, n);
                  break;
                case 7:
                  core = make_core<7>(settings, tab, statistics, n);
                  break;
                default:
                  core = make_core<9>(settings, tab, statistics, n);
                  break;
              }
            core_n = n;
          }
        core->integrate(system, t0, y0, output_interval, n_outputs, observer, step_observer);
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings             settings;
      Tableau                        tab;
      std::unique_ptr<RadauCoreBase> core;
      int                            core_n = 0;
    };
  } // namespace

  std::unique_ptr<Integrator> make_radau_iia(const IntegratorSettings &settings)
  {
    return std::make_unique<RadauIIA>(settings);
  }
} // namespace hertzgear::dynamics
