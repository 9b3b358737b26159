// The processes of MPI_COMM_WORLD (main initialises MPI); before MPI is initialised, one process.
#include "common/processes.h"

#include <mpi.h>

namespace hertzgear::processes
{
  namespace
  {
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
} // namespace hertzgear::processes
