// Ring-down analysis (vibration benchmarks): the frequency and damping ratio of
// damped oscillations about an offset are recovered; signals without an
// oscillation give zeros instead of numbers.
#include "tbio/signal_analysis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

// x(t) = offset + A exp(-zeta w t) cos(w_d t), w_d = w sqrt(1 - zeta^2), sampled at rate fs.
void damped(double f, double zeta, double offset, double duration, double fs, std::vector<double>& t,
            std::vector<double>& x) {
  const double w = 2 * M_PI * f, wd = w * std::sqrt(1 - zeta * zeta);
  t.clear();
  x.clear();
  for (int i = 0; i <= static_cast<int>(duration * fs); ++i) {
    t.push_back(i / fs);
    x.push_back(offset + 0.01 * std::exp(-zeta * w * t.back()) * std::cos(wd * t.back()));
  }
}

}  // namespace

TEST(RingDown, RecoversTheDampedFrequencyAndTheDampingRatio) {
  std::vector<double> t, x;
  for (double zeta : {0.02, 0.05, 0.1}) {
    damped(5.0, zeta, 0.3, 4.0, 4000.0, t, x);
    const tbio::RingDown r = tbio::analyse_ring_down(t, x);
    const double fd = 5.0 * std::sqrt(1 - zeta * zeta);
    EXPECT_NEAR(r.frequency, fd, 2e-3 * fd) << zeta;
    EXPECT_NEAR(r.damping_ratio, zeta, 0.02 * zeta) << zeta;
    // Peaks used until they fall below 2% of the first (ln(50) / (2 pi zeta)
    // cycles) or the record ends (4 s).
    EXPECT_NEAR(r.peaks, std::min(std::log(50.0) / (2 * M_PI * zeta) + 1, 4.0 * fd), 1.5) << zeta;
    EXPECT_GE(r.crossings, r.peaks - 1);
  }
}

TEST(RingDown, UndampedOscillationHasZeroDampingAndItsExactFrequency) {
  std::vector<double> t, x;
  damped(12.0, 0.0, -1.0, 2.0, 10000.0, t, x);
  const tbio::RingDown r = tbio::analyse_ring_down(t, x);
  EXPECT_NEAR(r.frequency, 12.0, 1e-4);
  EXPECT_NEAR(r.damping_ratio, 0.0, 1e-4);
}

TEST(RingDown, NoOscillationGivesZeros) {
  // Too short, constant, and a monotone decay (overdamped): no crossings, no two peaks.
  EXPECT_EQ(tbio::analyse_ring_down({0.0, 1.0}, {0.0, 1.0}).frequency, 0.0);
  const std::vector<double> t{0, 1, 2, 3, 4, 5, 6, 7, 8};
  const tbio::RingDown flat = tbio::analyse_ring_down(t, std::vector<double>(t.size(), 2.0));
  EXPECT_EQ(flat.frequency, 0.0);
  EXPECT_EQ(flat.damping_ratio, 0.0);
  EXPECT_EQ(flat.peaks, 0);
  std::vector<double> decay;
  for (double ti : t) decay.push_back(std::exp(-ti));
  const tbio::RingDown over = tbio::analyse_ring_down(t, decay);
  EXPECT_EQ(over.frequency, 0.0);
  EXPECT_EQ(over.damping_ratio, 0.0);
}

TEST(RingDown, AfterAStartItIgnoresWhatCameBefore) {
  // A held preload (a constant), then the ring-down from t0 = 1 s.
  std::vector<double> t, x, tt, xx;
  damped(5.0, 0.05, 0.0, 3.0, 2000.0, t, x);
  for (size_t i = 0; t[i] < 1.0; ++i) {
    tt.push_back(t[i]);
    xx.push_back(0.01);
  }
  for (size_t i = 0; i < t.size(); ++i) {
    tt.push_back(1.0 + t[i]);
    xx.push_back(x[i]);
  }
  const tbio::RingDown after = tbio::analyse_ring_down_after(tt, xx, 1.0);
  const tbio::RingDown alone = tbio::analyse_ring_down(t, x);
  EXPECT_NEAR(after.frequency, alone.frequency, 1e-9);
  EXPECT_NEAR(after.damping_ratio, alone.damping_ratio, 1e-9);
  EXPECT_EQ(after.peaks, alone.peaks);
}
