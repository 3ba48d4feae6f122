#include "leg/analysis.hpp"

#include "tbio/signal_analysis.hpp"

#include "msd/core/types.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace leg {

std::optional<double> swing_centre(const std::vector<double>& a, double least_swing) {
  // The turning points, alternating by construction, with hysteresis: the
  // running extreme becomes a turning point once the signal has come back
  // from it by more than least_swing, so noise smaller than that does not
  // split one turn into several.
  std::vector<double> e;
  if (a.empty()) return std::nullopt;
  int direction = 0;  // +1 rising, -1 falling, 0 not yet known
  double extreme = a.front(), low = a.front(), high = a.front();
  for (double v : a) {
    if (direction == 0) {
      low = std::min(low, v);
      high = std::max(high, v);
      if (v - low > least_swing) direction = +1, extreme = v;
      else if (high - v > least_swing) direction = -1, extreme = v;
    } else if (direction > 0) {
      if (v >= extreme) extreme = v;
      else if (extreme - v > least_swing) e.push_back(extreme), direction = -1, extreme = v;
    } else {
      if (v <= extreme) extreme = v;
      else if (v - extreme > least_swing) e.push_back(extreme), direction = +1, extreme = v;
    }
  }
  // Aitken's estimate over each three successive turning points whose swings
  // are both at least least_swing: e3 - (e3 - e2)^2 / ((e3 - e2) - (e2 - e1)).
  // The swings have opposite signs, so the denominator is at least
  // least_swing in size.
  std::vector<double> estimates;
  for (size_t k = 0; k + 2 < e.size(); ++k) {
    const double d1 = e[k + 1] - e[k], d2 = e[k + 2] - e[k + 1];
    if (std::abs(d1) < least_swing || std::abs(d2) < least_swing) continue;
    estimates.push_back(e[k + 2] - d2 * d2 / (d2 - d1));
  }
  if (estimates.empty()) return std::nullopt;
  const auto mid = estimates.begin() + static_cast<std::ptrdiff_t>(estimates.size() / 2);
  std::nth_element(estimates.begin(), mid, estimates.end());
  if (estimates.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(estimates.begin(), mid));
}

void drop_metrics(const std::vector<double>& t, const std::vector<double>& angle_deg, double release,
                  std::map<std::string, double>& out) {
  std::vector<double> tt, aa;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= release) {
      tt.push_back(t[i]);
      aa.push_back(angle_deg[i]);
    }
  if (aa.size() < 5) return;
  // The final rest angle: the mean of the last fifth.
  const size_t tail = aa.size() - aa.size() / 5;
  double rest = 0.0;
  for (size_t i = tail; i < aa.size(); ++i) rest += aa[i];
  rest /= static_cast<double>(aa.size() - tail);
  std::vector<double> peaks, peak_t;
  for (size_t i = 1; i + 1 < aa.size(); ++i)
    if (aa[i] > aa[i - 1] && aa[i] >= aa[i + 1] && aa[i] - rest > 0.5) {
      peaks.push_back(aa[i]);
      peak_t.push_back(tt[i]);
    }
  out["drop_rest_angle_deg"] = rest;
  out["drop_start_angle_deg"] = aa.front();
  if (!peaks.empty()) {
    out["drop_first_swing_peak_deg"] = peaks[0];
    out["drop_first_swing_amplitude_deg"] = peaks[0] - aa.front();
  }
  if (peaks.size() >= 2) {
    out["drop_successive_peak_ratio"] = (peaks[1] - rest) / (peaks[0] - rest);
    out["drop_swing_period_s"] = peak_t[1] - peak_t[0];
  }
  int oscillations = 0;
  for (double p : peaks)
    if (p - rest > 0.02 * (peaks[0] - rest) && p - rest > 1.0) ++oscillations;
  out["drop_oscillations"] = oscillations;
  if (!peaks.empty())
    if (const auto centre = swing_centre(aa, 0.02 * std::abs(peaks[0] - aa.front())))
      out["drop_swing_centre_deg"] = *centre;
  const tbio::RingDown r = tbio::analyse_ring_down(tt, aa);
  out["drop_frequency_hz"] = r.frequency;
  out["drop_damping_ratio"] = r.damping_ratio;
}

