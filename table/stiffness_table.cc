#include "table/stiffness_table.h"

#include "common/input_file.h"

#include "common/atomic_file.h"
#include "common/errors.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace hertzgear::table
{
  namespace
  {
    constexpr const char *schema_name = "hertzgear-stiffness-table/1";

    std::vector<double> optional_vector(const nlohmann::json &j, const char *key)
    {
      return j.contains(key) ? j.at(key).get<std::vector<double>>() : std::vector<double>{};
    }
  } // namespace

  void LoadLadder::check(const std::string &where) const
  {
    const std::size_t J = load_N.size(), S = n_positions();
    HG_REQUIRE_INPUT(J >= 2, where, ": a load ladder needs at least 2 loads (load_N has ", J, ")");
    HG_REQUIRE_INPUT(approach_m.size() == J && hertz_approach_m.size() == J, where, ": ", J,
                     " loads but ", approach_m.size(), " rows of approach_m and ",
                     hertz_approach_m.size(), " of hertz_approach_m");
    HG_REQUIRE_INPUT(S >= 1, where, ": approach_m has no positions");
    for (std::size_t j = 0; j < J; ++j)
      HG_REQUIRE_INPUT(approach_m[j].size() == S && hertz_approach_m[j].size() == S, where,
                       ": the rung at ", load_N[j], " N has ", approach_m[j].size(),
                       " approaches and ", hertz_approach_m[j].size(),
                       " Hertzian parts; the first rung has ", S, " positions");
    HG_REQUIRE_INPUT(load_N[0] > 0.0 && std::isfinite(load_N[0]), where,
                     ": the loads must be positive (the first is ", load_N[0], " N)");
    for (std::size_t j = 1; j < J; ++j)
      HG_REQUIRE_INPUT(load_N[j] > load_N[j - 1] && std::isfinite(load_N[j]), where,
                       ": the loads must increase (", load_N[j - 1], " N, then ", load_N[j], " N)");
    HG_REQUIRE_INPUT(nominal_load_N > 0.0, where, ": nominal_load_N = ", nominal_load_N,
                     " N must be positive");
    HG_REQUIRE_INPUT(load_N.back() >= nominal_load_N, where, ": the ladder does not reach the "
                     "nominal load: its top is ", load_N.back(), " N, the nominal load ",
                     nominal_load_N, " N");
    // a, a_h and a - a_h per rung and position; each positive and growing with the load.
    for (std::size_t s = 0; s < S; ++s)
      for (std::size_t j = 0; j < J; ++j)
        {
          const double a = approach_m[j][s], ah = hertz_approach_m[j][s];
          const auto   at = [&](const std::size_t r) {
            return msg("position ", s, " (mesh phase ", double(s) / S, ") at ", load_N[r], " N");
          };
          HG_REQUIRE_INPUT(std::isfinite(a) && std::isfinite(ah) && ah > 0.0 && a > ah, where,
                           ": at ", at(j), " the approach ", a * 1e6, " um and its Hertzian part ",
                           ah * 1e6, " um must be positive with the Hertzian part the smaller");
          if (j == 0)
            continue;
          const double a0 = approach_m[j - 1][s], ah0 = hertz_approach_m[j - 1][s];
          HG_REQUIRE_INPUT(a > a0, where, ": the approach does not grow with the load at ", at(j),
                           ": ", a * 1e6, " um against ", a0 * 1e6, " um at ", load_N[j - 1], " N");
          HG_REQUIRE_INPUT(ah > ah0, where, ": the Hertzian approach does not grow with the load at ",
                           at(j), ": ", ah * 1e6, " um against ", ah0 * 1e6, " um at ",
                           load_N[j - 1], " N");
          HG_REQUIRE_INPUT(a - ah > a0 - ah0, where,
                           ": the structural approach (approach minus Hertzian part) does not "
                           "grow with the load at ",
                           at(j), ": ", (a - ah) * 1e6, " um against ", (a0 - ah0) * 1e6,
                           " um at ", load_N[j - 1], " N");
        }
  }

  void StiffnessTable::check() const
  {
    HG_REQUIRE_INPUT(hertz_exponent >= 1.0 && hertz_exponent <= 2.0,
                     "stiffness table: hertz_exponent = ", hertz_exponent, " is outside [1, 2]");
    for (const auto *s : {&k_rest_N_per_m, &k_hertz_N_per_m_pow_n, &unloaded_ste_m})
      HG_REQUIRE_INPUT(s->amplitudes.size() == s->phases_rad.size(),
                       "stiffness table: a Fourier series has ", s->amplitudes.size(),
                       " amplitudes but ", s->phases_rad.size(), " phases");
    HG_REQUIRE_INPUT(k_rest_N_per_m.mean > 0.0, "stiffness table: the mean rest stiffness k = ",
                     k_rest_N_per_m.mean, " N/m must be positive");
    HG_REQUIRE_INPUT(k_rest_N_per_m.amplitude_bound() < k_rest_N_per_m.mean,
                     "stiffness table: the harmonics of k (sum of amplitudes ",
                     k_rest_N_per_m.amplitude_bound(), " N/m) may make k negative (mean ",
                     k_rest_N_per_m.mean, " N/m)");
    HG_REQUIRE_INPUT(k_hertz_N_per_m_pow_n.mean >= 0.0, "stiffness table: k_mh = ",
                     k_hertz_N_per_m_pow_n.mean, " must not be negative");
    HG_REQUIRE_INPUT(k_hertz_N_per_m_pow_n.amplitude_bound() <= k_hertz_N_per_m_pow_n.mean,
                     "stiffness table: the harmonics of k_h (sum of amplitudes ",
                     k_hertz_N_per_m_pow_n.amplitude_bound(), ") may make k_h negative (mean ",
                     k_hertz_N_per_m_pow_n.mean, ")");
    if (!ladder.empty())
      ladder.check("stiffness table: load_ladder");
  }

  StiffnessTable stiffness_table_from_json_text(const std::string &text, const std::string &where)
  {
    nlohmann::json j;
    try
      {
        j = nlohmann::json::parse(text);
      }
    catch (const nlohmann::json::exception &e)
      {
        throw InputError(msg(where, ": not valid JSON: ", e.what()));
      }
    try
      {
        HG_REQUIRE_INPUT(j.is_object(), where, ": expected a JSON object");
        if (j.contains("schema"))
          HG_REQUIRE_INPUT(j.at("schema").get<std::string>() == schema_name, where,
                           ": unknown schema '", j.at("schema").get<std::string>(), "' (expected ",
                           schema_name, ")");
        StiffnessTable t;
        HG_REQUIRE_INPUT(j.contains("hertz_exponent"), where, ": missing key 'hertz_exponent'");
        t.hertz_exponent = j.at("hertz_exponent").get<double>();
        t.source         = j.value("source", std::string());

        if (j.contains("samples"))
          {
            const auto &s          = j.at("samples");
            t.samples.mesh_phase   = optional_vector(s, "mesh_phase");
            t.samples.k_total_N_per_m       = optional_vector(s, "k_total_N_per_m");
            t.samples.k_hertz_N_per_m_pow_n = optional_vector(s, "k_hertz_N_per_m_pow_n");
            t.samples.k_rest_N_per_m        = optional_vector(s, "k_rest_N_per_m");
            t.samples.ste_m                 = optional_vector(s, "ste_m");
            t.samples.unloaded_ste_m        = optional_vector(s, "unloaded_ste_m");
            const std::size_t n = t.samples.mesh_phase.size();
            for (const auto *v : {&t.samples.k_total_N_per_m, &t.samples.k_hertz_N_per_m_pow_n,
                                  &t.samples.k_rest_N_per_m, &t.samples.ste_m,
                                  &t.samples.unloaded_ste_m})
              HG_REQUIRE_INPUT(v->empty() || v->size() == n, where, ": samples: a series has ",
                               v->size(), " values but mesh_phase has ", n);
            for (std::size_t i = 0; i < n; ++i)
              HG_REQUIRE_INPUT(std::abs(t.samples.mesh_phase[i] - double(i) / n) < 1e-9, where,
                               ": samples: mesh_phase must be uniform i/S over one cycle (entry ",
                               i, " is ", t.samples.mesh_phase[i], ")");
          }
        // Fourier series are given, or fitted here from uniform samples.
        const unsigned n_fit = j.value("harmonics", (unsigned(t.samples.mesh_phase.size()) - 1) / 2);
        auto series_or_fit = [&](const char *key, const std::vector<double> &samples,
                                 FourierSeries &out) -> bool {
          if (j.contains(key))
            {
              out = fourier_series_from_json(j.at(key), where + ": " + key);
              return true;
            }
          if (!samples.empty())
            {
              out = fit_fourier_series(samples, n_fit);
              return true;
            }
          return false;
        };
        HG_REQUIRE_INPUT(series_or_fit("k_rest_N_per_m", t.samples.k_rest_N_per_m, t.k_rest_N_per_m),
                         where, ": needs 'k_rest_N_per_m' (Fourier) or samples.k_rest_N_per_m");
        HG_REQUIRE_INPUT(series_or_fit("k_hertz_N_per_m_pow_n", t.samples.k_hertz_N_per_m_pow_n,
                                       t.k_hertz_N_per_m_pow_n),
                         where,
                         ": needs 'k_hertz_N_per_m_pow_n' (Fourier) or samples.k_hertz_N_per_m_pow_n");
        t.has_unloaded_ste =
          series_or_fit("unloaded_ste_m", t.samples.unloaded_ste_m, t.unloaded_ste_m);
        if (j.contains("load_ladder"))
          {
            const auto &l           = j.at("load_ladder");
            t.ladder.nominal_load_N = l.at("nominal_load_N").get<double>();
            t.ladder.load_N         = l.at("load_N").get<std::vector<double>>();
            t.ladder.approach_m     = l.at("approach_m").get<std::vector<std::vector<double>>>();
            t.ladder.hertz_approach_m =
              l.at("hertz_approach_m").get<std::vector<std::vector<double>>>();
            t.ladder.check(where + ": load_ladder");
          }
        t.check();
        return t;
      }
    catch (const nlohmann::json::exception &e)
      {
        throw InputError(msg(where, ": ", e.what()));
      }
  }

  StiffnessTable read_stiffness_table(const std::filesystem::path &file)
  {
    return stiffness_table_from_json_text(read_input_file(file, "stiffness table", max_table_bytes),
                                          file.string());
  }

  std::string stiffness_table_to_json_text(const StiffnessTable &t)
  {
    nlohmann::json j;
    j["schema"]                = schema_name;
    j["source"]                = t.source;
    j["hertz_exponent"]        = t.hertz_exponent;
    j["k_rest_N_per_m"]        = fourier_series_json(t.k_rest_N_per_m);
    j["k_hertz_N_per_m_pow_n"] = fourier_series_json(t.k_hertz_N_per_m_pow_n);
    if (t.has_unloaded_ste)
      j["unloaded_ste_m"] = fourier_series_json(t.unloaded_ste_m);
    if (!t.samples.empty())
      {
        nlohmann::json s;
        s["mesh_phase"] = t.samples.mesh_phase;
        auto put        = [&s](const char *key, const std::vector<double> &v) {
          if (!v.empty())
            s[key] = v;
        };
        put("k_total_N_per_m", t.samples.k_total_N_per_m);
        put("k_hertz_N_per_m_pow_n", t.samples.k_hertz_N_per_m_pow_n);
        put("k_rest_N_per_m", t.samples.k_rest_N_per_m);
        put("ste_m", t.samples.ste_m);
        put("unloaded_ste_m", t.samples.unloaded_ste_m);
        j["samples"] = s;
      }
    if (!t.ladder.empty())
      j["load_ladder"] = {{"nominal_load_N", t.ladder.nominal_load_N},
                          {"load_N", t.ladder.load_N},
                          {"approach_m", t.ladder.approach_m},
                          {"hertz_approach_m", t.ladder.hertz_approach_m}};
    return j.dump(2) + "\n";
  }

  void write_stiffness_table(const std::filesystem::path &file, const StiffnessTable &table)
  {
    write_file_atomically(file, stiffness_table_to_json_text(table));
  }
} // namespace hertzgear::table
