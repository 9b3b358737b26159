#include "fem/mpi_root.h"

#include "common/errors.h"

#include <deal.II/base/mpi.h>

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
    throw_for_exit_code(code, text);
  }
} // namespace hertzgear::fem
