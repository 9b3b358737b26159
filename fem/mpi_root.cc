#include "fem/mpi_root.h"

#include "common/errors.h"
#include "common/processes.h"

#include <deal.II/base/mpi.h>

#include <exception>
#include <string>

namespace hertzgear::fem
{
  void on_root(const MPI_Comm comm, const std::function<void()> &work)
  {
    int         code = exit_success;
    std::string text;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        try
          {
            work();
          }
        catch (const std::exception &e)
          {
            code = exit_code_of(e);
            text = e.what();
          }
      }
    if (dealii::Utilities::MPI::n_mpi_processes(comm) > 1)
      {
        code = dealii::Utilities::MPI::broadcast(comm, code, 0);
        text = dealii::Utilities::MPI::broadcast(comm, text, 0);
      }
    if (code != exit_success)
      processes::mark_failure_shared(); // every rank throws it
    throw_for_exit_code(code, text);
  }

  void on_every_rank(const MPI_Comm comm, const std::function<void()> &work)
  {
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    if (n_ranks == 1)
      {
        work();
        return;
      }
    int                code = exit_success;
    std::string        text;
    std::exception_ptr failure;
    try
      {
        work();
      }
    catch (const std::exception &e)
      {
        code    = exit_code_of(e);
        text    = e.what();
        failure = std::current_exception();
      }
    const unsigned int me    = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int first = dealii::Utilities::MPI::min(failure ? me : n_ranks, comm);
    if (first == n_ranks)
      return;
    code = dealii::Utilities::MPI::broadcast(comm, code, first);
    text = dealii::Utilities::MPI::broadcast(comm, text, first);
    processes::mark_failure_shared(); // every rank throws it
    if (me == first)
      std::rethrow_exception(failure); // its own kind, e.g. a ParameterError naming a value
    throw_for_exit_code(code, text);
  }
} // namespace hertzgear::fem
