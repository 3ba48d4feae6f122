// The finite-element reference solver: 3-D total-Lagrangian finite-strain
// hyperelasticity (deal.II 9.4, SUNDIALS IDA for dynamics). This header is the
// whole public interface and includes no deal.II header, so benchmarks/ and
// apps/ can use the solver without paying for deal.II's compile times.
//
// Strain energy (compressible, decoupled neo-Hookean), with C = F^T F,
// J = det F, I1 = tr C:
//     Psi(F) = mu/2 (J^(-2/3) I1 - 3) + kappa/4 (J^2 - 1 - 2 ln J)
// Formulations:
//  - Displacement: Psi evaluated pointwise (Q_k elements; locks when nearly
//    incompressible, kept to show it);
//  - ThreeField: Hu-Washizu u-p-J~ with p and J~ discontinuous of degree k-1 on
//    each cell (Q_k-P_{k-1}-P_{k-1}, the element family of deal.II's step-44),
//    statically condensed: the volumetric energy uses J~, the cell-wise L2
//    projection of J (Simo, Taylor & Pister 1985; for k = 1 the mean-dilatation
//    method). Does not lock up to nu = 0.4999.
#pragma once

#include <array>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fem {

/// Owns MPI (and what deal.II, PETSc and Trilinos need of it) for the process.
/// Create exactly one, first thing in main(); everything else in fem needs it.
class Session {
 public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  static int rank();
  static int size();
  /// Waits until every process arrives (MPI_Barrier on the world communicator).
  static void barrier();
  /// The process id of rank 0, the same on every process (MPI_Bcast): names
  /// a temporary that all processes share.
  static long root_pid();
  /// Rank 0's `text` on every process (MPI_Bcast); every process must call it.
  static std::string broadcast(const std::string& text);
};

/// The deal.II version the solver was built with (e.g. "9.4.1").
std::string library_version();

/// Bad input or a solve that cannot go on; the message names what and when.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

enum class Formulation { Displacement, ThreeField };
enum class LinearSolver { Direct, Amg };

struct NeoHookean {
  double mu = 0.0;       ///< shear modulus, Pa
  double kappa = 0.0;    ///< bulk modulus, Pa
  double density = 0.0;  ///< kg/m^3
};

/// Shear and bulk moduli from Young's modulus and Poisson's ratio.
NeoHookean neo_hookean_from(double youngs_modulus, double poisson_ratio, double density);

/// Reference geometry and its coarse mesh. Boundary faces are numbered
/// 0 x-min, 1 x-max, 2 y-min, 3 y-max, 4 z-min (bottom), 5 z-max (top),
/// 6 the curved hull of a cylinder.
struct MeshSpec {
  enum class Shape { Box, Cylinder, CooksMembrane } shape = Shape::Box;
  std::array<double, 3> size{{0, 0, 0}};   ///< box: [0, size]
  double radius = 0.0, height = 0.0;       ///< cylinder: axis z, base at z = 0
  std::array<unsigned, 3> cells{{1, 1, 1}}; ///< coarse subdivisions (box, Cook's x/y);
                                           ///< cylinder: cells[2] layers along z
  unsigned refinement = 0;                 ///< global refinements of the coarse mesh
};

/// A scalar function of time through way-points, piecewise linear, constant
/// outside.
struct Path {
  std::vector<std::pair<double, double>> points{{0.0, 1.0}};
  double operator()(double t) const;
};

/// Prescribed displacement on a face: for every component c with mask[c],
/// u_c(X, t) = (vector_c + sum_J gradient[c][J] X_J) * path(t).
struct Dirichlet {
  int face = 0;
  std::array<bool, 3> mask{{true, true, true}};
  std::array<double, 3> vector{{0, 0, 0}};
  std::array<std::array<double, 3>, 3> gradient{{{{0, 0, 0}}, {{0, 0, 0}}, {{0, 0, 0}}}};
  Path path;
};

