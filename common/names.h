#pragma once
// The names of an enumeration's values, in a scene, on the command line and in outputs: one table
// per enumeration serves both directions.
#include "common/errors.h"

#include <cstddef>
#include <string>
#include <utility>

namespace hertzgear
{
  // A name table: {"name", value} pairs, in the order messages list them.
  template <typename E, std::size_t N>
  using NameTable = std::pair<const char *, E>[N];

  // The value named `name` in `table`; else ParameterError(field, "name is not one of a, b, c").
  template <typename E, std::size_t N>
  E from_name(const std::string &name, const NameTable<E, N> &table, const std::string &field)
  {
    std::string list;
    for (const auto &[choice, value] : table)
      {
        if (name == choice)
          return value;
        list += (list.empty() ? "" : ", ") + std::string(choice);
      }
    throw ParameterError(field, name + " is not one of " + list);
  }

  // The name of `value` in `table`, or "?" for a value the table lacks.
  template <typename E, std::size_t N>
  std::string name_of(const E value, const NameTable<E, N> &table)
  {
    for (const auto &[choice, named] : table)
      if (named == value)
        return choice;
    return "?";
  }
} // namespace hertzgear
