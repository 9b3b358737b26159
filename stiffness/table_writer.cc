#include "stiffness/table_writer.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace hertzgear::stiffness
{
  void summarise_rows(StiffnessResult &r)
  {
    std::vector<double> phase, k_total, ste;
    for (const auto &row : r.rows)
      {
        phase.push_back(row.mesh_phase);
        k_total.push_back(row.k_total_N_per_m);
        ste.push_back(row.ste_um * 1e-6);
      }
    const auto H          = static_cast<unsigned int>(r.harmonics);
    r.k_total_N_per_m     = fit_fourier_series(phase, k_total, H);
    r.ste_m               = fit_fourier_series(phase, ste, H);
    r.mean_k_rest_N_per_m = r.table.k_rest_N_per_m.mean;
  }

  double ste_peak_to_peak_um(const StiffnessResult &r)
  {
    if (r.rows.empty())
      return 0.0;
    const auto [lo, hi] = std::minmax_element(r.rows.begin(), r.rows.end(), [](const auto &a, const auto &b) {
      return a.ste_um < b.ste_um;
    });
    return hi->ste_um - lo->ste_um;
  }

  std::string stiffness_csv(const StiffnessResult &r)
  {
    std::ostringstream os;
    os << std::setprecision(10);
    os << "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,pairs_in_contact,"
          "load_share_1,load_share_2,hertz_penetration_um,contact_a_mm,contact_b_mm,"
          "peak_pressure_MPa\n";
    const auto optional = [&](const auto &v) {
      if (v)
        os << *v;
      os << ',';
    };
    for (std::size_t i = 0; i < r.rows.size(); ++i)
      {
        const auto &p = r.rows[i];
        os << i << ',' << p.mesh_phase << ',' << p.ste_um << ',' << p.k_total_N_per_m << ','
           << p.k_hertz_N_per_m_pow_n << ',' << p.k_rest_N_per_m << ',';
        optional(p.pairs_in_contact);
        optional(p.load_share_1);
        optional(p.load_share_2);
        os << p.hertz_penetration_um << ',' << p.contact_a_mm << ',' << p.contact_b_mm << ','
           << p.peak_pressure_MPa << '\n';
      }
    return os.str();
  }

  nlohmann::json stiffness_json(const StiffnessResult &r)
  {
    nlohmann::json j = nlohmann::json::parse(dynamics::stiffness_table_to_json_text(r.table));
    j["k_total_N_per_m"]            = fourier_series_json(r.k_total_N_per_m, true);
    j["ste_m"]                      = fourier_series_json(r.ste_m, true);
    j["k_hertz_unit"]               = "N/m^n";
    j["mean_k_total_N_per_m"]       = r.k_total_N_per_m.mean;
    j["mean_k_hertz_N_per_m_pow_n"] = r.table.k_hertz_N_per_m_pow_n.mean;
    j["mean_k_rest_N_per_m"]        = r.mean_k_rest_N_per_m;
    j["ste_peak_to_peak_um"]        = ste_peak_to_peak_um(r);
    j["load_N"]                     = r.load_N;
    j["harmonics"]                  = r.harmonics;
    if (!r.notes_key.empty())
      j[r.notes_key] = r.notes;
    return j;
  }
} // namespace hertzgear::stiffness
