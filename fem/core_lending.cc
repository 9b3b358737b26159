#include "fem/core_lending.h"

#include "fem/petsc_ksp.h"

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <sched.h>

namespace hertzgear::fem
{
  namespace
  {
    constexpr int done_tag = 4711; // the one message each way

    // mpirun binds each of two ranks to one core by default (Open MPI, --bind-to core for up to
    // two processes), and threads inherit the binding: a rank could not use a lent core. Every
    // thread of this process (OpenBLAS's pool included) may run on every core of the node; the
    // thread counts alone share the cores out.
    void allow_every_core(const int cores)
    {
      cpu_set_t all;
      CPU_ZERO(&all);
      for (int c = 0; c < cores && c < CPU_SETSIZE; ++c)
        CPU_SET(c, &all);
      std::error_code ec;
      for (const auto &task : std::filesystem::directory_iterator("/proc/self/task", ec))
        {
          const pid_t tid = static_cast<pid_t>(std::stol(task.path().filename().string()));
          sched_setaffinity(tid, sizeof(all), &all); // best effort: a refusal leaves the binding
        }
    }
  }

  CoreLending::CoreLending(const MPI_Comm communicator)
    : comm(communicator)
  {
    int size = 1, rank = 0;
    MPI_Comm_size(comm, &size);
    MPI_Comm_rank(comm, &rank);
    if (size != 2 || ranks_on_node(comm) != 2)
      return;
    all_threads = cores_of_node();
    own_threads = std::max(1, all_threads / 2);
    if (all_threads <= own_threads || !set_blas_threads(own_threads))
      return; // nothing to lend, or not OpenBLAS
    partner = 1 - rank;
    allow_every_core(all_threads);
    MPI_Irecv(&message, 1, MPI_INT, partner, done_tag, comm, &request);
  }

  CoreLending::~CoreLending()
  {
    finish();
  }

  bool CoreLending::test_partner()
  {
    if (!partner_done)
      {
        int flag = 0;
        MPI_Test(&request, &flag, MPI_STATUS_IGNORE);
        partner_done = flag != 0;
      }
    return partner_done;
  }

  void CoreLending::poll()
  {
    if (partner < 0 || finished || took_cores || given_back || !test_partner())
      return;
    took_cores = set_blas_threads(all_threads);
  }

  void CoreLending::give_back()
  {
    if (partner < 0 || given_back)
      return;
    given_back = true;
    if (took_cores)
      set_blas_threads(own_threads);
  }

  void CoreLending::announce()
  {
    if (partner < 0 || announced)
      return;
    announced     = true;
    const int one = 1;
    MPI_Send(&one, 1, MPI_INT, partner, done_tag, comm); // one int: sent eagerly
  }

  void CoreLending::finish()
  {
    if (partner < 0 || finished)
      return;
    announce();
    finished = true;
    while (!test_partner())
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    set_blas_threads(own_threads);
  }
} // namespace hertzgear::fem