/// A dead load: nominal traction total_force / (reference face area) * path(t).
struct Traction {
  int face = 0;
  std::array<double, 3> total_force{{0, 0, 0}};
  Path path;
};

/// The mesh vertex at `point` held fixed in the masked components (removes
/// rigid motions, e.g. between frictionless platens). The mesh must have a
/// vertex there (within 1e-8 of the geometry's size).
struct Pin {
  std::array<double, 3> point{{0, 0, 0}};
  std::array<bool, 3> mask{{true, true, false}};
};

/// A rigid circular cylinder of unbounded length pressed against the body:
/// frictionless penalty contact on the boundary faces `faces`. At a face point
/// with current position x, the axis at c(t) = point + motion * path(t),
/// d = (x - c) - ((x - c) . a) a, r = |d|, n = d / r and penetration
/// g = radius - r, the body receives the nominal traction
///     t = penalty * max(g, 0) * n            (energy penalty/2 g^2 per area),
/// linearised consistently:
///     dt/dx = penalty [ -n n^T + (g / r)(I - a a^T - n n^T) ]   (g > 0).
/// As penalty grows the solution tends to the exact frictionless one with
/// penetration ~ contact pressure / penalty.
struct RigidCylinderContact {
  std::array<double, 3> point{{0, 0, 0}};   ///< a point of the axis at rest, m
  std::array<double, 3> axis{{0, 1, 0}};    ///< unit axis direction
  double radius = 0.0;                      ///< m
  std::array<double, 3> motion{{0, 0, 0}};  ///< displacement of the cylinder where path = 1, m
  Path path;
  double penalty = 0.0;                     ///< Pa/m (traction per penetration)
  std::vector<int> faces{5};                ///< boundary faces tested
};

struct NewtonSettings {
  double residual_tolerance = 1e-9;   ///< |R_free| <= tol * force scale
  double increment_tolerance = 1e-9;  ///< |du| <= tol * max(|u|, 1e-3 L)
  unsigned max_iterations = 25;
  unsigned max_cuts = 8;              ///< halvings of a failed load increment
};

/// Free vibration: an initial displacement - a prescribed axial field, or the
/// static equilibrium under `preload` tractions, solved quasi-statically and
/// reported over [0, release_time] - then the solution evolves from rest at
/// release_time with fixed Dirichlet data and the `tractions` of the problem.
struct Dynamics {
  enum class Initial { Rest, AxialMode, AxialStretch, Preload } initial = Initial::Rest;
  double amplitude = 0.0;          ///< strain amplitude of the initial field
  std::vector<Traction> preload;   ///< Preload: dead loads before the release
  double release_time = 0.0;       ///< s; dynamics start here
  double end_time = 0.0;           ///< s
  double rayleigh_mass = 0.0;      ///< C = a M + b K0
  double rayleigh_stiffness = 0.0;
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 1e-12;
};

struct Problem {
  MeshSpec mesh;
  unsigned degree = 1;
  Formulation formulation = Formulation::ThreeField;
  NeoHookean material;
  std::vector<Dirichlet> dirichlet;
  std::vector<Traction> tractions;
  std::vector<Pin> pins;
  std::vector<RigidCylinderContact> contacts;
  bool plane_strain = false;               ///< u_z = 0 everywhere
  std::array<double, 3> gravity{{0, 0, 0}};
  Path gravity_path;                       ///< scales gravity with the load time (default 1)
  LinearSolver linear_solver = LinearSolver::Direct;
  NewtonSettings newton;
  /// Quasi-static: the load parameter values ("times") at which to report;
  /// increments between them may be cut on failure.
  std::vector<double> report_times;
  double max_increment = 0.0;              ///< 0: one increment per report interval
  bool dynamic = false;
  Dynamics dynamics;
  double report_interval = 0.0;            ///< dynamics: s between reports
  std::vector<int> reaction_faces;         ///< faces whose reaction force is reported
  std::vector<std::array<double, 3>> probes;  ///< reference points whose displacement is reported
  /// Reference points where the displacement field is evaluated at every
  /// field frame (e.g. the MSD model's nodes); NaN where outside the mesh.
  std::vector<std::array<double, 3>> field_probes;
  std::string vtu_directory;               ///< non-empty: write VTU/PVD there
  std::string vtu_basename = "solution";
  double fields_interval = 0.0;            ///< 0: surface/VTU at every report
};

