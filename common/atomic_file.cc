#include "common/atomic_file.h"

#include <atomic>
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

  void produce_file_atomically(const fs::path &path,
                               const std::function<void(const fs::path &)> &producer)
  {
    if (!path.parent_path().empty())
      fs::create_directories(path.parent_path());
    const fs::path tmp = temporary_path_for(path);
    try
      {
        producer(tmp);
        if (!fs::exists(tmp))
          throw std::runtime_error("producer wrote nothing to " + tmp.string());
        fs::rename(tmp, path);
      }
    catch (...)
      {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
      }
  }

  void write_file_atomically(const fs::path &path,
                             const std::function<void(std::ostream &)> &writer)
  {
    produce_file_atomically(path, [&](const fs::path &tmp) {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out)
        throw std::runtime_error("cannot open " + tmp.string() + " for writing");
      writer(out);
      out.flush();
      if (!out)
        throw std::runtime_error("write to " + path.string() + " failed");
    });
  }

  void write_file_atomically(const fs::path &path, const std::string &content)
  {
    write_file_atomically(path, [&](std::ostream &out) { out << content; });
  }
} // namespace hertzgear
