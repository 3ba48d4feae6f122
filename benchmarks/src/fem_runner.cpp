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
  throw msd::Error(spec.path + ": loading.type '" + spec.loading.type + "' needs a box or cylinder geometry");
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

}  // namespace

fem::Problem make_fem_problem(const Spec& spec, const std::string& vtu_directory) {
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

  // Geometry and coarse mesh: by default about mesh.spacing (or 1 cm) per cell.
  const GeometrySpec& g = spec.geometry;
  const double h = spec.mesh ? spec.mesh->spacing : 0.01;
  auto cells_for = [&](double len) { return static_cast<unsigned>(std::max(1L, std::lround(len / h))); };
  p.mesh.refinement = f.refinement;
  if (g.shape == "box") {
    p.mesh.shape = fem::MeshSpec::Shape::Box;
    p.mesh.size = {{g.size.x(), g.size.y(), g.size.z()}};
    p.mesh.cells = f.cells.value_or(std::array<unsigned, 3>{{cells_for(g.size.x()), cells_for(g.size.y()),
                                                             cells_for(g.size.z())}});
  } else if (g.shape == "cylinder") {
    p.mesh.shape = fem::MeshSpec::Shape::Cylinder;
    p.mesh.radius = g.radius;
    p.mesh.height = g.height;
    p.mesh.cells = f.cells.value_or(std::array<unsigned, 3>{
        {1, 1, static_cast<unsigned>(std::max(1L, std::lround(g.height / g.radius)))}});
  } else if (g.shape == "cooks_membrane") {
    p.mesh.shape = fem::MeshSpec::Shape::CooksMembrane;
    p.mesh.cells = f.cells.value_or(std::array<unsigned, 3>{{16, 16, 1}});
  } else {
    throw msd::Error(spec.path + ": geometry.shape '" + g.shape + "' is not supported by the fem solver "
                                 "(supported: box, cylinder, cooks_membrane)");
  }

  const LoadingSpec& l = spec.loading;
  if (l.type == "uniaxial") {
    const double L = length_along_z(spec);
    fem::Dirichlet bottom, top;
    bottom.face = 4;
    top.face = 5;
    top.vector = {{0, 0, L}};
    top.path = path_of(spec);
    if (l.platens == "frictionless") {
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
  } else if (l.type == "simple_shear") {
    if (g.shape != "box") throw msd::Error(spec.path + ": simple_shear needs a box geometry");
    // homogeneous: u = gamma(t) Z e_x on the whole boundary (exactly simple
    // shear); platens: bottom held, top moved along x by gamma H, sides free.
    const std::vector<int> faces = l.boundary == "homogeneous" ? std::vector<int>{0, 1, 2, 3, 4, 5}
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
  } else if (l.type == "cooks_membrane") {
    if (g.shape != "cooks_membrane") throw msd::Error(spec.path + ": loading cooks_membrane needs that geometry");
    fem::Dirichlet clamp;
    clamp.face = 0;
    p.dirichlet = {clamp};
    fem::Traction shear;
    shear.face = 1;
    shear.total_force = {{0.0, l.force, 0.0}};
    shear.path = path_of(spec);
    p.tractions = {shear};
    p.plane_strain = true;
    p.probes = {{{0.048, 0.060, 0.0}}, {{0.048, 0.052, 0.0}}};
    p.reaction_faces = {0};
    p.report_times = report_times(spec);
  } else if (l.type == "static") {
    if (g.shape != "box" && g.shape != "cylinder")
      throw msd::Error(spec.path + ": loading static needs a box or cylinder geometry");
    const std::vector<std::string> names{"left", "right", "front", "back", "bottom", "top"};
    auto face_id = [&](const std::string& n) {
      return static_cast<int>(std::find(names.begin(), names.end(), n) - names.begin());
    };
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
  } else if (l.type == "indentation") {
    // Bonded base; a rigid cylinder touching the top face above its centre,
    // moved down by depth * path(t); frictionless penalty contact on the top
    // face with penalty = contact_penalty * E / h_e.
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
    c.penalty = f.contact_penalty * E / h_cell;
    c.faces = {5};
    p.contacts = {c};
    p.reaction_faces = {4};
    p.report_times = report_times(spec);
  } else if (l.type == "vibration") {
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
      const std::vector<std::string> names{"left", "right", "front", "back", "bottom", "top"};
      fem::Traction t;
      t.face = static_cast<int>(std::find(names.begin(), names.end(), l.traction_face) - names.begin());
      t.total_force = {{l.traction.x(), l.traction.y(), l.traction.z()}};
      t.path.points.clear();  // the preload up to the release (solved quasi-statically)
      for (const auto& pt : preload_path(l))
        if (pt.first <= l.release) t.path.points.push_back(pt);
      p.dynamics.preload = {t};
      p.dynamics.release_time = l.release;
    }
    p.dynamics.end_time = l.release + l.duration;
    p.dynamics.rayleigh_mass = f.rayleigh_mass;
    p.dynamics.rayleigh_stiffness = spec.material.damping_time.value_or(0.0);
    p.dynamics.relative_tolerance = f.relative_tolerance;
    p.dynamics.absolute_tolerance = f.absolute_tolerance;
    p.report_interval = spec.output.interval;
    p.probes = {g.shape == "box" ? std::array<double, 3>{{0.5 * g.size.x(), 0.5 * g.size.y(), L}}
                                 : std::array<double, 3>{{0.0, 0.0, L}}};
    p.reaction_faces = {4};
  }
  // With an msd grid in the spec, evaluate the solution at the msd nodes' rest
  // positions too, for the displacement-field comparison.
  if (spec.mesh && spec.msd && l.type != "cooks_membrane") {
    const msd::SampleMesh sample = make_sample_mesh(spec);
    for (int n = 0; n < sample.mesh.num_nodes(); ++n)
      p.field_probes.push_back({{sample.mesh.nodes(0, n), sample.mesh.nodes(1, n), sample.mesh.nodes(2, n)}});
  }
  return p;
}

