#include "app/run_directory.h"

#include "common/errors.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "common/atomic_file.h"

#include <hertzgear/version.h>

#include <chrono>
#include <ctime>

namespace hertzgear
{
  namespace fs = std::filesystem;

  nlohmann::json provenance(const Scene &scene)
  {
    return {{"hertzgear_version", version},
            {"git_revision", git_revision},
            {"scene_file", scene.file.string()},
            {"scene_hash", scene.hash}};
  }

  RunLock::RunLock(const fs::path &directory, const std::string &role)
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

  RunLock::~RunLock()
  {
    if (fd >= 0)
      ::close(fd); // releases the lock
  }

  RunDirectory::RunDirectory(fs::path directory, const Scene &scene, std::string command_line)
    : directory(std::move(directory)), scene(scene), command_line(std::move(command_line))
  {}

  void RunDirectory::lock() const
  {
    if (!held)
      held = std::make_shared<RunLock>(directory);
  }

  void RunDirectory::write_text(const std::string &name, const std::string &content) const
  {
    lock();
    write_file_atomically(directory / name, content);
  }

  void RunDirectory::write_json(const std::string &name, const nlohmann::json &value) const
  {
    write_text(name, value.dump(2) + "\n");
  }

  void RunDirectory::finish(const PhaseTimer &timer, const nlohmann::json &extra) const
  {
    write_text("used_parameters.prm", scene.used_parameters_prm);
    nlohmann::json run = provenance(scene);
    run["command"]     = command_line;
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char              stamp[32];
    std::strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    run["finished_utc"]   = stamp;
    nlohmann::json stages = nlohmann::json::array();
    for (const auto &[phase, seconds] : timer.phases())
      stages.push_back({{"stage", phase}, {"wall_time_s", seconds}});
    run["stage_timings"] = stages;
    run["wall_time_s"]   = timer.total_seconds();
    run.update(extra);
    write_json("run.json", run);
    timer.print_summary(progress_stream());
  }
} // namespace hertzgear
