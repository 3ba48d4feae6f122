// The summary's signal analyses (leg/src/analysis.cpp) on signals whose
// answer is known in closed form: the wobble's ring-down under a slow creep,
// and the pendulum test's swing.
#include "leg/analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

// A ring A exp(-zeta w s) cos(w_d s), s = t - t0, along (0.8, 0.6, 0), plus
// a creep C (1 - exp(-s / tau)) along z, sampled at 250 Hz (the wobble
// scene's output interval). Before t0 the probe is still.
struct Probe {
  std::vector<double> t, x, y, z;
};

constexpr double kT0 = 0.25, kF = 8.0, kZeta = 0.05, kA = 3e-4, kTau = 0.3;

Probe ring_with_creep(double creep) {
  Probe p;
  const double w = 2.0 * M_PI * kF, wd = w * std::sqrt(1.0 - kZeta * kZeta);
  for (int i = 0; i <= 750; ++i) {
    const double t = 0.004 * i, s = t - kT0;
    const double ring = s < 0.0 ? 0.0 : kA * std::exp(-kZeta * w * s) * std::cos(wd * s);
    const double c = s < 0.0 ? 0.0 : creep * (1.0 - std::exp(-s / kTau));
    p.t.push_back(t);
    p.x.push_back(0.8 * ring);
    p.y.push_back(0.6 * ring);
    p.z.push_back(c);
  }
  return p;
}

// The creep's mean over the window of width w centred on t (t - w / 2 >= t0).
double creep_mean(double creep, double t, double w) {
  const double a = t - 0.5 * w - kT0, b = t + 0.5 * w - kT0;
  return creep * (1.0 - kTau / w * (std::exp(-a / kTau) - std::exp(-b / kTau)));
}

TEST(WobbleMetrics, ReadsTheRingUnderACreepThreeTimesItsSize) {
  const Probe p = ring_with_creep(1e-3);
  std::map<std::string, double> out;
  leg::wobble_metrics(p.t, p.x, p.y, p.z, kT0, out);
  const double fd = kF * std::sqrt(1.0 - kZeta * kZeta);
  EXPECT_NEAR(out.at("wobble_frequency_hz"), fd, 0.02 * fd);
  EXPECT_NEAR(out.at("wobble_damping_ratio"), kZeta, 0.15 * kZeta);
  // Analysed from t0 + half the window on: the ring has decayed by
  // exp(-zeta w 0.25 s) = 0.53 there.
  EXPECT_GT(out.at("wobble_amplitude_m"), 0.8 * kA * std::exp(-kZeta * 2.0 * M_PI * kF * 0.25));
  EXPECT_LT(out.at("wobble_amplitude_m"), 1.2 * kA * std::exp(-kZeta * 2.0 * M_PI * kF * 0.25));
  EXPECT_GE(out.at("wobble_peaks"), 8.0);
  // The slow motion is the creep's moving mean between the ends of the
  // analysed span (the ring's own moving mean adds a little: it decays
  // within the window).
  const double w = leg::kSlowWindow;
  const double slow = creep_mean(1e-3, 3.0 - 0.5 * w, w) - creep_mean(1e-3, kT0 + 0.5 * w, w);
  EXPECT_NEAR(out.at("wobble_slow_motion_m"), slow, 0.05 * slow);
}

TEST(WobbleMetrics, APureRingHasNoSlowMotion) {
  const Probe p = ring_with_creep(0.0);
  std::map<std::string, double> out;
  leg::wobble_metrics(p.t, p.x, p.y, p.z, kT0, out);
  const double fd = kF * std::sqrt(1.0 - kZeta * kZeta);
  EXPECT_NEAR(out.at("wobble_frequency_hz"), fd, 0.02 * fd);
  EXPECT_NEAR(out.at("wobble_damping_ratio"), kZeta, 0.15 * kZeta);
  // A decaying ring's moving mean is not quite zero: below a tenth of it.
  EXPECT_LT(out.at("wobble_slow_motion_m"), 0.1 * out.at("wobble_amplitude_m"));
}

