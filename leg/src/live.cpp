#include "leg/live.hpp"

#include "leg/drive.hpp"

#include "tbio/json.hpp"
#include "tbio/series_tools.hpp"

#include <algorithm>
#include <cmath>

namespace leg {

namespace {

/// How fast an obstacle follows its knobs (m/s): a knob's jump moves the
/// obstacle over several steps, never through the tissue in one.
constexpr double kObstacleSpeed = 0.2;
/// The knobs' reach from an obstacle's rest placement, m, and the added knee torque's, N m.
constexpr double kObstacleReach = 0.15, kTorqueReach = 30.0;

/// Why `value` cannot be set on control `id` of `controls` ("" when it can).
std::string control_refusal(const std::vector<LiveControl>& controls, const std::string& id, double value) {
  if (!std::isfinite(value)) return "the value is not finite";
  for (const LiveControl& c : controls)
    if (c.id == id)
      return value < c.min || value > c.max ? id + " = " + tbio::json_number(value) + " is outside [" +
                                                  tbio::json_number(c.min) + ", " + tbio::json_number(c.max) + "]"
                                            : "";
  return "no control '" + id + "'";
}

}  // namespace

std::string parse_live_message(const std::string& text, const std::vector<LiveControl>& controls, LiveCommand& cmd) {
  cmd = LiveCommand{};
  if (text.size() > kLiveMessageBytes)
    return "message refused: " + std::to_string(text.size()) + " bytes (at most " + std::to_string(kLiveMessageBytes) +
           ")";
  const tbio::Json j = tbio::Json::parse(text, nullptr, false);
  if (j.is_discarded()) return "message refused: not JSON";
  if (!j.is_object() || !j.contains("type") || !j["type"].is_string())
    return "message refused: not an object with a \"type\" string";
  const std::string type = j["type"].get<std::string>();
  if (type == "reset") {
    cmd.reset = true;
    return "";
  }
  if (type != "set") return "message refused: unknown type '" + type + "' (set, reset)";
  if (!j.contains("id") || !j["id"].is_string()) return "message refused: set needs an \"id\" string";
  if (!j.contains("value") || !j["value"].is_number()) return "message refused: set needs a numeric \"value\"";
  cmd.id = j["id"].get<std::string>();
  cmd.value = j["value"].get<double>();
  const std::string why = control_refusal(controls, cmd.id, cmd.value);
  return why.empty() ? "" : "message refused: " + why;
}

LiveLeg::LiveLeg(LegScene scene)
    : scene_(std::make_unique<const LegScene>(std::move(scene))), compiled_(compile_leg(*scene_)),
      in_(make_leg_instruments(compiled_, *scene_)), sensors_(leg_sensors(in_)) {
  const LegScene& s = *scene_;
  variant_ = s.variants.empty() ? LegVariant{"", s.front_activation, s.back_activation} : s.variants.front();
  const double front = s.script ? s.script->activation("FRONT_MUSCLE", 0.0) : variant_.front;
  const double back = s.script ? s.script->activation("BACK_MUSCLE", 0.0) : variant_.back;
  controls_.push_back({"activation.front_muscle", "front muscle (quadriceps) activation", "slider", "1", 0.0, 1.0,
                       0.01, front});
  controls_.push_back({"activation.back_muscle", "back muscle (hamstrings) activation", "slider", "1", 0.0, 1.0, 0.01,
                       back});
  controls_.push_back({"joint_torque", "added knee torque (flexion +)", "knob", "N m", -kTorqueReach, kTorqueReach, 0.5,
                       0.0});
  const auto& obstacles = compiled_.model.obstacles;
  for (size_t k = 0; k < obstacles.size(); ++k) {
    const msd::Vec3 start =
        k < s.obstacle_motion.size() && !s.obstacle_motion[k].empty() ? s.obstacle_motion[k].at(0.0) : msd::Vec3::Zero();
    const char* axes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
      controls_.push_back({"obstacle." + obstacles[k].name + "." + axes[a],
                           obstacles[k].name + " offset " + axes[a], "knob", "m",
                           std::min(-kObstacleReach, start[a]), std::max(kObstacleReach, start[a]), 0.001, start[a]});
  }
  start_controls_ = controls_;
  reset();
}

void LiveLeg::reset_controls() { controls_ = start_controls_; }

std::string LiveLeg::set(const std::string& id, double value) {
  const std::string why = control_refusal(controls_, id, value);
  if (!why.empty()) return why;
  for (LiveControl& c : controls_)
    if (c.id == id) c.value = value;
  return "";
}

msd::Vec3 LiveLeg::knob_target(size_t obstacle) const {
  msd::Vec3 target;
  for (int a = 0; a < 3; ++a) target[a] = controls_[3 + 3 * obstacle + static_cast<size_t>(a)].value;
  return target;
}

void LiveLeg::reset() {
  const LegScene& s = *scene_;
  const msd::LegModel& leg = compiled_.model;
  state_ = start_state(leg, s);
  scratch_ = msd::LegScratch{};
  leg_controls_ = initial_controls(leg, s);
  engaged_ = !s.tendons_engage_at;
  activation_[0] = start_controls_[0].value;
  activation_[1] = start_controls_[1].value;
  obstacle_at_.resize(leg.obstacles.size());
  for (size_t k = 0; k < leg.obstacles.size(); ++k) obstacle_at_[k] = knob_target(k);
  steps_ = 0;
  apply_controls(0.0, 0.0);
  msd::LegState probe = state_;  // the step-0 diagnostics, as a run's first row
  msd::step_leg(leg, probe, leg_controls_, 0.0, scratch_);
}

void LiveLeg::apply_controls(double t, double elapsed) {
  const LegScene& s = *scene_;
  drive(s, variant_, t, s.dt, leg_controls_);  // the knee's script, pre-tension, the scene's torque
  for (int m = 0; m < 2; ++m) {
    const double gap = controls_[static_cast<size_t>(m)].value - activation_[m];
    activation_[m] += std::clamp(gap, -kActivationRate * elapsed, kActivationRate * elapsed);
  }
  leg_controls_.front_activation = activation_[0];
  leg_controls_.back_activation = activation_[1];
  leg_controls_.joint_torque += controls_[2].value;
  for (size_t k = 0; k < obstacle_at_.size(); ++k) {
    const msd::Vec3 gap = knob_target(k) - obstacle_at_[k];
    const double reach = kObstacleSpeed * elapsed;
    const msd::Vec3 move = gap.norm() > reach ? msd::Vec3(gap * (reach / gap.norm())) : gap;
    obstacle_at_[k] += move;
    leg_controls_.obstacle_offset[k] = obstacle_at_[k];
    leg_controls_.obstacle_velocity[k] = elapsed > 0.0 ? msd::Vec3(move / elapsed) : msd::Vec3::Zero();
  }
}

bool LiveLeg::step(long n) {
  const LegScene& s = *scene_;
  const msd::LegModel& leg = compiled_.model;
  try {
    for (long i = 0; i < n; ++i) {
      if (!engaged_ && tendons_due(s, steps_ * s.dt)) {
        engage_tendons(leg, state_, leg_controls_);
        engaged_ = true;
      }
      ++steps_;
      apply_controls(steps_ * s.dt, s.dt);
      msd::step_leg(leg, state_, leg_controls_, s.dt, scratch_, s.integrator);
      state_.tissue.t = steps_ * s.dt;
    }
  } catch (const msd::SimulationFailure& e) {
    failure_ = e.what();
    reset();
    return false;
  }
  return true;
}

double LiveLeg::time() const { return state_.tissue.t; }

const Frame& LiveLeg::frame() {
  observe(in_, state_, scratch_, leg_controls_, frame_);
  return frame_;
}

}  // namespace leg
