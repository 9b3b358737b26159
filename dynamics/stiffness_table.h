#pragma once
// The one contract between the FE stage and the dynamics: the mesh stiffness over a mesh cycle.
// A plain value type plus its JSON form (schema in docs/architecture.md, "Stiffness table schema").
// Everything is in SI units; the JSON keys carry their units.
#include "common/fourier_series.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  // The same series in the form mean + sum_j a_j cos(j theta) + b_j sin(j theta), evaluated with one
  // cos/sin pair per call (the angle-addition recurrence gives the higher orders; its rounding
  // grows like j eps). For right-hand sides that evaluate a series at every stage.
  class FourierEvaluator
  {
  public:
    FourierEvaluator() = default;
    explicit FourierEvaluator(const FourierSeries &series);
    // Value, d / d theta and d^2 / d theta^2 at the angle theta given by cos(theta) and
    // sin(theta) (so that several series at one angle share them), in one pass over the
    // harmonics, into taylor[0..2].
    void taylor(double cos_theta, double sin_theta, double taylor[3]) const;
    bool constant() const { return a.empty(); }

  private:
    double              mean = 0.0;
    std::vector<double> a, b;
  };

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
    std::string      source; // free text: which stage or scene produced the table

    // Throws InputError for a table that cannot drive the dynamics (negative means, n out of
    // [1, 2], amplitude and phase counts that differ, a k_h that may turn negative).
    void check() const;
  };

  // A stiffness table holds a few series of at most some thousand samples: far below this.
  constexpr std::uintmax_t max_table_bytes = 64u << 20;
  StiffnessTable read_stiffness_table(const std::filesystem::path &file);
  StiffnessTable stiffness_table_from_json_text(const std::string &text,
                                                const std::string &where = "stiffness table");
  std::string    stiffness_table_to_json_text(const StiffnessTable &table);
  void write_stiffness_table(const std::filesystem::path &file, const StiffnessTable &table);
} // namespace hertzgear::dynamics
