#include "bench/msd_runner.hpp"

#include "bench/shared_io.hpp"
#include "tbio/surface_check.hpp"

#include "tbio/checkpoint.hpp"
#include "tbio/json.hpp"
#include "msd/io/interrupt.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <cmath>

namespace bench {

const MsdSpec& msd_section(const Spec& spec) {
  if (!spec.msd || !spec.mesh)
    throw msd::Error(spec.path + ": the msd solver needs 'mesh' and 'msd' sections in the spec");
  const Loading t = spec.loading.type;
  if (t == Loading::CooksMembrane)
    throw msd::Error(spec.path + ": loading.type 'cooks_membrane' is a plane-strain benchmark for the fem solver only");
  if (t == Loading::SimpleShear && spec.loading.boundary != "platens")
    throw msd::Error(spec.path + ": loading.boundary 'homogeneous' is for the fem solver only (msd shears between platens)");
  return *spec.msd;
}

msd::TriangleMesh make_surface(const GeometrySpec& g) {
  if (g.shape == "cylinder") return msd::make_cylinder(g.radius, g.height, g.segments);
  if (g.shape == "box") return msd::make_box(msd::Vec3::Zero(), g.size);
  if (g.shape == "obj") {  // .obj, .stl or .ply: closed, and not crossing itself
    msd::TriangleMesh m = msd::read_surface(g.file);
    msd::validate_closed_surface(m, g.file);
    tbio::refuse_intersections({{&m, g.file}}, {});
    return m;
  }
  if (g.shape == "cooks_membrane")
    throw msd::Error("geometry.shape: cooks_membrane is a plane-strain benchmark for the fem solver only");
  throw msd::Error("geometry.shape: unsupported shape '" + g.shape + "'");
}

msd::SampleMesh make_sample_mesh(const Spec& spec) {
  msd_section(spec);
  const MeshSpec& mesh = *spec.mesh;
  msd::SampleMeshOptions o;
  o.spacing = mesh.spacing;
  o.rule = msd::parse_cube_rule(mesh.rule);
  o.origin = mesh.origin;
  o.max_cubes = mesh.max_cubes;
  o.memory.bytes = 1e9 * mesh.memory_limit_gb;
  o.memory.how_to_raise = "mesh.memory_limit_gb in " + spec.path;
  o.memory.context = spec.path + ": mesh.spacing " + tbio::json_number(mesh.spacing) + " m: ";
  o.solid_bytes_per_cube = msd::kRunBytesPerCube;
  const std::string name = spec.geometry.shape == "obj" ? spec.geometry.file
                                                        : spec.path + ": geometry";
  return msd::mesh_closed_surface(make_surface(spec.geometry), o, name);
}

msd::TissueMaterial make_material(const Spec& spec) {
  const MsdSpec& ms = msd_section(spec);
  msd::TissueMaterial m;
  m.density = spec.material.density;
  m.lumping = ms.mass_lumping == "equal" ? msd::MassLumping::EqualPerNode
                                               : msd::MassLumping::PerTet;
  m.repulsion_floor = ms.repulsion_floor;
  if (ms.constants == "raw") {
    m.mode = msd::ConstantsMode::Raw;
    m.k_s = ms.k_s;
    m.k_d = ms.k_d;
    m.k_r = ms.k_r;
    m.k_v = ms.k_v;
  } else {
    m.mode = msd::ConstantsMode::Physical;
    m.youngs_modulus = spec.material.youngs_modulus.value_or(0.0);
    m.damping_time = ms.damping_time.value_or(spec.material.damping_time.value_or(0.0));
    m.stiffness_scale = ms.stiffness_scale;
    m.repulsion_factor = ms.repulsion_factor;
    m.volume_factor = ms.volume_factor;
    m.bulk_factor = ms.bulk_factor;
    m.zero_length_springs = ms.zero_length_springs;
    m.poisson_ratio = spec.material.poisson_ratio;
  }
  m.edge_laws = ms.edge_laws;
  msd::check_material(m, spec.path + ": material");
  return m;
}

MsdProblem compile_msd(const Spec& spec) {
  const MsdSpec& ms = msd_section(spec);
  const LoadingSpec& l = spec.loading;
  // Paths: strain (uniaxial), shear strain (simple_shear), load factor (static);
  // vibration holds its loads (gravity, if any) at factor 1.
  std::vector<std::pair<double, double>> path = l.path;
  if (l.type == Loading::Vibration) {
    // Load factor: gravity (if any) throughout; a preload ramps smoothly over
    // the first half of [0, release], holds, and is removed at the release.
    path = {{0.0, 1.0}, {l.release + l.duration, 1.0}};
    if (l.initial == "preload") path = preload_path(l);
  }
  MsdProblem p{make_sample_mesh(spec), {}, msd::LoadingPath(path, spec.path + ": loading.path"), {}, l.type,
               {}, {}, {}, {}, 0.0, {}, false, {}};
  msd::ModelOptions o;
  o.terms = 0;
  for (const auto& t : ms.terms) o.terms |= msd::parse_force_term(t);
  if (l.gravity.squaredNorm() > 0.0) o.terms |= msd::kGravity;
  o.gravity = l.gravity;
  o.nonlinear_threshold = ms.nonlinear_threshold;
  o.threads = ms.threads;
  o.newton = {ms.newton_tolerance, ms.newton_max_iterations, ms.newton_max_step_cuts, ms.newton_reuse_factorization,
              msd::parse_linear_solver(ms.newton_linear_solver), ms.newton_keep_orientation, ms.newton_anderson_depth};
  o.reference_forces = ms.forces == "reference";
  const bool bulk = o.terms & msd::kBulk;
  if (ms.continuum_volume == "per_cube" || bulk) {
    if (p.sample.info.tet_cube_id.size() != p.sample.mesh.tets.size())
      throw msd::Error(spec.path + (bulk ? ": msd.terms: the bulk term" : ": msd.continuum_volume: per_cube") +
                       " needs the lattice's cubes, and this mesh has none");
    o.volume_group = p.sample.info.tet_cube_id;
  }
  o.region_materials.assign(1, make_material(spec));
  const msd::TetMesh& mesh = p.sample.mesh;
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
  p.size = (hi - lo).maxCoeff();
  switch (l.type) {
    case Loading::Uniaxial:
      p.platens = msd::add_platens(mesh, msd::parse_platen_contact(l.platens), o);
      break;
    case Loading::SimpleShear:
      p.platens = msd::add_platens(mesh, msd::PlatenContact::Bonded, o);
      break;
    case Loading::Static:
      p.clamp = msd::add_clamp(mesh, msd::parse_face(l.fixed), o);
      if (!l.traction_face.empty())
        o.external_force = msd::face_load(mesh, msd::face_nodes(mesh, msd::parse_face(l.traction_face)), l.traction);
      break;
    case Loading::Vibration:
      p.clamp = msd::add_clamp(mesh, msd::Face::Bottom, o);
      if (l.initial == "preload")
        o.external_force = msd::face_load(mesh, msd::face_nodes(mesh, msd::parse_face(l.traction_face)), l.traction);
      break;
    case Loading::Indentation: {
      msd::IndenterOptions ind;
      ind.radius = l.indenter_radius;
      ind.axis = l.indenter_axis == "x" ? 0 : 1;
      ind.max_depth = l.indenter_depth;
      ind.response = msd::parse_contact_response(l.indenter_response);
      p.indenter = msd::add_indenter(mesh, ind, o);
      break;
    }
    case Loading::CooksMembrane:
      throw msd::Error(spec.path + ": loading.type '" + loading_name(l.type) + "' is not supported by the msd solver");
  }
  p.columns = series_columns(l.type, Solver::Msd);
  p.model = msd::build_model(mesh, o);
  p.initial = l.type == Loading::Vibration && l.initial != "preload"
                  ? msd::displaced_state(p.model, l.initial == "axial_mode", l.amplitude)
                  : msd::rest_state(p.model);
  if (l.type == Loading::Vibration) {
    // The clamped base must start at rest with the field it prescribes (zero).
    for (int n : p.model.groups.at(static_cast<size_t>(p.clamp.clamp_group)).nodes)
      p.initial.x.col(n) = p.model.rest_positions.col(n);
  }
  p.cvode = ms.integrator == "cvode";
  if (p.cvode && !p.model.obstacles.empty())
    throw msd::Error(spec.path + ": msd.integrator 'cvode' cannot integrate contact with a rigid obstacle (the thesis' "
                                 "response is a position projection, not an ODE); use a fixed-step integrator");
  p.stepping.dt = p.cvode ? spec.output.interval : ms.dt;
  p.stepping.integrator = p.cvode ? msd::Integrator::SymplecticEuler : msd::parse_integrator(ms.integrator);
  p.stepping.output_interval = spec.output.interval;
  p.cvode_options.rtol = ms.rtol;
  p.cvode_options.atol_position = ms.atol;
  p.cvode_options.time_scale = spec.output.interval;
  p.cvode_options.output_interval = spec.output.interval;
  if (!p.cvode && spec.output.interval < ms.dt)
    throw msd::Error(spec.path + ": output.interval (" + std::to_string(spec.output.interval) +
                     " s) is shorter than msd.dt (" + std::to_string(ms.dt) + " s)");
  return p;
}

msd::ExperimentHooks msd_hooks(const MsdProblem& p, const std::function<bool(const std::vector<double>&)>& row,
                               const std::function<void(const msd::State&)>& frame) {
  msd::ExperimentHooks h;
  switch (p.loading) {
    case Loading::Uniaxial:
      h.controls = [&p](double t) { return msd::uniaxial_controls(p.model, p.platens, p.path, t); };
      h.sample = [&p, row, frame](const msd::State& st, msd::Scratch& sc) {
        if (frame) frame(st);
        const msd::UniaxialSample x = msd::measure_uniaxial(p.model, p.platens, st, sc);
        return row(series_row(p.columns, {{"time", x.time},
                                          {"strain", x.strain},
                                          {"nominal_stress", x.nominal_stress},
                                          {"volume_ratio", x.volume_ratio},
                                          {"inverted_elements", static_cast<double>(x.inverted_elements)},
                                          {"lateral_force", x.lateral_force},
                                          {"kinetic_energy", x.kinetic_energy},
                                          {"nonlinear_active_elements", static_cast<double>(x.nonlinear_active)}}));
      };
      break;
    case Loading::SimpleShear:
      h.controls = [&p](double t) { return msd::shear_controls(p.model, p.platens, p.path, t); };
      h.sample = [&p, row, frame](const msd::State& st, msd::Scratch& sc) {
        if (frame) frame(st);
        const msd::ShearSample x = msd::measure_shear(p.model, p.platens, st, sc);
        return row(series_row(p.columns, {{"time", x.time},
                                          {"shear_strain", x.shear_strain},
                                          {"shear_stress", x.shear_stress},
                                          {"normal_stress_zz", x.normal_stress},
                                          {"volume_ratio", x.volume_ratio},
                                          {"inverted_elements", static_cast<double>(x.inverted_elements)},
                                          {"kinetic_energy", x.kinetic_energy}}));
      };
      break;
    case Loading::Indentation:
      h.controls = [&p](double t) { return msd::indentation_controls(p.model, p.indenter, p.path, t); };
      h.sample = [&p, row, frame](const msd::State& st, msd::Scratch& sc) {
        if (frame) frame(st);
        const msd::IndentationSample x = msd::measure_indentation(p.model, p.indenter, p.path, st, sc);
        return row(series_row(p.columns, {{"time", x.time},
                                          {"depth", x.depth},
                                          {"indentation_force", x.force},
                                          {"contact_nodes", static_cast<double>(x.contact_nodes)},
                                          {"base_reaction_z", x.base_reaction},
                                          {"volume_ratio", x.volume_ratio},
                                          {"inverted_elements", static_cast<double>(x.inverted_elements)},
                                          {"kinetic_energy", x.kinetic_energy}}));
      };
      break;
    case Loading::Vibration:
      h.controls = [&p](double t) { return msd::clamp_controls(p.model, p.path, t); };
      h.sample = [&p, row, frame](const msd::State& st, msd::Scratch& sc) {
        if (frame) frame(st);
        const msd::ClampSample x = msd::measure_clamp(p.model, p.clamp, p.path, st, sc);
        return row(series_row(p.columns, {{"time", x.time},
                                          {"tip_displacement", x.probe_displacement.z()},
                                          {"kinetic_energy", x.kinetic_energy},
                                          {"volume_ratio", x.volume_ratio},
                                          {"inverted_elements", static_cast<double>(x.inverted_elements)}}));
      };
      break;
    case Loading::Static:
      h.controls = [&p](double t) { return msd::clamp_controls(p.model, p.path, t); };
      h.sample = [&p, row, frame](const msd::State& st, msd::Scratch& sc) {
        if (frame) frame(st);
        const msd::ClampSample x = msd::measure_clamp(p.model, p.clamp, p.path, st, sc);
        return row(series_row(p.columns, {{"time", x.time},
                                          {"load_factor", x.load_factor},
                                          {"tip_displacement_x", x.probe_displacement.x()},
                                          {"tip_displacement_y", x.probe_displacement.y()},
                                          {"tip_displacement_z", x.probe_displacement.z()},
                                          {"reaction_force_x", x.reaction.x()},
                                          {"reaction_force_y", x.reaction.y()},
                                          {"reaction_force_z", x.reaction.z()},
                                          {"volume_ratio", x.volume_ratio},
                                          {"inverted_elements", static_cast<double>(x.inverted_elements)},
                                          {"kinetic_energy", x.kinetic_energy}}));
      };
      break;
    case Loading::CooksMembrane:
      throw msd::Error("msd_hooks: loading cooks_membrane is for the fem solver only");
  }
  return h;
}

std::vector<std::pair<std::string, double>> material_record(const Spec& spec,
                                                            const msd::Model& model) {
  msd_section(spec);
  const msd::TissueMaterial& m = model.region_materials.at(0);
  std::vector<std::pair<std::string, double>> r{{"density", m.density},
                                                {"repulsion_floor", m.repulsion_floor},
                                                {"nonlinear_threshold", model.nonlinear_threshold},
                                                {"mesh_spacing", spec.mesh->spacing},
                                                {"total_mass", model.mass.sum()}};
  if (m.mode == msd::ConstantsMode::Raw) {
    r.insert(r.end(), {{"k_s", m.k_s}, {"k_d", m.k_d}, {"k_r", m.k_r}, {"k_v", m.k_v}});
  } else {
    r.insert(r.end(), {{"youngs_modulus", m.youngs_modulus},
                       {"damping_time", m.damping_time},
                       {"stiffness_scale", m.stiffness_scale},
                       {"lattice_factor", msd::kLatticeStiffnessFactor},
                       {"repulsion_factor", m.repulsion_factor},
                       {"volume_factor", m.volume_factor}});
    // Range of the per-element constants the physical rule produced.
    double ks_min = 1e300, ks_max = 0.0;
    for (const auto& el : model.elements)
      for (double k : el.k.k_s) {
        ks_min = std::min(ks_min, k);
        ks_max = std::max(ks_max, k);
      }
    r.insert(r.end(), {{"k_s_min", ks_min}, {"k_s_max", ks_max}});
  }
  if (spec.material.poisson_ratio) r.emplace_back("poisson_ratio", *spec.material.poisson_ratio);
  if (model.terms & msd::kBulk && !model.volume_groups.bulk_law.empty()) {
    const msd::BulkLaw& law = model.volume_groups.bulk_law.front();
    r.emplace_back("lattice_bulk_factor", m.bulk_factor);
    if (law.neo_hookean)  // its modulus is lambda, the rest modulus mu (bulk_volume.hpp)
      r.insert(r.end(), {{"lattice_zero_length_springs", 1.0}, {"lattice_lambda", law.modulus}, {"lattice_rest_modulus", law.rest_modulus}});
    else
      r.emplace_back("lattice_bulk_modulus", law.modulus);
  }
  if (!m.thesis_springs())
    for (int c = 0; c < msd::kEdgeClasses; ++c) {
      const msd::SpringLaw& law = m.edge_laws[static_cast<size_t>(c)];
      const std::string name = std::string("edge_") + msd::to_string(static_cast<msd::EdgeClass>(c));
      r.insert(r.end(), {{name + "_stiffness", law.stiffness},
                         {name + "_tension_exponent", law.tension_exponent},
                         {name + "_compression_exponent", law.compression_exponent}});
    }
  return r;
}

namespace {

// A field of /proc/self/status in MB (VmRSS: resident now, VmHWM: peak); NaN
// where the file does not exist.
double proc_status_mb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string k = std::string(key) + ":";
  while (std::getline(in, line))
    if (line.rfind(k, 0) == 0) return std::stod(line.substr(k.size())) / 1024.0;  // kB
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

SummaryColumns summary_columns(Loading loading, const std::vector<SeriesColumn>& columns) {
  const LoadingInfo& info = loading_info(loading);
  return {column_index(columns, info.strain_column), column_index(columns, info.stress_column),
          column_index(columns, "volume_ratio"), column_index(columns, "inverted_elements")};
}

void track_row(RunSummary& s, const SummaryColumns& c, const std::vector<double>& row) {
  auto widen = [&](int k, double& lo, double& hi) {
    if (k >= 0) {
      lo = std::min(lo, row[static_cast<size_t>(k)]);
      hi = std::max(hi, row[static_cast<size_t>(k)]);
    }
  };
  widen(c.strain, s.min_strain, s.max_strain);
  widen(c.stress, s.min_stress, s.max_stress);
  widen(c.volume_ratio, s.min_volume_ratio, s.max_volume_ratio);
  if (c.inverted_elements >= 0)
    s.max_inverted = std::max(s.max_inverted, static_cast<int>(row[static_cast<size_t>(c.inverted_elements)]));
}

std::string checkpoint_path_for(const std::string& out_path) { return out_path + ".checkpoint"; }

namespace {

// What a checkpoint of an MSD run holds besides the results written so far.
struct MsdCheckpoint {
  msd::LoopPosition at;
  double next_frame = 0.0;
  msd::State state;
  tbio::ResultsSnapshot results;
};

// The inputs a checkpoint must match: the spec's text and the constants the
// run used (a calibration changes them), the mesh by the model's fingerprint.
std::string run_input_hash(const Spec& spec, const MsdProblem& p) {
  std::ostringstream o;
  o << "run\n" << spec.text << "\n";
  o.precision(17);
  for (const auto& [k, v] : material_record(spec, p.model)) o << k << "=" << v << "\n";
  o << "dt=" << p.stepping.dt << " interval=" << p.stepping.output_interval << " integrator="
    << msd::to_string(p.stepping.integrator) << "\n";
  return sha256_hex(o.str());
}

MsdCheckpoint read_msd_checkpoint(const std::string& path, const Spec& spec, const MsdProblem& p) {
  tbio::CheckpointReader r(path, "run", run_input_hash(spec, p), tbio::fingerprint(p.model.rest_positions, p.model.mass));
  MsdCheckpoint c;
  c.at.step = r.integer();
  c.at.outputs = r.integer();
  c.next_frame = r.number();
  c.state = r.state();
  c.results = r.snapshot();
  r.finish();
  if (c.state.x.cols() != p.model.num_nodes() || c.state.v.cols() != p.model.num_nodes())
    throw msd::Error(path + ": the checkpoint's state does not match the model");
  return c;
}

void check_checkpointing(const Spec& spec, const MsdProblem& p, const Checkpointing& cp) {
  if (!(cp.every >= 0.0) || !std::isfinite(cp.every))
    throw msd::Error("--checkpoint-every: must be a finite number of simulated seconds > 0");
  if ((cp.every > 0.0 || !cp.resume.empty()) && p.cvode)
    throw msd::Error(spec.path + ": msd.integrator 'cvode' cannot be checkpointed or resumed bit-identically (its "
                                 "step size, order and history live inside CVODE); use a fixed-step integrator");
}

RunMeta msd_meta(const Spec& spec, const MsdProblem& p) {
  const MsdSpec& ms = *spec.msd;
  RunMeta meta;
  meta.solver = "msd";
  meta.spec_text = spec.text;
  meta.spec_path = spec.path;
  meta.spec_name = spec.name;
  meta.material = material_record(spec, p.model);
  meta.text = {{"terms", msd::force_terms_to_string(p.model.terms)},
               {"integrator", p.cvode ? "cvode (BDF, rtol " + std::to_string(ms.rtol) + ", atol " +
                                            std::to_string(ms.atol) + " m)"
                                      : msd::to_string(p.stepping.integrator)},
               {"mass_lumping", ms.mass_lumping},
               {"continuum_volume", p.model.terms & msd::kNeoHookean ? ms.continuum_volume : "none"},
               {"mesh_rule", spec.mesh->rule},
               {"test", test_label(spec.loading.type, spec.loading.platens)}};
  if (!spec.msd->calibration.empty()) meta.text.emplace_back("calibration", spec.msd->calibration);
  return meta;
}

RunSummary start_summary(const Spec& spec, const MsdProblem& p, const std::string& out_path) {
  RunSummary s;
  s.name = spec.name;
  s.loading = spec.loading.type;
  s.out_path = out_path;
  s.nodes = p.model.num_nodes();
  s.tets = p.model.num_elements();
  s.cubes = p.sample.cubes;
  s.min_strain = s.min_stress = 1e300;
  s.max_strain = s.max_stress = -1e300;
  s.min_volume_ratio = 1e300;
  s.max_volume_ratio = -1e300;
  return s;
}

void add_node_set(ResultsWriter& out, const MsdProblem& p) {
  std::vector<std::array<double, 3>> pts;
  for (int n = 0; n < p.model.num_nodes(); ++n)
    pts.push_back({{p.model.rest_positions(0, n), p.model.rest_positions(1, n), p.model.rest_positions(2, n)}});
  std::vector<std::vector<int>> tets;
  for (const auto& t : p.sample.mesh.tets) tets.push_back({t[0], t[1], t[2], t[3]});
  out.add_point_set("nodes", pts, tets);
}

// The end of a run: ring-down metrics, timing, then the status (a write
// failure while finishing leaves nothing and says so).
void finish_msd_file(ResultsWriter& out, RunSummary& s, const Spec& spec, const MsdProblem& p,
                     const std::vector<double>& times, const std::vector<double>& tip, double rss_start,
                     std::clock_t cpu_start) {
  try {
    if (loading_info(p.loading).ring_down) {
      const RingDown rd = analyse_ring_down_after(times, tip, spec.loading.release);  // from the release
      s.highlights = {{"f1_Hz", rd.frequency}, {"zeta", rd.damping_ratio}};
      out.set_metric("first_frequency", rd.frequency);
      out.set_metric("damping_ratio", rd.damping_ratio);
      out.set_metric("zero_crossings", rd.crossings);
    }
    out.set_timing(s.wall_seconds, s.steps, p.stepping.dt, 1);
    if (msd::is_implicit(p.stepping.integrator) && !p.cvode) {
      out.set_timing_detail("newton_iterations", static_cast<double>(s.newton_iterations));
      out.set_timing_detail("step_cuts", static_cast<double>(s.step_cuts));
      out.set_timing_detail("factorizations", static_cast<double>(s.factorizations));
    }
    out.set_timing_detail("cpu_seconds", static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    // Memory of the run: the process peak and the peak above the resident size
    // before the model was built (the model, its state and the results buffers).
    const double hwm = proc_status_mb("VmHWM");
    out.set_timing_detail("peak_rss_mb", hwm);
    out.set_timing_detail("model_rss_mb", hwm - rss_start);
    if (s.complete) {
      out.finish();
      return;
    }
  } catch (const tbio::WriteError& e) {
    s.complete = false;
    s.failure = s.failure.empty() ? e.what() : s.failure + "; then " + e.what();
  }
  s.kept = out.fail(s.failure);
}

}  // namespace

RunSummary run_msd(const Spec& spec, const std::string& out_path, const Progress& progress, const Checkpointing& cp) {
  const double rss_start = proc_status_mb("VmRSS");
  MsdProblem p = compile_msd(spec);  // every input error surfaces here, before any file exists
  check_checkpointing(spec, p, cp);
  std::optional<MsdCheckpoint> resumed;
  if (!cp.resume.empty()) resumed = read_msd_checkpoint(cp.resume, spec, p);
  const std::string cp_path = cp.path.empty() ? checkpoint_path_for(out_path) : cp.path;
  const auto parent = std::filesystem::path(out_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);

  ResultsWriter out(out_path, msd_meta(spec, p), p.columns);
  const msd::InterruptibleSection interruptible;  // SIGINT/SIGTERM: stop at the next step, mark the file
  out.set_meta("mesh_counts", "nodes " + std::to_string(p.model.num_nodes()) + ", tets " +
                                  std::to_string(p.model.num_elements()) + ", cubes " +
                                  std::to_string(p.sample.cubes));
  RunSummary s = start_summary(spec, p, out_path);
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const double end = p.path.end_time();
  const LoadingInfo& info = loading_info(p.loading);
  const SummaryColumns tracked = summary_columns(p.loading, p.columns);
  const int c_ring_down = info.ring_down ? column_index(p.columns, info.load_series) : -1;
  std::vector<double> times, tip;
  const auto note_row = [&](const std::vector<double>& r) {
    track_row(s, tracked, r);
    if (c_ring_down >= 0) {
      times.push_back(r[0]);
      tip.push_back(r[static_cast<size_t>(c_ring_down)]);
    }
    s.simulated_seconds = r[0];
  };
  add_node_set(out, p);  // /fields: every node's displacement at the field frames
  double next_frame = 0.0, next_checkpoint = cp.every;
  if (resumed) {
    out.set_meta("resumed_from", cp.resume + " at t = " + tbio::json_number(resumed->state.t) + " s");
    out.restore(resumed->results);
    for (const auto& r : resumed->results.rows) note_row(r);
    next_frame = resumed->next_frame;
    if (cp.every > 0.0) next_checkpoint = (std::floor(resumed->state.t / cp.every + 1e-9) + 1.0) * cp.every;
  }
  const auto frame = [&](const msd::State& st) {
    if (st.t < next_frame - 1e-9 * p.stepping.dt) return;
    std::vector<std::array<double, 3>> d(static_cast<size_t>(p.model.num_nodes()));
    for (int n = 0; n < p.model.num_nodes(); ++n)
      for (int c = 0; c < 3; ++c) d[static_cast<size_t>(n)][static_cast<size_t>(c)] = st.x(c, n) - p.model.rest_positions(c, n);
    out.append_frame("nodes", st.t, d);
    next_frame = st.t + spec.output.fields_interval;
  };
  const std::string input_hash = run_input_hash(spec, p);
  const std::string model_hash = tbio::fingerprint(p.model.rest_positions, p.model.mass);
  msd::RunStats stats;
  try {
    msd::ExperimentHooks hooks = msd_hooks(p, [&](const std::vector<double>& r) {
      out.append(r);
      note_row(r);
      if (progress) progress(r[0], end);
      return true;
    }, frame);
    if (cp.every > 0.0)
      hooks.after_sample = [&](const msd::State& st, long k, long outputs) {
        if (st.t < next_checkpoint - 1e-9 * p.stepping.dt || k == 0) return;
        tbio::CheckpointWriter w("run", input_hash, model_hash);
        w.integer(k);
        w.integer(outputs);
        w.number(next_frame);
        w.state(st);
        w.snapshot(out.snapshot());
        w.save(cp_path);
        next_checkpoint = (std::floor(st.t / cp.every + 1e-9) + 1.0) * cp.every;
      };
    stats = resumed ? msd::run_experiment(p.model, resumed->state, end, p.size, p.stepping, hooks, &resumed->at)
                    : integrate_msd(p, hooks);
    s.complete = true;
  } catch (const msd::SimulationFailure& f) {
    s.failure = f.what();
    s.steps = f.step;
    if (const auto* i = dynamic_cast<const msd::Interrupted*>(&f)) s.interrupted = i->signal;
  } catch (const msd::Error& e) {  // a write failure (results or checkpoint): stop, keep what can be kept
    s.failure = e.what();
  }
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (s.complete) s.steps = stats.steps;
  s.newton_iterations = stats.newton_iterations;
  s.step_cuts = stats.step_cuts;
  s.factorizations = stats.factorizations;
  finish_msd_file(out, s, spec, p, times, tip, rss_start, cpu_start);
  std::error_code ignore;
  // A completed run's checkpoint (written now, or resumed from) is of no more use.
  const bool resumed_here = !cp.resume.empty() && std::filesystem::equivalent(cp.resume, cp_path, ignore);
  if (s.complete && (cp.every > 0.0 || resumed_here)) std::filesystem::remove(cp_path, ignore);
  return s;
}

msd::RunStats integrate_msd(const MsdProblem& p, const msd::ExperimentHooks& hooks) {
  const double end = p.path.end_time();
  if (!p.cvode) return msd::run_experiment(p.model, p.initial, end, p.size, p.stepping, hooks);
  const CvodeStats c = run_experiment_cvode(p.model, p.initial, end, p.size, p.cvode_options, hooks);
  msd::RunStats r;
  r.steps = c.steps;
  r.simulated_seconds = c.simulated_seconds;
  return r;
}

}  // namespace bench
