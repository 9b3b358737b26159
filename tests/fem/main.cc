// The fem suite's own main: deal.II/PETSc need MPI initialised before any test and finalised
// after all of them. Rank 0 prints gtest's report; other ranks print only their failures.
#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <iostream>

namespace
{
  class FailurePrinter : public ::testing::EmptyTestEventListener
  {
  public:
    explicit FailurePrinter(const unsigned int rank)
      : rank(rank)
    {}
    void OnTestPartResult(const ::testing::TestPartResult &result) override
    {
      if (result.failed())
        std::cerr << "[rank " << rank << "] " << (result.file_name() ? result.file_name() : "") << ":"
                  << result.line_number() << ": failure\n"
                  << result.summary() << std::endl;
    }

  private:
    unsigned int rank;
  };
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
  if (rank != 0)
    {
      auto &listeners = ::testing::UnitTest::GetInstance()->listeners();
      delete listeners.Release(listeners.default_result_printer());
      listeners.Append(new FailurePrinter(rank));
    }
  return RUN_ALL_TESTS();
}
