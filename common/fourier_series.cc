#include "common/fourier_series.h"

#include "common/errors.h"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <cmath>

namespace hertzgear
{
  double FourierSeries::value(const double theta) const
  {
    double y = mean;
    for (unsigned int j = 0; j < amplitudes.size(); ++j)
      y += amplitudes[j] * std::cos((j + 1) * theta - phases_rad[j]);
    return y;
  }

  double FourierSeries::derivative(const double theta) const
  {
    double d = 0.0;
    for (unsigned int j = 0; j < amplitudes.size(); ++j)
      d -= (j + 1) * amplitudes[j] * std::sin((j + 1) * theta - phases_rad[j]);
    return d;
  }

  double FourierSeries::at_phase(const double phase_cycles) const
  {
    return value(2.0 * M_PI * phase_cycles);
  }

  FourierEvaluator::FourierEvaluator(const FourierSeries &series) : mean(series.mean)
  {
    for (unsigned j = 0; j < series.amplitudes.size(); ++j)
      {
        a.push_back(series.amplitudes[j] * std::cos(series.phases_rad[j]));
        b.push_back(series.amplitudes[j] * std::sin(series.phases_rad[j]));
      }
  }

  void FourierEvaluator::taylor(const double c1, const double s1, double taylor[3]) const
  {
    double v = mean, d1 = 0.0, d2 = 0.0;
    double cj = c1, sj = s1;
    for (std::size_t j = 0; j < a.size(); ++j)
      {
        const double order = double(j + 1), term = a[j] * cj + b[j] * sj;
        v += term;
        d1 += order * (b[j] * cj - a[j] * sj);
        d2 -= order * order * term;
        const double c_next = cj * c1 - sj * s1;
        sj                  = sj * c1 + cj * s1;
        cj                  = c_next;
      }
    taylor[0] = v;
    taylor[1] = d1;
    taylor[2] = d2;
  }

  double FourierSeries::amplitude_bound() const
  {
    double b = 0.0;
    for (const double a : amplitudes)
      b += std::abs(a);
    return b;
  }

  FourierSeries FourierSeries::scaled(const double factor) const
  {
    FourierSeries s = *this;
    s.mean *= factor;
    for (double &a : s.amplitudes)
      a *= factor;
    s.residual_rms *= std::abs(factor);
    return s;
  }

  FourierSeries fit_fourier_series(const std::vector<double> &phase_cycles,
                                   const std::vector<double> &samples,
                                   const unsigned int         n_harmonics)
  {
    const std::size_t n_samples = samples.size();
    HG_REQUIRE_INPUT(phase_cycles.size() == n_samples, "Fourier fit: ", phase_cycles.size(),
                     " phases for ", n_samples, " samples");
    HG_REQUIRE_INPUT(n_samples >= 2 * n_harmonics + 1, "Fourier fit: ", n_samples,
                     " samples are too few for ", n_harmonics,
                     " harmonics; at least 2 harmonics + 1 = ", 2 * n_harmonics + 1,
                     " samples per cycle are needed");

    // Columns: 1, cos(j theta), sin(j theta): c cos + s sin = A cos(j theta - phi) with
    // A = hypot(c, s), phi = atan2(s, c).
    const Eigen::Index n_cols = 1 + 2 * static_cast<Eigen::Index>(n_harmonics);
    Eigen::MatrixXd    basis(static_cast<Eigen::Index>(n_samples), n_cols);
    Eigen::VectorXd    y(static_cast<Eigen::Index>(n_samples));
    for (std::size_t k = 0; k < n_samples; ++k)
      {
        const Eigen::Index row   = static_cast<Eigen::Index>(k);
        const double       theta = 2.0 * M_PI * phase_cycles[k];
        basis(row, 0)            = 1.0;
        for (unsigned int j = 1; j <= n_harmonics; ++j)
          {
            basis(row, 2 * j - 1) = std::cos(j * theta);
            basis(row, 2 * j)     = std::sin(j * theta);
          }
        y(row) = samples[k];
      }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
    HG_REQUIRE_INPUT(qr.rank() == n_cols, "Fourier fit: the ", n_samples,
                     " phases do not determine ", n_harmonics, " harmonics (repeated phases?)");
    const Eigen::VectorXd coefficients = qr.solve(y);

    FourierSeries series;
    series.mean = coefficients(0);
    for (unsigned int j = 1; j <= n_harmonics; ++j)
      {
        const double c = coefficients(2 * j - 1), s = coefficients(2 * j);
        series.amplitudes.push_back(std::hypot(c, s));
        series.phases_rad.push_back(std::atan2(s, c));
      }
    series.residual_rms = std::sqrt((basis * coefficients - y).squaredNorm() / n_samples);
    return series;
  }