namespace {

struct Layout {
  std::vector<SeriesColumn> columns;
};

Layout layout_for(const std::string& type) {
  if (type == "uniaxial")
    return {{{"time", "s"},
             {"strain", "1"},
             {"nominal_stress", "Pa"},
             {"volume_ratio", "1"},
             {"inverted_elements", "1"},
             {"lateral_force", "N"},
             {"kinetic_energy", "J"},
             {"newton_iterations", "1"},
             {"min_jacobian", "1"}}};
  if (type == "simple_shear")
    return {{{"time", "s"},
             {"shear_strain", "1"},
             {"shear_stress", "Pa"},
             {"normal_stress_xx", "Pa"},
             {"normal_stress_yy", "Pa"},
             {"normal_stress_zz", "Pa"},
             {"shear_stress_mean", "Pa"},
             {"volume_ratio", "1"},
             {"newton_iterations", "1"}}};
  if (type == "cooks_membrane")
    return {{{"time", "s"},
             {"load_factor", "1"},
             {"tip_displacement", "m"},
             {"mid_edge_displacement", "m"},
             {"volume_ratio", "1"},
             {"newton_iterations", "1"}}};
  if (type == "static")
    return {{{"time", "s"},
             {"load_factor", "1"},
             {"tip_displacement_x", "m"},
             {"tip_displacement_y", "m"},
             {"tip_displacement_z", "m"},
             {"reaction_force_x", "N"},
             {"reaction_force_y", "N"},
             {"reaction_force_z", "N"},
             {"volume_ratio", "1"},
             {"newton_iterations", "1"}}};
  if (type == "indentation")
    return {{{"time", "s"},
             {"depth", "m"},
             {"indentation_force", "N"},
             {"base_reaction_z", "N"},
             {"max_penetration", "m"},
             {"stored_energy", "J"},
             {"volume_ratio", "1"},
             {"newton_iterations", "1"},
             {"min_jacobian", "1"}}};
  return {{{"time", "s"}, {"tip_displacement", "m"}, {"kinetic_energy", "J"}, {"volume_ratio", "1"}}};
}

}  // namespace

