// The live protocol's message check (leg::parse_live_message): what the page
// may send, and every kind of refusal the server answers instead of acting.
#include "leg/live.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

std::vector<leg::LiveControl> controls() {
  return {{"activation.back_muscle", "back", "slider", "1", 0.0, 1.0, 0.01, 0.0},
          {"joint_torque", "torque", "knob", "N m", -30.0, 30.0, 0.5, 0.0}};
}

std::string why(const std::string& text) {
  leg::LiveCommand cmd;
  return leg::parse_live_message(text, controls(), cmd);
}

TEST(LiveMessage, SetAndResetAreTaken) {
  leg::LiveCommand cmd;
  EXPECT_EQ(leg::parse_live_message(R"({"type":"set","id":"activation.back_muscle","value":0.75})", controls(), cmd), "");
  EXPECT_FALSE(cmd.reset);
  EXPECT_EQ(cmd.id, "activation.back_muscle");
  EXPECT_DOUBLE_EQ(cmd.value, 0.75);
  EXPECT_EQ(leg::parse_live_message(R"({"type":"set","id":"joint_torque","value":-30})", controls(), cmd), "");
  EXPECT_DOUBLE_EQ(cmd.value, -30.0);
  EXPECT_EQ(leg::parse_live_message(R"({"type":"reset"})", controls(), cmd), "");
  EXPECT_TRUE(cmd.reset);
}

TEST(LiveMessage, EveryMalformedOrHostileMessageIsRefusedWithItsReason) {
  EXPECT_NE(why("not json").find("not JSON"), std::string::npos);
  EXPECT_NE(why("").find("not JSON"), std::string::npos);
  EXPECT_NE(why("[1,2]").find("not an object"), std::string::npos);
  EXPECT_NE(why(R"({"type":3})").find("not an object"), std::string::npos);
  EXPECT_NE(why(R"({"type":"shutdown"})").find("unknown type 'shutdown'"), std::string::npos);
  EXPECT_NE(why(R"({"type":"set","value":1})").find("\"id\""), std::string::npos);
  EXPECT_NE(why(R"({"type":"set","id":"joint_torque"})").find("numeric"), std::string::npos);
  EXPECT_NE(why(R"({"type":"set","id":"joint_torque","value":"1"})").find("numeric"), std::string::npos);
  EXPECT_NE(why(R"({"type":"set","id":"hip","value":1})").find("no control 'hip'"), std::string::npos);
  EXPECT_NE(why(R"({"type":"set","id":"activation.back_muscle","value":1e308})").find("outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(why(R"({"type":"set","id":"activation.back_muscle","value":-0.01})").find("outside"), std::string::npos);
  EXPECT_NE(why(std::string(leg::kLiveMessageBytes + 1, ' ')).find("bytes (at most 4096)"), std::string::npos);
}

}  // namespace
