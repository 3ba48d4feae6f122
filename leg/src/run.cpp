#include "leg/run.hpp"

#include "leg/analysis.hpp"
#include "leg/drive.hpp"
#include "leg/limb_input.hpp"
#include "leg/outputs.hpp"
#include "leg/sensors.hpp"
#include "msd/experiments/blowup.hpp"
#include "leg/session.hpp"

#include "tbio/checkpoint.hpp"
#include "tbio/series_tools.hpp"
#include "tbio/sha256.hpp"

#include "msd/io/interrupt.hpp"
#include "msd/io/output_lock.hpp"

#include <chrono>
#include <cstdint>
#include <optional>
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
  if (scene.hip) msd::place_leg_on_femur(state, scene.hip->at(0.0));  // the hip's first pose
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

std::string leg_checkpoint_path(const std::string& dir) { return (fs::path(dir) / "leg.checkpoint").string(); }

namespace {

constexpr double kDeg = M_PI / 180.0;

// The inputs a checkpoint must match: the scene's text and the options that
// change what a run writes; the limb by the model's fingerprint.
std::string leg_input_hash(const LegScene& scene, const LegVariant& variant) {
  std::ostringstream o;
  o.precision(17);
  o << "leg\n" << scene.text << "\nvariant=" << variant.name << " duration=" << scene.duration
    << " obj_every=" << scene.obj_every << " dt=" << scene.dt << " interval=" << scene.output_interval << "\n";
  return tbio::sha256_hex(o.str());
}

// Everything the time loop carries from one step to the next, and what was
// written so far: a checkpoint's content.
struct LegLoop {
  long step = 0;
  msd::LegState state;
  msd::LegControls controls;
  bool engaged = false;
  std::vector<double> frame_times;
  std::vector<std::pair<double, double>> trajectory;
  std::vector<std::pair<long, msd::Points>> obj_frames;  ///< (frame index, skin positions) of the OBJ frames
  std::vector<double> strain_peak;  ///< per tendon: the largest strand strain of any step so far
};

void write_leg_checkpoint(const std::string& path, const std::string& input_hash, const std::string& model_hash,
                          const LegLoop& l, tbio::ResultsWriter& writer) {
  tbio::CheckpointWriter w("leg", input_hash, model_hash);
  w.integer(l.step);
  w.state(l.state.tissue);
  w.number(l.state.knee.angle);
  w.number(l.state.knee.velocity);
  const msd::LegControls& c = l.controls;
  std::vector<double> scalars{c.front_activation, c.back_activation, c.joint_torque};
  scalars.insert(scalars.end(), l.state.activation.begin(), l.state.activation.end());  // activation dynamics' state
  w.numbers(scalars);
  w.numbers(c.tendon_length_scale);
  w.numbers(c.strand_natural_length);
  w.numbers(c.scripted_knee ? std::vector<double>{c.scripted_knee->angle, c.scripted_knee->velocity}
                            : std::vector<double>{});
  auto vec3s = [&](const std::vector<msd::Vec3>& v) {
    msd::Points p(3, static_cast<Eigen::Index>(v.size()));
    for (size_t i = 0; i < v.size(); ++i) p.col(static_cast<Eigen::Index>(i)) = v[i];
    w.points(p);
  };
  vec3s(c.obstacle_offset);
  vec3s(c.obstacle_velocity);
  w.integer(l.engaged ? 1 : 0);
  w.numbers(l.frame_times);
  std::vector<double> traj;
  for (const auto& [time, angle] : l.trajectory) traj.insert(traj.end(), {time, angle});
  w.numbers(traj);
  w.integer(static_cast<std::int64_t>(l.obj_frames.size()));
  for (const auto& [index, x] : l.obj_frames) {
    w.integer(index);
    w.points(x);
  }
  w.numbers(l.strain_peak);
  w.snapshot(writer.snapshot());
  w.save(path);
}

LegLoop read_leg_checkpoint(tbio::CheckpointReader& r, const msd::LegModel& leg, tbio::ResultsSnapshot& results) {
  LegLoop l;
  l.step = r.integer();
  l.state.tissue = r.state();
  l.state.knee.angle = r.number();
  l.state.knee.velocity = r.number();
  msd::LegControls& c = l.controls;
  const std::vector<double> scalars = r.numbers();
  c.tendon_length_scale = r.numbers();
  c.strand_natural_length = r.numbers();
  const std::vector<double> knee = r.numbers();
  if ((scalars.size() != 3 && scalars.size() != 5) || (knee.size() != 0 && knee.size() != 2))
    throw msd::Error(r.path() + ": the checkpoint is damaged (controls)");
  c.front_activation = scalars[0];
  c.back_activation = scalars[1];
  c.joint_torque = scalars[2];
  l.state.activation.assign(scalars.begin() + 3, scalars.end());
  if (knee.size() == 2) c.scripted_knee = msd::HingeState{knee[0], knee[1]};
  for (std::vector<msd::Vec3>* v : {&c.obstacle_offset, &c.obstacle_velocity}) {
    const msd::Points p = r.points();
    for (int i = 0; i < p.cols(); ++i) v->push_back(p.col(i));
  }
  l.engaged = r.integer() != 0;
  l.frame_times = r.numbers();
  const std::vector<double> traj = r.numbers();
  for (size_t i = 0; i + 1 < traj.size(); i += 2) l.trajectory.emplace_back(traj[i], traj[i + 1]);
  const std::int64_t objs = r.integer();
  for (std::int64_t i = 0; i < objs && i < 10000000; ++i) {
    const long index = static_cast<long>(r.integer());
    l.obj_frames.emplace_back(index, r.points());
  }
  l.strain_peak = r.numbers();
  if (l.strain_peak.size() != leg.tendon_names.size())
    throw msd::Error(r.path() + ": the checkpoint is damaged (tendon strains)");
  results = r.snapshot();
  r.finish();
  if (l.state.tissue.x.cols() != leg.tissue.num_nodes() || l.state.tissue.v.cols() != leg.tissue.num_nodes())
    throw msd::Error(r.path() + ": the checkpoint's state does not match the leg");
  return l;
}

// The files after the loop: leg.h5's status (renamed into place), leg.xdmf,
// summary.json. A write failure is reported in the summary, never thrown.
void finish_leg_files(LegRunSummary& sum, const LegScene& scene, const Instruments& in, tbio::ResultsWriter& writer,
                      const std::vector<double>& frame_times, const std::string& dir) {
  try {
    writer.set_timing(sum.wall_seconds, sum.steps, scene.dt, 1);
    writer.set_timing_detail("wall_per_simulated_second", sum.wall_per_simulated());
    if (sum.status != "failed") writer.finish();
  } catch (const msd::Error& e) {
    sum.status = "failed";
    sum.failure = sum.failure.empty() ? e.what() : sum.failure + "; then " + e.what();
  }
  if (sum.status == "failed") sum.kept = writer.fail(sum.failure);
  try {
    if (sum.kept)
      write_xdmf((fs::path(dir) / "leg.xdmf").string(), "leg.h5", frame_times, sum.nodes, sum.tets,
                 in.skin->num_vertices(), in.skin->num_triangles(), in.bones.num_vertices(), in.bones.num_triangles());
    tbio::write_json_file((fs::path(dir) / "summary.json").string(), summary_json(sum, scene));
  } catch (const msd::Error& e) {
    sum.status = "failed";
    sum.failure += (sum.failure.empty() ? "" : "; then ") + std::string(e.what());
  }
}

// The tendons' strain peaks over every step of the run (frames miss most
// steps; a tear in a lead-in before analysis.from counts too) into the
// summary's values, and a warning for each tendon past the failure strain.
void add_tendon_strains(LegRunSummary& sum, const LegScene& scene, const msd::LegModel& leg,
                        const std::vector<double>& strain_peak) {
  for (size_t k = 0; k < leg.tendon_names.size() && k < strain_peak.size(); ++k)
    sum.values["tendon_" + leg.tendon_names[k] + "_strain_max"] = strain_peak[k];
  for (const std::string& t : leg.tendon_names) {
    const auto it = sum.values.find("tendon_" + t + "_strain_max");
    if (it != sum.values.end() && it->second > scene.tendon_failure_strain) {
      char w[256];
      std::snprintf(w, sizeof w,
                    "tendon %s: a strand reached %.1f %% strain, past the failure strain %.1f %% "
                    "(tendons.failure_strain): a real tendon would have torn",
                    t.c_str(), 100.0 * it->second, 100.0 * scene.tendon_failure_strain);
      sum.warnings.push_back(w);
    }
  }
}

// One variant: step from rest (or a checkpoint) to the scene's duration,
// recording every output interval; a blow-up, a write failure or a signal
// ends the run marked failed with what was recorded.
LegRunSummary run_variant(const LegScene& scene, const LegVariant& variant, const msd::LegModel& leg,
                          const Instruments& in, const std::string& dir,
                          const std::function<void(double, double)>& progress, const LegCheckpointing& cp) {
  const std::string input_hash = leg_input_hash(scene, variant);
  const std::string model_hash = tbio::fingerprint(leg.tissue.rest_positions, leg.tissue.mass);
  std::optional<tbio::CheckpointReader> reader;  // a bad checkpoint is refused before anything is written
  if (!cp.resume.empty()) reader.emplace(cp.resume, "leg", input_hash, model_hash);
  tbio::ResultsSnapshot restored;
  std::optional<LegLoop> resumed;
  if (reader) resumed = read_leg_checkpoint(*reader, leg, restored);
  fs::create_directories(fs::path(dir) / "skin");
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
  std::error_code ignore;
  fs::remove(fs::path(dir) / "summary.json", ignore);  // an earlier run's summary must not outlive this one
  const msd::InterruptibleSection interruptible;
  add_rest_geometry(writer, leg, *in.skin, in.bones, in.obstacles);

  LegLoop l;
  l.state = start_state(leg, scene);
  l.controls = initial_controls(leg, scene);
  l.engaged = !scene.tendons_engage_at;
  l.strain_peak.assign(leg.tendon_names.size(), 0.0);
  msd::LegScratch scratch;
  drive(scene, variant, 0.0, scene.dt, l.controls);
  {
    msd::LegState probe = l.state;  // the step-0 diagnostics (forces at rest) for the first row
    msd::step_leg(leg, probe, l.controls, 0.0, scratch);
  }

  // Blow-up limits (msd/experiments/blowup.hpp): the leg's extent as its
  // size, the knee's swing and the obstacles' scripted motion as the loading.
  const msd::Points& rest = leg.tissue.rest_positions;
  const double size = (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
  msd::BlowUpLimits limits(leg.tissue, size, 10.0);
  const auto check_blow_up = [&]() {
    double v = std::abs(l.state.knee.velocity) * size;
    for (const msd::Vec3& o : l.controls.obstacle_velocity) v = std::max(v, o.norm());
    if (const auto& f = l.controls.femur) v = std::max(v, f->angular_velocity.norm() * size + f->velocity.norm());
    limits.see_load_speed(v);
    limits.check(leg.tissue, l.state.tissue, l.controls.femur ? &l.state.femur : nullptr);
  };

  Recorded recorded;
  Frame frame;
  std::vector<double> row(sensors.size());
  const bool keep_objs = cp.every > 0.0;
  auto record = [&]() {
    observe(in, l.state, scratch, l.controls, frame);
    for (size_t c = 0; c < sensors.size(); ++c) row[c] = sensors[c].read(frame);
    writer.append(row);
    for (size_t c = 0; c < sensors.size(); ++c) recorded[sensors[c].name].push_back(row[c]);
    append_frame_fields(writer, frame, in);
    const long index = static_cast<long>(l.frame_times.size());
    if (scene.obj_every > 0 && index % scene.obj_every == 0) {
      write_skin_obj(dir, index, frame.skin_x, *in.skin);
      if (keep_objs) l.obj_frames.emplace_back(index, frame.skin_x);
    }
    const double t = l.state.tissue.t;
    l.frame_times.push_back(t);
    if (std::fmod(t + 1e-9, 0.2) < 0.5 * scene.output_interval || index == 0)
      l.trajectory.emplace_back(t, l.state.knee.angle / kDeg);
  };

  const long steps_per_frame = std::lround(scene.output_interval / scene.dt);
  const long total_steps = std::lround(scene.duration / scene.dt);
  double next_checkpoint = cp.every;
  const auto start = std::chrono::steady_clock::now();
  try {
    if (resumed) {
      l = std::move(*resumed);
      if (scene.hip) l.state.femur = *(l.controls.femur = scene.hip->at(l.state.tissue.t));  // (not in the checkpoint: the script's)
      writer.set_meta("resumed_from", cp.resume + " at t = " + tbio::json_number(l.state.tissue.t) + " s");
      writer.restore(restored);
      for (const auto& r : restored.rows)
        for (size_t c = 0; c < sensors.size() && c < r.size(); ++c) recorded[sensors[c].name].push_back(r[c]);
      for (const auto& [index, x] : l.obj_frames) write_skin_obj(dir, index, x, *in.skin);
      if (!keep_objs) l.obj_frames.clear();
      sum.steps = l.step;
      if (cp.every > 0.0) next_checkpoint = (std::floor(l.step * scene.dt / cp.every + 1e-9) + 1.0) * cp.every;
    } else {
      record();
    }
    for (long k = l.step + 1; k <= total_steps; ++k) {
      msd::throw_if_interrupted((k - 1) * scene.dt, k - 1);
      if (!l.engaged && tendons_due(scene, (k - 1) * scene.dt)) {
        engage_tendons(leg, l.state, l.controls);
        l.engaged = true;
      }
      drive(scene, variant, k * scene.dt, scene.dt, l.controls);
      msd::step_leg(leg, l.state, l.controls, scene.dt, scratch, scene.integrator);
      for (size_t t = 0; t < l.strain_peak.size() && t < scratch.tendon_strain.size(); ++t)
        l.strain_peak[t] = std::max(l.strain_peak[t], scratch.tendon_strain[t]);
      l.state.tissue.t = k * scene.dt;  // no drift from summing dt
      l.step = k;
      sum.steps = k;
      if (k % steps_per_frame == 0) {
        check_blow_up();
        record();
        if (cp.every > 0.0 && l.state.tissue.t >= next_checkpoint - 1e-9 * scene.dt && k < total_steps) {
          write_leg_checkpoint(leg_checkpoint_path(dir), input_hash, model_hash, l, writer);
          next_checkpoint = (std::floor(l.state.tissue.t / cp.every + 1e-9) + 1.0) * cp.every;
        }
      }
      if (progress && k % 500 == 0) progress(l.state.tissue.t, scene.duration);
    }
  } catch (const msd::SimulationFailure& e) {
    sum.status = "failed";
    sum.failure = e.what();
    if (const auto* i = dynamic_cast<const msd::Interrupted*>(&e)) sum.interrupted = i->signal;
  } catch (const msd::Error& e) {  // a write failure (results, OBJ or checkpoint)
    sum.status = "failed";
    sum.failure = std::string(e.what()) + " at t = " + tbio::json_number(sum.steps * scene.dt) + " s";
  }
  sum.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sum.newton_iterations = scratch.tissue.newton_iterations;
  sum.step_cuts = scratch.tissue.step_cuts;
  sum.factorizations = scratch.tissue.factorizations;
  sum.simulated = sum.steps * scene.dt;
  sum.frames = static_cast<long>(l.frame_times.size());
  sum.trajectory = l.trajectory;

  std::vector<std::string> obstacle_names;
  for (const msd::RigidObstacle& ob : leg.obstacles) obstacle_names.push_back(ob.name);
  sum.values = summarise(std::move(recorded), scene, leg.tendon_names, obstacle_names, leg.joint_space_tets);
  add_tendon_strains(sum, scene, leg, l.strain_peak);
  finish_leg_files(sum, scene, in, writer, l.frame_times, dir);
  // A completed run's checkpoint (written now, or resumed from) is of no more use.
  const bool resumed_here = !cp.resume.empty() && fs::equivalent(cp.resume, leg_checkpoint_path(dir), ignore);
  if (sum.status == "complete" && (cp.every > 0.0 || resumed_here)) fs::remove(leg_checkpoint_path(dir), ignore);
  return sum;
}

// The variant a checkpoint belongs to: the one whose input fingerprint
// (leg_input_hash: the scene, the variant, the options) its header carries.
// With one variant, or a checkpoint not of a leg run, the variant's own
// reader gives the message (run_variant).
size_t checkpoint_variant(const LegScene& scene, const std::vector<LegVariant>& variants, const std::string& path) {
  if (variants.size() == 1) return 0;  // no need to read the file twice
  const tbio::CheckpointHeader h = tbio::read_checkpoint_header(path);
  if (h.kind != "leg") return 0;
  std::string names;
  for (size_t i = 0; i < variants.size(); ++i) {
    if (h.input_hash == leg_input_hash(scene, variants[i])) return i;
    names += (i ? ", " : "") + variants[i].name;
  }
  throw msd::Error(path + ": --resume: a checkpoint of none of the variants of " + scene.file + " (" + names +
                   ") with these options; refused");
}

// `--out` must not name the scene, its script, its limb or a surface: the
// files a run writes (every variant's) are checked against them.
void refuse_outputs_over_inputs(const LegScene& scene, const CompiledLeg& c, const std::string& out_dir) {
  std::vector<std::string> inputs{scene.file, scene.script_path, scene.geometry};
  for (const auto& [region, file] : c.input.surfaces.source) inputs.push_back(file);
  std::vector<std::string> outputs{out_dir, (fs::path(out_dir) / "summary.json").string()};
  std::vector<std::string> dirs{out_dir};
  for (const LegVariant& v : scene.variants) dirs.push_back((fs::path(out_dir) / v.name).string());
  const long frames = std::lround(scene.duration / scene.output_interval) + 1;
  for (const std::string& d : dirs) {
    for (const char* f : {"leg.h5", "leg.csv", "leg.xdmf", "summary.json", "leg.checkpoint"})
      outputs.push_back((fs::path(d) / f).string());
    for (long k = 0; scene.obj_every > 0 && k < frames; k += scene.obj_every) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04ld.obj", k);
      outputs.push_back((fs::path(d) / "skin" / name).string());
    }
  }
  msd::refuse_output_over_inputs("--out", outputs, inputs);
}

}  // namespace

