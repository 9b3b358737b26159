#pragma once
// Least-squares Fourier fit of a quantity sampled over one mesh cycle (the paper's eq. (4)):
//   y(theta) = mean + sum_{j=1..H} A_j cos(j theta - phi_j),  theta = 2 pi (mesh phase),
// from S >= 2H + 1 samples. Uniform samples make the fit the truncated DFT; non-uniform samples
// (refined near contact-ratio transitions) are fitted in the least-squares sense.
#include <vector>

namespace hertzgear
{
  struct FourierSeries
  {
    double              mean = 0;
    std::vector<double> amplitudes; // A_j, j = 1..H, same unit as the samples
    std::vector<double> phases_rad; // phi_j
    double              residual_rms = 0; // RMS of (samples - series) at the samples

    unsigned int n_harmonics() const { return static_cast<unsigned int>(amplitudes.size()); }
    // Value at a mesh phase in cycles (1 = one mesh period).
    double value(double mesh_phase) const;
  };

  // Fit H harmonics to samples y_k at mesh phases (in cycles, any order, within one period).
  // Throws InputError if there are fewer than 2H + 1 distinct samples.
  FourierSeries fit_fourier_series(const std::vector<double> &mesh_phase,
                                   const std::vector<double> &samples, unsigned int n_harmonics);
} // namespace hertzgear
