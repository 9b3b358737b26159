#include "fem/fourier_fit.h"

#include "common/errors.h"

#include <Eigen/Dense>

#include <cmath>

namespace hertzgear
{
  double FourierSeries::value(const double mesh_phase) const
  {
    const double theta = 2.0 * M_PI * mesh_phase;
    double       y     = mean;
    for (unsigned int j = 0; j < amplitudes.size(); ++j)
      y += amplitudes[j] * std::cos((j + 1) * theta - phases_rad[j]);
    return y;
  }

  FourierSeries fit_fourier_series(const std::vector<double> &mesh_phase,
                                   const std::vector<double> &samples,
                                   const unsigned int         n_harmonics)
  {
    const std::size_t n_samples = samples.size();
    HG_REQUIRE_INPUT(mesh_phase.size() == n_samples, "Fourier fit: ", mesh_phase.size(),
                     " phases for ", n_samples, " samples");
    HG_REQUIRE_INPUT(n_samples >= 2 * n_harmonics + 1, "Fourier fit: ", n_samples,
                     " samples are too few for ", n_harmonics,
                     " harmonics; at least 2 harmonics + 1 = ", 2 * n_harmonics + 1,
                     " positions per cycle are needed");

    // Columns: 1, cos(j theta), sin(j theta): c cos + s sin = A cos(j theta - phi) with
    // A = hypot(c, s), phi = atan2(s, c).
    const Eigen::Index n_cols = 1 + 2 * static_cast<Eigen::Index>(n_harmonics);
    Eigen::MatrixXd    basis(static_cast<Eigen::Index>(n_samples), n_cols);
    Eigen::VectorXd    y(static_cast<Eigen::Index>(n_samples));
    for (std::size_t k = 0; k < n_samples; ++k)
      {
        const Eigen::Index row   = static_cast<Eigen::Index>(k);
        const double       theta = 2.0 * M_PI * mesh_phase[k];
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
                     " mesh phases do not determine ", n_harmonics,
                     " harmonics (repeated phases?)");
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
} // namespace hertzgear
