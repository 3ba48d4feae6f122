// The viewer's C++ side (leg/src/viewer.cpp): base64, the page's assembly and
// escaping, and the run data `tissuebench view` builds from a results file -
// frames chosen, displacements quantised, bones, a failed run, a folder that
// is not a run.
#include "leg/viewer.hpp"

#include "tbio/results_file.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>

namespace {

std::string b64(const std::string& s) { return leg::base64(s.data(), s.size()); }

std::vector<unsigned char> unbase64(const std::string& s) {
  static const std::string abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> out;
  uint32_t w = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    w = (w << 6) | static_cast<uint32_t>(abc.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((w >> bits) & 0xff));
    }
  }
  return out;
}

template <class T>
std::vector<T> decode(const std::string& s) {
  const std::vector<unsigned char> bytes = unbase64(s);
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

TEST(Viewer, Base64MatchesRfc4648TestVectors) {
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  const unsigned char all[3] = {0xff, 0xfe, 0x00};
  EXPECT_EQ(leg::base64(all, 3), "//4A");
}

TEST(Viewer, PageInlinesTheConfigOnceAndEscapesScriptEnds) {
  tbio::Json config;
  config["mode"] = "run";
  config["run"]["title"] = "a </script><script>alert(1)</script> title";
  config["run"]["failure"] = "<!--TISSUEBENCH_BUNDLE--> <!-- <script>";
  const std::string page = leg::viewer_page(config);
  EXPECT_EQ(page.find("<!--TISSUEBENCH_CONFIG-->"), std::string::npos);
  EXPECT_EQ(page.find("<!--TISSUEBENCH_BUNDLE-->"), std::string::npos);
  const size_t at = page.find("<script id=\"tissuebench-config\" type=\"application/json\">");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(page.find("<script id=\"tissuebench-config\"", at + 1), std::string::npos);
  EXPECT_EQ(page.find("</script><script>alert(1)"), std::string::npos) << "the title ended the script element";
  EXPECT_NE(page.find("\\u003c/script>\\u003cscript>alert(1)\\u003c/script>"), std::string::npos);
  // A placeholder inside the data is data: the bundle is inlined once, where the template says.
  EXPECT_NE(page.find("\\u003c!--TISSUEBENCH_BUNDLE-->"), std::string::npos);
  const size_t config_end = page.find("</script>", at);
  EXPECT_EQ(page.substr(at, config_end - at).find('<', 1), std::string::npos) << "a '<' inside the config JSON";
  // The bundle (three.js, uPlot, the viewer) is in the page: no file or URL is loaded.
  EXPECT_GT(page.size(), 100000u);
  EXPECT_EQ(page.find("<script src="), std::string::npos);
}

tbio::RunMeta leg_meta() {
  tbio::RunMeta m;
  m.solver = "msd-leg";
  m.spec_text = "name: tiny\n";
  m.spec_path = "tiny.yaml";
  m.spec_name = "tiny";
  m.text = {{"variant", ""}};
  return m;
}

/// A leg-like results file: a 3-vertex skin and a 3-vertex bone, `frames` frames
/// moving the skin's first vertex by 1 mm per frame in x.
void write_run(const std::string& dir, int frames, bool fail) {
  std::filesystem::create_directories(dir);
  tbio::ResultsWriter w(dir + "/leg.h5", leg_meta(), {{"time", "s"}, {"knee_angle", "deg"}});
  const std::vector<std::array<double, 3>> tri = {{{0, 0, 0}}, {{0.1, 0, 0}}, {{0, 0, 0.1}}};
  w.add_point_set("skin", tri, {{0, 1, 2}});
  w.add_point_set("bones", tri, {{0, 2, 1}});
  for (int f = 0; f < frames; ++f) {
    const double t = 0.04 * f;
    w.append({t, 2.0 * f});
    std::vector<std::array<double, 3>> d(3, {{0, 0, 0}});
    d[0][0] = 1e-3 * f;
    w.append_frame("skin", t, d);
    w.append_frame("bones", t, std::vector<std::array<double, 3>>(3, {{0, 0, 0}}));
  }
  if (fail)
    w.fail("non-finite element force at t = 1.0 s (step 5000), element 7, node 3");
  else
    w.finish();
}

TEST(Viewer, RunDataKeepsEveryKthFrameAndTheLastWithDisplacementsWithinHalfACount) {
  testing_support::TempDir dir("viewer_run");
  write_run(dir.file("run"), 101, false);
  leg::ViewOptions o;
  o.max_frames = 21;
  const tbio::Json run = leg::view_run_data(dir.file("run"), o);
  EXPECT_EQ(run["format"], "tissuebench-view/1");
  EXPECT_EQ(run["status"], "complete");
  EXPECT_EQ(run["title"], "tiny");
  const auto& times = run["frame_times"];
  ASSERT_EQ(times.size(), 21u);  // frames 0, 5, ..., 100
  EXPECT_DOUBLE_EQ(times[1].get<double>(), 0.04 * 5);
  EXPECT_DOUBLE_EQ(times[20].get<double>(), 0.04 * 100);
  ASSERT_EQ(run["meshes"].size(), 2u);
  const auto& skin = run["meshes"][0];
  EXPECT_EQ(skin["name"], "skin");
  EXPECT_EQ(run["meshes"][1]["name"], "bones");
  EXPECT_EQ(decode<uint32_t>(skin["triangles_b64"]), (std::vector<uint32_t>{0, 1, 2}));
  const std::vector<float> rest = decode<float>(skin["rest_b64"]);
  ASSERT_EQ(rest.size(), 9u);
  EXPECT_FLOAT_EQ(rest[3], 0.1f);
  const double scale = skin["displacement_scale"];
  const std::vector<int16_t> counts = decode<int16_t>(skin["displacement_b64"]);
  ASSERT_EQ(counts.size(), 21u * 3u * 3u);
  for (size_t k = 0; k < 21; ++k) {
    const double expected = 1e-3 * static_cast<double>(5 * k);
    EXPECT_NEAR(scale * counts[k * 9], expected, 0.5 * scale + 1e-15) << "frame " << k;
    EXPECT_EQ(counts[k * 9 + 1], 0);
  }
  EXPECT_NEAR(scale, 0.1 / 32767.0, 1e-12);  // the largest displacement (0.1 m) is the largest count
  ASSERT_EQ(run["series"]["columns"].size(), 1u);
  EXPECT_EQ(run["series"]["columns"][0]["name"], "knee_angle");
  EXPECT_EQ(run["series"]["columns"][0]["unit"], "deg");
  EXPECT_EQ(run["series"]["time"].size(), 101u);
  EXPECT_EQ(run["plots"], tbio::Json::array({"knee_angle"}));
}

TEST(Viewer, FailedRunShowsWhatWasWrittenAndWhy) {
  testing_support::TempDir dir("viewer_failed");
  write_run(dir.file("run"), 3, true);
  const tbio::Json run = leg::view_run_data(dir.file("run"));
  EXPECT_EQ(run["status"], "failed");
  EXPECT_NE(run["failure"].get<std::string>().find("element 7, node 3"), std::string::npos);
  EXPECT_EQ(run["frame_times"].size(), 3u);
}

TEST(Viewer, FolderWithoutARunIsRefusedNamingIt) {
  testing_support::TempDir dir("viewer_none");
  std::filesystem::create_directories(dir.file("empty"));
  try {
    leg::view_run_data(dir.file("empty"));
    FAIL() << "no error";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no leg.h5"), std::string::npos) << e.what();
  }
  write_run(dir.file("scene/relaxed"), 2, false);
  write_run(dir.file("scene/active"), 2, false);
  try {
    leg::view_run_data(dir.file("scene"));
    FAIL() << "no error";
  } catch (const msd::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene/active"), std::string::npos) << what;
    EXPECT_NE(what.find("scene/relaxed"), std::string::npos) << what;
  }
  EXPECT_THROW(leg::view_run_data(dir.file("missing")), msd::Error);
}

}  // namespace
