// The live leg (`tissuebench serve`): one scene compiled once and stepped on
// demand, its muscles, added knee torque and obstacles set from outside
// (sliders and knobs on a web page) instead of by the scene's script. The
// rest of the scene - the knee's script and release, tendon engagement and
// pre-tension - drives it as in `tissuebench leg`.
#pragma once

#include "leg/scene.hpp"
#include "leg/sensors.hpp"
#include "leg/session.hpp"

#include <memory>
#include <string>
#include <vector>

namespace leg {

/// How fast the activation in effect follows a muscle's slider, per second:
/// the fastest ramp of the shipped scripts (msd/data/scripts/isometric.txt,
/// 0 to 1 over 2 s; the thesis' own ramp 0.4 per second, 5.7). The scenes
/// were only ever run at such rates: a slider's jump from 0 to 1 applied in
/// one step blows the hamstrings scene up within 10 steps. Held at full
/// activation the back muscle still blows that scene up (about 2.1 s after
/// the ramp starts; the scene's own script stops at 0.85): serve then resets.
constexpr double kActivationRate = 0.5;

/// One control a user can set: a muscle's activation (slider), the added
/// knee torque or an obstacle's offset along one axis (knobs).
struct LiveControl {
  std::string id, label, kind, unit;  ///< kind: "slider" or "knob"
  double min = 0.0, max = 1.0, step = 0.01, value = 0.0;
};

/// A message from the page (viewer/README.md, "Live protocol"), checked.
struct LiveCommand {
  bool reset = false;  ///< {"type":"reset"}; else {"type":"set","id","value"}
  std::string id;
  double value = 0.0;
};

/// Messages longer than this are refused (the protocol's are a few dozen bytes).
constexpr size_t kLiveMessageBytes = 4096;

/// Checks one message from the page against the protocol and the controls'
/// ranges. Returns "" and fills `cmd`, or why it is refused: too long, not
/// JSON, not an object with a "type" string, an unknown type or control, a
/// value that is not a finite number or is out of range.
std::string parse_live_message(const std::string& text, const std::vector<LiveControl>& controls, LiveCommand& cmd);

class LiveLeg {
 public:
  /// Compiles the scene (throws msd::Error naming the file) and places the leg at its start.
  explicit LiveLeg(LegScene scene);
  LiveLeg(const LiveLeg&) = delete;
  LiveLeg& operator=(const LiveLeg&) = delete;

  const LegScene& scene() const { return *scene_; }
  const Instruments& instruments() const { return in_; }
  const std::vector<Sensor>& sensors() const { return sensors_; }
  const std::vector<LiveControl>& controls() const { return controls_; }

  /// Sets control `id`. Returns "" when taken, else why it was refused (an
  /// unknown id, a value that is not finite or outside [min, max]).
  std::string set(const std::string& id, double value);
  /// Back to the scene's start (t = 0, the leg at rest); the controls keep
  /// their values, the muscles' activations start from the scene's again.
  void reset();
  /// Every control back to its value at the scene's start.
  void reset_controls();
  /// Steps `n` steps of the scene's dt. After a blow-up returns false, keeps
  /// its message in failure() and resets.
  bool step(long n);
  const std::string& failure() const { return failure_; }
  double time() const;
  /// The current state observed: skin and bone positions and what the sensors read.
  const Frame& frame();

 private:
  /// The controls of the step ending at t; the activations and obstacles move
  /// towards their sliders and knobs for `elapsed` seconds (0: not at all).
  void apply_controls(double t, double elapsed);
  /// Where obstacle `obstacle`'s knobs ask it to be (its offset, m).
  msd::Vec3 knob_target(size_t obstacle) const;
  std::unique_ptr<const LegScene> scene_;
  CompiledLeg compiled_;
  Instruments in_;
  std::vector<Sensor> sensors_;
  std::vector<LiveControl> controls_, start_controls_;
  double activation_[2] = {0.0, 0.0};  ///< in effect: follows the sliders at kActivationRate
  msd::LegState state_;
  msd::LegScratch scratch_;
  msd::LegControls leg_controls_;
  std::vector<msd::Vec3> obstacle_at_;  ///< each obstacle's current offset (slews to its knobs' target)
  LegVariant variant_;
  bool engaged_ = true;
  long steps_ = 0;
  std::string failure_;
  Frame frame_;
};

}  // namespace leg