  FourierSeries fit_fourier_series(const std::vector<double> &uniform_samples,
                                   const unsigned int         n_harmonics)
  {
    std::vector<double> phases(uniform_samples.size());
    for (std::size_t k = 0; k < phases.size(); ++k)
      phases[k] = double(k) / phases.size();
    return fit_fourier_series(phases, uniform_samples, n_harmonics);
  }

  FourierSeries interpolate_fourier_series(const std::vector<double> &y)
  {
    const std::size_t S = y.size();
    HG_REQUIRE_INPUT(S >= 1, "Fourier interpolation: no samples");
    // Below the Nyquist order the least-squares fit of uniform samples is the discrete transform
    // itself; the Nyquist cosine, orthogonal to all of them at the samples, completes it.
    FourierSeries series = fit_fourier_series(y, static_cast<unsigned>((S - 1) / 2));
    if (S % 2 == 0)
      {
        double a = 0.0;
        for (std::size_t k = 0; k < S; ++k)
          a += (k % 2 == 0 ? y[k] : -y[k]);
        a /= double(S);
        series.amplitudes.push_back(std::abs(a));
        series.phases_rad.push_back(a < 0.0 ? M_PI : 0.0);
      }
    double sum = 0.0;
    for (std::size_t k = 0; k < S; ++k)
      sum += std::pow(series.at_phase(double(k) / S) - y[k], 2);
    series.residual_rms = std::sqrt(sum / S);
    return series;
  }

  nlohmann::json fourier_series_json(const FourierSeries &s, const bool with_residual)
  {
    nlohmann::json j = {{"mean", s.mean}, {"amplitudes", s.amplitudes}, {"phases_rad", s.phases_rad}};
    if (with_residual)
      j["residual_rms"] = s.residual_rms;
    return j;
  }

  FourierSeries fourier_series(const double mean, const std::vector<double> &amplitudes,
                               const std::vector<double> &phases_rad)
  {
    FourierSeries s;
    s.mean       = mean;
    s.amplitudes = amplitudes;
    s.phases_rad = phases_rad.empty() ? std::vector<double>(amplitudes.size(), 0.0) : phases_rad;
    return s;
  }

  FourierSeries fourier_series_from_json(const nlohmann::json &j, const std::string &where)
  {
    HG_REQUIRE_INPUT(j.is_object(), where, ": expected an object with mean, amplitudes, phases_rad");
    HG_REQUIRE_INPUT(j.contains("mean"), where, ": missing key 'mean'");
    const auto list = [&](const char *key) {
      return j.contains(key) ? j.at(key).get<std::vector<double>>() : std::vector<double>();
    };
    const double        mean       = j.at("mean").get<double>();
    const auto          amplitudes = list("amplitudes");
    const FourierSeries s          = fourier_series(mean, amplitudes, list("phases_rad"));
    HG_REQUIRE_INPUT(s.phases_rad.size() == s.amplitudes.size(), where, ": ",
                     s.amplitudes.size(), " amplitudes but ", s.phases_rad.size(), " phases");
    return s;
  }
} // namespace hertzgear