/// Everything measured at one report time. Rank 0 holds the values.
struct Report {
  double time = 0.0;
  unsigned newton_iterations = 0;          ///< since the previous report
  unsigned cuts = 0;                       ///< increment halvings since the previous report
  std::vector<std::array<double, 3>> reactions;    ///< per reaction face: the force the
                                                   ///< support applies to the body, i.e. the
                                                   ///< residual f_int - f_ext summed over the
                                                   ///< face's DoFs, N
  std::vector<double> reaction_areas;      ///< reference area of each reaction face, m^2
  std::vector<std::array<double, 3>> probe_displacements;
  double volume_ratio = 1.0;               ///< integral of J over the rest volume
  std::array<double, 6> mean_cauchy{{0, 0, 0, 0, 0, 0}};  ///< volume average, xx yy zz yz xz xy
  double kinetic_energy = 0.0;             ///< dynamics
  double min_jacobian = 1.0;               ///< smallest J at a quadrature point
  /// Stored energy: the strain energy (with J~ in the volumetric part for
  /// ThreeField) plus the contact penalty energy, J.
  double stored_energy = 0.0;
  /// Per contact: the total force the cylinder exerts on the body (N) and the
  /// largest penetration at a face quadrature point (m).
  std::vector<std::array<double, 3>> contact_forces;
  std::vector<double> contact_penetrations;
};

/// The deformed boundary surface: topology once, displacements per frame.
struct Surface {
  std::vector<std::array<double, 3>> points;   ///< reference positions
  std::vector<std::array<int, 3>> triangles;
};

struct Callbacks {
  std::function<void(const Report&)> on_report;
  std::function<void(const Surface&)> on_surface;  ///< once, before the first frame
  std::function<void(double t, const std::vector<std::array<double, 3>>& displacement)> on_frame;
  /// Once per field frame: the displacement at each field probe (rank 0).
  std::function<void(double t, const std::vector<std::array<double, 3>>& displacement)> on_probe_frame;
  std::function<void(double t, double end)> progress;
};

struct Summary {
  unsigned long dofs = 0;
  unsigned long cells = 0;
  unsigned processes = 1;
  unsigned newton_iterations = 0;
  unsigned increments = 0;
  unsigned cuts = 0;
  unsigned factorizations = 0;        ///< tangent factorizations (or AMG set-ups)
  unsigned long time_steps = 0;       ///< dynamics: IDA steps
  double wall_seconds = 0.0;
  double assembly_seconds = 0.0;
  double linear_solver_seconds = 0.0;
  double reference_volume = 0.0;
  std::vector<double> face_areas;     ///< reference areas of reaction_faces
  std::vector<std::array<double, 3>> probe_vertices;  ///< the vertex standing for each probe
  std::vector<std::string> vtu_files; ///< PVD record and per-frame files
};

/// A solve that failed after all retries: when it failed, and the statistics
/// of the work done up to then.
class SolveError : public Error {
 public:
  SolveError(const std::string& what, double when, Summary partial)
      : Error(what), time(when), summary(std::move(partial)) {}
  double time;
  Summary summary;
};

/// Runs the problem. Throws fem::Error for bad input (before any callback) and
/// fem::SolveError when a solve fails after all retries (after the reports so
/// far).
Summary solve(const Problem& problem, const Callbacks& callbacks);

}  // namespace fem
