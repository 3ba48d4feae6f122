// Scripted activation (thesis 5.7): the thesis' own script gives the ramps it
// describes; interrupted ramps start from the current value; malformed lines
// are named by file and line.
#include "msd/control/activation_script.hpp"

#include "msd/core/types.hpp"

#include <gtest/gtest.h>

namespace {

std::string error_of(const std::string& text, const std::set<std::string>& known = {}) {
  try {
    msd::parse_activation_script(text, "s.txt", known);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ActivationScript, TheThesisHamstringsScriptRampsAsDescribed) {
  const msd::ActivationScript s =
      msd::read_activation_script(std::string(TISSUEBENCH_DATA_DIR) + "/scripts/hamstrings.txt", {"BACK_MUSCLE", "FRONT_MUSCLE"});
  ASSERT_EQ(s.commands.size(), 5u);
  EXPECT_EQ(s.muscles(), std::vector<std::string>{"BACK_MUSCLE"});
  const auto a = [&](double t) { return s.activation("back_muscle", t); };
  EXPECT_DOUBLE_EQ(a(0.0), 0.0);
  EXPECT_NEAR(a(0.505), 0.4 * 0.495 / 0.99, 1e-12);  // rising to 0.4 over 0.99 s from t = 0.01
  EXPECT_NEAR(a(1.0), 0.4, 1e-12);
  EXPECT_NEAR(a(1.5), 0.525, 1e-12);                 // 0.4 -> 0.65 over 1 s
  EXPECT_NEAR(a(2.5), 0.75, 1e-12);                  // 0.65 -> 0.85
  EXPECT_NEAR(a(5.0), 0.85, 1e-12);                  // held
  EXPECT_NEAR(a(8.25), 0.85 * 0.75, 1e-12);          // falling to 0 over 1 s
  EXPECT_DOUBLE_EQ(a(9.0), 0.0);
  EXPECT_DOUBLE_EQ(s.activation("FRONT_MUSCLE", 5.0), 0.0);  // never named: relaxed
}

TEST(ActivationScript, ACommandDuringARampStartsFromTheCurrentValueAndZeroTimeScaleSteps) {
  const auto s = msd::parse_activation_script("0 FRONT 1.0 2.0\n1 FRONT 0.0 1.0  % halfway up, turn back\n3 FRONT 0.7 0\n",
                                              "s.txt");
  EXPECT_NEAR(s.activation("FRONT", 1.0), 0.5, 1e-12);
  EXPECT_NEAR(s.activation("FRONT", 1.5), 0.25, 1e-12);
  EXPECT_NEAR(s.activation("FRONT", 2.9), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.activation("FRONT", 3.0), 0.7);
}

TEST(ActivationScript, MalformedLinesAreNamedByFileAndLine) {
  EXPECT_NE(error_of("% ok\n0 BACK 0.5\n").find("s.txt:2: expected '<time> <muscle name> <activation value> <time scale>', found 3 fields"),
            std::string::npos)
      << error_of("% ok\n0 BACK 0.5\n");
  EXPECT_NE(error_of("0 BACK half 1\n").find("s.txt:1: the activation value 'half' is not a number"), std::string::npos);
  EXPECT_NE(error_of("0 BACK 1.5 1\n").find("s.txt:1: the activation value must lie in [0, 1]"), std::string::npos);
  EXPECT_NE(error_of("1 BACK 0.5 1\n\n0.5 BACK 0 1\n").find("s.txt:3: the time 0.5 s is earlier"), std::string::npos);
  EXPECT_NE(error_of("0 BACK 0.5 -1\n").find("s.txt:1: the time scale must not be negative"), std::string::npos);
  EXPECT_NE(error_of("-1 BACK 0.5 1\n").find("s.txt:1: the time must not be negative"), std::string::npos);
  EXPECT_NE(error_of("0 CALF 0.5 1\n", {"BACK_MUSCLE", "FRONT_MUSCLE"}).find("s.txt:1: unknown muscle 'CALF' (known: BACK_MUSCLE, FRONT_MUSCLE)"),
            std::string::npos)
      << error_of("0 CALF 0.5 1\n", {"BACK_MUSCLE", "FRONT_MUSCLE"});
  EXPECT_THROW(msd::read_activation_script("/nonexistent/script.txt"), msd::Error);
}
