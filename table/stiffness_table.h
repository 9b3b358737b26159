#pragma once
// The one contract between the stiffness stage and the dynamics: the mesh stiffness over a mesh
// cycle. A plain value type plus its JSON form (schema in docs/architecture.md, "Stiffness table
// schema"), in a library of its own (hertzgear_table) that both sides link and neither owns.
// Everything is in SI units; the JSON keys carry their units.
#include "common/fourier_series.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear::table
{
  // Optional sampled series over one mesh cycle, as the FE stage computes them.
  struct StiffnessSamples
  {
    std::vector<double> mesh_phase;        // in [0, 1): fraction of the mesh cycle
    std::vector<double> k_total_N_per_m;   // total mesh stiffness (secant)
    std::vector<double> k_hertz_N_per_m_pow_n;
    std::vector<double> k_rest_N_per_m;
    std::vector<double> ste_m;             // static transmission error along the line of action
    std::vector<double> unloaded_ste_m;    // unloaded (geometric) transmission error

    bool empty() const { return mesh_phase.empty(); }
  };

  // The mesh force over the loads the dynamics visit (the load ladder of the FE load map,
  // docs/dynamics.md "The FE force law"): at J rungs of increasing line-of-action load F_j and at
  // S mesh positions (mesh phases s / S, s = 0..S-1, as the samples), the elastic approach a_js
  // of the drive flanks along the line of action (loaded minus unloaded STE) and its Hertzian
  // (local) part a_h,js; the structural part is a - a_h. Every part grows with the load at every
  // position (check()).
  struct LoadLadder
  {
    double                           nominal_load_N = 0.0; // F_0 of the analysis that made it
    std::vector<double>              load_N;               // F_j, increasing, J >= 2
    std::vector<std::vector<double>> approach_m;           // [rung][position]
    std::vector<std::vector<double>> hertz_approach_m;     // [rung][position]

    bool        empty() const { return load_N.empty(); }
    std::size_t n_rungs() const { return load_N.size(); }
    std::size_t n_positions() const { return approach_m.empty() ? 0 : approach_m[0].size(); }
    // Throws InputError, `where` first, naming the rung and position of a value that cannot
    // drive the FE force law: fewer than 2 rungs, loads not increasing, a top below the nominal
    // load, shapes that differ, a part that is not positive or does not grow with the load.
    void check(const std::string &where = "load ladder") const;
  };

  struct StiffnessTable
  {
    double        hertz_exponent = 1.0; // n of F = k_h delta^n
    FourierSeries k_rest_N_per_m;       // structural (rest) stiffness k
    FourierSeries k_hertz_N_per_m_pow_n; // Hertzian stiffness k_h
    // Unloaded STE as a displacement excitation along the line of action (m); empty series
    // (mean 0, no harmonics) when the table has none.
    FourierSeries    unloaded_ste_m;
    bool             has_unloaded_ste = false;
    StiffnessSamples samples;
    LoadLadder       ladder; // empty unless the source made one (the FE load map)
    std::string      source; // free text: which stage or scene produced the table

    // Throws InputError for a table that cannot drive the dynamics (negative means, n out of
    // [1, 2], amplitude and phase counts that differ, a k_h that may turn negative, a load
    // ladder that LoadLadder::check refuses).
    void check() const;
  };

  // A stiffness table holds a few series of at most some thousand samples: far below this.
  constexpr std::uintmax_t max_table_bytes = 64u << 20;
  StiffnessTable read_stiffness_table(const std::filesystem::path &file);
  StiffnessTable stiffness_table_from_json_text(const std::string &text,
                                                const std::string &where = "stiffness table");
  std::string    stiffness_table_to_json_text(const StiffnessTable &table);
  void write_stiffness_table(const std::filesystem::path &file, const StiffnessTable &table);
} // namespace hertzgear::table