// At 200 Hz the window's half-width is 50 samples (0.25 s / 5 ms, far from
// a rounding edge): 2 x 50 + 8 = 108 samples leave the 8 the analysis needs
// where the whole window fits, 107 leave 7.
TEST(WobbleMetrics, AddsNothingWithFewerThanEightSamplesWhereTheWholeWindowFits) {
  const auto run = [](int samples) {
    std::vector<double> t, x, zero(static_cast<size_t>(samples), 0.0);
    for (int i = 0; i < samples; ++i) {
      t.push_back(0.005 * i);
      x.push_back(1e-4 * std::cos(2.0 * M_PI * 8.0 * t.back()));
    }
    std::map<std::string, double> out;
    leg::wobble_metrics(t, x, zero, zero, 0.0, out);
    return out;
  };
  EXPECT_TRUE(run(107).empty());
  EXPECT_FALSE(run(108).empty());
  // Times that do not increase: nothing, not a division by zero.
  std::vector<double> same(200, 1.0), x(200, 0.0);
  std::map<std::string, double> out;
  leg::wobble_metrics(same, x, x, x, 0.0, out);
  EXPECT_TRUE(out.empty());
}

// A pendulum released at 0 deg towards its rest at R: the angle is
// R (1 - exp(-zeta w s) cos(w_d s)) after the release, so the first swing
// peaks where w_d s = pi - asin(zeta), at R (1 + sqrt(1 - zeta^2)
// exp(-zeta w s)), and the next one a damped period T later, exp(-zeta w T)
// as far from rest; the rest is the last fifth's mean.
TEST(DropMetrics, ReadsTheSwingOfADampedPendulum) {
  constexpr double kRest = 70.0, kRelease = 0.2, kPeriod = 1.1, kZ = 0.07;
  const double wd = 2.0 * M_PI / kPeriod, w = wd / std::sqrt(1.0 - kZ * kZ);
  std::vector<double> t, a;
  for (int i = 0; i <= 5000; ++i) {  // 20 s: the last fifth is at rest to 0.2 deg
    const double ti = 0.004 * i, s = std::max(0.0, ti - kRelease);
    t.push_back(ti);
    a.push_back(kRest * (1.0 - std::exp(-kZ * w * s) * std::cos(wd * s)));
  }
  std::map<std::string, double> out;
  leg::drop_metrics(t, a, kRelease, out);
  EXPECT_NEAR(out.at("drop_rest_angle_deg"), kRest, 0.5);
  EXPECT_NEAR(out.at("drop_start_angle_deg"), 0.0, 1e-9);
  const double s1 = (M_PI - std::asin(kZ)) / wd;
  EXPECT_NEAR(out.at("drop_first_swing_peak_deg"), kRest * (1.0 + std::sqrt(1.0 - kZ * kZ) * std::exp(-kZ * w * s1)),
              0.02);
  EXPECT_NEAR(out.at("drop_swing_period_s"), kPeriod, 0.01);
  EXPECT_NEAR(out.at("drop_successive_peak_ratio"), std::exp(-kZ * w * kPeriod), 0.01);
  EXPECT_NEAR(out.at("drop_damping_ratio"), kZ, 0.1 * kZ);
}

