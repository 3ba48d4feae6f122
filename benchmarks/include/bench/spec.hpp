// A benchmark specification: one YAML file read by every solver (design notes:
// "one spec, one result schema"). Field reference: benchmarks/specs/README.md.
// Parsing is strict - unknown fields, wrong types and unphysical values are
// errors naming the file, line and field - and happens before anything runs.
#pragma once

#include "bench/loading.hpp"
#include "msd/forces/spring_law.hpp"
#include "tbio/parameter.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

struct GeometrySpec {
  std::string shape;                 ///< cylinder | box | cooks_membrane | obj
  double radius = 0.0, height = 0.0; ///< cylinder, m
  int segments = 64;                 ///< cylinder polygon
  Eigen::Vector3d size{Eigen::Vector3d::Zero()};  ///< box, m (lowest corner at 0)
  std::string file;                  ///< obj, resolved against the spec's folder
};

struct MeshSpec {
  double spacing = 0.0;              ///< cube edge h, m
  std::string rule = "centre";       ///< centre | inside | overlap
  std::optional<Eigen::Vector3d> origin;
  long max_cubes = 20'000'000;
  double memory_limit_gb = 0.0;      ///< 0: half of this machine's memory (msd/core/memory.hpp)
};

struct MaterialSpec {
  std::string name;
  double density = 0.0;                   ///< kg/m^3
  std::optional<double> youngs_modulus;   ///< Pa
  std::optional<double> poisson_ratio;    ///< used by continuum solvers
  std::optional<double> shear_modulus;    ///< Pa (alternative to E, nu)
  std::optional<double> bulk_modulus;     ///< Pa (alternative to E, nu)
  std::optional<double> damping_time;     ///< s, stiffness-proportional damping
};

struct MsdSpec {
  std::string constants = "physical";     ///< raw | physical
  // raw
  double k_s = 0.0, k_d = 0.0, k_r = 0.0, k_v = 0.0;
  // physical
  double stiffness_scale = 1.0, repulsion_factor = 0.0, volume_factor = 0.0;
  /// The bulk term's factor on its modulus (msd::lattice_bulk_law: K = lambda
  /// - mu, or lambda with zero-length springs).
  double bulk_factor = 1.0;
  /// Zero-length springs with cotangent weights and the bulk term's
  /// neo-Hookean law (msd/forces/zero_length_springs.hpp).
  bool zero_length_springs = false;
  /// s; the MSD dampers' time constant (k_d = damping_time k_s) in place of the
  /// material's damping_time, which stays the FEM's Rayleigh constant. The
  /// dampers sit on the springs only, so the lattice needs a longer one to damp
  /// like the continuum; a calibration fits it (empty: the material's).
  std::optional<double> damping_time;
  /// Calibration file the physical factors above were read from ("" =
  /// given in the spec); `msd.calibration: FILE`, relative to the spec's folder.
  std::string calibration;
  double repulsion_floor = 0.01;
  std::string mass_lumping = "per_tet";   ///< per_tet | equal
  std::vector<std::string> terms{"springs", "dampers", "repulsion", "volume"};
  double nonlinear_threshold = 0.0;       ///< 0 = off
  /// explicit_euler | symplectic_euler | velocity_verlet | backward_euler | bdf2
  /// (implicit) | cvode (SUNDIALS BDF, adaptive; the time-exact reference of
  /// the time-error study)
  std::string integrator = "symplectic_euler";
  int threads = 1;                        ///< force-evaluation threads (results identical for every count)
  std::string forces = "engine";          ///< engine or reference (the per-tet loop)
  double dt = 0.0;                        ///< s; fixed-step integrators
  double rtol = 1e-8, atol = 1e-10;       ///< cvode: relative, absolute on positions (m)
  /// backward_euler: Newton's relative tolerance, iterations, step halvings (msd::NewtonOptions)
  double newton_tolerance = 1e-8;
  int newton_max_iterations = 20, newton_max_step_cuts = 6;
  bool newton_reuse_factorization = true;  ///< modified Newton (msd::NewtonOptions)
  std::string newton_linear_solver = "sparse_lu";  ///< sparse_lu | symmetric_ldlt (msd::LinearSolver)
  bool newton_keep_orientation = false;  ///< every accepted iterate keeps every tet's orientation (msd::NewtonOptions)
  int newton_anderson_depth = 0;         ///< Anderson acceleration of the chord steps (msd::NewtonOptions)
  std::string continuum_volume = "per_tet";  ///< per_tet | per_cube: the neo_hookean term's volume ratio (per cube: mean dilatation)
  /// msd.edge_classes.CLASS.{stiffness, tension_exponent, compression_exponent}:
  /// each edge class's factor on k_s and its spring law (msd/forces/spring_law.hpp),
  /// in msd::EdgeClass order; the default is the thesis' spring on every class.
  std::array<msd::SpringLaw, msd::kEdgeClasses> edge_laws{};
};

