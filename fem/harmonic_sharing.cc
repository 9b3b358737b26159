#include "fem/harmonic_sharing.h"

#include "common/errors.h"
#include "common/progress.h"

#include <deal.II/lac/lapack_templates.h>

#include <algorithm>
#include <array>
#include <memory>
#include <chrono>
#include <cmath>
#include <complex>
#include <numeric>
#include <thread>

namespace hertzgear::fem
{
  namespace
  {
    // Tags of body b: 5100 + 8 b + kind.
    enum Kind
    {
      free_kind   = 0,
      job_kind    = 1,
      result_kind = 2,
      stop_kind   = 3,
      bye_kind    = 4
    };
    int tag(const int body, const Kind kind) { return 5100 + 8 * body + kind; }

    void send_matrix(const Eigen::MatrixXd &a, const int to, const int t, MPI_Comm comm)
    {
      const long dims[2] = {static_cast<long>(a.rows()), static_cast<long>(a.cols())};
      MPI_Send(dims, 2, MPI_LONG, to, t, comm);
      MPI_Send(a.data(), static_cast<int>(a.size()), MPI_DOUBLE, to, t, comm);
    }

    Eigen::MatrixXd receive_matrix(const int from, const int t, MPI_Comm comm)
    {
      long dims[2] = {0, 0};
      MPI_Recv(dims, 2, MPI_LONG, from, t, comm, MPI_STATUS_IGNORE);
      Eigen::MatrixXd a(dims[0], dims[1]);
      MPI_Recv(a.data(), static_cast<int>(a.size()), MPI_DOUBLE, from, t, comm, MPI_STATUS_IGNORE);
      return a;
    }

    void send_ints(const std::vector<int> &v, const int to, const int t, MPI_Comm comm)
    {
      const int n = static_cast<int>(v.size());
      MPI_Send(&n, 1, MPI_INT, to, t, comm);
      MPI_Send(v.data(), n, MPI_INT, to, t, comm);
    }

    std::vector<int> receive_ints(const int from, const int t, MPI_Comm comm)
    {
      int n = 0;
      MPI_Recv(&n, 1, MPI_INT, from, t, comm, MPI_STATUS_IGNORE);
      std::vector<int> v(static_cast<std::size_t>(n));
      MPI_Recv(v.data(), n, MPI_INT, from, t, comm, MPI_STATUS_IGNORE);
      return v;
    }

    bool message_waiting(const int from, const int t, MPI_Comm comm)
    {
      int flag = 0;
      MPI_Iprobe(from, t, comm, &flag, MPI_STATUS_IGNORE);
      return flag != 0;
    }

    // A helper's result on its way: the status words (ok and the sectors, or failed and the
    // text's length), the text of a failure, the sectors' displacements; sent without blocking.
    struct Outgoing
    {
      std::vector<int>             ints;
      int                          n_ints = 0;
      std::string                  text;
      std::vector<Eigen::MatrixXd> matrices;
      std::vector<std::array<long, 2>> dims;
      std::vector<MPI_Request>     requests;

      void post(const int to, const int t, MPI_Comm comm)
      {
        n_ints = static_cast<int>(ints.size());
        requests.emplace_back();
        MPI_Isend(&n_ints, 1, MPI_INT, to, t, comm, &requests.back());
        requests.emplace_back();
        MPI_Isend(ints.data(), n_ints, MPI_INT, to, t, comm, &requests.back());
        if (!text.empty())
          {
            requests.emplace_back();
            MPI_Isend(text.data(), static_cast<int>(text.size()), MPI_CHAR, to, t, comm, &requests.back());
          }
        dims.reserve(matrices.size());
        for (const auto &a : matrices)
          {
            dims.push_back({static_cast<long>(a.rows()), static_cast<long>(a.cols())});
            requests.emplace_back();
            MPI_Isend(dims.back().data(), 2, MPI_LONG, to, t, comm, &requests.back());
            requests.emplace_back();
            MPI_Isend(a.data(), static_cast<int>(a.size()), MPI_DOUBLE, to, t, comm, &requests.back());
          }
      }
      bool done()
      {
        int flag = 0;
        MPI_Testall(static_cast<int>(requests.size()), requests.data(), &flag, MPI_STATUSES_IGNORE);
        return flag != 0;
      }
      void wait() { MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE); }
    };

