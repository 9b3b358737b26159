#pragma once
// The libraries below app/ name their own input fields in messages: a ParameterError names the
// offending field, and any message may name further fields as {field}. This maps those names to
// the scene keys they are filled from, so that a user reads the key to change.
#include "common/errors.h"

#include <functional>
#include <string>

namespace hertzgear
{
  // "{teeth_per_sector}" -> "Mesh/teeth_per_sector" for every field the libraries name; other
  // braces are left as they are.
  std::string with_scene_keys(const std::string &text);

  // The message of a ParameterError with its field (and the fields it names) as scene keys:
  // "torque_Nm = 0: ..." -> "Operating/torque_Nm = 0: ...".
  std::string scene_message(const ParameterError &error);

  // The same with the keys of `key_of`, which names every field ("Sweep/" + field, ...).
  std::string keyed_message(const ParameterError                                   &error,
                            const std::function<std::string(const std::string &)> &key_of);
} // namespace hertzgear