RunSummary run_fem(const Spec& spec, const std::string& out_path, const Progress& progress) {
  const bool root = fem::Session::rank() == 0;
  const fs::path out(out_path);
  const std::string vtu_dir = spec.fem.vtu ? (out.parent_path() / (out.stem().string() + "_vtu")).string() : "";
  fem::Problem problem;
  try {
    problem = make_fem_problem(spec, vtu_dir);  // input errors surface here
  } catch (const fem::Error& e) {
    throw msd::Error(spec.path + ": " + e.what());
  }
  const fem::NeoHookean mat = problem.material;
  if (root) {
    if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
    if (!vtu_dir.empty()) fs::create_directories(vtu_dir);
  }

  // The results file is created at the first report, so input errors the
  // solver detects while setting up (a pin with no vertex, a face that does not
  // exist) leave nothing behind.
  std::unique_ptr<ResultsWriter> writer;
  const Layout layout = layout_for(spec.loading.type);
  auto open_writer = [&] {
    if (!root || writer) return;
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
                 {"test", spec.loading.type + (spec.loading.type == "uniaxial" ? " (" + spec.loading.platens + " platens)" : "")}};
    writer = std::make_unique<ResultsWriter>(out_path, meta, layout.columns);
  };

  RunSummary s;
  s.name = spec.name;
  s.solver = "fem";
  s.loading = spec.loading.type;
  s.out_path = out_path;
  s.min_strain = s.min_stress = s.min_volume_ratio = 1e300;
  s.max_strain = s.max_stress = s.max_volume_ratio = -1e300;
  std::vector<double> times, tip;
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
    std::vector<double> row;
    const std::string& type = spec.loading.type;
    s.min_volume_ratio = std::min(s.min_volume_ratio, r.volume_ratio);
    s.max_volume_ratio = std::max(s.max_volume_ratio, r.volume_ratio);
    if (type == "uniaxial") {
      const double strain = path.value(r.time);
      const double stress = r.reactions[0][2] / r.reaction_areas[0];
      row = {r.time, strain, stress, r.volume_ratio, 0.0, std::hypot(r.reactions[0][0], r.reactions[0][1]), 0.0,
             static_cast<double>(r.newton_iterations), r.min_jacobian};
      s.min_strain = std::min(s.min_strain, strain);
      s.max_strain = std::max(s.max_strain, strain);
      s.min_stress = std::min(s.min_stress, stress);
      s.max_stress = std::max(s.max_stress, stress);
    } else if (type == "simple_shear") {
      const double tau = r.reactions[0][0] / r.reaction_areas[0];
      row = {r.time, path.value(r.time), tau, r.mean_cauchy[0], r.mean_cauchy[1], r.mean_cauchy[2],
             r.mean_cauchy[4], r.volume_ratio, static_cast<double>(r.newton_iterations)};
      s.min_stress = std::min(s.min_stress, tau);
      s.max_stress = std::max(s.max_stress, tau);
    } else if (type == "static") {
      const auto& d = r.probe_displacements[0];
      const auto& f = r.reactions[0];
      row = {r.time, path.value(r.time), d[0], d[1], d[2], f[0], f[1], f[2], r.volume_ratio,
             static_cast<double>(r.newton_iterations)};
      tip.push_back(d[2]);
    } else if (type == "indentation") {
      // The force the cylinder exerts on the body, along the indenting direction -z.
      const double force = -r.contact_forces[0][2];
      row = {r.time, spec.loading.indenter_depth * path.value(r.time), force, r.reactions[0][2],
             r.contact_penetrations[0], r.stored_energy, r.volume_ratio, static_cast<double>(r.newton_iterations), r.min_jacobian};
      s.min_stress = std::min(s.min_stress, force);
      s.max_stress = std::max(s.max_stress, force);
    } else if (type == "cooks_membrane") {
      row = {r.time, path.value(r.time), r.probe_displacements[0][1], r.probe_displacements[1][1], r.volume_ratio,
             static_cast<double>(r.newton_iterations)};
      tip.push_back(r.probe_displacements[0][1]);
    } else {
      row = {r.time, r.probe_displacements[0][2], r.kinetic_energy, r.volume_ratio};
      times.push_back(r.time);
      tip.push_back(r.probe_displacements[0][2]);
    }
    writer->append(row);
    s.simulated_seconds = r.time;
  };

  fem::Summary sum;
  const std::clock_t cpu_start = std::clock();
  try {
    sum = fem::solve(problem, cb);
    s.complete = true;
  } catch (const fem::SolveError& e) {
    s.failure = e.what();
    sum = e.summary;
    open_writer();  // a failure before the first report still leaves a record
  } catch (const fem::Error& e) {
    if (root && !vtu_dir.empty() && fs::is_empty(vtu_dir)) fs::remove(vtu_dir);
    throw msd::Error(spec.path + ": " + e.what());
  }
  s.dofs = sum.dofs;
  s.cells = sum.cells;
  s.steps = static_cast<long>(problem.dynamic ? sum.time_steps : sum.increments);
  s.wall_seconds = sum.wall_seconds;
  if (spec.loading.type == "cooks_membrane" && !tip.empty()) s.highlights.push_back({"tip_mm", 1e3 * tip.back()});
  if (spec.loading.type == "vibration") {
    const RingDown rd = analyse_ring_down_after(times, tip, spec.loading.release);  // from the release
    s.highlights.push_back({"f1_Hz", rd.frequency});
    s.highlights.push_back({"zeta", rd.damping_ratio});
    if (writer) {
      writer->set_metric("first_frequency", rd.frequency);
      writer->set_metric("damping_ratio", rd.damping_ratio);
      writer->set_metric("zero_crossings", rd.crossings);
    }
  }
  if (writer) {
    writer->set_timing(sum.wall_seconds, s.steps, 0.0, 1);
    // This process's CPU time over the solve (what the guard's cost ratio
    // uses: unlike wall time it does not grow when another job shares the core).
    writer->set_timing_detail("cpu_seconds", static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    writer->set_timing_detail("processes", sum.processes);
    writer->set_timing_detail("dofs", static_cast<double>(sum.dofs));
    writer->set_timing_detail("cells", static_cast<double>(sum.cells));
    writer->set_timing_detail("newton_iterations", sum.newton_iterations);
    writer->set_timing_detail("increment_cuts", sum.cuts);
    writer->set_timing_detail("factorizations", sum.factorizations);
    writer->set_timing_detail("assembly_seconds", sum.assembly_seconds);
    writer->set_timing_detail("linear_solver_seconds", sum.linear_solver_seconds);
    writer->set_meta("mesh_counts", std::to_string(sum.cells) + " cells, " + std::to_string(sum.dofs) + " dofs");
    if (!sum.vtu_files.empty()) writer->set_meta("vtu", sum.vtu_files.front());
    if (s.complete) writer->finish();
    else writer->fail(s.failure);
  }
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
