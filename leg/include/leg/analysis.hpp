// The summary of a leg run: scalars from the recorded series (extremes from
// the scene's `analysis.from` on), the pendulum (drop) test's metrics and the
// flesh's wobble as a ring-down.
#pragma once

#include "leg/scene.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace leg {

/// Recorded series by column name, all of one length.
using Recorded = std::map<std::string, std::vector<double>>;

/// The value a decaying swing `a` (samples in time order) turns about, from
/// its turning points e_k (its extremes between reversals of more than
/// least_swing, so that smaller noise does not split a turn): for a
/// linear damped oscillation about c, e_k - c = (-q)^k A exactly, so each
/// three successive turning points give c by Aitken's delta-squared formula,
///   c = e3 - (e3 - e2)^2 / ((e3 - e2) - (e2 - e1))
/// (Aitken 1926, Proc R Soc Edinb 46:289). The median over every three whose
/// two swings are both at least least_swing (the same units as a) is
/// returned; nothing when no three qualify. Unlike a mean over the record's
/// end, it does not need the swing to have died out.
std::optional<double> swing_centre(const std::vector<double>& a, double least_swing);

/// Peaks of the knee angle (deg) about its final rest value after `release`
/// (the pendulum test's swing): rest and start angles, first swing, successive
/// peak ratio, swing period, oscillations, frequency and damping ratio. Adds
/// nothing when fewer than five samples follow the release. The rest
/// (drop_rest_angle_deg) is the mean of the last fifth of the record, which is
/// off by what the leg still swings there; drop_swing_centre_deg is the angle
/// the swing decays towards (swing_centre, over turning points whose swings
/// are at least 2 % of the first swing), added when three such turning points
/// exist.
void drop_metrics(const std::vector<double>& t, const std::vector<double>& angle_deg, double release,
                  std::map<std::string, double>& out);

/// The window of the wobble's slow motion, s: what the probe does slower than
/// about 1 / kSlowWindow = 2 Hz is not the ring.
inline constexpr double kSlowWindow = 0.5;

/// The probe's mean displacement (x, y, z) after `after` (samples evenly
/// spaced in time) less its centred moving mean over kSlowWindow, where the
/// whole window fits (from after + kSlowWindow / 2 to the record's end less
/// as much), on the direction of largest variance of what is left, as a
/// ring-down: wobble_frequency_hz, wobble_damping_ratio, wobble_amplitude_m
/// (the ring's largest excursion there) and wobble_peaks; and
/// wobble_slow_motion_m, the moving mean's largest distance from its first
/// value (settling, creep; from after + kSlowWindow / 2 on). The moving mean
/// takes 2 h + 1 samples, h = round(kSlowWindow / (2 dt)). Subtracting it
/// scales a ring at f by |1 - sinc(f kSlowWindow)| (1.05 at 3.8 Hz, 1.21
/// near 3 Hz): frequencies and damping ratios are kept, amplitudes are not
/// quite, and below about 2 Hz a ring is weakened rather than removed. Adds
/// nothing with fewer than 8 samples where the whole window fits, or when
/// the times do not increase.
void wobble_metrics(const std::vector<double>& t, const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& z, double after, std::map<std::string, double>& out);

/// The summary's scalars from `recorded` (times in recorded["time"]): the
/// samples before scene.analysis_from are dropped first (a scripted lead-in
/// is not part of the result).
std::map<std::string, double> summarise(Recorded recorded, const LegScene& scene,
                                        const std::vector<std::string>& tendon_names,
                                        const std::vector<std::string>& obstacle_names, long joint_space_tets);

}  // namespace leg
