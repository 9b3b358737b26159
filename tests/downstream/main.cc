// Requirement: an installed hertzgear is usable from another CMake project: its common library and
// the stiffness table, the contract a downstream tool reads or writes.
#include <common/hash.h>
#include <hertzgear/version.h>
#include <table/stiffness_table.h>

#include <iostream>

int main()
{
  const bool hash_ok = hertzgear::hash_hex("") == "cbf29ce484222325";
  const auto table   = hertzgear::table::stiffness_table_from_json_text(
    R"({"hertz_exponent": 1.5, "k_rest_N_per_m": {"mean": 2.79e8},
        "k_hertz_N_per_m_pow_n": {"mean": 5.095e10}})");
  const bool table_ok = table.hertz_exponent == 1.5 && table.k_rest_N_per_m.mean == 2.79e8;
  std::cout << "hertzgear " << hertzgear::version << (hash_ok ? " ok" : " wrong hash")
            << (table_ok ? ", table ok" : ", table read wrong") << std::endl;
  return hash_ok && table_ok ? 0 : 1;
}
