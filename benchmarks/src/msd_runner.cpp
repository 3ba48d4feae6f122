#include "bench/msd_runner.hpp"

#include "bench/results_file.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace bench {

const MsdSpec& msd_section(const Spec& spec) {
  if (!spec.msd || !spec.mesh)
    throw msd::Error(spec.path + ": the msd solver needs 'mesh' and 'msd' sections in the spec");
  if (spec.loading.type != "uniaxial")
    throw msd::Error(spec.path + ": loading.type '" + spec.loading.type +
                     "' is not supported by the msd solver yet (supported: uniaxial)");
  return *spec.msd;
}

msd::TriangleMesh make_surface(const GeometrySpec& g) {
  if (g.shape == "cylinder") return msd::make_cylinder(g.radius, g.height, g.segments);
  if (g.shape == "box") return msd::make_box(msd::Vec3::Zero(), g.size);
  if (g.shape == "obj") return msd::read_obj(g.file);
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
    m.damping_time = spec.material.damping_time.value_or(0.0);
    m.stiffness_scale = ms.stiffness_scale;
    m.repulsion_factor = ms.repulsion_factor;
    m.volume_factor = ms.volume_factor;
  }
  msd::check_material(m, spec.path + ": material");
  return m;
}

MsdProblem compile_msd(const Spec& spec) {
  const MsdSpec& ms = msd_section(spec);
  MsdProblem p{make_sample_mesh(spec), {}, {}, msd::LoadingPath(spec.loading.path, spec.path + ": loading.path"), {}};
  msd::ModelOptions o;
  o.terms = 0;
  for (const auto& t : ms.terms) o.terms |= msd::parse_force_term(t);
  if (spec.loading.gravity.squaredNorm() > 0.0) o.terms |= msd::kGravity;
  o.gravity = spec.loading.gravity;
  o.nonlinear_threshold = ms.nonlinear_threshold;
  o.region_materials.assign(1, make_material(spec));
  p.setup = msd::add_platens(p.sample.mesh, msd::parse_platen_contact(spec.loading.platens), o);
  p.model = msd::build_model(p.sample.mesh, o);
  p.stepping.dt = ms.dt;
  p.stepping.integrator = msd::parse_integrator(ms.integrator);
  p.stepping.output_interval = spec.output.interval;
  if (spec.output.interval < ms.dt)
    throw msd::Error(spec.path + ": output.interval (" + std::to_string(spec.output.interval) +
                     " s) is shorter than msd.dt (" + std::to_string(ms.dt) + " s)");
  return p;
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
  return r;
}

RunSummary run_msd(const Spec& spec, const std::string& out_path, const Progress& progress) {
  const MsdSpec& ms = msd_section(spec);
  MsdProblem p = compile_msd(spec);  // every input error surfaces here, before any file exists
  const auto parent = std::filesystem::path(out_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);

  RunMeta meta;
  meta.solver = "msd";
  meta.spec_text = spec.text;
  meta.spec_path = spec.path;
  meta.spec_name = spec.name;
  meta.material = material_record(spec, p.model);
  meta.text = {{"terms", msd::force_terms_to_string(p.model.terms)},
               {"integrator", msd::to_string(p.stepping.integrator)},
               {"mass_lumping", ms.mass_lumping},
               {"mesh_rule", spec.mesh->rule},
               {"test", spec.loading.type + " (" + spec.loading.platens + " platens)"}};
  ResultsWriter out(out_path, meta,
                    {{"time", "s"},
                     {"strain", "1"},
                     {"nominal_stress", "Pa"},
                     {"volume_ratio", "1"},
                     {"inverted_elements", "1"},
                     {"lateral_force", "N"},
                     {"kinetic_energy", "J"},
                     {"nonlinear_active_elements", "1"}});
  out.set_meta("mesh_counts", "nodes " + std::to_string(p.model.num_nodes()) + ", tets " +
                                  std::to_string(p.model.num_elements()) + ", cubes " +
                                  std::to_string(p.sample.cubes));

  RunSummary s;
  s.name = spec.name;
  s.out_path = out_path;
  s.nodes = p.model.num_nodes();
  s.tets = p.model.num_elements();
  s.cubes = p.sample.cubes;
  s.min_strain = s.min_stress = 1e300;
  s.max_strain = s.max_stress = -1e300;
  s.min_volume_ratio = 1e300;
  s.max_volume_ratio = -1e300;
  const auto start = std::chrono::steady_clock::now();
  const double end = p.path.end_time();
  msd::RunStats stats;
  try {
    stats = msd::run_uniaxial(p.model, p.setup, p.path, p.stepping,
                              [&](const msd::UniaxialSample& x, const msd::State&) {
                                out.append({x.time, x.strain, x.nominal_stress, x.volume_ratio,
                                            static_cast<double>(x.inverted_elements), x.lateral_force,
                                            x.kinetic_energy, static_cast<double>(x.nonlinear_active)});
                                s.min_strain = std::min(s.min_strain, x.strain);
                                s.max_strain = std::max(s.max_strain, x.strain);
                                s.min_stress = std::min(s.min_stress, x.nominal_stress);
                                s.max_stress = std::max(s.max_stress, x.nominal_stress);
                                s.min_volume_ratio = std::min(s.min_volume_ratio, x.volume_ratio);
                                s.max_volume_ratio = std::max(s.max_volume_ratio, x.volume_ratio);
                                s.max_inverted = std::max(s.max_inverted, x.inverted_elements);
                                s.simulated_seconds = x.time;
                                if (progress) progress(x.time, end);
                                return true;
                              });
    s.complete = true;
  } catch (const msd::SimulationFailure& f) {
    s.failure = f.what();
    s.steps = f.step;
  }
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (s.complete) s.steps = stats.steps;
  out.set_timing(s.wall_seconds, s.steps, p.stepping.dt, 1);
  if (s.complete) out.finish();
  else out.fail(s.failure);
  return s;
}

}  // namespace bench
