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

  // Bad input about one named field of a library's plain input (e.g. "torque_Nm"). The libraries
  // below app/ name their own fields; app/ replaces the field by the scene key it came from.
  // what() reads "<parameter> = <text>"; `text` starts with the offending value and writes other
  // fields it names as {field}.
  class ParameterError : public InputError
  {
  public:
    ParameterError(const std::string &parameter, const std::string &text)
      : InputError(parameter + " = " + text), name(parameter), rest(text)
    {}
    const std::string &parameter() const { return name; }
    const std::string &text() const { return rest; }

  private:
    std::string name, rest;
  };

  // The exit code of an exception: InputError 2, NumericalError 3, anything else 1.
  inline int exit_code_of(const std::exception &e)
  {
    if (dynamic_cast<const InputError *>(&e))
      return exit_bad_input;
    if (dynamic_cast<const NumericalError *>(&e))
      return exit_numerical;
    return exit_other;
  }

  // Throws the exception of that exit code with that text (the inverse of exit_code_of, for an
  // error passed between processes); does nothing for exit_success.
  inline void throw_for_exit_code(const int code, const std::string &text)
  {
    if (code == exit_bad_input)
      throw InputError(text);
    if (code == exit_numerical)
      throw NumericalError(text);
    if (code != exit_success)
      throw std::runtime_error(text);
  }

  // Build a message from streamable pieces: throw InputError(msg("teeth = ", z, " < 6")).
  template <typename... Args>
  std::string msg(const Args &...args)
  {
    std::ostringstream os;
    os.precision(10);
    (os << ... << args);
    return os.str();
  }

  // Always-on checks with a streamed message (in the spirit of MFEM_VERIFY / AssertThrow): throw
  // `error` with the message when `cond` fails.
#define HG_REQUIRE(error, cond, ...)                                                             \
  do                                                                                             \
    {                                                                                            \
      if (!(cond))                                                                               \
        throw error(::hertzgear::msg(__VA_ARGS__));                                              \
    }                                                                                            \
  while (false)

#define HG_REQUIRE_INPUT(cond, ...) HG_REQUIRE(::hertzgear::InputError, cond, __VA_ARGS__)
#define HG_REQUIRE_NUMERIC(cond, ...) HG_REQUIRE(::hertzgear::NumericalError, cond, __VA_ARGS__)
} // namespace hertzgear
