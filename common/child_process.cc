#include "common/child_process.h"

#include "common/errors.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace hertzgear
{
  int run_process(const std::vector<std::string> &args)
  {
    std::vector<char *> argv;
    for (const auto &a : args)
      argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    std::cout.flush();
    std::cerr.flush();
    const pid_t pid = ::fork();
    if (pid < 0)
      throw std::runtime_error(msg("cannot start ", args[0], ": ", std::strerror(errno)));
    if (pid == 0)
      {
        ::execvp(argv[0], argv.data());
        std::fprintf(stderr, "hertzgear: error: cannot run %s: %s\n", argv[0], std::strerror(errno));
        ::_exit(127);
      }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
      if (errno != EINTR)
        throw std::runtime_error(msg("waiting for ", args[0], ": ", std::strerror(errno)));
    if (WIFEXITED(status))
      return WEXITSTATUS(status);
    return -1;
  }
} // namespace hertzgear