void wobble_metrics(const std::vector<double>& t, const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& z, double after, std::map<std::string, double>& out) {
  std::vector<double> tt;
  std::vector<msd::Vec3> d;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= after) {
      tt.push_back(t[i]);
      d.emplace_back(x[i], y[i], z[i]);
    }
  if (d.size() < 8) return;
  const size_t n = d.size();
  // The ring about the probe's slow motion: less the centred moving mean
  // over kSlowWindow (the settling and the creep, which a straight line does
  // not follow), where the whole window fits.
  const double dt = (tt.back() - tt.front()) / static_cast<double>(n - 1);
  if (!(dt > 0.0)) return;
  // 2 h + 1 samples: the odd count nearest kSlowWindow.
  const size_t h = std::max<size_t>(1, static_cast<size_t>(std::lround(0.5 * kSlowWindow / dt)));
  if (n < 2 * h + 8) return;
  std::vector<msd::Vec3> prefix(n + 1, msd::Vec3::Zero());
  for (size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + d[i];
  const auto trend = [&](size_t i) -> msd::Vec3 {
    return (prefix[i + h + 1] - prefix[i - h]) / static_cast<double>(2 * h + 1);
  };
  const msd::Vec3 first_trend = trend(h);
  std::vector<double> ts;
  std::vector<msd::Vec3> ring;
  double slow = 0.0;
  for (size_t i = h; i + h < n; ++i) {
    const msd::Vec3 m = trend(i);
    slow = std::max(slow, (m - first_trend).norm());
    ts.push_back(tt[i]);
    ring.push_back(d[i] - m);
  }
  msd::Mat3 cov = msd::Mat3::Zero();
  for (const auto& p : ring) cov += p * p.transpose();
  Eigen::SelfAdjointEigenSolver<msd::Mat3> es(cov);
  const msd::Vec3 axis = es.eigenvectors().col(2);
  std::vector<double> sig(ring.size());
  double amp = 0.0;
  for (size_t i = 0; i < ring.size(); ++i) {
    sig[i] = axis.dot(ring[i]);
    amp = std::max(amp, std::abs(sig[i]));
  }
  const tbio::RingDown r = tbio::analyse_ring_down(ts, sig);
  out["wobble_frequency_hz"] = r.frequency;
  out["wobble_damping_ratio"] = r.damping_ratio;
  out["wobble_amplitude_m"] = amp;
  out["wobble_peaks"] = r.peaks;
  out["wobble_slow_motion_m"] = slow;
}

