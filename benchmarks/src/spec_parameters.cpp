// Every field of a test spec, declared once: path, unit, default, range, doc.
// The spec reader (spec.cpp) reads through these; the field table in
// benchmarks/specs/README.md is generated from them
// (tests/bench/spec_parameters_test.cpp holds it to them). Defaults come from
// the spec structs (GeometrySpec{}, MeshSpec{}, MsdSpec{}, FemSpec{},
// LoadingSpec{}, OutputSpec{}), not restated here. Rules between fields (raw
// versus physical constants, cvode versus dt, per-loading fields) stay in the
// reader; the docs say when a field applies.
#include "bench/spec.hpp"


namespace bench {

namespace {

using tbio::Kind;
using tbio::Parameter;
using tbio::Range;

using namespace tbio::declare;
using tbio::number_text;

std::vector<std::string> loading_choices() {
  std::vector<std::string> names;
  for (const Loading l : kLoadings) names.emplace_back(loading_name(l));
  return names;
}

std::vector<Parameter> declare_model() {
  const GeometrySpec geometry;
  const MeshSpec mesh;
  const MsdSpec msd;
  const Range positive = Range::positive(), non_negative = Range::non_negative();
  return {
      other("name", Kind::Text, "", "required", "names the results"),
      other("description", Kind::Text, "", "empty", "one line on what the spec is"),
      choice("geometry.shape", {"cylinder", "box", "cooks_membrane", "obj"}, "",
             "the sample's closed surface; cooks_membrane: fem only (fixed 48/44/16/1 mm)"),
      number("geometry.radius", "m", std::nullopt, positive, "cylinder (axis along z, base at z = 0)"),
      number("geometry.height", "m", std::nullopt, positive, "cylinder"),
      integer("geometry.segments", geometry.segments, Range::closed(3, 100000), "cylinder: the polygon's sides"),
      vector3("geometry.size", "m", std::nullopt, "box: its sides, each > 0; lowest corner at the origin"),
      other("geometry.file", Kind::Text, "", "required", "obj: a .obj, .stl or .ply surface, relative to the spec's folder"),
      number("mesh.spacing", "m", std::nullopt, positive, "the msd solver's cube edge h (cubic grid + five-tet split, thesis 4.5)"),
      choice("mesh.rule", {"centre", "center", "inside", "overlap"}, mesh.rule, "which cubes are kept (docs/msd-model.md)"),
      vector3("mesh.origin", "m", std::nullopt, "the grid's origin", "the surface's lowest corner"),
      integer("mesh.max_cubes", static_cast<double>(mesh.max_cubes), Range::closed_open(1, 1.0 / 0.0), "refuse larger grids"),
      optional_number("mesh.memory_limit_gb", "GB", positive,
                      "refuse a grid whose estimated memory is larger (default: half of this machine's; docs/memory.md)"),
      other("material.library", Kind::Text, "", "none", "start from this entry of benchmarks/materials.yaml; the spec's fields override it"),
      other("material.name", Kind::Text, "", "empty", "a label"),
      number("material.density", "kg/m^3", std::nullopt, positive, "required (or from the library)"),
      optional_number("material.youngs_modulus", "Pa", positive, "required when msd.constants is physical"),
      optional_number("material.poisson_ratio", "1", Range::open(-1, 0.5), "for the fem solver and the msd term neo_hookean; the MSD lattice's own is 0.2"),
      optional_number("material.shear_modulus", "Pa", positive, "fem alternative to youngs_modulus + poisson_ratio, with bulk_modulus"),
      optional_number("material.bulk_modulus", "Pa", positive, "fem alternative to youngs_modulus + poisson_ratio, with shear_modulus"),
      optional_number("material.damping_time", "s", non_negative, "stiffness-proportional damping: k_d = b k_s (msd), C = b K0 (fem)"),
      choice("msd.constants", {"raw", "physical"}, msd.constants, "raw: k_s, k_d, k_r, k_v given; physical: from the material"),
      number("msd.k_s", "N/m", std::nullopt, positive, "raw (required): spring constant, the same on every edge"),
      number("msd.k_d", "N s/m", msd.k_d, non_negative, "raw: damper constant"),
      number("msd.k_r", "N/m", msd.k_r, non_negative, "raw: face-repulsion constant"),
      number("msd.k_v", "N/m", msd.k_v, non_negative, "raw: volume-preservation constant"),
      number("msd.stiffness_scale", "1", msd.stiffness_scale, positive, "physical: calibration factor on k_s, k_r, k_v"),
      number("msd.repulsion_factor", "1", msd.repulsion_factor, non_negative, "physical: k_r relative to the element's reference stiffness"),
      number("msd.volume_factor", "1", msd.volume_factor, non_negative, "physical: k_v relative to the element's reference stiffness"),
      number("msd.bulk_factor", "1", msd.bulk_factor, positive, "physical, with the bulk term: factor on its modulus, K = lambda - mu of E and poisson_ratio, or lambda with zero_length_springs (msd/forces/bulk_volume.hpp)"),
      flag("msd.zero_length_springs", msd.zero_length_springs, "physical, with the springs and bulk terms, no edge_classes: springs of rest length 0 with cotangent weights (k = mu w) and the bulk term's neo-Hookean law - the lattice with the neo-Hookean energy (msd/forces/zero_length_springs.hpp)"),
      optional_number("msd.damping_time", "s", non_negative, "physical: the dampers' k_d = b k_s with this b in place of the material's (which stays the FEM's)", "material.damping_time"),
      other("msd.calibration", Kind::Text, "", "none", "physical: the factors above and damping_time from a calibration file (relative to the spec's folder); not with them"),
      number("msd.repulsion_floor", "1", msd.repulsion_floor, Range::open(0, 1), "repulsion continues along its tangent below this fraction of x0"),
      choice("msd.mass_lumping", {"per_tet", "equal"}, msd.mass_lumping, "equal: the thesis' choice"),
      other("msd.terms", Kind::List, "", "all", "only these are computed: springs, dampers, repulsion, volume, neo_hookean (the continuum element: needs poisson_ratio), bulk (the lattice's per-cube volume term: needs poisson_ratio > 0.25 and the lattice's cubes)"),
      optional_number("msd.nonlinear_threshold", "1", Range{0.0, 1.0, false, true}, "off (or false), or repulsion/volume only in elements deformed past it", "off"),
      choice("msd.integrator", {"explicit_euler", "symplectic_euler", "semi_implicit_euler", "velocity_verlet", "backward_euler", "bdf2", "quasi_static", "cvode"},
             msd.integrator, "backward_euler, bdf2: implicit (first, second order), Newton with exact Jacobians, for stiff scenes and large steps; quasi_static: the equilibrium at each step, no inertia or dampers (the FEM's static problem; not for vibration); cvode: SUNDIALS BDF, adaptive - the time-exact reference"),
      number("msd.newton_tolerance", "1", msd.newton_tolerance, Range::open(0, 1), "backward_euler, bdf2 and quasi_static only: Newton's residual relative to the balance's largest term"),
      integer("msd.newton_max_iterations", msd.newton_max_iterations, Range::closed(1, 1000), "backward_euler, bdf2 and quasi_static only: Newton iterations before the step is halved"),
      integer("msd.newton_max_step_cuts", msd.newton_max_step_cuts, Range::closed(0, 30), "backward_euler, bdf2 and quasi_static only: halvings of a step whose Newton solve failed before the run fails"),
      flag("msd.newton_reuse_factorization", msd.newton_reuse_factorization, "backward_euler, bdf2 and quasi_static only: modified Newton - try an earlier step's LU factorisation first (false: factorise every iteration)"),
      choice("msd.newton_linear_solver", {"sparse_lu", "symmetric_ldlt"}, msd.newton_linear_solver, "backward_euler, bdf2 and quasi_static only: sparse_lu factorises Newton's matrix (exact Newton); symmetric_ldlt its symmetric part (approximate Newton, cheaper factorisations)"),
      integer("msd.newton_anderson_depth", msd.newton_anderson_depth, Range::closed(0, 8), "backward_euler, bdf2 and quasi_static with newton_reuse_factorization only: Anderson acceleration of the chord steps, mixing in this many earlier ones (0: plain chord steps)"),
      flag("msd.newton_keep_orientation", msd.newton_keep_orientation, "backward_euler, bdf2 and quasi_static only: every iterate Newton accepts keeps every tet's orientation (with the repulsion and a small repulsion_floor as a barrier, no element inverts)"),
      choice("msd.continuum_volume", {"per_tet", "per_cube"}, msd.continuum_volume, "the neo_hookean term's volume ratio: each tet's own, or one per cube of the lattice (mean dilatation: no locking near nu = 0.5)"),
      number("msd.edge_classes.axis.stiffness", "1", 1.0, positive, "factor on the k_s and k_d of the cube edges (along a grid axis); the Cauchy-Born lattice is isotropic at half the face diagonals' (docs/msd-model.md section 4, edge classes)"),
      number("msd.edge_classes.axis.tension_exponent", "1", 1.0, non_negative, "m of the cube edges' spring law T = k r (lambda^m - lambda^-n) / (m + n); m = 1, n = 0: the thesis' linear spring"),
      number("msd.edge_classes.axis.compression_exponent", "1", 0.0, non_negative, "n of that law: n > 0 stiffens the spring as it is crushed (m = 1, n = 2: the neo-Hookean bar)"),
      number("msd.edge_classes.face_diagonal.stiffness", "1", 1.0, positive, "factor on the k_s and k_d of the cube faces' diagonals"),
      number("msd.edge_classes.face_diagonal.tension_exponent", "1", 1.0, non_negative, "m of the face diagonals' spring law"),
      number("msd.edge_classes.face_diagonal.compression_exponent", "1", 0.0, non_negative, "n of the face diagonals' spring law"),
      number("msd.edge_classes.other.stiffness", "1", 1.0, positive, "factor on the k_s and k_d of any other edge (a mesh not from the axis-aligned grid)"),
      number("msd.edge_classes.other.tension_exponent", "1", 1.0, non_negative, "m of the other edges' spring law"),
      number("msd.edge_classes.other.compression_exponent", "1", 0.0, non_negative, "n of the other edges' spring law"),
      integer("msd.threads", msd.threads, Range::closed(1, 256), "threads of the force evaluation; the results are bit-identical for every count"),
      choice("msd.forces", {"engine", "reference"}, msd.forces, "engine: each edge once, threaded; reference: the per-tet loop (same forces up to round-off)"),
      number("msd.dt", "s", std::nullopt, positive, "time step; required by the fixed-step integrators, not with cvode"),
      number("msd.rtol", "1", msd.rtol, positive, "cvode only: relative tolerance"),
      number("msd.atol", "m", msd.atol, positive, "cvode only: absolute tolerance on positions (velocities: atol / output.interval)"),
  };
}

std::vector<Parameter> declare_fem() {
  const FemSpec fem;
  const Range tolerance = Range::open(0, 1);
  return {
      choice("fem.formulation", {"three_field", "displacement"}, fem.formulation, "three_field: Q_k-P_{k-1}-P_{k-1}, condensed"),
      integer("fem.degree", fem.degree, Range::closed(1, 3), "element degree k"),
      integer("fem.refinement", fem.refinement, Range::closed(0, 8), "global refinements of the coarse mesh"),
      other("fem.cells", Kind::List, "1", "from the geometry", "[nx, ny, nz] coarse cells, 1 ... 4096 (box: from mesh.spacing or 1 cm; cylinder: [1, 1, layers]; cooks_membrane: [16, 16, 1])"),
      choice("fem.linear_solver", {"direct", "amg"}, fem.linear_solver, "direct: MUMPS; amg: CG + Trilinos ML"),
      number("fem.residual_tolerance", "1", fem.residual_tolerance, tolerance, "Newton, relative to the force scale"),
      number("fem.increment_tolerance", "1", fem.increment_tolerance, tolerance, "Newton, relative to the displacement scale"),
      number("fem.relative_tolerance", "1", fem.relative_tolerance, tolerance, "dynamics (SUNDIALS IDA)"),
      number("fem.absolute_tolerance", "1", fem.absolute_tolerance, tolerance, "dynamics (SUNDIALS IDA)"),
      integer("fem.max_iterations", fem.max_iterations, Range::closed(1, 1000), "Newton iterations per increment"),
      integer("fem.max_cuts", fem.max_cuts, Range::closed(0, 30), "halvings of a failed load increment"),
      number("fem.max_increment", "s", fem.max_increment, Range::non_negative(), "load-time units; 0: one increment per output interval"),
      number("fem.rayleigh_mass", "1/s", fem.rayleigh_mass, Range::non_negative(), "C = rayleigh_mass M + damping_time K0"),
      number("fem.contact_penalty", "1", fem.contact_penalty, Range::closed(1, 1e8), "indentation: penalty = this * E / h_e (h_e = cell size / degree)"),
      flag("fem.vtu", fem.vtu, "write FILE_vtu/NAME.pvd for ParaView"),
  };
}

std::vector<Parameter> declare_loading() {
  const LoadingSpec loading;
  const OutputSpec output;
  const Range positive = Range::positive();
  const std::vector<std::string> faces{"left", "right", "front", "back", "bottom", "top"};
  return {
      choice("loading.type", loading_choices(), "", "the virtual experiment; the fields below say which loading they belong to"),
      other("loading.path", Kind::List, "", "see what", "[[time s, value], ...] from time 0, piecewise linear: nominal strain (uniaxial; or `thesis_cycle`), gamma (simple_shear), load factor (cooks_membrane, static: default [[0, 0], [1, 1]]), depth factor in [0, 1] (indentation); vibration: none"),
      vector3("loading.gravity", "m/s^2", loading.gravity, "uniaxial, static, vibration: a non-zero vector adds the gravity term"),
      choice("loading.platens", {"bonded", "frictionless"}, loading.platens, "uniaxial: bonded (thesis) or frictionless (only the normal is prescribed)"),
      choice("loading.boundary", {"platens", "homogeneous"}, loading.boundary, "simple_shear: platens, or homogeneous (fem: u = gamma Z e_x on the whole boundary)"),
      number("loading.force", "N", std::nullopt, Range::any(), "cooks_membrane (required): total upward shear on the right edge"),
      choice("loading.fixed", faces, loading.fixed, "static: the clamped face"),
      choice("loading.traction.face", faces, "", "static (optional section), vibration with preload: the face carrying the dead load"),
      vector3("loading.traction.force", "N", std::nullopt, "the total dead load on that face"),
      choice("loading.indenter.shape", {"cylinder"}, "cylinder", "indentation: a rigid cylinder touching the top face above its centre at rest"),
      number("loading.indenter.radius", "m", std::nullopt, positive, "indentation: the cylinder's radius"),
      choice("loading.indenter.axis", {"x", "y"}, loading.indenter_axis, "indentation: the cylinder's axis"),
      number("loading.indenter.depth", "m", std::nullopt, positive, "indentation: moves down by depth * path(t); less than the block's height"),
      choice("loading.indenter.response", {"stick", "frictionless"}, loading.indenter_response, "indentation, msd contact: stick (the thesis') or frictionless (fem: frictionless penalty)"),
      choice("loading.initial", {"axial_mode", "axial_stretch", "preload"}, loading.initial, "vibration (z = 0 face fixed): the start; preload: a dead load (traction) ramped, held and removed at release"),
      number("loading.amplitude", "1", std::nullopt, Range::any(), "vibration, not with preload (required): strain amplitude"),
      number("loading.duration", "s", std::nullopt, positive, "vibration (required): the ring-down's length"),
      number("loading.release", "s", std::nullopt, positive, "vibration with preload (required): when the load is removed"),
      optional_number("output.interval", "s", positive, "s between recorded samples (>= msd.dt); required in an output section", number_text(output.interval)),
      number("output.fields_interval", "s", output.fields_interval, Range::non_negative(), "s between /fields (and VTU) frames; 0: every sample"),
  };
}

std::vector<Parameter> declare() {
  std::vector<Parameter> all = declare_model();
  for (auto part : {declare_fem(), declare_loading()}) all.insert(all.end(), part.begin(), part.end());
  return all;
}

}  // namespace

const std::vector<tbio::Parameter>& spec_parameters() {
  static const std::vector<tbio::Parameter> all = declare();
  return all;
}

const tbio::Parameter& spec_parameter(const std::string& path) {
  return tbio::find_parameter(spec_parameters(), path, "spec");
}

}  // namespace bench
