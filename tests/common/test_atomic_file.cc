// Requirement: an artifact is either absent or complete; an interrupted or failed write never
// leaves a half-written file under the final name.
#include "common/atomic_file.h"
#include "common/hash.h"

#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace hertzgear;

namespace
{
  const auto &fresh_dir = hertzgear::testing::fresh_temp_dir;
} // namespace

TEST(AtomicFile, WritesCompleteContentAndCreatesFolders)
{
  const fs::path dir = fresh_dir("atomic_ok");
  write_file_atomically(dir / "sub" / "a.csv", "x,y\n1,2\n");
  EXPECT_EQ(hertzgear::testing::slurp(dir / "sub" / "a.csv"), "x,y\n1,2\n");
  // No temporary left next to it.
  for (const auto &entry : fs::directory_iterator(dir / "sub"))
    EXPECT_FALSE(is_temporary_artifact(entry.path())) << entry.path();
}

TEST(AtomicFile, FailedWriterLeavesNoArtifactAndKeepsTheOldOne)
{
  const fs::path dir = fresh_dir("atomic_fail");
  write_file_atomically(dir / "a.json", "{\"old\": true}\n");
  EXPECT_THROW(write_file_atomically(dir / "a.json",
                                     [](std::ostream &out) {
                                       out << "{\"new\": ";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_EQ(hertzgear::testing::slurp(dir / "a.json"), "{\"old\": true}\n");
  int n_files = 0;
  for ([[maybe_unused]] const auto &entry : fs::directory_iterator(dir))
    ++n_files;
  EXPECT_EQ(n_files, 1) << "the temporary of the failed write must be removed";

  EXPECT_THROW(write_file_atomically(dir / "b.csv",
                                     [](std::ostream &out) {
                                       out << "partial";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "b.csv"));
}

TEST(AtomicFile, ProducerThatWritesNothingIsAnError)
{
  const fs::path dir = fresh_dir("atomic_empty");
  EXPECT_THROW(produce_file_atomically(dir / "mesh.msh", [](const fs::path &) {}),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "mesh.msh"));
}

TEST(Hash, IsStableAcrossRuns)
{
  // FNV-1a 64 reference values (the published test vectors of the algorithm).
  EXPECT_EQ(hash_hex(""), "cbf29ce484222325");
  EXPECT_EQ(hash_hex("a"), "af63dc4c8601ec8c");
  EXPECT_NE(hash_hex("set teeth = 23"), hash_hex("set teeth = 24"));
}
