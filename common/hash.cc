#include "common/hash.h"

#include <cstdio>

namespace hertzgear
{
  std::uint64_t fnv1a_64(std::string_view data, std::uint64_t seed)
  {
    std::uint64_t h = seed;
    for (const unsigned char c : data)
      {
        h ^= c;
        h *= 0x100000001b3ULL;
      }
    return h;
  }

  std::string hash_hex(std::string_view data)
  {
    char buffer[17];
    std::snprintf(buffer, sizeof(buffer), "%016llx",
                  static_cast<unsigned long long>(fnv1a_64(data)));
    return buffer;
  }
} // namespace hertzgear
