#pragma once
// The one Fourier series of hertzgear: a quantity periodic over one cycle (the mesh cycle of the
// paper's eq. (4)),
//   y(theta) = mean + sum_{j=1..H} A_j cos(j theta - phi_j),  theta = 2 pi (phase in cycles),
// its least-squares fit to samples, and its JSON form {mean, amplitudes, phases_rad}. Any
// consistent unit: the series carries the unit of its samples.
#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace hertzgear
{
  struct FourierSeries
  {
    double              mean = 0.0;
    std::vector<double> amplitudes; // A_j, j = 1..H
    std::vector<double> phases_rad; // phi_j
    double              residual_rms = 0.0; // of a fit: RMS of (samples - series) at the samples

    unsigned int n_harmonics() const { return static_cast<unsigned int>(amplitudes.size()); }
    // Value and d/d theta at the angle theta [rad] (theta = omega_m t for the mesh cycle).
    double value(double theta) const;
    double derivative(double theta) const;
    // Value at a phase in cycles (1 = one period).
    double at_phase(double phase_cycles) const;
    // The same series without its harmonics (the mean only).
    FourierSeries constant_part() const { return {mean, {}, {}, 0.0}; }
    // Bound of |value - mean|: the sum of |A_j|.
    double amplitude_bound() const;
    // The series times a factor (a change of unit; phases unchanged).
    FourierSeries scaled(double factor) const;
  };

  // The same series in the form mean + sum_j a_j cos(j theta) + b_j sin(j theta), evaluated with one
  // cos/sin pair per call (the angle-addition recurrence gives the higher orders; its rounding
  // grows like j eps): for right-hand sides that evaluate a series at every stage. It lives beside
  // FourierSeries because it is that series in another form: the convention A_j cos(j theta -
  // phi_j) that its coefficients a_j, b_j are taken from is defined here once, for every user.
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

  // The series of a mean, amplitudes A_j and phases phi_j; no phases stand for phases of zero.
  FourierSeries fourier_series(double mean, const std::vector<double> &amplitudes,
                               const std::vector<double> &phases_rad);

  // Least-squares fit of `n_harmonics` harmonics to samples y_k taken at phases (in cycles, any
  // order, within one period). Uniform phases make it the truncated discrete Fourier transform.
  // Throws InputError with fewer than 2H + 1 samples or phases that do not determine H harmonics.
  FourierSeries fit_fourier_series(const std::vector<double> &phase_cycles,
                                   const std::vector<double> &samples, unsigned int n_harmonics);
  // The same for samples at the uniform phases k / S, k = 0..S-1.
  FourierSeries fit_fourier_series(const std::vector<double> &uniform_samples,
                                   unsigned int n_harmonics);

  // The trigonometric interpolant of samples at the uniform phases k / S, k = 0..S-1: the series
  // through every sample, with floor(S / 2) harmonics (for even S the last, at the Nyquist
  // order S / 2, is the cosine term of half the discrete transform's weight, phase 0 or pi).
  // Throws InputError without samples.
  FourierSeries interpolate_fourier_series(const std::vector<double> &uniform_samples);

  // {"mean", "amplitudes", "phases_rad"} (and "residual_rms" when asked).
  nlohmann::json fourier_series_json(const FourierSeries &series, bool with_residual = false);
  // Reads that form; `where` names the object in messages. Missing phases are zero; amplitude
  // and phase counts must agree (InputError).
  FourierSeries fourier_series_from_json(const nlohmann::json &j, const std::string &where);
} // namespace hertzgear
