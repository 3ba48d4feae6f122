// The fuzz targets' bodies (fuzz_targets.hpp; docs/fuzzing.md).
#include "fuzz_targets.hpp"

#include "bench/calibration.hpp"
#include "bench/guard.hpp"
#include "bench/spec.hpp"
#include "leg/limb_input.hpp"
#include "leg/scene.hpp"
#include "msd/control/activation_script.hpp"
#include "msd/core/types.hpp"
#include "msd/geometry/triangle_mesh.hpp"

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <typeinfo>

#include <unistd.h>

namespace tbfuzz {

namespace fs = std::filesystem;

namespace {

const std::string kSource = TISSUEBENCH_SOURCE_DIR;

// A private folder for the inputs written as files, laid out like the shipped
// data so a scene's relative references (../scripts/..., skin.obj) resolve:
//   scenes/     a leg scene (scripts -> msd/data/scripts, leg -> msd/data/leg)
//   mesh/       a mesh scene beside five small box surfaces named like the
//               shipped leg's (reading the shipped 2.4 MB of OBJ per input
//               would leave the fuzzer a few executions a second)
// Removed when the process ends.
class Workspace {
 public:
  Workspace() {
    std::string pattern = (fs::temp_directory_path() / "tbfuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("tbfuzz: cannot create a temporary folder");
    root_ = pattern;
    fs::create_directories(root_ / "scenes");
    fs::create_directories(root_ / "mesh");
    fs::create_directory_symlink(fs::path(kSource) / "msd/data/scripts", root_ / "scripts");
    fs::create_directory_symlink(fs::path(kSource) / "msd/data/leg", root_ / "leg");
    const std::map<std::string, std::pair<msd::Vec3, msd::Vec3>> boxes{
        {"skin", {{-0.15, -0.15, 0.0}, {0.15, 0.15, 1.0}}},
        {"upper_bone", {{-0.02, -0.02, 0.52}, {0.02, 0.02, 0.95}}},
        {"lower_bone", {{-0.045, -0.02, 0.05}, {0.045, 0.02, 0.51}}},
        {"back_muscle", {{-0.12, -0.1, 0.55}, {-0.03, 0.1, 0.9}}},
        {"front_muscle", {{0.03, -0.1, 0.55}, {0.12, 0.1, 0.9}}}};
    for (const auto& [name, box] : boxes)
      msd::write_obj((root_ / "mesh" / (name + ".obj")).string(), msd::make_box(box.first, box.second));
  }
  ~Workspace() {
    std::error_code ignore;
    fs::remove_all(root_, ignore);
  }
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

  // Writes `bytes` to ROOT/relative and returns its path.
  std::string write(const std::string& relative, const std::string& bytes) const {
    const fs::path p = root_ / relative;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("tbfuzz: cannot write " + p.string());
    return p.string();
  }

 private:
  fs::path root_;
};

const Workspace& workspace() {
  static const Workspace w;
  return w;
}

std::string spec(const std::string& bytes) {
  // As if the file were one of the shipped specs: `msd.calibration:
  // ../calibration/...` and `material.library:` read the shipped files.
  const bench::Spec s = bench::parse_spec(bytes, kSource + "/benchmarks/specs/fuzz_input.yaml");
  return s.name;
}

std::string calibration(const std::string& bytes) {
  std::string material;
  const bench::CalibrationParameters p = bench::read_calibration(workspace().write("calibration.yaml", bytes), &material);
  return material + std::to_string(p.stiffness_scale);
}

std::string baseline(const std::string& bytes) {
  const bench::Baseline b = bench::read_baseline(workspace().write("baseline.yaml", bytes));
  // Check the baseline against its own values and against nothing.
  std::map<std::string, double> same;
  for (const auto& [key, e] : b.metrics) same[key] = e.value;
  const bench::GuardReport r = bench::check_metrics(same, b);
  (void)bench::check_metrics({}, b);
  return std::to_string(r.checked);
}

std::string activation_script(const std::string& bytes) {
  const msd::ActivationScript s = msd::parse_activation_script(bytes, "fuzz.txt", {"FRONT_MUSCLE", "BACK_MUSCLE"});
  double sum = 0.0;
  for (const auto& m : s.muscles())
    for (const auto& c : s.commands)
      for (double t : {c.time, c.time + 0.5 * c.timescale, c.time + c.timescale}) sum += s.activation(m, t);
  return std::to_string(sum);
}

std::string leg_scene(const std::string& bytes) {
  const leg::LegScene s = leg::read_leg_scene(workspace().write("scenes/scene.yaml", bytes));
  return s.name;
}

std::string mesh_scene(const std::string& bytes) {
  const leg::LimbInput in = leg::read_limb_input(workspace().write("mesh/leg.yaml", bytes));
  return in.name;
}

std::string surface(const std::string& bytes, const char* file, msd::TriangleMesh (*read)(const std::string&)) {
  const msd::TriangleMesh m = read(workspace().write(file, bytes));
  double sum = 0.0;
  for (const auto& t : m.triangles) sum += m.vertices.col(t[0]).sum() + m.vertices.col(t[1]).sum() + m.vertices.col(t[2]).sum();
  return std::to_string(sum);
}
std::string obj(const std::string& bytes) { return surface(bytes, "surface.obj", msd::read_obj); }
std::string stl(const std::string& bytes) { return surface(bytes, "surface.stl", msd::read_stl); }
std::string ply(const std::string& bytes) { return surface(bytes, "surface.ply", msd::read_ply); }

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all{
      {"spec", "bench::parse_spec (a benchmark spec, with the calibration file it names)", spec},
      {"calibration", "bench::read_calibration (benchmarks/calibration/*.yaml)", calibration},
      {"baseline", "bench::read_baseline and check_metrics (reports/baselines/*.yaml)", baseline},
      {"activation_script", "msd::parse_activation_script (msd/data/scripts/*.txt)", activation_script},
      {"leg_scene", "leg::read_leg_scene (msd/data/scenes/*.yaml, with the script it names)", leg_scene},
      {"mesh_scene", "leg::read_limb_input (msd/data/leg/leg.yaml: surfaces, mesh, tendons)", mesh_scene},
      {"obj", "msd::read_obj", obj},
      {"stl", "msd::read_stl (ASCII and binary)", stl},
      {"ply", "msd::read_ply (ASCII, binary little and big endian)", ply},
  };
  return all;
}

const Target* find_target(const std::string& name) {
  for (const auto& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

std::string run_target(const Target& target, const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    target.run(bytes);
  } catch (const msd::Error&) {
    return "";  // refused with a message for the user: what bad input must get
  } catch (const std::exception& e) {
    return std::string(target.name) + ": an exception other than msd::Error escaped the reader (" +
           typeid(e).name() + "): " + e.what();
  } catch (...) {
    return std::string(target.name) + ": a non-standard exception escaped the reader";
  }
  return "";
}

}  // namespace tbfuzz
