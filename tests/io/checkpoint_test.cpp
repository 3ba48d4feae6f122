// Checkpoints: what is written is read back exactly; a checkpoint of another
// kind, input, model or format version, or a damaged one, is refused naming the file.
#include "tbio/checkpoint.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Checkpoint, WhatIsWrittenIsReadBackExactly) {
  testing_support::TempDir dir("checkpoint");
  const std::string path = dir.file("c.checkpoint");
  msd::Points x = msd::Points::Random(3, 7);
  tbio::ResultsSnapshot snap;
  snap.rows = {{0.0, 1.0 / 3.0}, {0.1, -2.5e-300}};
  snap.fields["nodes"].time = {0.0, 0.1};
  snap.fields["nodes"].displacement = {{{{1, 2, 3}}}, {{{4, 5, 6.000000000000001}}}};
  tbio::CheckpointWriter w("run", "in", "model");
  w.integer(-42);
  w.number(0.1);
  w.numbers({1.0, 2.0});
  w.text("hello");
  w.points(x);
  w.snapshot(snap);
  w.save(path);
  tbio::CheckpointReader r(path, "run", "in", "model");
  EXPECT_EQ(r.integer(), -42);
  EXPECT_EQ(r.number(), 0.1);
  EXPECT_EQ(r.numbers(), (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(r.text(), "hello");
  EXPECT_EQ(r.points(), x);
  const tbio::ResultsSnapshot back = r.snapshot();
  EXPECT_EQ(back.rows, snap.rows);
  EXPECT_EQ(back.fields.at("nodes").time, snap.fields.at("nodes").time);
  EXPECT_EQ(back.fields.at("nodes").displacement, snap.fields.at("nodes").displacement);
  EXPECT_NO_THROW(r.finish());
}

TEST(Checkpoint, AnotherInputModelKindVersionOrADamagedFileIsRefused) {
  testing_support::TempDir dir("checkpoint");
  const std::string path = dir.file("c.checkpoint");
  tbio::CheckpointWriter w("leg", "in", "model");
  w.numbers({1.0, 2.0, 3.0});
  w.save(path);
  EXPECT_NE(error_of([&] { tbio::CheckpointReader(path, "leg", "other", "model"); }).find("different input"),
            std::string::npos);
  EXPECT_NE(error_of([&] { tbio::CheckpointReader(path, "leg", "in", "other"); }).find("different model"),
            std::string::npos);
  EXPECT_NE(error_of([&] { tbio::CheckpointReader(path, "run", "in", "model"); }).find("not of 'run'"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { tbio::CheckpointReader(path, "leg", "in", "model"); }), "");
  // Truncated: the count says three numbers, the file holds fewer.
  std::string bytes = testing_support::read_text(path);
  std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() - 8);
  EXPECT_NE(error_of([&] {
              tbio::CheckpointReader r(path, "leg", "in", "model");
              r.numbers();
            }).find(path + ": the checkpoint is truncated"),
            std::string::npos);
  // Another format version.
  bytes[8] = 99;
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_NE(error_of([&] { tbio::CheckpointReader(path, "leg", "in", "model"); }).find("format version 99"),
            std::string::npos);
  std::ofstream(path) << "name: a spec\n";
  EXPECT_NE(error_of([&] { tbio::CheckpointReader(path, "leg", "in", "model"); }).find("not a tissuebench checkpoint"),
            std::string::npos);
}

TEST(Checkpoint, AStateIsReadBackWholeWithTheIntegratorsMemories) {
  // Velocity Verlet's acceleration, BDF2's history and the joints: a resumed
  // run continues from exactly the state it left.
  testing_support::TempDir dir("checkpoint");
  const std::string path = dir.file("s.checkpoint");
  msd::State s;
  s.x = msd::Points::Random(3, 5);
  s.v = msd::Points::Random(3, 5);
  s.t = 0.123;
  s.step = 77;
  s.a = msd::Points::Random(3, 5);
  s.a_valid = true;
  s.x_prev = msd::Points::Random(3, 5);
  s.v_prev = msd::Points::Random(3, 5);
  s.dt_prev = 1.0 / 3.0e3;
  s.joints = {{0.5, -1.25}, {1.0 / 7.0, 0.0}};
  tbio::CheckpointWriter w("run", "in", "model");
  w.state(s);
  w.save(path);
  tbio::CheckpointReader r(path, "run", "in", "model");
  const msd::State b = r.state();
  EXPECT_NO_THROW(r.finish());
  EXPECT_EQ(b.x, s.x);
  EXPECT_EQ(b.v, s.v);
  EXPECT_EQ(b.t, s.t);
  EXPECT_EQ(b.step, s.step);
  EXPECT_EQ(b.a, s.a);
  EXPECT_TRUE(b.a_valid);
  EXPECT_EQ(b.x_prev, s.x_prev);
  EXPECT_EQ(b.v_prev, s.v_prev);
  EXPECT_EQ(b.dt_prev, s.dt_prev);
  ASSERT_EQ(b.joints.size(), 2u);
  EXPECT_EQ(b.joints[1].angle, s.joints[1].angle);
  EXPECT_EQ(b.joints[0].velocity, s.joints[0].velocity);
}
