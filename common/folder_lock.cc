#include "common/folder_lock.h"

#include "common/errors.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace hertzgear
{
  namespace fs = std::filesystem;

  FolderLock::FolderLock(const fs::path &directory, const std::string &role)
  {
    const std::string name = role + " " + directory.string();
    std::error_code   ec;
    if (fs::exists(directory, ec) && !fs::is_directory(directory, ec))
      throw InputError(msg(name, ": is a file, not a folder"));
    fs::create_directories(directory, ec);
    if (ec)
      throw InputError(msg(name, ": cannot create the folder: ", ec.message()));
    const fs::path lock_file = directory / ".hertzgear.lock";
    fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw InputError(msg(name, ": cannot write into the folder: ", std::strerror(errno)));
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
  }

  FolderLock::~FolderLock()
  {
    if (fd >= 0)
      ::close(fd); // releases the lock
  }
} // namespace hertzgear
