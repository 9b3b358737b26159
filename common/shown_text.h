#pragma once
// User text as a message quotes it (a scene value, key or line, a --set argument).
#include "common/errors.h"

#include <cstddef>
#include <cstdio>
#include <string>

namespace hertzgear
{
  // Control and non-ASCII bytes as \xNN, and at most `keep` characters followed by
  // "... (N characters)" with the whole length, so that a message about a value of megabytes
  // stays a line. Every message that quotes a scene value, key or line goes through it.
  inline std::string shown(const std::string &text, const std::size_t keep = 60)
  {
    std::string out;
    for (std::size_t i = 0; i < text.size() && i < keep; ++i)
      {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 || c >= 0x7f)
          {
            char code[8];
            std::snprintf(code, sizeof(code), "\\x%02x", c);
            out += code;
          }
        else
          out += static_cast<char>(c);
      }
    if (text.size() > keep)
      out += msg("... (", text.size(), " characters)");
    return out;
  }
} // namespace hertzgear
