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
