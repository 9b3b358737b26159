#pragma once
// One hertzgear process per output folder.
#include <filesystem>
#include <string>

namespace hertzgear
{
  // Exclusive use of an output folder for the life of this object: creates the folder (and its
  // parents) and takes an advisory lock (flock) on DIR/.hertzgear.lock, which the kernel releases
  // when the process ends in any way, and writes this process's number into it. Throws
  // InputError naming the folder (after `role`, the option or argument that gave it) and the
  // reason when the folder cannot be made or written, and naming the holder's process when
  // another hertzgear process uses it: a second run on one folder exits 2 at once instead of
  // racing the first.
  class FolderLock
  {
  public:
    explicit FolderLock(const std::filesystem::path &directory, const std::string &role = "--out");
    ~FolderLock();
    FolderLock(const FolderLock &)            = delete;
    FolderLock &operator=(const FolderLock &) = delete;

  private:
    int fd = -1;
  };
} // namespace hertzgear
