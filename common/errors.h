#pragma once
// Error types that carry the process exit code the command line returns for them.
//   InputError      -> 2  bad scene, bad argument, impossible geometry
//   NumericalError  -> 3  a solver that does not converge, a blow-up, a NaN
// Anything else (std::exception) -> 1.
#include <sstream>
#include <stdexcept>
#include <string>

namespace hertzgear
{
  enum ExitCode : int
  {
    exit_success   = 0,
    exit_other     = 1,
    exit_bad_input = 2,
    exit_numerical = 3
  };

  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  class NumericalError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  // Build a message from streamable pieces: throw InputError(msg("teeth = ", z, " < 6")).
  template <typename... Args>
  std::string msg(const Args &...args)
  {
    std::ostringstream os;
    os.precision(10);
    (os << ... << args);
    return os.str();
  }

  // Always-on checks with a streamed message (in the spirit of MFEM_VERIFY / AssertThrow).
#define HG_REQUIRE_INPUT(cond, ...)                                                              \
  do                                                                                             \
    {                                                                                            \
      if (!(cond))                                                                               \
        throw ::hertzgear::InputError(::hertzgear::msg(__VA_ARGS__));                            \
    }                                                                                            \
  while (false)

#define HG_REQUIRE_NUMERIC(cond, ...)                                                            \
  do                                                                                             \
    {                                                                                            \
      if (!(cond))                                                                               \
        throw ::hertzgear::NumericalError(::hertzgear::msg(__VA_ARGS__));                        \
    }                                                                                            \
  while (false)
} // namespace hertzgear