std::map<std::string, double> summarise(Recorded recorded, const LegScene& scene,
                                        const std::vector<std::string>& tendon_names,
                                        const std::vector<std::string>& obstacle_names, long joint_space_tets) {
  size_t first = 0;
  const std::vector<double>& frame_times = recorded.at("time");
  while (first + 1 < frame_times.size() && frame_times[first] < scene.analysis_from - 1e-9) ++first;
  for (auto& [name, series] : recorded) series.erase(series.begin(), series.begin() + static_cast<long>(first));
  const std::vector<double> times = recorded.at("time");
  auto largest = [&](const std::string& column) {
    const auto& c = recorded.at(column);
    return *std::max_element(c.begin(), c.end());
  };
  std::map<std::string, double> v;
  v["analysis_from_s"] = times.front();
  v["joint_space_tets_left_out"] = static_cast<double>(joint_space_tets);
  const auto& angle = recorded["knee_angle"];
  v["knee_angle_start_deg"] = angle.front();
  v["knee_angle_end_deg"] = angle.back();
  v["knee_angle_max_deg"] = *std::max_element(angle.begin(), angle.end());
  v["knee_angle_min_deg"] = *std::min_element(angle.begin(), angle.end());
  v["time_of_max_knee_angle_s"] =
      times[static_cast<size_t>(std::max_element(angle.begin(), angle.end()) - angle.begin())];
  v["time_of_min_knee_angle_s"] =
      times[static_cast<size_t>(std::min_element(angle.begin(), angle.end()) - angle.begin())];
  if (const auto femur = recorded.find("femur_angle"); femur != recorded.end()) {
    v["femur_angle_max_deg"] = *std::max_element(femur->second.begin(), femur->second.end());
    v["femur_angle_min_deg"] = *std::min_element(femur->second.begin(), femur->second.end());
  }
  const auto& below = recorded["lower_leg_below_horizontal"];
  v["lower_leg_highest_below_horizontal_deg"] = *std::min_element(below.begin(), below.end());
  v["lower_leg_end_below_horizontal_deg"] = below.back();
  v["knee_contact_area_max_m2"] = largest("knee_contact_area");
  v["knee_contact_area_end_m2"] = recorded["knee_contact_area"].back();
  for (size_t i = 0; i < times.size(); ++i)
    if (recorded["knee_contacts"][i] > 0.0) {
      v["knee_contact_first_s"] = times[i];
      break;
    }
  for (size_t a = 0; a < scene.bulge_areas.size(); ++a) {
    v["bulge_" + scene.bulge_areas[a].name + "_max_m"] = largest("bulge_" + scene.bulge_areas[a].name);
    v["bulge_" + scene.bulge_areas[a].name + "_end_m"] = recorded["bulge_" + scene.bulge_areas[a].name].back();
  }
  for (const char* m : {"front_muscle", "back_muscle"}) {
    const auto& len = recorded[std::string("length_ratio_") + m];
    const auto& rad = recorded[std::string("radius_ratio_") + m];
    const auto& vol = recorded[std::string("volume_ratio_") + m];
    v[std::string(m) + "_length_ratio_min"] = *std::min_element(len.begin(), len.end());
    v[std::string(m) + "_radius_ratio_max"] = *std::max_element(rad.begin(), rad.end());
    v[std::string(m) + "_volume_ratio_min"] = *std::min_element(vol.begin(), vol.end());
    v[std::string(m) + "_volume_ratio_max"] = *std::max_element(vol.begin(), vol.end());
  }
  const auto& pv = recorded["volume_ratio_passive"];
  v["passive_volume_ratio_min"] = *std::min_element(pv.begin(), pv.end());
  for (size_t k = 0; k < tendon_names.size(); ++k) {
    const auto& T = recorded["tension_" + tendon_names[k]];
    v["tendon_" + tendon_names[k] + "_tension_max_N"] = *std::max_element(T.begin(), T.end());
    v["tendon_" + tendon_names[k] + "_straightness_start"] = recorded["straightness_" + tendon_names[k]].front();
    v["tendon_" + tendon_names[k] + "_straightness_max"] = largest("straightness_" + tendon_names[k]);
  }
  for (size_t k = 0; k < obstacle_names.size(); ++k)
    v["obstacle_" + obstacle_names[k] + "_force_max_N"] = largest("obstacle_force_" + obstacle_names[k]);
  const auto& sag = recorded["thigh_flesh_sag"];
  v["thigh_flesh_sag_end_m"] = sag.back();
  v["thigh_flesh_sag_max_m"] = *std::max_element(sag.begin(), sag.end());
  const auto& speed = recorded["max_node_speed"];
  v["max_node_speed_end_m_s"] = speed.back();
  const auto& ke = recorded["kinetic_energy"];
  v["kinetic_energy_end_J"] = ke.back();
  if (scene.drop_release) drop_metrics(times, angle, *scene.drop_release, v);
  if (scene.wobble_probe)
    wobble_metrics(times, recorded["probe_x"], recorded["probe_y"], recorded["probe_z"], scene.wobble_after, v);
  return v;
}

}  // namespace leg
