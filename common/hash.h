#pragma once
// A stable 64-bit content hash (FNV-1a) for cache keys and scene hashes. Stable across
// platforms, compilers and runs, unlike std::hash.
#include <cstdint>
#include <string>
#include <string_view>

namespace hertzgear
{
  std::uint64_t fnv1a_64(std::string_view data, std::uint64_t seed = 0xcbf29ce484222325ULL);

  // 16 lower-case hex digits.
  std::string hash_hex(std::string_view data);
} // namespace hertzgear
