#pragma once
// An enumeration value from its name in a scene or on the command line.
#include "common/errors.h"

#include <initializer_list>
#include <string>
#include <utility>

namespace hertzgear
{
  // The value named `name` among `choices`; else ParameterError(field, "name is not one of a, b, c").
  template <typename E>
  E from_name(const std::string &name, std::initializer_list<std::pair<const char *, E>> choices,
              const std::string &field)
  {
    std::string list;
    for (const auto &[choice, value] : choices)
      {
        if (name == choice)
          return value;
        list += (list.empty() ? "" : ", ") + std::string(choice);
      }
    throw ParameterError(field, name + " is not one of " + list);
  }
} // namespace hertzgear
