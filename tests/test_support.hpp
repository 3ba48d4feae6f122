// Helpers shared by the test suites: random tets, finite-difference gradients,
// temporary folders.
#pragma once

#include "msd/core/types.hpp"
#include "msd/mesh/limb_mesher.hpp"
#include "msd/mesh/tet_mesh.hpp"
#include "msd/model/model.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace testing_support {

/// The whole file at `path` as text ("" when it cannot be read).
inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The length of the polyline through the columns `nodes` of `x` and, when
/// given, on to the point `end` (a strand's anchor): the strand's length.
inline double polyline_length(const msd::Points& x, const std::vector<int>& nodes, const msd::Vec3* end = nullptr) {
  double length = 0.0;
  for (size_t i = 0; i + 1 < nodes.size(); ++i) length += (x.col(nodes[i + 1]) - x.col(nodes[i])).norm();
  if (end && !nodes.empty()) length += (*end - msd::Vec3(x.col(nodes.back()))).norm();
  return length;
}

/// A random, positively oriented, reasonably shaped tet (quality > 0.2) near
/// the origin with edges of about `scale`.
inline void random_tet(std::mt19937& rng, msd::Vec3 x[4], double scale = 1.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    for (int i = 0; i < 4; ++i) x[i] = scale * msd::Vec3(u(rng), u(rng), u(rng));
    if (msd::tet_signed_volume(x[0], x[1], x[2], x[3]) < 0) std::swap(x[2], x[3]);
    if (msd::tet_quality(x[0], x[1], x[2], x[3]) > 0.2) return;
  }
}

/// Central-difference gradient of `energy` with respect to the 12 coordinates.
inline void fd_gradient(const std::function<double(const msd::Vec3*)>& energy, const msd::Vec3 x[4],
                        double h, msd::Vec3 grad[4]) {
  msd::Vec3 y[4] = {x[0], x[1], x[2], x[3]};
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) {
      const double keep = y[i][a];
      y[i][a] = keep + h;
      const double up = energy(y);
      y[i][a] = keep - h;
      const double down = energy(y);
      y[i][a] = keep;
      grad[i][a] = (up - down) / (2 * h);
    }
}

/// The right-corner tet (0,0,0), (e,0,0), (0,e,0), (0,0,e) as a one-tet mesh.
inline msd::TetMesh corner_tet_mesh(double e) {
  msd::TetMesh m;
  m.nodes.resize(3, 4);
  m.nodes << 0, e, 0, 0,  //
      0, 0, e, 0,         //
      0, 0, 0, e;
  m.tets = {{0, 1, 2, 3}};
  m.region = {0};
  return m;
}

/// The 10 cm corner tet as a model: k_s = 1 N/m on every edge, water's density;
/// `opt` adds the rest (its region materials are replaced).
inline msd::Model corner_tet_model(msd::ModelOptions opt = {}) {
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 1.0;
  opt.region_materials = {mat};
  return msd::build_model(corner_tet_mesh(0.1), opt);
}

/// A squeezed, jittered state of a model: positions = rest with z scaled by
/// `squeeze` plus uniform noise of `jitter` m, velocities uniform in
/// +-0.05 m/s (seeded, reproducible).
inline void deform(const msd::Model& m, double squeeze, double jitter, msd::Points& x, msd::Points& v,
                   unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  x = m.rest_positions;
  x.row(2) *= squeeze;
  v.setZero(3, x.cols());
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (int a = 0; a < 3; ++a) {
      x(a, i) += jitter * u(rng);
      v(a, i) = 0.05 * u(rng);
    }
}

/// A small uni-axial spec (a 2 x 2 x 4 cm box at h = 1 cm, 80 tets, physical
/// constants, compression to -0.1 then extension to +0.1 in 0.4 s) shared by
/// the benchmark-layer suites.
inline const char* small_uniaxial_spec() {
  return R"(name: small
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {density: 1000, youngs_modulus: 5000, damping_time: 0.002}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 0.5, dt: 1.0e-4}
loading: {type: uniaxial, path: [[0, 0], [0.2, -0.1], [0.4, 0.1]]}
output: {interval: 0.02}
)";
}

/// A cylindrical "limb" (radius 5 cm, 30 cm long, axis z from the origin) with
/// a bone in each half (the lower one reaching within 5 mm of the skin's end)
/// and a muscle in front of (+y) and behind the upper bone.
inline msd::LimbSurfaces cylinder_limb() {
  auto moved = [](msd::TriangleMesh m, const msd::Vec3& by) {
    m.vertices.colwise() += by;
    return m;
  };
  msd::LimbSurfaces s;
  s.skin = msd::make_cylinder(0.05, 0.30, 48);
  s.inner[msd::kUpperBone] = moved(msd::make_cylinder(0.012, 0.12, 16), {0, 0, 0.165});
  s.inner[msd::kLowerBone] = moved(msd::make_cylinder(0.012, 0.13, 16), {0, 0, 0.005});
  s.inner[msd::kFrontMuscle] = msd::make_box({-0.025, 0.018, 0.17}, {0.025, 0.042, 0.28});
  s.inner[msd::kBackMuscle] = msd::make_box({-0.025, -0.042, 0.17}, {0.025, -0.018, 0.28});
  return s;
}

/// A fresh empty folder under the system temp dir, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("tb_" + tag + "_" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace testing_support