std::vector<LegRunSummary> run_leg_scene(const LegScene& scene, const std::string& out_dir,
                                         const std::function<void(double, double)>& progress,
                                         const LegCheckpointing& cp) {
  if (!(cp.every >= 0.0) || !std::isfinite(cp.every))
    throw msd::Error("--checkpoint-every: must be a finite number of simulated seconds > 0");
  const CompiledLeg c = compile_leg(scene);  // input errors surface here, before anything is written
  const Instruments in = make_leg_instruments(c, scene);
  std::vector<LegVariant> variants = scene.variants;
  if (variants.empty()) variants.push_back({"", scene.front_activation, scene.back_activation});
  // Each variant checkpoints into its own folder; a resume continues the
  // checkpoint's variant, runs the variants before it again (deterministic:
  // the same results) and the ones after it from rest.
  const size_t resumed = cp.resume.empty() ? 0 : checkpoint_variant(scene, variants, cp.resume);
  refuse_outputs_over_inputs(scene, c, out_dir);
  const fs::path out(out_dir);
  if (!out.lexically_normal().parent_path().empty()) fs::create_directories(out.lexically_normal().parent_path());
  fs::path folder = out.lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();  // "out/leg/" locks out/leg.lock
  const msd::OutputLock lock(folder.string(), msd::this_command_line());
  fs::create_directories(out_dir);
  std::vector<LegRunSummary> summaries;
  for (size_t i = 0; i < variants.size(); ++i) {
    const LegVariant& variant = variants[i];
    const std::string dir = variant.name.empty() ? out_dir : (fs::path(out_dir) / variant.name).string();
    LegCheckpointing this_cp = cp;
    if (i != resumed) this_cp.resume.clear();
    summaries.push_back(run_variant(scene, variant, c.model, in, dir, progress, this_cp));
    if (summaries.back().interrupted) return summaries;  // the user asked to stop: no further variant
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
  for (const std::string& w : s.warnings) o << "  warning: " << w << "\n";
  for (const auto& [k, v] : s.values) {
    std::snprintf(line, sizeof line, "  %-44s %12.5g\n", k.c_str(), v);
    o << line;
  }
  return o.str();
}

}  // namespace leg
