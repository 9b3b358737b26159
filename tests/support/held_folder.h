#pragma once
// What the folder-lock tests share: a folder held as a running hertzgear process holds it, and
// the files below a folder with their content (to show that a refused command changed nothing).
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <filesystem>
#include <map>
#include <string>
#include <sys/file.h>
#include <unistd.h>

namespace hertzgear::testing
{
  // Holds DIR's lock as a running hertzgear process does: a flock on DIR/.hertzgear.lock with the
  // holder's process number inside, for the life of the object.
  class HeldFolder
  {
  public:
    explicit HeldFolder(const std::filesystem::path &dir) : pid(std::to_string(::getpid()))
    {
      std::filesystem::create_directories(dir);
      fd = ::open((dir / ".hertzgear.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      EXPECT_GE(fd, 0);
      EXPECT_EQ(::flock(fd, LOCK_EX), 0);
      EXPECT_EQ(::pwrite(fd, pid.data(), pid.size(), 0), static_cast<ssize_t>(pid.size()));
    }
    ~HeldFolder() { ::close(fd); }
    HeldFolder(const HeldFolder &)            = delete;
    HeldFolder &operator=(const HeldFolder &) = delete;
    const std::string pid;

  private:
    int fd = -1;
  };

  // Every file below DIR with its content.
  inline std::map<std::string, std::string> contents_below(const std::filesystem::path &dir)
  {
    std::map<std::string, std::string> files;
    for (const auto &e : std::filesystem::recursive_directory_iterator(dir))
      if (e.is_regular_file())
        files[std::filesystem::relative(e.path(), dir).string()] = slurp(e.path());
    return files;
  }
} // namespace hertzgear::testing
