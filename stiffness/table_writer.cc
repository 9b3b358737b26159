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

  namespace
  {
    const char *row_columns = "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,"
                              "pairs_in_contact,load_share_1,load_share_2,hertz_penetration_um,"
                              "contact_a_mm,contact_b_mm,peak_pressure_MPa,k_total_tangent_N_per_m,"
                              "contact_centre_z_mm,face_end_contact,tip_contact";

    void write_row(std::ostream &os, const std::size_t i, const PositionRow &p)
    {
      const auto optional = [&](const auto &v, const char *end) {
        if (v)
          os << *v;
        os << end;
      };
      os << i << ',' << p.mesh_phase << ',' << p.ste_um << ',' << p.k_total_N_per_m << ','
         << p.k_hertz_N_per_m_pow_n << ',' << p.k_rest_N_per_m << ',';
      optional(p.pairs_in_contact, ",");
      optional(p.load_share_1, ",");
      optional(p.load_share_2, ",");
      os << p.hertz_penetration_um << ',' << p.contact_a_mm << ',' << p.contact_b_mm << ','
         << p.peak_pressure_MPa << ',';
      optional(p.k_total_tangent_N_per_m, ",");
      optional(p.contact_centre_z_mm, ",");
      const auto flag = [&](const std::optional<bool> &v, const char *end) {
        if (v)
          os << (*v ? 1 : 0);
        os << end;
      };
      flag(p.face_end_contact, ",");
      flag(p.tip_contact, "\n");
    }

    // Summary of a set of rows: STE peak-to-peak, means, largest peak pressure, edge contacts.
    nlohmann::json rows_summary(const std::vector<PositionRow> &rows)
    {
      double ste_min = 0, ste_max = 0, k_total = 0, k_rest = 0, p_max = 0, p_off_tips = 0, z_min = 0,
             z_max = 0;
      int    face_end = 0, tip = 0;
      for (std::size_t i = 0; i < rows.size(); ++i)
        {
          const auto &r = rows[i];
          const double z = r.contact_centre_z_mm.value_or(0.0);
          ste_min        = i == 0 ? r.ste_um : std::min(ste_min, r.ste_um);
          ste_max        = i == 0 ? r.ste_um : std::max(ste_max, r.ste_um);
          z_min          = i == 0 ? z : std::min(z_min, z);
          z_max          = i == 0 ? z : std::max(z_max, z);
          k_total += r.k_total_N_per_m / rows.size();
          k_rest += r.k_rest_N_per_m / rows.size();
          p_max = std::max(p_max, r.peak_pressure_MPa);
          if (!r.tip_contact.value_or(false))
            p_off_tips = std::max(p_off_tips, r.peak_pressure_MPa);
          face_end += r.face_end_contact.value_or(false);
          tip += r.tip_contact.value_or(false);
        }
      return {{"ste_peak_to_peak_um", ste_max - ste_min},
              {"mean_ste_um", rows.empty() ? 0.0 : 0.5 * (ste_min + ste_max)},
              {"mean_k_total_N_per_m", k_total},
              {"mean_k_rest_N_per_m", k_rest},
              {"max_peak_pressure_MPa", p_max},
              // without the positions whose contact reaches a tip (its edge pressure)
              {"max_peak_pressure_off_tips_MPa", p_off_tips},
              {"contact_centre_z_min_mm", z_min},
              {"contact_centre_z_max_mm", z_max},
              {"face_end_contact_positions", face_end},
              {"tip_contact_positions", tip}};
    }
  } // namespace

  std::string stiffness_csv(const StiffnessResult &r)
  {
    std::ostringstream os;
    os << std::setprecision(10);
    os << row_columns << '\n';
    for (std::size_t i = 0; i < r.rows.size(); ++i)
      write_row(os, i, r.rows[i]);
    return os.str();
  }

  std::string stiffness_map_csv(const StiffnessResult &r)
  {
    std::ostringstream os;
    os << std::setprecision(10);
    os << "case,torque_Nm,torque_percent,load_N,pinion_crowning_um,gear_crowning_um,mesh_misalignment_um,"
          "pinion_helix_slope_deviation_um,gear_helix_slope_deviation_um,"
       << row_columns
       << '\n';
    for (std::size_t c = 0; c < r.map.size(); ++c)
      {
        const auto &m = r.map[c];
        for (std::size_t i = 0; i < m.rows.size(); ++i)
          {
            os << c << ',' << m.torque_Nm << ',' << m.torque_percent << ',' << m.load_N << ','
               << m.pinion_crowning_mm * 1e3 << ',' << m.gear_crowning_mm * 1e3 << ','
               << m.mesh_misalignment_mm * 1e3 << ',' << m.pinion_helix_slope_deviation_mm * 1e3 << ','
               << m.gear_helix_slope_deviation_mm * 1e3 << ',';
            write_row(os, i, m.rows[i]);
          }
      }
    return os.str();
  }

  std::string contact_pattern_csv(const StiffnessResult &r)
  {
    std::ostringstream os;
    os << std::setprecision(8);
    os << "case,position,pair,pinion_roll_mm,z_mm,pressure_MPa\n";
    const auto cells = [&](const int c, const std::vector<ContactPatternCell> &pattern) {
      for (const auto &k : pattern)
        os << c << ',' << k.position << ',' << k.pair << ',' << k.pinion_roll_mm << ',' << k.z_mm
           << ',' << k.pressure_MPa << '\n';
    };
    cells(-1, r.pattern);
    for (std::size_t c = 0; c < r.map.size(); ++c)
      cells(static_cast<int>(c), r.map[c].pattern);
    return os.str();
  }

  nlohmann::json stiffness_map_json(const StiffnessResult &r)
  {
    nlohmann::json cases = nlohmann::json::array();
    for (std::size_t c = 0; c < r.map.size(); ++c)
      {
        const auto    &m = r.map[c];
        nlohmann::json j = rows_summary(m.rows);
        j["case"]                 = c;
        j["torque_Nm"]            = m.torque_Nm;
        j["torque_percent"]       = m.torque_percent;
        j["load_N"]               = m.load_N;
        j["pinion_crowning_um"]   = m.pinion_crowning_mm * 1e3;
        j["gear_crowning_um"]     = m.gear_crowning_mm * 1e3;
        j["mesh_misalignment_um"] = m.mesh_misalignment_mm * 1e3;
        j["pinion_helix_slope_deviation_um"] = m.pinion_helix_slope_deviation_mm * 1e3;
        j["gear_helix_slope_deviation_um"]   = m.gear_helix_slope_deviation_mm * 1e3;
        j["contact_time_s"]       = m.contact_time_s;
        cases.push_back(j);
      }
    return cases;
  }

  nlohmann::json stiffness_json(const StiffnessResult &r)
  {
    nlohmann::json j = nlohmann::json::parse(table::stiffness_table_to_json_text(r.table));
    j["k_total_N_per_m"]            = fourier_series_json(r.k_total_N_per_m, true);
    j["ste_m"]                      = fourier_series_json(r.ste_m, true);
    j["k_hertz_unit"]               = "N/m^n";
    j["mean_k_total_N_per_m"]       = r.k_total_N_per_m.mean;
    j["mean_k_hertz_N_per_m_pow_n"] = r.table.k_hertz_N_per_m_pow_n.mean;
    j["mean_k_rest_N_per_m"]        = r.mean_k_rest_N_per_m;
    j["ste_peak_to_peak_um"]        = ste_peak_to_peak_um(r);
    j["load_N"]                     = r.load_N;
    j["harmonics"]                  = r.harmonics;
    if (!r.pattern.empty())
      {
        j["contact"] = rows_summary(r.rows);
        j["contact"]["pinion_active_roll_min_mm"] = r.pinion_active_roll_min_mm;
        j["contact"]["pinion_active_roll_max_mm"] = r.pinion_active_roll_max_mm;
        j["contact"]["face_width_mm"]             = r.face_width_mm;
      }
    if (!r.map.empty())
      j["map"] = stiffness_map_json(r);
    if (!r.notes_key.empty())
      j[r.notes_key] = r.notes;
    return j;
  }
} // namespace hertzgear::stiffness
