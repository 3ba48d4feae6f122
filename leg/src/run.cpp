#include "leg/run.hpp"

#include "leg/analysis.hpp"
#include "leg/drive.hpp"
#include "leg/limb_input.hpp"
#include "leg/outputs.hpp"
#include "leg/sensors.hpp"
#include "msd/experiments/blowup.hpp"
#include "leg/session.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace leg {

CompiledLeg compile_leg(const LegScene& scene) {
  CompiledLeg c;
  c.input = read_limb_input(scene.geometry);
  if (!scene.mesh_pull) c.input.options.pull_areas.clear();
  c.limb = mesh_limb_input(c.input);
  msd::LegModelOptions options = scene.model;
  if (scene.insert_at_path_end)
    for (const msd::TendonPathSpec& t : c.input.tendons) options.tendon_insertions.push_back(t.path.back());
  c.model = msd::build_leg_model(c.limb.mesh, c.limb.tendons, options);
  return c;
}

msd::LegState start_state(const msd::LegModel& leg, const LegScene& scene) {
  msd::LegState state = msd::leg_rest_state(leg, scene.initial_angle);
  state.knee.velocity = scene.initial_velocity;
  msd::place_attached(leg.knee, state.knee, leg.tissue.rest_positions, leg.lower_nodes, state.tissue.x, state.tissue.v);
  return state;
}

Instruments make_leg_instruments(const CompiledLeg& c, const LegScene& scene) {
  Instruments in = make_instruments(c.model, scene, c.input.surfaces.skin,
                                    c.limb.mesh.embedded.at(msd::kPassiveTissue), c.limb.mesh.mesh.tets);
  auto surface = [&](int region) -> const msd::TriangleMesh* {
    const auto it = c.input.surfaces.inner.find(region);
    return it == c.input.surfaces.inner.end() ? nullptr : &it->second;
  };
  add_bone_surfaces(in, surface(msd::kUpperBone), surface(msd::kLowerBone));
  return in;
}