    double seconds_since(const std::chrono::steady_clock::time_point t0)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  } // namespace

  std::vector<int> work_levelling_shares(const int todo, const double seconds_per_harmonic,
                                         const std::vector<double> &group_levels,
                                         const std::vector<double> &helper_levels)
  {
    std::vector<int> shares(helper_levels.size(), 0);
    if (todo < 2 || seconds_per_harmonic <= 0 || helper_levels.empty())
      return shares;
    // The level L: the remaining work poured onto the lowest levels first.
    std::vector<double> levels = group_levels;
    levels.insert(levels.end(), helper_levels.begin(), helper_levels.end());
    std::sort(levels.begin(), levels.end());
    const double work  = todo * seconds_per_harmonic;
    double       below = 0, L = 0;
    for (std::size_t k = 1; k <= levels.size(); ++k)
      {
        below += levels[k - 1];
        L = (work + below) / static_cast<double>(k);
        if (k == levels.size() || L <= levels[k])
          break;
      }
    for (std::size_t i = 0; i < helper_levels.size(); ++i)
      shares[i] = std::max(0, static_cast<int>(std::lround((L - helper_levels[i]) / seconds_per_harmonic)));
    // The owner's group keeps at least one.
    while (std::accumulate(shares.begin(), shares.end(), 0) > todo - 1)
      --*std::max_element(shares.begin(), shares.end());
    return shares;
  }

  void add_cyclic_harmonic(const int k, const int N, const Eigen::MatrixXd &D, const Eigen::MatrixXd &E,
                           const std::map<int, Eigen::MatrixXd> &q, const int s_min, const int s_max,
                           std::map<int, Eigen::MatrixXd> &u, HarmonicWorkspace &work)
  {
    using dealii::types::blas_int;
    const Eigen::Index         n = D.rows();
    const Eigen::Index         m = q.begin()->second.cols();
    const std::complex<double> w = std::polar(1.0, 2.0 * M_PI * k / N);
    Eigen::MatrixXcd          &H = work.H;
    Eigen::MatrixXcd          &x = work.x;
    H = D.cast<std::complex<double>>() + w * E.cast<std::complex<double>>() +
        std::conj(w) * E.transpose().cast<std::complex<double>>();
    x.setZero(n, m);
    for (const auto &[s, qs] : q)
      x += std::polar(1.0 / N, -2.0 * M_PI * k * s / N) * qs.template cast<std::complex<double>>();
    const double   cpu0 = process_cpu_seconds();
    const blas_int nn = static_cast<blas_int>(n), mm = static_cast<blas_int>(m);
    blas_int       info = 0;
    dealii::potrf("L", &nn, H.data(), &nn, &info);
    HG_REQUIRE_NUMERIC(info == 0, "cyclic harmonic ", k, " of ", N,
                       ": the cut-face matrix is not positive definite (zpotrf info ", info, ")");
    dealii::potrs("L", &nn, &mm, H.data(), &nn, x.data(), &nn, &info);
    HG_REQUIRE_NUMERIC(info == 0, "cyclic harmonic ", k, ": zpotrs info ", info);
    // u_s = sum over all N harmonics; k and N - k are complex conjugates.
    const double weight = (k == 0 || 2 * k == N) ? 1.0 : 2.0;
    for (int s = s_min; s <= s_max; ++s)
      u.at(s) += weight * (x * std::polar(1.0, 2.0 * M_PI * k * s / N)).real();
    ++work.solved;
    work.cpu_s += process_cpu_seconds() - cpu0;
  }

  HarmonicSharing::HarmonicSharing(MPI_Comm communicator, std::vector<int> body_owners,
                                   std::vector<std::vector<int>> body_helpers,
                                   std::function<void(int)> first_help, std::function<double()> work)
    : comm(communicator), owners(std::move(body_owners)), helpers(std::move(body_helpers)),
      on_first_help(std::move(first_help)), work_so_far(std::move(work))
  {
    if (!work_so_far)
      work_so_far = process_cpu_seconds;
    MPI_Comm_rank(comm, &me);
    MPI_Comm_size(comm, &size);
    helpers.resize(owners.size());
    // Every owner helps the other bodies once its own is done.
    for (std::size_t b = 0; b < owners.size(); ++b)
      for (std::size_t c = 0; c < owners.size(); ++c)
        if (owners[c] != owners[b] &&
            std::find(helpers[b].begin(), helpers[b].end(), owners[c]) == helpers[b].end())
          helpers[b].push_back(owners[c]);
  }

  bool HarmonicSharing::active(const int body) const
  {
    return size > 1 && !finished && body >= 0 && body < static_cast<int>(owners.size()) &&
           owners[static_cast<std::size_t>(body)] == me && !helpers[static_cast<std::size_t>(body)].empty();
  }

  void HarmonicSharing::receive_frees(const int body)
  {
    for (const int h : helpers[static_cast<std::size_t>(body)])
      while (message_waiting(h, tag(body, free_kind), comm))
        {
          double level = 0;
          MPI_Recv(&level, 1, MPI_DOUBLE, h, tag(body, free_kind), comm, MPI_STATUS_IGNORE);
          ++frees_received[body][h];
          waiting[body][h] = level;
        }
  }

  void HarmonicSharing::lend(const int body, std::deque<int> &todo, const int n_teeth,
                             const Eigen::MatrixXd &D, const Eigen::MatrixXd &E,
                             const std::map<int, Eigen::MatrixXd> &q, const int s_min, const int s_max,
                             const double seconds_per_harmonic, const std::vector<double> &group_levels)
  {
    if (!active(body))
      return;
    receive_frees(body);
    auto &free_now = waiting[body];
    if (free_now.empty() || todo.size() < 2 || seconds_per_harmonic <= 0)
      return;
    std::vector<int>    free_helpers;
    std::vector<double> helper_levels;
    for (const auto &[h, level] : free_now)
      {
        free_helpers.push_back(h);
        helper_levels.push_back(level);
      }
    const std::vector<int> shares =
      work_levelling_shares(static_cast<int>(todo.size()), seconds_per_harmonic,
                            group_levels.empty() ? std::vector<double>{work_so_far()} : group_levels, helper_levels);
    for (std::size_t i = 0; i < free_helpers.size(); ++i)
      {
        if (shares[i] == 0)
          continue;
        const int h = free_helpers[i];
        free_now.erase(h);
        std::vector<int> harmonics;
        for (int j = 0; j < shares[i]; ++j)
          {
            harmonics.push_back(todo.back());
            todo.pop_back();
          }
        if (helped_once.insert(body).second && on_first_help)
          on_first_help(body);
        const bool send_operator = has_operator[body].insert(h).second;
        // Header: the harmonics, then N, s_min, s_max, whether D and E follow, the sectors of q.
        std::vector<int> header = {n_teeth, s_min, s_max, send_operator ? 1 : 0};
        for (const auto &[s, qs] : q)
          header.push_back(s);
        const int t = tag(body, job_kind);
        send_ints(harmonics, h, t, comm);
        send_ints(header, h, t, comm);
        if (send_operator)
          {
            send_matrix(D, h, t, comm);
            send_matrix(E, h, t, comm);
          }
        for (const auto &[s, qs] : q)
          send_matrix(qs, h, t, comm);
        ++shares_out[body][h];
      }
  }

  void HarmonicSharing::collect(const int body, std::map<int, Eigen::MatrixXd> &u)
  {
    if (size == 1)
      return;
    std::string failure;
    for (auto &[h, count] : shares_out[body])
      for (; count > 0; --count)
        {
          const int  t      = tag(body, result_kind);
          const auto status = receive_ints(h, t, comm); // {ok, sectors ... } or {failed, text length}
          if (status.at(0) != 0)
            {
              std::string text(static_cast<std::size_t>(status.at(1)), '\0');
              MPI_Recv(text.data(), status.at(1), MPI_CHAR, h, t, comm, MPI_STATUS_IGNORE);
              if (failure.empty())
                failure = text;
              continue;
            }
          for (std::size_t i = 1; i < status.size(); ++i)
            u.at(status[i]) += receive_matrix(h, t, comm);
        }
    if (!failure.empty())
      throw NumericalError(failure);
  }

  void HarmonicSharing::last_words(const int body, const bool of_owners)
  {
    for (const int h : helpers[static_cast<std::size_t>(body)])
      {
        const bool is_owner = std::find(owners.begin(), owners.end(), h) != owners.end();
        if (is_owner != of_owners)
          continue;
        int frees_sent = 0;
        MPI_Recv(&frees_sent, 1, MPI_INT, h, tag(body, bye_kind), comm, MPI_STATUS_IGNORE);
        for (int i = frees_received[body][h]; i < frees_sent; ++i)
          {
            double level = 0;
            MPI_Recv(&level, 1, MPI_DOUBLE, h, tag(body, free_kind), comm, MPI_STATUS_IGNORE);
          }
      }
  }

  void HarmonicSharing::finish()
  {
    if (finished || size == 1)
      {
        finished = true;
        return;
      }
    finished = true;
    std::vector<int> mine, others;
    for (std::size_t b = 0; b < owners.size(); ++b)
      {
        const auto &h = helpers[b];
        if (owners[b] == me)
          mine.push_back(static_cast<int>(b));
        else if (std::find(h.begin(), h.end(), me) != h.end())
          others.push_back(static_cast<int>(b));
      }
    // Own bodies: STOP to every helper (the other owners too: they read it when they come to
    // help). Their last words come after this rank's help: a helper without a body of its own
    // may still be working for another body's group (fem/sector_group.h), and this rank helps
    // that body meanwhile.
    for (const int b : mine)
      for (const int h : helpers[static_cast<std::size_t>(b)])
        {
          const int word = 0;
          MPI_Send(&word, 1, MPI_INT, h, tag(b, stop_kind), comm);
        }

    // Help the other bodies at once until each owner says STOP.
    std::map<int, int> frees_sent;
    // FREE carries this rank's work so far, by which the owner sizes its share.
    for (const int b : others)
      {
        const double level = work_so_far();
        MPI_Send(&level, 1, MPI_DOUBLE, owners[static_cast<std::size_t>(b)], tag(b, free_kind), comm);
        ++frees_sent[b];
      }
    std::set<int>                         open(others.begin(), others.end());
    std::vector<std::unique_ptr<Outgoing>> sending;
    while (!open.empty())
      {
        bool worked = false;
        for (auto it = open.begin(); it != open.end();)
          {
            const int b     = *it;
            const int owner = owners[static_cast<std::size_t>(b)];
            if (message_waiting(owner, tag(b, job_kind), comm))
              {
                const int  t         = tag(b, job_kind);
                const auto harmonics = receive_ints(owner, t, comm);
                const auto header    = receive_ints(owner, t, comm);
                if (header.at(3) != 0)
                  {
                    auto D = receive_matrix(owner, t, comm);
                    auto E = receive_matrix(owner, t, comm);
                    operators[b] = {std::move(D), std::move(E)};
                  }
                std::map<int, Eigen::MatrixXd> q;
                for (std::size_t i = 4; i < header.size(); ++i)
                  q[header[i]] = receive_matrix(owner, t, comm);
                const int N = header[0], s_min = header[1], s_max = header[2];
                const auto &[D, E] = operators.at(b);
                std::map<int, Eigen::MatrixXd> u;
                for (int s = s_min; s <= s_max; ++s)
                  u[s] = Eigen::MatrixXd::Zero(D.rows(), q.begin()->second.cols());
                const auto  t0 = std::chrono::steady_clock::now();
                std::string failure;
                try
                  {
                    HarmonicWorkspace work;
                    for (const int k : harmonics)
                      add_cyclic_harmonic(k, N, D, E, q, s_min, s_max, u, work);
                  }
                catch (const std::exception &e)
                  {
                    failure = e.what();
                  }
                busy_s += seconds_since(t0);
                helped[b] += static_cast<int>(harmonics.size());
                // The result goes out without waiting for the owner to take it (an owner may
                // be sending this helper's next share, or another's): its buffers are kept
                // until the sends are done.
                sending.push_back(std::make_unique<Outgoing>());
                auto &o = *sending.back();
                o.ints  = {failure.empty() ? 0 : 1};
                if (!failure.empty())
                  o.ints.push_back(static_cast<int>(failure.size()));
                else
                  for (const auto &[s, us] : u)
                    o.ints.push_back(s);
                o.text = failure;
                for (auto &[s, us] : u)
                  o.matrices.push_back(std::move(us));
                o.post(owner, tag(b, result_kind), comm);
                const double level = work_so_far();
                MPI_Send(&level, 1, MPI_DOUBLE, owner, tag(b, free_kind), comm);
                ++frees_sent[b];
                worked = true;
                ++it;
              }
            else if (message_waiting(owner, tag(b, stop_kind), comm))
              {
                int word = 0;
                MPI_Recv(&word, 1, MPI_INT, owner, tag(b, stop_kind), comm, MPI_STATUS_IGNORE);
                MPI_Send(&frees_sent[b], 1, MPI_INT, owner, tag(b, bye_kind), comm);
                it     = open.erase(it);
                worked = true;
              }
            else
              ++it;
          }
        sending.erase(std::remove_if(sending.begin(), sending.end(), [](const auto &o) { return o->done(); }),
                      sending.end());
        if (!worked)
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    // Every result was taken before its owner said STOP.
    for (auto &o : sending)
      o->wait();
    sending.clear();
    // The last words of every helper: each sends them when it reads STOP, in its own help.
    for (const int b : mine)
      {
        last_words(b, false);
        last_words(b, true);
      }
    operators.clear();
  }
} // namespace hertzgear::fem
