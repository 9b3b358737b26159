#include "common/atomic_file.h"

#include "common/errors.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *temporary_marker = ".hg-partial-";
  }

  fs::path temporary_path_for(const fs::path &path)
  {
    static std::atomic<unsigned long> counter{0};
    const std::string name = "." + path.filename().string() + temporary_marker +
                             std::to_string(::getpid()) + "-" + std::to_string(counter++);
    return path.parent_path() / name;
  }

  bool is_temporary_artifact(const fs::path &path)
  {
    return path.filename().string().find(temporary_marker) != std::string::npos;
  }

  namespace
  {
    // Data and metadata of `path` on the disk before it is renamed into place, and the rename in
    // its folder after (the order a power loss needs: a name never points at unwritten data).
    void sync_to_disk(const fs::path &path, const int flags)
    {
      const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
      if (fd < 0)
        throw InputError(msg("cannot sync ", path.string(), ": ", std::strerror(errno)));
      const int status = ::fsync(fd);
      const int error  = errno;
      ::close(fd);
      if (status != 0 && error != EINVAL) // EINVAL: a file system without fsync (e.g. a pipe)
        throw InputError(msg("cannot sync ", path.string(), ": ", std::strerror(error)));
    }
  } // namespace

  void produce_file_atomically(const fs::path &path,
                               const std::function<void(const fs::path &)> &producer)
  {
    const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
      throw InputError(msg("cannot create the folder ", folder.string(), " for ",
                           path.filename().string(), ": ", ec.message()));
    const fs::path tmp = temporary_path_for(path);
    try
      {
        producer(tmp);
        if (!fs::exists(tmp))
          throw std::runtime_error("producer wrote nothing to " + tmp.string());
        if (fs::is_regular_file(tmp))
          sync_to_disk(tmp, O_RDONLY);
        fs::rename(tmp, path, ec);
        if (ec)
          throw InputError(msg("cannot write ", path.string(), ": ", ec.message()));
        sync_to_disk(folder, O_RDONLY | O_DIRECTORY);
      }
    catch (...)
      {
        fs::remove_all(tmp, ec);
        throw;
      }
  }

  void write_file_atomically(const fs::path &path,
                             const std::function<void(std::ostream &)> &writer)
  {
    produce_file_atomically(path, [&](const fs::path &tmp) {
      errno = 0;
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out)
        throw InputError(msg("cannot write ", path.string(), ": ", std::strerror(errno)));
      writer(out);
      out.flush();
      out.close();
      if (!out)
        throw InputError(msg("cannot write ", path.string(), ": ",
                             errno != 0 ? std::strerror(errno) : "write error"));
    });
  }

  void write_file_atomically(const fs::path &path, const std::string &content)
  {
    write_file_atomically(path, [&](std::ostream &out) { out << content; });
  }
} // namespace hertzgear
