// Requirements on the Fourier fit of quantities over the mesh cycle (the paper's eq. (4)).
#include "common/errors.h"
#include "common/fourier_series.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear;

TEST(FourierFit, RecoversAnExactSeriesFromUniformSamples)
{
  // Requirement: samples of a series with H harmonics are fitted exactly by H harmonics; the
  // only error is round-off of a 9 x 9 QR solve (~1e-15 relative, 1e-12 leaves margin).
  const double mean = 3.0e8, a1 = 4.0e7, p1 = 0.7, a2 = 1.0e7, p2 = -2.0;
  std::vector<double> phase, y;
  for (int k = 0; k < 9; ++k)
    {
      const double tau = k / 9.0, th = 2 * M_PI * tau;
      phase.push_back(tau);
      y.push_back(mean + a1 * std::cos(th - p1) + a2 * std::cos(2 * th - p2));
    }
  const FourierSeries s = fit_fourier_series(phase, y, 4);
  EXPECT_NEAR(s.mean, mean, 1e-12 * mean);
  EXPECT_NEAR(s.amplitudes[0], a1, 1e-12 * mean);
  EXPECT_NEAR(s.phases_rad[0], p1, 1e-12);
  EXPECT_NEAR(s.amplitudes[1], a2, 1e-12 * mean);
  EXPECT_NEAR(s.phases_rad[1], p2, 1e-12);
  EXPECT_NEAR(s.amplitudes[2], 0.0, 1e-12 * mean);
  EXPECT_NEAR(s.at_phase(0.3), mean + a1 * std::cos(0.6 * M_PI - p1) + a2 * std::cos(1.2 * M_PI - p2),
              1e-12 * mean);
  EXPECT_LT(s.residual_rms, 1e-12 * mean);
}

TEST(FourierFit, NonUniformSamplesAreFittedInLeastSquares)
{
  // Requirement: positions refined near transitions (non-uniform) still give the series; with
  // more samples than unknowns and an exact series, the least-squares residual is round-off.
  std::vector<double> phase, y;
  for (int k = 0; k < 15; ++k)
    {
      const double tau = std::pow(k / 15.0, 1.3);
      phase.push_back(tau);
      y.push_back(1.0 + 0.2 * std::cos(2 * M_PI * tau - 0.3));
    }
  const FourierSeries s = fit_fourier_series(phase, y, 3);
  EXPECT_NEAR(s.mean, 1.0, 1e-12);
  EXPECT_NEAR(s.amplitudes[0], 0.2, 1e-12);
  EXPECT_NEAR(s.phases_rad[0], 0.3, 1e-11);
}

TEST(FourierFit, TooFewSamplesForTheHarmonicsIsAnInputError)
{
  // Requirement: S >= 2 H + 1; the message names the counts.
  const std::vector<double> phase{0, 0.25, 0.5, 0.75}, y{1, 2, 3, 4};
  try
    {
      fit_fourier_series(phase, y, 2);
      FAIL() << "expected InputError";
    }
  catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("at least 2 harmonics + 1 = 5"), std::string::npos)
        << e.what();
    }
}

// Requirement: the fit of S uniform samples (the overload without phases) of a series with
// h <= (S-1)/2 harmonics returns its mean, amplitudes and phases, and asking for more harmonics
// than S samples determine is an InputError. Tolerance 1e-12 relative: the 9 x 7 QR solve of exact
// samples is exact up to round-off (~1e-15).
TEST(FourierFit, RecoversASeriesFromUniformSamplesWithoutPhases)
{
  const FourierSeries truth{5.0e10, {2.0e10, 4.0e9, 6.0e9}, {0.3, -2.0, 1.1}};
  std::vector<double> samples(9);
  for (int i = 0; i < 9; ++i)
    samples[i] = truth.value(2.0 * M_PI * i / 9);
  const FourierSeries fit = fit_fourier_series(samples, 3);
  EXPECT_NEAR(fit.mean, truth.mean, 1e-12 * truth.mean);
  for (int j = 0; j < 3; ++j)
    {
      EXPECT_NEAR(fit.amplitudes[j], truth.amplitudes[j], 1e-12 * truth.mean);
      EXPECT_NEAR(std::remainder(fit.phases_rad[j] - truth.phases_rad[j], 2 * M_PI), 0.0, 1e-12);
    }
  EXPECT_THROW(fit_fourier_series(samples, 5), InputError);
}

// Requirement: the cos/sin-form evaluator the model uses at every new phase returns the series'
// value and its first two derivatives. 20 harmonics of decreasing amplitude at 50 phases: the
// recurrence's rounding grows like j eps, so 1e-13 of the amplitude sum (times the order j and
// j^2 that the derivatives weigh it with, at most 20 and 400) bounds the difference.
TEST(FourierEvaluator, MatchesTheSeriesAndItsDerivatives)
{
  FourierSeries series{5.0e10, {}, {}};
  for (int j = 1; j <= 20; ++j)
    {
      series.amplitudes.push_back(2.0e10 / j);
      series.phases_rad.push_back(0.7 * j - 3.0);
    }
  const FourierEvaluator fast(series);
  const double           scale = series.amplitude_bound();
  for (int i = 0; i < 50; ++i)
    {
      const double theta = -20.0 + 0.83 * i;
      const double c = std::cos(theta), s = std::sin(theta);
      double taylor[3];
      fast.taylor(c, s, taylor);
      double second = 0.0;
      for (unsigned j = 0; j < series.amplitudes.size(); ++j)
        second -= (j + 1.0) * (j + 1.0) * series.amplitudes[j] *
                  std::cos((j + 1) * theta - series.phases_rad[j]);
      EXPECT_NEAR(taylor[0], series.value(theta), 1e-13 * (series.mean + scale));
      EXPECT_NEAR(taylor[1], series.derivative(theta), 1e-13 * 20 * scale);
      EXPECT_NEAR(taylor[2], second, 1e-13 * 400 * scale);
    }
}

// Requirement: the trigonometric interpolant passes through every uniform sample, for odd and
// even S (the even case needs the Nyquist cosine), and gives back a series of fewer than S/2
// harmonics exactly. Both to rounding: the transform of S <= 16 samples of size 1 rounds at a
// few 1e-16; 1e-12 leaves room.
TEST(FourierSeries, InterpolantPassesThroughEverySample)
{
  for (const std::size_t S : {1u, 2u, 7u, 16u})
    {
      std::vector<double> y;
      for (std::size_t k = 0; k < S; ++k)
        y.push_back(std::sin(1.0 + 3.7 * k) + 0.3 * (k % 3));
      const auto series = hertzgear::interpolate_fourier_series(y);
      EXPECT_EQ(series.n_harmonics(), S / 2);
      for (std::size_t k = 0; k < S; ++k)
        EXPECT_NEAR(series.at_phase(double(k) / S), y[k], 1e-12) << "S = " << S << ", k = " << k;
      EXPECT_LT(series.residual_rms, 1e-12);
    }
  const auto exact = hertzgear::fourier_series(2.0, {0.5, 0.25, 0.1}, {0.3, -1.0, 2.0});
  std::vector<double> samples;
  for (int k = 0; k < 16; ++k)
    samples.push_back(exact.at_phase(k / 16.0));
  const auto back = hertzgear::interpolate_fourier_series(samples);
  for (const double theta : {0.05, 1.3, 4.0})
    EXPECT_NEAR(back.value(theta), exact.value(theta), 1e-12);
}
