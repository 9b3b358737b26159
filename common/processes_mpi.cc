// The processes of MPI_COMM_WORLD (main initialises MPI); before MPI is initialised, one process.
#include "common/processes.h"

#include "common/errors.h"

#include <mpi.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>

#include <unistd.h>

namespace hertzgear::processes
{
  namespace
  {
    bool shared_failure = false;

    bool mpi_running()
    {
      int initialised = 0, finalised = 0;
      MPI_Initialized(&initialised);
      MPI_Finalized(&finalised);
      return initialised && !finalised;
    }
  } // namespace

  int rank()
  {
    int r = 0;
    if (mpi_running())
      MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
  }

  int count()
  {
    int n = 1;
    if (mpi_running())
      MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
  }

  bool is_root() { return rank() == 0; }

  std::vector<std::string> all_gather(const std::string &mine)
  {
    const int n = count();
    if (n == 1)
      return {mine};
    const int        length = static_cast<int>(mine.size());
    std::vector<int> lengths(n), offsets(n, 0);
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (int r = 1; r < n; ++r)
      offsets[r] = offsets[r - 1] + lengths[r - 1];
    std::string all(static_cast<std::size_t>(offsets[n - 1] + lengths[n - 1]), '\0');
    MPI_Allgatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(),
                   MPI_CHAR, MPI_COMM_WORLD);
    std::vector<std::string> parts;
    for (int r = 0; r < n; ++r)
      parts.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(lengths[r])));
    return parts;
  }

  std::string broadcast(const std::string &from_root)
  {
    if (count() == 1)
      return from_root;
    int length = static_cast<int>(from_root.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string text = is_root() ? from_root : std::string(static_cast<std::size_t>(length), '\0');
    MPI_Bcast(text.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
    return text;
  }

  void agree(const std::function<void()> &step, const bool root_only)
  {
    if (count() == 1)
      {
        step();
        return;
      }
    int                code = exit_success;
    std::string        text;
    std::exception_ptr failure;
    if (!root_only || is_root())
      try
        {
          step();
        }
      catch (const std::exception &e)
        {
          code    = exit_code_of(e);
          text    = e.what();
          failure = std::current_exception();
        }
    // The lowest failing rank, then its exit code and text from it.
    const int mine  = failure ? rank() : count();
    int       first = count();
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == count())
      return;
    MPI_Bcast(&code, 1, MPI_INT, first, MPI_COMM_WORLD);
    int length = static_cast<int>(text.size());
    MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
    text.resize(static_cast<std::size_t>(length));
    MPI_Bcast(text.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
    shared_failure = true;
    if (rank() == first)
      std::rethrow_exception(failure); // its own kind, e.g. a ParameterError naming a value
    throw_for_exit_code(code == exit_success ? exit_other : code, text);
  }

  void mark_failure_shared() { shared_failure = true; }
  bool failure_is_shared() { return shared_failure; }

  void abort_all(const int exit_code)
  {
    if (count() > 1)
      MPI_Abort(MPI_COMM_WORLD, exit_code);
  }

  namespace
  {
    // The line a rank ended by a signal prints, formed before any signal comes: a handler may
    // only call async-signal-safe functions (write, _exit), so it picks a prepared line.
    struct FatalSignal
    {
      int         number;
      const char *name;
      char        line[256];
    };
    FatalSignal fatal_signals[] = {{SIGTERM, "SIGTERM (sent by mpirun when another rank has failed, or from outside)", {}},
                                   {SIGSEGV, "SIGSEGV", {}}, {SIGBUS, "SIGBUS", {}},   {SIGFPE, "SIGFPE", {}},
                                   {SIGILL, "SIGILL", {}},   {SIGABRT, "SIGABRT", {}}, {SIGXCPU, "SIGXCPU", {}},
                                   {SIGHUP, "SIGHUP", {}}};

    extern "C" void end_rank_on_signal(const int number)
    {
      for (const auto &s : fatal_signals)
        if (s.number == number)
          {
            const ssize_t written = write(STDERR_FILENO, s.line, std::strlen(s.line));
            (void)written;
            break;
          }
      _exit(exit_numerical);
    }
  } // namespace

  void end_with_exit_code_on_fatal_signals()
  {
    if (count() == 1)
      return;
    for (auto &s : fatal_signals)
      {
        std::snprintf(s.line, sizeof(s.line),
                      "hertzgear: error: rank %d of %d ended by signal %s: no result is written, this "
                      "rank exits with %d and mpirun ends the others\n",
                      rank(), count(), s.name, exit_numerical);
        struct sigaction action = {};
        action.sa_handler       = end_rank_on_signal;
        sigemptyset(&action.sa_mask);
        sigaction(s.number, &action, nullptr);
      }
  }
} // namespace hertzgear::processes
