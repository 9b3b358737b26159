#include "common/folder_lock.h"

#include "common/errors.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <set>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    std::mutex            held_mutex;
    std::set<std::string> &held_folders()
    {
      static std::set<std::string> folders;
      return folders;
    }

    // The absolute, normal form of a folder, without a trailing separator.
    fs::path normal_absolute(const fs::path &directory)
    {
      std::error_code ec;
      fs::path        p = fs::absolute(directory, ec).lexically_normal();
      if (!p.has_filename() && p.has_parent_path() && p != p.root_path())
        p = p.parent_path();
      return p;
    }

    std::string key_of(const fs::path &directory)
    {
      std::error_code ec;
      const fs::path  canonical = fs::weakly_canonical(normal_absolute(directory), ec);
      return normal_absolute(ec ? normal_absolute(directory) : canonical).string();
    }

    // The outermost of `directory` and its parents that does not exist yet (empty if it exists).
    fs::path outermost_missing(const fs::path &directory)
    {
      std::error_code ec;
      fs::path        missing;
      for (fs::path p = normal_absolute(directory); !p.empty(); p = p.parent_path())
        {
          if (fs::exists(fs::symlink_status(p, ec)))
            break;
          missing = p;
          if (p == p.parent_path())
            break;
        }
      return missing;
    }
  } // namespace

  FolderLock::FolderLock(const fs::path &directory, const std::string &role)
    : folder(directory), key(key_of(directory))
  {
    const std::string name = role + " " + directory.string();
    std::error_code   ec;
    if (fs::exists(directory, ec) && !fs::is_directory(directory, ec))
      throw InputError(msg(name, ": is a file, not a folder"));
    first_created = outermost_missing(directory);
    // A file where a folder above must be: name it (the system would say "Not a directory").
    const fs::path existing = first_created.empty() ? fs::path() : first_created.parent_path();
    if (!existing.empty() && fs::exists(existing, ec) && !fs::is_directory(existing, ec))
      throw InputError(msg(name, ": cannot create the folder: ", existing.string(),
                           " is a file, not a folder (", std::strerror(ENOTDIR), ")"));
    fs::create_directories(directory, ec);
    if (ec)
      throw InputError(msg(name, ": cannot create the folder: ", ec.message()));
    const fs::path lock_file = directory / ".hertzgear.lock";
    // O_NOFOLLOW: a symbolic link in the lock's place is refused, not followed; O_NONBLOCK: a
    // FIFO there does not block the open (it is refused below as not a regular file).
    fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd < 0)
      {
        const int error = errno;
        if (error == ELOOP)
          throw InputError(msg(name, ": ", lock_file.string(),
                               " is a symbolic link; hertzgear does not follow it (remove it)"));
        if (error == EISDIR)
          throw InputError(msg(name, ": ", lock_file.string(),
                               " is a folder, not hertzgear's lock file (remove it)"));
        throw InputError(msg(name, ": cannot write into the folder: ", std::strerror(error)));
      }
    struct stat st
    {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
      {
        ::close(fd);
        fd = -1;
        throw InputError(msg(name, ": ", lock_file.string(),
                             " is not a regular file, not hertzgear's lock file (remove it)"));
      }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
      {
        const int error = errno;
        char      holder[32] = {0};
        const auto n          = ::pread(fd, holder, sizeof(holder) - 1, 0);
        ::close(fd);
        fd = -1;
        if (error == EWOULDBLOCK)
          throw InputError(msg(name, ": the folder is in use by process ",
                               n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : "?",
                               " (another hertzgear run writes there); wait for it to end",
                               role == "--out" ? " or choose another --out" : ""));
        throw InputError(msg(name, ": cannot lock the folder: ", std::strerror(error)));
      }
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) < 0)
      {
        // The lock holds without the process number; only the message of a second run lacks it.
      }
    const std::lock_guard<std::mutex> guard(held_mutex);
    held_folders().insert(key);
  }

  FolderLock::~FolderLock()
  {
    if (fd < 0)
      return;
    {
      const std::lock_guard<std::mutex> guard(held_mutex);
      held_folders().erase(key);
    }
    // A folder made here that holds only the lock: the command wrote nothing (refused after its
    // start); leave no trace. The lock file goes while it is still held.
    std::error_code ec;
    if (!first_created.empty())
      {
        bool only_lock = true;
        for (const auto &e : fs::directory_iterator(folder, ec))
          only_lock = only_lock && e.path().filename() == ".hertzgear.lock";
        if (!ec && only_lock)
          {
            fs::remove(folder / ".hertzgear.lock", ec);
            // The folder and the parents this object made, innermost first, while empty.
            for (fs::path p = normal_absolute(folder);; p = p.parent_path())
              {
                if (!fs::is_empty(p, ec) || ec || !fs::remove(p, ec))
                  break;
                if (p == first_created || p == p.parent_path())
                  break;
              }
          }
      }
    ::close(fd); // releases the lock
  }

  bool FolderLock::held_here(const fs::path &directory)
  {
    const std::lock_guard<std::mutex> guard(held_mutex);
    return held_folders().count(key_of(directory)) > 0;
  }
} // namespace hertzgear