/// Settings of the finite-element reference solver.
struct FemSpec {
  std::string formulation = "three_field";  ///< three_field | displacement
  unsigned degree = 1;
  unsigned refinement = 0;
  std::optional<std::array<unsigned, 3>> cells;  ///< coarse cells (default from mesh.spacing)
  std::string linear_solver = "direct";     ///< direct | amg
  double residual_tolerance = 1e-9;
  double increment_tolerance = 1e-9;
  unsigned max_iterations = 25;
  unsigned max_cuts = 8;
  double max_increment = 0.0;               ///< load-time units; 0 = one per output interval
  double relative_tolerance = 1e-6;         ///< dynamics (SUNDIALS IDA)
  double absolute_tolerance = 1e-12;
  double rayleigh_mass = 0.0;               ///< 1/s
  /// Indentation: contact penalty as a multiple of E / h_e (h_e the element
  /// size over the degree); the penetration is about pressure / penalty.
  double contact_penalty = 100.0;
  bool vtu = true;
};

struct LoadingSpec {
  Loading type = Loading::Uniaxial;
  std::string fixed = "bottom";           ///< static: the clamped face
  std::string traction_face;              ///< static: face carrying `traction` (empty: none)
  Eigen::Vector3d traction{Eigen::Vector3d::Zero()};  ///< static: total force, N
  std::string platens = "bonded";         ///< uniaxial: bonded | frictionless
  std::string boundary = "platens";       ///< simple_shear: platens | homogeneous (fem only)
  /// (time s, value): nominal strain (uniaxial), shear strain gamma
  /// (simple_shear), load factor (cooks_membrane, static: scales the traction
  /// and gravity).
  std::vector<std::pair<double, double>> path;
  double force = 0.0;                     ///< cooks_membrane: total shear force, N
  std::string initial = "axial_mode";     ///< vibration: axial_mode | axial_stretch | preload
  double release = 0.0;                   ///< vibration with preload: release time, s
  double amplitude = 0.0;                 ///< vibration: strain amplitude
  double duration = 0.0;                  ///< vibration: s
  Eigen::Vector3d gravity{Eigen::Vector3d::Zero()};
  /// indentation: a rigid cylinder along `indenter_axis` (x | y), touching the
  /// top face above its centre at rest, pressed down by depth * path(t); the
  /// bottom face is bonded. `indenter_response` is the MSD contact response
  /// (stick, the thesis' | frictionless); the FEM contact is frictionless.
  double indenter_radius = 0.0;           ///< m
  double indenter_depth = 0.0;            ///< m, where path = 1
  std::string indenter_axis = "y";
  std::string indenter_response = "stick";
};

struct OutputSpec {
  double interval = 0.01;                 ///< s between samples
  double fields_interval = 0.0;           ///< s between /fields frames; 0: every sample
};

struct Spec {
  std::string name, description;
  std::string path;   ///< file it was read from ("" for text)
  std::string text;   ///< the YAML text, stored verbatim in every results file
  GeometrySpec geometry;
  std::optional<MeshSpec> mesh;   ///< the MSD cubic grid (needed by the msd solver)
  MaterialSpec material;
  std::optional<MsdSpec> msd;     ///< needed by the msd solver
  FemSpec fem;
  LoadingSpec loading;
  OutputSpec output;
};

/// Every field of a spec, declared once (path, unit, default, range, doc);
/// benchmarks/specs/README.md's field table is generated from it.
const std::vector<tbio::Parameter>& spec_parameters();
/// The declaration at `path` (throws std::logic_error if none: a reader's typo).
const tbio::Parameter& spec_parameter(const std::string& path);

/// Reads and validates a spec file. Throws msd::Error with file:line context.
Spec load_spec(const std::string& path);

/// Parses spec text; `source` names it in messages and resolves relative paths.
Spec parse_spec(const std::string& text, const std::string& source);

/// The msd fields of Newton's method, meaningful only with an implicit
/// integrator (backward_euler, bdf2, quasi_static; msd::is_implicit).
const std::vector<std::string>& newton_fields();

/// Whether the msd section steps with a fixed explicit step (not CVODE's own
/// steps, not an implicit integrator's).
bool has_explicit_step(const MsdSpec& msd);

/// Load factor of a vibration preload (loading.initial: preload) as way-points
/// (time s, factor): 0 -> 1 over the first half of [0, release] along the
/// smooth ramp (1 - cos(pi t / T)) / 2 in 16 linear pieces, held to the
/// release, removed there, 0 to release + duration. A dynamic solver (the MSD
/// model) is left ringing at the release by about 1/(omega T) of the static
/// stretch after a linear ramp and by about (pi / omega T)^2 after a smooth
/// one; the FEM solves the preload quasi-statically, where only the end counts.
std::vector<std::pair<double, double>> preload_path(const LoadingSpec& loading);

}  // namespace bench
