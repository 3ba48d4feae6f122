#include "bench/fem_runner.hpp"

#include "bench/shared_io.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>

namespace bench {

namespace fs = std::filesystem;

fem::NeoHookean fem_material(const Spec& spec) {
  const MaterialSpec& m = spec.material;
  if (m.shear_modulus && m.bulk_modulus) return {*m.shear_modulus, *m.bulk_modulus, m.density};
  if (m.youngs_modulus && m.poisson_ratio) return fem::neo_hookean_from(*m.youngs_modulus, *m.poisson_ratio, m.density);
  throw msd::Error(spec.path + ": the fem solver needs material.youngs_modulus and material.poisson_ratio "
                               "(or shear_modulus and bulk_modulus)");
}

namespace {

double length_along_z(const Spec& spec) {
  if (spec.geometry.shape == "cylinder") return spec.geometry.height;
  if (spec.geometry.shape == "box") return spec.geometry.size.z();
  throw msd::Error(spec.path + ": loading.type '" + loading_name(spec.loading.type) + "' needs a box or cylinder geometry");
}

// Report times: every output interval from 0 to the end of the path, plus the
// path's way-points (so extremes are hit exactly).
std::vector<double> report_times(const Spec& spec) {
  const double end = spec.loading.path.back().first, dt = spec.output.interval;
  std::vector<double> t;
  const long n = std::lround(std::floor(end / dt + 1e-9));
  for (long k = 1; k <= n; ++k) t.push_back(k * dt);
  for (const auto& p : spec.loading.path)
    if (p.first > 0.0) t.push_back(p.first);
  std::sort(t.begin(), t.end());
  std::vector<double> out;
  for (double v : t)
    if (out.empty() || v - out.back() > 1e-9 * dt) out.push_back(v);
  return out;
}

fem::Path path_of(const Spec& spec) {
  fem::Path p;
  p.points = spec.loading.path;
  return p;
}

// The face number of a box face name (left right front back bottom top: 0-5).
int face_id(const std::string& name) {
  const std::vector<std::string> names{"left", "right", "front", "back", "bottom", "top"};
  return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
}

// Material, element, nonlinear solver and output settings of the spec.
fem::Problem solver_settings(const Spec& spec, const std::string& vtu_directory) {
  fem::Problem p;
  const FemSpec& f = spec.fem;
  p.material = fem_material(spec);
  p.degree = f.degree;
  p.formulation = f.formulation == "displacement" ? fem::Formulation::Displacement : fem::Formulation::ThreeField;
  p.linear_solver = f.linear_solver == "amg" ? fem::LinearSolver::Amg : fem::LinearSolver::Direct;
  p.newton.residual_tolerance = f.residual_tolerance;
  p.newton.increment_tolerance = f.increment_tolerance;
  p.newton.max_iterations = f.max_iterations;
  p.newton.max_cuts = f.max_cuts;
  p.max_increment = f.max_increment;
  p.gravity = {{spec.loading.gravity.x(), spec.loading.gravity.y(), spec.loading.gravity.z()}};
  p.vtu_directory = vtu_directory;
  p.vtu_basename = spec.name;
  p.fields_interval = spec.output.fields_interval;
  return p;
}

// Geometry and coarse mesh: by default about mesh.spacing (or 1 cm) per cell.
fem::MeshSpec coarse_mesh(const Spec& spec) {
  const FemSpec& f = spec.fem;
  const GeometrySpec& g = spec.geometry;
  const double h = spec.mesh ? spec.mesh->spacing : 0.01;
  auto cells_for = [&](double len) { return static_cast<unsigned>(std::max(1L, std::lround(len / h))); };
  fem::MeshSpec m;
  m.refinement = f.refinement;
  if (g.shape == "box") {
    m.shape = fem::MeshSpec::Shape::Box;
    m.size = {{g.size.x(), g.size.y(), g.size.z()}};
    m.cells = f.cells.value_or(std::array<unsigned, 3>{{cells_for(g.size.x()), cells_for(g.size.y()),
                                                        cells_for(g.size.z())}});
  } else if (g.shape == "cylinder") {
    m.shape = fem::MeshSpec::Shape::Cylinder;
    m.radius = g.radius;
    m.height = g.height;
    m.cells = f.cells.value_or(std::array<unsigned, 3>{
        {1, 1, static_cast<unsigned>(std::max(1L, std::lround(g.height / g.radius)))}});
  } else if (g.shape == "cooks_membrane") {
    m.shape = fem::MeshSpec::Shape::CooksMembrane;
    m.cells = f.cells.value_or(std::array<unsigned, 3>{{16, 16, 1}});
  } else {
    throw msd::Error(spec.path + ": geometry.shape '" + g.shape + "' is not supported by the fem solver "
                                 "(supported: box, cylinder, cooks_membrane)");
  }
  return m;
}

// Bottom held, top moved along z by strain * L; frictionless platens hold only
// z, with two pins against rigid motion.
void rig_uniaxial(const Spec& spec, fem::Problem& p) {
  const GeometrySpec& g = spec.geometry;
  const double L = length_along_z(spec);
  fem::Dirichlet bottom, top;
  bottom.face = 4;
  top.face = 5;
  top.vector = {{0, 0, L}};
  top.path = path_of(spec);
  if (spec.loading.platens == "frictionless") {
    bottom.mask = top.mask = {{false, false, true}};
    // Pins at vertices on the x axis of the bottom face: the body's centre line
    // and a point on the +x side, free to slide in x.
    const double x1 = g.shape == "box" ? g.size.x() : g.radius;
    p.pins.push_back({{{0.0, 0.0, 0.0}}, {{true, true, false}}});
    p.pins.push_back({{{x1, 0.0, 0.0}}, {{false, true, false}}});
  }
  p.dirichlet = {bottom, top};
  p.reaction_faces = {5, 4};
  p.report_times = report_times(spec);
}

void rig_simple_shear(const Spec& spec, fem::Problem& p) {
  if (spec.geometry.shape != "box") throw msd::Error(spec.path + ": simple_shear needs a box geometry");
  // homogeneous: u = gamma(t) Z e_x on the whole boundary (exactly simple
  // shear); platens: bottom held, top moved along x by gamma H, sides free.
  const std::vector<int> faces = spec.loading.boundary == "homogeneous" ? std::vector<int>{0, 1, 2, 3, 4, 5}
                                                                        : std::vector<int>{4, 5};
  for (int face : faces) {
    fem::Dirichlet d;
    d.face = face;
    d.gradient[0][2] = 1.0;
    d.path = path_of(spec);
    p.dirichlet.push_back(d);
  }
  p.reaction_faces = {5};
  p.report_times = report_times(spec);
}

void rig_cooks_membrane(const Spec& spec, fem::Problem& p) {
  if (spec.geometry.shape != "cooks_membrane")
    throw msd::Error(spec.path + ": loading cooks_membrane needs that geometry");
  fem::Dirichlet clamp;
  clamp.face = 0;
  p.dirichlet = {clamp};
  fem::Traction shear;
  shear.face = 1;
  shear.total_force = {{0.0, spec.loading.force, 0.0}};
  shear.path = path_of(spec);
  p.tractions = {shear};
  p.plane_strain = true;
  p.probes = {{{0.048, 0.060, 0.0}}, {{0.048, 0.052, 0.0}}};
  p.reaction_faces = {0};
  p.report_times = report_times(spec);
}

void rig_static(const Spec& spec, fem::Problem& p) {
  const GeometrySpec& g = spec.geometry;
  const LoadingSpec& l = spec.loading;
  if (g.shape != "box" && g.shape != "cylinder")
    throw msd::Error(spec.path + ": loading static needs a box or cylinder geometry");
  const int fixed_face = face_id(l.fixed);
  if (g.shape == "cylinder" && fixed_face < 4)
    throw msd::Error(spec.path + ": a cylinder has only bottom and top faces to fix");
  fem::Dirichlet clamp;
  clamp.face = fixed_face;
  p.dirichlet = {clamp};
  if (!l.traction_face.empty()) {
    fem::Traction t;
    t.face = face_id(l.traction_face);
    t.total_force = {{l.traction.x(), l.traction.y(), l.traction.z()}};
    t.path = path_of(spec);
    p.tractions = {t};
  }
  p.gravity_path = path_of(spec);
  // Probe: the centre of the face opposite the fixed one.
  const std::array<double, 3> size = g.shape == "box" ? std::array<double, 3>{{g.size.x(), g.size.y(), g.size.z()}}
                                                      : std::array<double, 3>{{0.0, 0.0, g.height}};
  std::array<double, 3> probe = g.shape == "box" ? std::array<double, 3>{{0.5 * size[0], 0.5 * size[1], 0.5 * size[2]}}
                                                 : std::array<double, 3>{{0.0, 0.0, 0.0}};
  const int axis = fixed_face / 2;
  probe[static_cast<size_t>(axis)] = (fixed_face % 2 == 0) ? size[static_cast<size_t>(axis)] : 0.0;
  p.probes = {probe};
  p.reaction_faces = {fixed_face};
  p.report_times = report_times(spec);
}

// Bonded base; a rigid cylinder touching the top face above its centre,
// moved down by depth * path(t); frictionless penalty contact on the top
// face with penalty = contact_penalty * E / h_e.
void rig_indentation(const Spec& spec, fem::Problem& p) {
  const GeometrySpec& g = spec.geometry;
  const LoadingSpec& l = spec.loading;
  fem::Dirichlet base;
  base.face = 4;
  p.dirichlet = {base};
  fem::RigidCylinderContact c;
  c.radius = l.indenter_radius;
  c.axis = l.indenter_axis == "x" ? std::array<double, 3>{{1, 0, 0}} : std::array<double, 3>{{0, 1, 0}};
  c.point = {{0.5 * g.size.x(), 0.5 * g.size.y(), g.size.z() + l.indenter_radius}};
  c.motion = {{0.0, 0.0, -l.indenter_depth}};
  c.path = path_of(spec);
  double h_cell = 1e300;
  for (int a = 0; a < 3; ++a)
    h_cell = std::min(h_cell, g.size[a] / p.mesh.cells[static_cast<size_t>(a)]);
  h_cell /= std::pow(2.0, p.mesh.refinement) * p.degree;
  const double E = 9 * p.material.kappa * p.material.mu / (3 * p.material.kappa + p.material.mu);
  c.penalty = spec.fem.contact_penalty * E / h_cell;
  c.faces = {5};
  p.contacts = {c};
  p.reaction_faces = {4};
  p.report_times = report_times(spec);
}

// Base held; an initial axial mode or stretch, or a preload solved
// quasi-statically and released; then free dynamics (SUNDIALS IDA).
void rig_vibration(const Spec& spec, fem::Problem& p) {
  const GeometrySpec& g = spec.geometry;
  const LoadingSpec& l = spec.loading;
  const double L = length_along_z(spec);
  fem::Dirichlet fixed;
  fixed.face = 4;
  p.dirichlet = {fixed};
  p.dynamic = true;
  p.dynamics.initial = l.initial == "axial_stretch" ? fem::Dynamics::Initial::AxialStretch
                       : l.initial == "preload"     ? fem::Dynamics::Initial::Preload
                                                    : fem::Dynamics::Initial::AxialMode;
  p.dynamics.amplitude = l.amplitude;
  if (l.initial == "preload") {
    fem::Traction t;
    t.face = face_id(l.traction_face);
    t.total_force = {{l.traction.x(), l.traction.y(), l.traction.z()}};
    t.path.points.clear();  // the preload up to the release (solved quasi-statically)
    for (const auto& pt : preload_path(l))
      if (pt.first <= l.release) t.path.points.push_back(pt);
    p.dynamics.preload = {t};
    p.dynamics.release_time = l.release;
  }
  p.dynamics.end_time = l.release + l.duration;
  p.dynamics.rayleigh_mass = spec.fem.rayleigh_mass;
  p.dynamics.rayleigh_stiffness = spec.material.damping_time.value_or(0.0);
  p.dynamics.relative_tolerance = spec.fem.relative_tolerance;
  p.dynamics.absolute_tolerance = spec.fem.absolute_tolerance;
  p.report_interval = spec.output.interval;
  p.probes = {g.shape == "box" ? std::array<double, 3>{{0.5 * g.size.x(), 0.5 * g.size.y(), L}}
                               : std::array<double, 3>{{0.0, 0.0, L}}};
  p.reaction_faces = {4};
}

// The MSD nodes' rest positions, where the solution is evaluated too for the
// displacement-field comparison.
void add_msd_node_probes(const Spec& spec, fem::Problem& p) {
  const msd::SampleMesh sample = make_sample_mesh(spec);
  for (int n = 0; n < sample.mesh.num_nodes(); ++n)
    p.field_probes.push_back({{sample.mesh.nodes(0, n), sample.mesh.nodes(1, n), sample.mesh.nodes(2, n)}});
}

}  // namespace

fem::Problem make_fem_problem(const Spec& spec, const std::string& vtu_directory) {
  fem::Problem p = solver_settings(spec, vtu_directory);
  p.mesh = coarse_mesh(spec);
  switch (spec.loading.type) {
    case Loading::Uniaxial: rig_uniaxial(spec, p); break;
    case Loading::SimpleShear: rig_simple_shear(spec, p); break;
    case Loading::CooksMembrane: rig_cooks_membrane(spec, p); break;
    case Loading::Static: rig_static(spec, p); break;
    case Loading::Indentation: rig_indentation(spec, p); break;
    case Loading::Vibration: rig_vibration(spec, p); break;
  }
  if (spec.mesh && spec.msd && spec.loading.type != Loading::CooksMembrane) add_msd_node_probes(spec, p);
  return p;
}

namespace {

// One results row of a report, in the loading's FEM columns.
std::vector<double> fem_row(const Spec& spec, const msd::LoadingPath& path, const fem::Report& r) {
  const std::vector<SeriesColumn>& columns = series_columns(spec.loading.type, Solver::Fem);
  const double iterations = static_cast<double>(r.newton_iterations);
  switch (spec.loading.type) {
    case Loading::Uniaxial:
      return series_row(columns, {{"time", r.time},
                                  {"strain", path.value(r.time)},
                                  {"nominal_stress", r.reactions[0][2] / r.reaction_areas[0]},
                                  {"volume_ratio", r.volume_ratio},
                                  {"inverted_elements", 0.0},
                                  {"lateral_force", std::hypot(r.reactions[0][0], r.reactions[0][1])},
                                  {"kinetic_energy", 0.0},
                                  {"newton_iterations", iterations},
                                  {"min_jacobian", r.min_jacobian}});
    case Loading::SimpleShear:
      return series_row(columns, {{"time", r.time},
                                  {"shear_strain", path.value(r.time)},
                                  {"shear_stress", r.reactions[0][0] / r.reaction_areas[0]},
                                  {"normal_stress_xx", r.mean_cauchy[0]},
                                  {"normal_stress_yy", r.mean_cauchy[1]},
                                  {"normal_stress_zz", r.mean_cauchy[2]},
                                  {"shear_stress_mean", r.mean_cauchy[4]},
                                  {"volume_ratio", r.volume_ratio},
                                  {"newton_iterations", iterations}});
    case Loading::Static:
      return series_row(columns, {{"time", r.time},
                                  {"load_factor", path.value(r.time)},
                                  {"tip_displacement_x", r.probe_displacements[0][0]},
                                  {"tip_displacement_y", r.probe_displacements[0][1]},
                                  {"tip_displacement_z", r.probe_displacements[0][2]},
                                  {"reaction_force_x", r.reactions[0][0]},
                                  {"reaction_force_y", r.reactions[0][1]},
                                  {"reaction_force_z", r.reactions[0][2]},
                                  {"volume_ratio", r.volume_ratio},
                                  {"newton_iterations", iterations}});
    case Loading::Indentation:
      // The force the cylinder exerts on the body, along the indenting direction -z.
      return series_row(columns, {{"time", r.time},
                                  {"depth", spec.loading.indenter_depth * path.value(r.time)},
                                  {"indentation_force", -r.contact_forces[0][2]},
                                  {"base_reaction_z", r.reactions[0][2]},
                                  {"max_penetration", r.contact_penetrations[0]},
                                  {"stored_energy", r.stored_energy},
                                  {"volume_ratio", r.volume_ratio},
                                  {"newton_iterations", iterations},
                                  {"min_jacobian", r.min_jacobian}});
    case Loading::CooksMembrane:
      return series_row(columns, {{"time", r.time},
                                  {"load_factor", path.value(r.time)},
                                  {"tip_displacement", r.probe_displacements[0][1]},
                                  {"mid_edge_displacement", r.probe_displacements[1][1]},
                                  {"volume_ratio", r.volume_ratio},
                                  {"newton_iterations", iterations}});
    case Loading::Vibration:
      return series_row(columns, {{"time", r.time},
                                  {"tip_displacement", r.probe_displacements[0][2]},
                                  {"kinetic_energy", r.kinetic_energy},
                                  {"volume_ratio", r.volume_ratio}});
  }
  throw msd::Error("fem_row: not a Loading value");
}

// /meta of an FEM results file: the material constants used and the method.
RunMeta fem_meta(const Spec& spec, const fem::Problem& problem) {
  const fem::NeoHookean& mat = problem.material;
  RunMeta meta;
  meta.solver = "fem";
  meta.spec_text = spec.text;
  meta.spec_path = spec.path;
  meta.spec_name = spec.name;
  meta.material = {{"density", mat.density},
                   {"shear_modulus", mat.mu},
                   {"bulk_modulus", mat.kappa},
                   {"youngs_modulus", 9 * mat.kappa * mat.mu / (3 * mat.kappa + mat.mu)},
                   {"poisson_ratio", (3 * mat.kappa - 2 * mat.mu) / (2 * (3 * mat.kappa + mat.mu))},
                   {"rayleigh_stiffness", problem.dynamics.rayleigh_stiffness},
                   {"rayleigh_mass", problem.dynamics.rayleigh_mass}};
  meta.text = {{"formulation", spec.fem.formulation},
               {"strain_energy", "mu/2 (J^(-2/3) I1 - 3) + kappa/4 (J^2 - 1 - 2 ln J)"},
               {"element", "Q" + std::to_string(spec.fem.degree) +
                               (spec.fem.formulation == "three_field"
                                    ? "-P" + std::to_string(spec.fem.degree - 1) + "-P" +
                                          std::to_string(spec.fem.degree - 1) + " (condensed)"
                                    : "")},
               {"linear_solver", spec.fem.linear_solver},
               {"test", test_label(spec.loading.type, spec.loading.platens)}};
  return meta;
}

// The loading's key results from its rows: the ring-down's frequency and
// damping ratio (as metrics too), Cook's membrane's tip displacement.
void add_highlights(const Spec& spec, const std::vector<std::vector<double>>& rows, RunSummary& s,
                    ResultsWriter* writer) {
  const LoadingInfo& info = loading_info(spec.loading.type);
  const std::vector<SeriesColumn>& columns = series_columns(spec.loading.type, Solver::Fem);
  if (spec.loading.type == Loading::CooksMembrane && !rows.empty())
    s.highlights.push_back({"tip_mm", 1e3 * rows.back()[static_cast<size_t>(column_index(columns, "tip_displacement"))]});
  if (info.ring_down) {
    const size_t c = static_cast<size_t>(column_index(columns, info.load_series));
    std::vector<double> times, tip;
    for (const auto& row : rows) {
      times.push_back(row[0]);
      tip.push_back(row[c]);
    }
    const RingDown rd = analyse_ring_down_after(times, tip, spec.loading.release);  // from the release
    s.highlights.push_back({"f1_Hz", rd.frequency});
    s.highlights.push_back({"zeta", rd.damping_ratio});
    if (writer) {
      writer->set_metric("first_frequency", rd.frequency);
      writer->set_metric("damping_ratio", rd.damping_ratio);
      writer->set_metric("zero_crossings", rd.crossings);
    }
  }
}

// The solve's cost and counts in /timing and /meta, then the file's status.
void finish_fem_file(ResultsWriter& writer, const fem::Summary& sum, const RunSummary& s, std::clock_t cpu_start) {
  writer.set_timing(sum.wall_seconds, s.steps, 0.0, 1);
  // This process's CPU time over the solve (what the guard's cost ratio
  // uses: unlike wall time it does not grow when another job shares the core).
  writer.set_timing_detail("cpu_seconds", static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
  writer.set_timing_detail("processes", sum.processes);
  writer.set_timing_detail("dofs", static_cast<double>(sum.dofs));
  writer.set_timing_detail("cells", static_cast<double>(sum.cells));
  writer.set_timing_detail("newton_iterations", sum.newton_iterations);
  writer.set_timing_detail("increment_cuts", sum.cuts);
  writer.set_timing_detail("factorizations", sum.factorizations);
  writer.set_timing_detail("assembly_seconds", sum.assembly_seconds);
  writer.set_timing_detail("linear_solver_seconds", sum.linear_solver_seconds);
  writer.set_meta("mesh_counts", std::to_string(sum.cells) + " cells, " + std::to_string(sum.dofs) + " dofs");
  if (!sum.vtu_files.empty()) writer.set_meta("vtu", sum.vtu_files.front());
  if (s.complete) writer.finish();
  else writer.fail(s.failure);
}

// The FEM's ParaView frames (fem.vtu) go into OUT_vtu.partial-PID (rank 0's
// pid, the same on every process) and that folder is renamed onto OUT_vtu when
// the solve ends, converged or failed, so no reader sees a folder whose frames
// are still being written; an older OUT_vtu is replaced only then (and put
// back if the new one cannot take its place). A run that ends in an error
// (bad input, a write failure) removes the temporary folder.
void commit_vtu_folder(const std::string& tmp, const std::string& final_dir) {
  std::error_code ec, ignore;
  const std::string old = tmp + ".old";  // tmp's name is this run's own
  const bool had_old = fs::exists(final_dir);
  if (had_old) fs::rename(final_dir, old, ec);
  if (!ec) fs::rename(tmp, final_dir, ec);
  if (ec) {
    if (had_old && !fs::exists(final_dir)) fs::rename(old, final_dir, ignore);
    fs::remove_all(tmp, ignore);
    throw msd::Error(final_dir + ": cannot move the finished frames into place (" + ec.message() + ")");
  }
  if (had_old) fs::remove_all(old, ignore);
}

// commit_vtu_folder on rank 0, its outcome on every process: all of them
// throw the same error or none does (they go on to the same next job).
void commit_vtu_folder_everywhere(const std::string& tmp, const std::string& final_dir) {
  fem::Session::barrier();  // every process has written its pieces
  std::string failure;
  if (fem::Session::rank() == 0) {
    try {
      commit_vtu_folder(tmp, final_dir);
    } catch (const msd::Error& e) {
      failure = e.what();
    }
  }
  failure = fem::Session::broadcast(failure);
  if (!failure.empty()) throw msd::Error(failure);
}

}  // namespace

RunSummary run_fem(const Spec& spec, const std::string& out_path, const Progress& progress) {
  const bool root = fem::Session::rank() == 0;
  const fs::path out(out_path);
  const std::string vtu_final = spec.fem.vtu ? (out.parent_path() / (out.stem().string() + "_vtu")).string() : "";
  const std::string vtu_dir =
      vtu_final.empty() ? "" : vtu_final + ".partial-" + std::to_string(fem::Session::root_pid());
  fem::Problem problem;
  try {
    problem = make_fem_problem(spec, vtu_dir);  // input errors surface here
  } catch (const fem::Error& e) {
    throw msd::Error(spec.path + ": " + e.what());
  }
  if (root) {
    if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
    if (!vtu_dir.empty()) {  // a killed run with this pid may have left them
      std::error_code ignore;
      fs::remove_all(vtu_dir, ignore);
      fs::remove_all(vtu_dir + ".old", ignore);
      fs::create_directories(vtu_dir);
    }
  }

  // The results file is created at the first report, so input errors the
  // solver detects while setting up (a pin with no vertex, a face that does not
  // exist) leave nothing behind.
  std::unique_ptr<ResultsWriter> writer;
  const std::vector<SeriesColumn>& columns = series_columns(spec.loading.type, Solver::Fem);
  auto open_writer = [&] {
    if (root && !writer) writer = std::make_unique<ResultsWriter>(out_path, fem_meta(spec, problem), columns);
  };

  RunSummary s;
  s.name = spec.name;
  s.solver = "fem";
  s.loading = spec.loading.type;
  s.out_path = out_path;
  s.min_strain = s.min_stress = s.min_volume_ratio = 1e300;
  s.max_strain = s.max_stress = s.max_volume_ratio = -1e300;
  const SummaryColumns tracked = summary_columns(spec.loading.type, columns);
  std::vector<std::vector<double>> rows;
  bool probes_started = false;
  const msd::LoadingPath path(spec.loading.path, spec.path + ": loading.path");
  fem::Callbacks cb;
  cb.progress = progress;
  cb.on_surface = [&](const fem::Surface& surf) {
    open_writer();
    std::vector<std::vector<int>> tris;
    for (const auto& t : surf.triangles) tris.push_back({t[0], t[1], t[2]});
    if (writer) writer->add_point_set("surface", surf.points, tris);
  };
  cb.on_frame = [&](double t, const std::vector<std::array<double, 3>>& d) {
    if (writer) writer->append_frame("surface", t, d);
  };
  cb.on_probe_frame = [&](double t, const std::vector<std::array<double, 3>>& d) {
    open_writer();
    if (!writer) return;
    if (!probes_started) writer->add_point_set("probes", problem.field_probes);
    probes_started = true;
    writer->append_frame("probes", t, d);
  };
  cb.on_report = [&](const fem::Report& r) {
    open_writer();
    if (!writer) return;
    rows.push_back(fem_row(spec, path, r));
    track_row(s, tracked, rows.back());
    writer->append(rows.back());
    s.simulated_seconds = r.time;
  };

  fem::Summary sum;
  std::error_code ignore_error;
  const std::clock_t cpu_start = std::clock();
  try {
    sum = fem::solve(problem, cb);
    s.complete = true;
  } catch (const fem::SolveError& e) {
    s.failure = e.what();
    sum = e.summary;
    open_writer();  // a failure before the first report still leaves a record
  } catch (const fem::Error& e) {
    if (root && !vtu_dir.empty()) fs::remove_all(vtu_dir, ignore_error);
    throw msd::Error(spec.path + ": " + e.what());
  } catch (...) {  // a write failure in a callback (the results file on a full disk)
    if (root && !vtu_dir.empty()) fs::remove_all(vtu_dir, ignore_error);
    throw;
  }
  if (!vtu_dir.empty()) {
    commit_vtu_folder_everywhere(vtu_dir, vtu_final);
    for (auto& f : sum.vtu_files)
      if (f.rfind(vtu_dir, 0) == 0) f = vtu_final + f.substr(vtu_dir.size());
  }
  s.dofs = sum.dofs;
  s.cells = sum.cells;
  s.steps = static_cast<long>(problem.dynamic ? sum.time_steps : sum.increments);
  s.wall_seconds = sum.wall_seconds;
  add_highlights(spec, rows, s, writer.get());
  if (writer) finish_fem_file(*writer, sum, s, cpu_start);
  return s;
}

bool ensure_fem_reference(const Spec& spec, const std::string& out_path, const Progress& progress) {
  if (std::filesystem::exists(out_path)) {
    try {
      const Results old = read_results(out_path);
      if (old.status() == "complete" && old.meta.count("spec") && old.meta.at("spec") == spec.text &&
          old.meta.count("solver") && old.meta.at("solver") == "fem")
        return true;
    } catch (const std::exception&) {
      // unreadable: computed again below
    }
  }
  const RunSummary s = run_fem(spec, out_path, progress);
  if (!s.complete) throw msd::Error(spec.path + ": the FEM reference failed: " + s.failure);
  return false;
}

}  // namespace bench
