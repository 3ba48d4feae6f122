// The live leg (leg::LiveLeg, what `tissuebench serve` steps) on the shipped
// hamstrings scene: the page's controls drive it instead of the script - the
// activation in effect follows a slider at kActivationRate, the back muscle
// flexes the knee, reset goes back to the start, bad settings are refused.
#include "leg/live.hpp"

#include "leg/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

double read(const leg::LiveLeg& live, const leg::Frame& f, const std::string& name) {
  for (const leg::Sensor& s : live.sensors())
    if (s.name == name) return s.read(f);
  ADD_FAILURE() << "no sensor " << name;
  return NAN;
}

TEST(LiveLeg, SlidersDriveTheMusclesAndResetGoesBackToTheStart) {
  leg::LiveLeg live(leg::read_leg_scene(std::string(TISSUEBENCH_DATA_DIR) + "/scenes/hamstrings.yaml"));
  const double dt = live.scene().dt;
  // The controls: both muscles, the added torque; no obstacle in this scene.
  ASSERT_EQ(live.controls().size(), 3u);
  EXPECT_EQ(live.controls()[1].id, "activation.back_muscle");
  EXPECT_EQ(live.controls()[1].value, 0.0);  // the script's value at t = 0
  EXPECT_NE(live.set("activation.back_muscle", 1.5), "");
  EXPECT_NE(live.set("activation.back_muscle", NAN), "");
  EXPECT_NE(live.set("hip", 0.0), "");

  // Relaxed for 0.5 s: the knee barely moves.
  ASSERT_TRUE(live.step(std::lround(0.5 / dt)));
  const double relaxed = live.frame().state->knee.angle * 180.0 / M_PI;

  // The back muscle's slider to 0.6 (the scene's script reaches 0.65 at 2 s):
  // the activation in effect rises at kActivationRate (0.5 / s), so 0.2 s later it is 0.1.
  ASSERT_EQ(live.set("activation.back_muscle", 0.6), "");
  ASSERT_TRUE(live.step(std::lround(0.2 / dt)));
  EXPECT_NEAR(read(live, live.frame(), "back_activation"), 0.2 * leg::kActivationRate, 1e-9);
  // ... and 2 s more flexes the knee well past its relaxed angle.
  ASSERT_TRUE(live.step(std::lround(2.0 / dt))) << live.failure();
  const double flexed = live.frame().state->knee.angle * 180.0 / M_PI;
  EXPECT_GT(flexed - relaxed, 20.0) << "relaxed " << relaxed << " deg, flexed " << flexed << " deg";
  EXPECT_NEAR(live.time(), 2.7, 1e-9);

  // Reset: t = 0, the knee at the scene's initial angle, the slider kept.
  live.reset();
  EXPECT_EQ(live.time(), 0.0);
  EXPECT_NEAR(live.frame().state->knee.angle, live.scene().initial_angle, 1e-12);
  EXPECT_EQ(live.controls()[1].value, 0.6);
  EXPECT_DOUBLE_EQ(read(live, live.frame(), "back_activation"), 0.0);
  live.reset_controls();
  EXPECT_EQ(live.controls()[1].value, 0.0);
}

}  // namespace