namespace {

constexpr double kDeg = M_PI / 180.0;

// One variant: step from rest to the scene's duration, recording every output
// interval; a blow-up ends the run marked failed with what was recorded.
LegRunSummary run_variant(const LegScene& scene, const LegVariant& variant, const msd::LegModel& leg,
                          const Instruments& in, const std::string& dir,
                          const std::function<void(double, double)>& progress) {
  std::error_code ignore;
  fs::create_directories(fs::path(dir) / "skin");
  fs::remove(fs::path(dir) / "summary.json", ignore);
  LegRunSummary sum;
  sum.name = scene.name;
  sum.variant = variant.name;
  sum.dir = dir;
  sum.nodes = leg.tissue.num_nodes();
  sum.tets = static_cast<long>(leg.tets.size());

  const std::vector<Sensor> sensors = leg_sensors(in);
  std::vector<tbio::SeriesColumn> cols;
  for (const Sensor& s : sensors) cols.push_back({s.name, s.unit});
  tbio::ResultsWriter writer((fs::path(dir) / "leg.h5").string(), run_meta(scene, variant, leg), cols);
  add_rest_geometry(writer, leg, *in.skin, in.bones, in.obstacles);

  msd::LegState state = start_state(leg, scene);
  msd::LegScratch scratch;
  msd::LegControls controls = initial_controls(leg, scene);
  bool engaged = !scene.tendons_engage_at;
  drive(scene, variant, 0.0, scene.dt, controls);
  {
    msd::LegState probe = state;  // the step-0 diagnostics (forces at rest) for the first row
    msd::step_leg(leg, probe, controls, 0.0, scratch);
  }

  // Blow-up limits (msd/experiments/blowup.hpp): the leg's extent as its
  // size, the knee's swing and the obstacles' scripted motion as the loading.
  const msd::Points& rest = leg.tissue.rest_positions;
  const double size = (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
  msd::BlowUpLimits limits(leg.tissue, size, 10.0);
  const auto check_blow_up = [&]() {
    double v = std::abs(state.knee.velocity) * size;
    for (const msd::Vec3& o : controls.obstacle_velocity) v = std::max(v, o.norm());
    limits.see_load_speed(v);
    limits.check(leg.tissue, state.tissue);
  };

  Recorded recorded;
  std::vector<double> frame_times;
  Frame frame;
  std::vector<double> row(sensors.size());
  auto record = [&]() {
    observe(in, state, scratch, controls, frame);
    for (size_t c = 0; c < sensors.size(); ++c) row[c] = sensors[c].read(frame);
    writer.append(row);
    for (size_t c = 0; c < sensors.size(); ++c) recorded[sensors[c].name].push_back(row[c]);
    append_frame_fields(writer, frame, in);
    const long index = static_cast<long>(frame_times.size());
    if (scene.obj_every > 0 && index % scene.obj_every == 0) write_skin_obj(dir, index, frame, *in.skin);
    const double t = state.tissue.t;
    frame_times.push_back(t);
    if (std::fmod(t + 1e-9, 0.2) < 0.5 * scene.output_interval || index == 0)
      sum.trajectory.emplace_back(t, state.knee.angle / kDeg);
  };

  const long steps_per_frame = std::lround(scene.output_interval / scene.dt);
  const long total_steps = std::lround(scene.duration / scene.dt);
  const auto start = std::chrono::steady_clock::now();
  record();
  try {
    for (long k = 1; k <= total_steps; ++k) {
      if (!engaged && tendons_due(scene, (k - 1) * scene.dt)) {
        engage_tendons(leg, state, controls);
        engaged = true;
      }
      drive(scene, variant, k * scene.dt, scene.dt, controls);
      msd::step_leg(leg, state, controls, scene.dt, scratch);
      state.tissue.t = k * scene.dt;  // no drift from summing dt
      if (k % steps_per_frame == 0) {
        check_blow_up();
        record();
      }
      if (progress && k % 500 == 0) progress(state.tissue.t, scene.duration);
      sum.steps = k;
    }
  } catch (const msd::SimulationFailure& e) {
    sum.status = "failed";
    sum.failure = e.what();
  }
  sum.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sum.simulated = sum.steps * scene.dt;
  sum.frames = static_cast<long>(frame_times.size());
  writer.set_timing(sum.wall_seconds, sum.steps, scene.dt, 1);
  writer.set_timing_detail("wall_per_simulated_second", sum.wall_per_simulated());

  std::vector<std::string> obstacle_names;
  for (const msd::RigidObstacle& ob : leg.obstacles) obstacle_names.push_back(ob.name);
  sum.values = summarise(std::move(recorded), scene, leg.tendon_names, obstacle_names, leg.joint_space_tets);
  if (sum.status == "failed")
    writer.fail(sum.failure);
  else
    writer.finish();
  write_xdmf((fs::path(dir) / "leg.xdmf").string(), "leg.h5", frame_times, sum.nodes, sum.tets,
             in.skin->num_vertices(), in.skin->num_triangles(), in.bones.num_vertices(), in.bones.num_triangles());
  tbio::write_json_file((fs::path(dir) / "summary.json").string(), summary_json(sum, scene));
  return sum;
}

}  // namespace

std::vector<LegRunSummary> run_leg_scene(const LegScene& scene, const std::string& out_dir,
                                         const std::function<void(double, double)>& progress) {
  fs::create_directories(out_dir);
  std::error_code ignore;
  fs::remove(fs::path(out_dir) / "summary.json", ignore);
  const CompiledLeg c = compile_leg(scene);
  const Instruments in = make_leg_instruments(c, scene);
  std::vector<LegVariant> variants = scene.variants;
  if (variants.empty()) variants.push_back({"", scene.front_activation, scene.back_activation});
  std::vector<LegRunSummary> summaries;
  for (const LegVariant& variant : variants) {
    const std::string dir = variant.name.empty() ? out_dir : (fs::path(out_dir) / variant.name).string();
    summaries.push_back(run_variant(scene, variant, c.model, in, dir, progress));
  }
  if (!scene.variants.empty()) write_variants_summary(out_dir, scene, summaries);
  return summaries;
}

std::string format_leg_summary(const LegRunSummary& s) {
  std::ostringstream o;
  char line[256];
  std::snprintf(line, sizeof line, "%s%s%s: %s, %.2f s simulated in %.1f s wall (%.2f s per simulated s), %ld frames\n",
                s.name.c_str(), s.variant.empty() ? "" : " / ", s.variant.c_str(), s.status.c_str(), s.simulated,
                s.wall_seconds, s.wall_per_simulated(), s.frames);
  o << line;
  if (!s.failure.empty()) o << "  failure: " << s.failure << "\n";
  for (const auto& [k, v] : s.values) {
    std::snprintf(line, sizeof line, "  %-44s %12.5g\n", k.c_str(), v);
    o << line;
  }
  return o.str();
}

}  // namespace leg
