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
  //
  // The lock file is opened without following a symbolic link and must be a regular file: a
  // link or a folder of that name is refused (a link planted there must not make hertzgear
  // truncate the file it points at). A folder this object made and that holds nothing but the
  // lock file when the object ends (a command refused after its start) is removed again, so a
  // refused command leaves no empty folder behind.
  class FolderLock
  {
  public:
    explicit FolderLock(const std::filesystem::path &directory, const std::string &role = "--out");
    ~FolderLock();
    FolderLock(const FolderLock &)            = delete;
    FolderLock &operator=(const FolderLock &) = delete;

    // Whether this process holds the lock of `directory` (through any FolderLock alive).
    static bool held_here(const std::filesystem::path &directory);

  private:
    int                   fd = -1;
    std::filesystem::path folder;         // as given
    std::string           key;            // its absolute, normal form (held_here)
    std::filesystem::path first_created;  // the outermost folder this object made, or empty
  };
} // namespace hertzgear
