// Requirement: an installed hertzgear is usable from another CMake project.
#include <common/hash.h>
#include <hertzgear/version.h>

#include <iostream>

int main()
{
  const bool ok = hertzgear::hash_hex("") == "cbf29ce484222325";
  std::cout << "hertzgear " << hertzgear::version << (ok ? " ok" : " wrong hash") << std::endl;
  return ok ? 0 : 1;
}