// The same pendulum recorded for only 3.8 s after the release: the leg still
// swings (between about 51 and 85 deg about a rest of 70) in the record's
// last fifth, whose mean is then about 6 deg off; the turning points still
// give the centre, to the samples' timing - also under sample noise of
// +-0.2 deg, which a turning point taken at every reversal would split.
TEST(DropMetrics, FindsTheSwingsCentreBeforeTheSwingDiesOut) {
  constexpr double kRest = 70.0, kRelease = 0.2, kPeriod = 1.1, kZ = 0.07;
  const double wd = 2.0 * M_PI / kPeriod, w = wd / std::sqrt(1.0 - kZ * kZ);
  std::vector<double> t, a;
  for (int i = 0; i <= 1000; ++i) {
    const double ti = 0.004 * i, s = std::max(0.0, ti - kRelease);
    t.push_back(ti);
    a.push_back(kRest * (1.0 - std::exp(-kZ * w * s) * std::cos(wd * s)));
  }
  std::map<std::string, double> out;
  leg::drop_metrics(t, a, kRelease, out);
  EXPECT_GT(std::abs(out.at("drop_rest_angle_deg") - kRest), 1.0);  // the end's mean is not the rest here
  EXPECT_NEAR(out.at("drop_swing_centre_deg"), kRest, 0.05);
  std::mt19937 noise(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (double& x : a) x += u(noise);
  std::map<std::string, double> noisy;
  leg::drop_metrics(t, a, kRelease, noisy);
  ASSERT_TRUE(noisy.count("drop_swing_centre_deg"));
  EXPECT_NEAR(noisy.at("drop_swing_centre_deg"), kRest, 0.3);
}

// Exactly geometric turning points about 3 (ratio -0.5), with a plateau at
// the first turn: every three give 3. Swings below least_swing are not used.
TEST(SwingCentre, IsExactForGeometricTurningPointsAndSkipsSmallSwings) {
  // Turning points 3 + 4 (-0.5)^k = 7, 1, 4, 2.5, 3.25 (swings 6, 3, 1.5,
  // 0.75), the first on a plateau.
  const std::vector<double> g = {0.0, 4.0, 7.0, 7.0, 3.0, 1.0, 2.0, 4.0, 3.0, 2.5, 2.9, 3.25, 3.1};
  const auto c = leg::swing_centre(g, 0.1);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(*c, 3.0, 1e-12);
  // least_swing 1.0: the last three (swing 0.75) are left out; still 3.
  EXPECT_NEAR(*leg::swing_centre(g, 1.0), 3.0, 1e-12);
  // least_swing 4.0: no three qualify.
  EXPECT_FALSE(leg::swing_centre(g, 4.0).has_value());
  // Two estimates, 3 from (7, 1, 4) and 1.5 + 6.25 / 5.5 from (1, 4, 1.5):
  // their median is their mean.
  EXPECT_NEAR(*leg::swing_centre({0.0, 7.0, 1.0, 4.0, 1.5, 2.0}, 0.1), 0.5 * (3.0 + 1.5 + 6.25 / 5.5), 1e-12);
  // Four: turning points 7, 1, 4, 1.5, 3, 2 give 3, 1.5 + 6.25 / 5.5,
  // 3 - 2.25 / 4 and 2 + 1 / 2.5; the median is the mean of the middle two.
  EXPECT_NEAR(*leg::swing_centre({0.0, 7.0, 1.0, 4.0, 1.5, 3.0, 2.0, 2.5}, 0.1),
              0.5 * ((3.0 - 2.25 / 4.0) + (1.5 + 6.25 / 5.5)), 1e-12);
}

TEST(SwingCentre, IsNothingWithoutThreeTurningPoints) {
  EXPECT_FALSE(leg::swing_centre({}, 0.0).has_value());
  EXPECT_FALSE(leg::swing_centre({0.0, 1.0, 2.0, 3.0}, 0.0).has_value());        // no turn
  EXPECT_FALSE(leg::swing_centre({0.0, 2.0, 1.0, 1.0, 1.0}, 0.0).has_value());   // one turn
  EXPECT_FALSE(leg::swing_centre({0.0, 2.0, 1.0, 1.5, 1.5}, 0.0).has_value());   // two turns
  EXPECT_TRUE(leg::swing_centre({0.0, 2.0, 1.0, 1.5, 1.2}, 0.0).has_value());    // three
}

}  // namespace
