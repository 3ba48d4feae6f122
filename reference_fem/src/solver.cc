// The FEM reference solver, written as a literate program in the manner of
// deal.II's step-44 (but our own code): setup, constraints, assembly of the
// residual and consistent tangent for both formulations, the quasi-static
// Newton loop with load-increment cutting, SUNDIALS IDA for dynamics, and the
// measurements and field output every report.
#include "dilatation.h"
#include "mesh.h"
#include "neo_hookean.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_parallel_block_vector.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>
#include <deal.II/sundials/ida.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>

namespace fem {

namespace internal {

using namespace dealii;
using Clock = std::chrono::steady_clock;

namespace LA = TrilinosWrappers;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// u(X) = (vector + gradient X) * scale, the increment of a Dirichlet condition.
class DirichletField : public Function<3> {
 public:
  DirichletField(const Dirichlet& d, double scale) : Function<3>(3), d_(d), scale_(scale) {}
  double value(const Point<3>& p, const unsigned c) const override {
    double v = d_.vector[c];
    for (unsigned j = 0; j < 3; ++j) v += d_.gradient[c][j] * p[j];
    return v * scale_;
  }

 private:
  const Dirichlet& d_;
  double scale_;
};

// @sect3{Assembly data}
// As in step-44: the scratch of one cell's assembly (FE values, work arrays
// and the loads at the assembly's time, reused from cell to cell) and one
// cell's contribution (its matrix and vectors, and its share of the
// measurements), which copy_local_to_global adds to the global system.
struct AssemblyScratch {
  AssemblyScratch(const Mapping<3>& mapping, const FiniteElement<3>& fe, const Quadrature<3>& quad,
                  const Quadrature<2>& face_quad, const LA::MPI::Vector& u_ghost, double time, bool with_matrix)
      : fv(mapping, fe, quad, update_values | update_gradients | update_JxW_values | update_quadrature_points),
        traction_fv(mapping, fe, face_quad, update_values | update_JxW_values),
        contact_fv(mapping, fe, face_quad, update_values | update_JxW_values | update_quadrature_points),
        u(u_ghost),
        t(time),
        matrix(with_matrix),
        comp(fe.n_dofs_per_cell()),
        grad(quad.size()),
        Jq(quad.size()),
        JxWq(quad.size()),
        st(fe.n_dofs_per_cell()),
        face_u(face_quad.size()) {
    for (unsigned a = 0; a < fe.n_dofs_per_cell(); ++a) comp[a] = fe.system_to_component_index(a).first;
  }

  FEValues<3> fv;
  FEFaceValues<3> traction_fv, contact_fv;
  const LA::MPI::Vector& u;  ///< displacement (ghosted)
  double t;                  ///< load time
  bool matrix;               ///< assemble the tangent too
  double mu = 0.0, kappa = 0.0, rho = 0.0;  ///< rho: the density times the gravity path at t
  bool three_field = false;
  std::map<int, Tensor<1, 3>> traction;  ///< nominal traction density by boundary id, at t

  std::vector<unsigned> comp;  ///< each local dof's component
  std::vector<Tensor<2, 3>> grad;
  std::vector<double> Jq, JxWq;
  std::vector<ShapeTerms> st;
  std::vector<Tensor<1, 3>> face_u;
  CellDilatation dil;
  FullMatrix<double> B, GB;
};

struct CellAssembly {
  CellAssembly(unsigned dofs_per_cell, size_t contacts)
      : K(dofs_per_cell, dofs_per_cell),
        f_int(dofs_per_cell),
        f_ext(dofs_per_cell),
        residual(dofs_per_cell),
        dofs(dofs_per_cell),
        contact_penetration(contacts) {}

  FullMatrix<double> K;                         ///< tangent (when assembled)
  Vector<double> f_int, f_ext, residual;        ///< residual = f_ext - f_int
  std::vector<types::global_dof_index> dofs;
  bool valid = true;                            ///< false if some J <= 0
  double min_J = std::numeric_limits<double>::infinity();
  /// The cell's strain-energy terms in the order computed, and its contact
  /// forces per contact quadrature point: added to the global sums one by one
  /// in cell order, they give the serial loop's sums exactly.
  std::vector<double> energy;
  std::vector<std::pair<size_t, Tensor<1, 3>>> contact_force;
  std::vector<double> contact_penetration;      ///< per contact, the largest on the cell

  void reset() {
    K = 0.0;
    f_int = 0.0;
    f_ext = 0.0;
    valid = true;
    min_J = std::numeric_limits<double>::infinity();
    energy.clear();
    contact_force.clear();
    std::fill(contact_penetration.begin(), contact_penetration.end(), 0.0);
  }
};

// Empty (closed) constraints: distributes the unconstrained vectors.
const AffineConstraints<double>& no_constraints() {
  static const AffineConstraints<double> none = [] {
    AffineConstraints<double> c;
    c.close();
    return c;
  }();
  return none;
}

// @sect3{The solver}
class Solver {
 public:
  Solver(const Problem& problem, const Callbacks& callbacks);
  Summary run();

 private:
  // @sect4{Set-up}
  void check_problem() const;
  void setup();
  void find_vertices();
  std::vector<types::global_dof_index> vertex_dofs(const Point<3>& p, unsigned component) const;
  /// Constraints on increments: Dirichlet data change from t0 to t1 (zero when
  /// `inhomogeneous` is false), pins and plane strain.
  AffineConstraints<double> make_constraints(double t0, double t1, bool inhomogeneous) const;

  // @sect4{Assembly}
  struct Assembled {
    bool valid = true;       ///< false if some J <= 0
    double min_J = 1.0;
    double strain_energy = 0.0;  ///< integral of Psi (with J~ in U for ThreeField), J
  };
  /// Assembles, at displacement u (ghosted) and load time t: the tangent (if
  /// `matrix`), the constrained right-hand side -(f_int - f_ext), and the
  /// unconstrained vectors f_int_full and f_ext_full.
  Assembled assemble(const LA::MPI::Vector& u, double t, const AffineConstraints<double>& c, bool matrix);
  /// One cell's matrix and vectors (step-44's assemble_system_one_cell).
  void assemble_one_cell(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                         CellAssembly& data) const;
  void add_volume_terms(AssemblyScratch& s, CellAssembly& data) const;
  void add_dead_surface_loads(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                              CellAssembly& data) const;
  void add_cylinder_contact(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                            CellAssembly& data) const;
  /// Adds a cell's contribution to K and rhs through the constraints c, to
  /// f_int_full and f_ext_full unconstrained, and to the measurements.
  void copy_local_to_global(const CellAssembly& data, const AffineConstraints<double>& c, bool matrix,
                            Assembled& result);
  void assemble_mass_matrix();

  // @sect4{Linear solves}
  /// Prepares solves with A: a sparse direct factorization, or an AMG
  /// preconditioner for CG. Later solve_prepared() calls reuse it.
  void prepare_solver(LA::SparseMatrix& A);
  void solve_prepared(LA::SparseMatrix& A, LA::MPI::Vector& x, const LA::MPI::Vector& b);
  /// prepare_solver + solve_prepared.
  void solve_linear(LA::SparseMatrix& A, LA::MPI::Vector& x, const LA::MPI::Vector& b);

  // @sect4{Quasi-static and dynamic drivers}
  void run_quasi_static(const std::vector<double>& report_times);
  /// Report times of the preload phase: every report interval up to the release.
  std::vector<double> preload_times() const;
  bool newton_increment(double t0, double t1, unsigned& iterations);
  void run_dynamic();

  // @sect4{Measurements and output}
  Report measure(double t, const LA::MPI::Vector& u, const LA::MPI::Vector* velocity);
  void write_fields(double t, const LA::MPI::Vector& u_ghost);
  void gather_surface(const LA::MPI::Vector& u_ghost, bool topology, double t);
  /// Locates the field probes in locally owned cells (set-up) and evaluates
  /// the displacement there (every field frame).
  void locate_field_probes();
  void evaluate_field_probes(const LA::MPI::Vector& u_ghost, double t);

  struct LocatedProbe {
    unsigned index;
    std::vector<types::global_dof_index> dofs;
    std::vector<double> shape;  // shape values at the probe's unit point, by local dof
  };
  std::vector<LocatedProbe> located;

  const Problem& P;
  const Callbacks& cb;
  MPI_Comm comm = MPI_COMM_WORLD;
  parallel::distributed::Triangulation<3> tria;
  FESystem<3> fe;
  DoFHandler<3> dof;
  MappingQ<3> mapping;
  QGauss<3> quad;
  QGauss<2> face_quad;
  IndexSet owned, relevant;
  double length = 1.0;

  LA::SparseMatrix K, M, C, K_eff;
  LA::MPI::Vector rhs, f_int_full, f_ext_full, u_owned;
  AffineConstraints<double> zero_constraints;
  SolverControl direct_control{1, 0};  // outlives `direct`, which keeps a reference
  std::unique_ptr<LA::SolverDirect> direct;
  std::unique_ptr<LA::PreconditionAMG> amg;
  bool factorized = false;  // a tangent factorisation from an earlier iteration exists

  std::vector<std::vector<IndexSet>> face_dofs;  // [reaction face][component], owned
  std::vector<double> face_area;                 // by boundary id 0..6
  double reference_volume = 0.0;
  std::vector<Point<3>> probe_points, pin_points;

  Summary summary;
  std::vector<Traction> active_tractions;  // the dead surface loads in force now
  // Contact forces on the body and largest penetrations of the last assembly.
  std::vector<std::array<double, 3>> contact_force;
  std::vector<double> contact_penetration;
  double last_min_J = 1.0;
  unsigned newton_since_report = 0, cuts_since_report = 0;
  double next_fields_time = 0.0;
  unsigned frame = 0;
  std::vector<std::pair<double, std::string>> pvd_records;
  std::map<std::array<long long, 3>, int> surface_index;
  bool surface_sent = false;
  Clock::time_point start;
};

Solver::Solver(const Problem& problem, const Callbacks& callbacks)
    : P(problem), cb(callbacks), tria(MPI_COMM_WORLD), fe(FE_Q<3>(std::max(1u, problem.degree)), 3),
      dof(tria), mapping(std::max(1u, problem.degree)), quad(std::max(1u, problem.degree) + 1),
      face_quad(std::max(1u, problem.degree) + 1) {}

// @sect4{Input checks}
// Every request the solver cannot honour is refused here, before any output.
void Solver::check_problem() const {
  if (P.degree < 1 || P.degree > 3) throw Error("fem: element degree must be 1, 2 or 3");
  if (!(P.material.mu > 0.0)) throw Error("fem: shear modulus mu must be positive");
  if (!(P.material.kappa > 0.0)) throw Error("fem: bulk modulus kappa must be positive");
  if (!(P.material.density > 0.0)) throw Error("fem: density must be positive");
  for (const auto& d : P.dirichlet)
    if (d.face < 0 || d.face > 6) throw Error("fem: Dirichlet face id must be 0..6");
  for (const auto& t : P.tractions)
    if (t.face < 0 || t.face > 6) throw Error("fem: traction face id must be 0..6");
  if (P.dynamic) {
    if (!(P.dynamics.end_time > 0.0)) throw Error("fem: dynamics needs a positive end time");
    if (!(P.report_interval > 0.0)) throw Error("fem: dynamics needs a positive report interval");
    for (const auto& d : P.dirichlet)
      for (int c = 0; c < 3; ++c) {
        bool moving = d.vector[c] != 0.0;
        for (int j = 0; j < 3; ++j) moving = moving || d.gradient[c][j] != 0.0;
        if (moving) throw Error("fem: dynamics supports fixed (zero) Dirichlet data only");
      }
  } else if (P.report_times.empty()) {
    throw Error("fem: no report times");
  }
  for (const auto& c : P.contacts) {
    const double an = std::sqrt(c.axis[0] * c.axis[0] + c.axis[1] * c.axis[1] + c.axis[2] * c.axis[2]);
    if (std::abs(an - 1.0) > 1e-9) throw Error("fem: a contact cylinder's axis must be a unit vector");
    if (!(c.radius > 0.0)) throw Error("fem: a contact cylinder's radius must be positive");
    if (!(c.penalty > 0.0)) throw Error("fem: a contact penalty must be positive");
    for (int f : c.faces)
      if (f < 0 || f > 6) throw Error("fem: contact face id must be 0..6");
  }
  if (P.dirichlet.empty() && P.pins.empty())
    throw Error("fem: the problem has no Dirichlet condition (rigid motions are free)");
}

// @sect4{Set-up}
void Solver::setup() {
  make_mesh(tria, P.mesh);
  length = characteristic_length(P.mesh);
  dof.distribute_dofs(fe);
  owned = dof.locally_owned_dofs();
  DoFTools::extract_locally_relevant_dofs(dof, relevant);
  find_vertices();

  zero_constraints = make_constraints(0.0, 0.0, false);
  LA::SparsityPattern sp(owned, owned, relevant, comm);
  DoFTools::make_sparsity_pattern(dof, sp, zero_constraints, false, Utilities::MPI::this_mpi_process(comm));
  sp.compress();
  K.reinit(sp);
  rhs.reinit(owned, comm);
  f_int_full.reinit(owned, comm);
  f_ext_full.reinit(owned, comm);
  u_owned.reinit(owned, comm);
  if (P.dynamic) {
    M.reinit(sp);
    C.reinit(sp);
    K_eff.reinit(sp);
  }

  // Reaction faces: the owned DoFs of each component, and the face areas.
  for (int f : P.reaction_faces) {
    std::vector<IndexSet> per_component;
    for (unsigned c = 0; c < 3; ++c) {
      ComponentMask mask(3, false);
      mask.set(c, true);
      IndexSet s = DoFTools::extract_boundary_dofs(dof, mask, {static_cast<types::boundary_id>(f)});
      s = s & owned;
      per_component.push_back(s);
    }
    face_dofs.push_back(per_component);
  }
  FEFaceValues<3> fv(mapping, fe, face_quad, update_JxW_values);
  FEValues<3> cv(mapping, fe, quad, update_JxW_values);
  std::vector<double> areas(7, 0.0);
  double volume = 0.0;
  for (const auto& cell : dof.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    cv.reinit(cell);
    for (unsigned q = 0; q < quad.size(); ++q) volume += cv.JxW(q);
    for (unsigned f = 0; f < cell->n_faces(); ++f) {
      if (!cell->face(f)->at_boundary()) continue;
      const auto id = cell->face(f)->boundary_id();
      if (id > 6) continue;
      fv.reinit(cell, f);
      for (unsigned q = 0; q < face_quad.size(); ++q) areas[id] += fv.JxW(q);
    }
  }
  face_area.resize(areas.size());
  for (size_t k = 0; k < areas.size(); ++k) face_area[k] = Utilities::MPI::sum(areas[k], comm);
  reference_volume = Utilities::MPI::sum(volume, comm);
  for (const auto& t : P.tractions)
    if (!(face_area[static_cast<size_t>(t.face)] > 0.0))
      throw Error("fem: the geometry has no face " + std::to_string(t.face) + " to carry a traction");
  for (const auto& d : P.dirichlet)
    if (!(face_area[static_cast<size_t>(d.face)] > 0.0))
      throw Error("fem: the geometry has no face " + std::to_string(d.face) + " for a Dirichlet condition");
  summary.dofs = dof.n_dofs();
  summary.cells = tria.n_global_active_cells();
  summary.processes = Utilities::MPI::n_mpi_processes(comm);
  summary.reference_volume = reference_volume;
  locate_field_probes();
  for (int f : P.reaction_faces) summary.face_areas.push_back(face_area[static_cast<size_t>(f)]);
  for (const auto& p : probe_points) summary.probe_vertices.push_back({{p[0], p[1], p[2]}});
}

// Probes and pins name points; the nearest mesh vertex (over all processes,
// ties broken by coordinates) stands for each.
void Solver::find_vertices() {
  auto nearest = [&](const std::array<double, 3>& target) {
    const Point<3> p(target[0], target[1], target[2]);
    std::array<double, 4> best{{1e300, 0, 0, 0}};
    for (const auto& cell : tria.active_cell_iterators()) {
      if (cell->is_artificial()) continue;
      for (unsigned v = 0; v < cell->n_vertices(); ++v) {
        const double d = cell->vertex(v).distance(p);
        if (d < best[0]) best = {{d, cell->vertex(v)[0], cell->vertex(v)[1], cell->vertex(v)[2]}};
      }
    }
    const auto all = Utilities::MPI::all_gather(comm, best);
    const auto it = std::min_element(all.begin(), all.end());
    return Point<3>((*it)[1], (*it)[2], (*it)[3]);
  };
  for (const auto& p : P.probes) probe_points.push_back(nearest(p));
  for (const auto& p : P.pins) {
    const Point<3> v = nearest(p.point);
    if (v.distance(Point<3>(p.point[0], p.point[1], p.point[2])) > 1e-8 * length)
      throw Error("fem: no mesh vertex at the pin point (" + std::to_string(p.point[0]) + ", " +
                  std::to_string(p.point[1]) + ", " + std::to_string(p.point[2]) +
                  "); refine the mesh or change the cell counts");
    pin_points.push_back(v);
  }
}

std::vector<types::global_dof_index> Solver::vertex_dofs(const Point<3>& p, unsigned component) const {
  std::vector<types::global_dof_index> out;
  const double tol = 1e-10 * length;
  for (const auto& cell : dof.active_cell_iterators()) {
    if (cell->is_artificial()) continue;
    for (unsigned v = 0; v < cell->n_vertices(); ++v)
      if (cell->vertex(v).distance(p) < tol) out.push_back(cell->vertex_dof_index(v, component));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// @sect4{Constraints}
// Dirichlet data enter the first Newton iteration of an increment as the
// change u_D(t1) - u_D(t0); later iterations and all Jacobian solves use zero.
AffineConstraints<double> Solver::make_constraints(double t0, double t1, bool inhomogeneous) const {
  AffineConstraints<double> c;
  c.reinit(relevant);
  for (const auto& d : P.dirichlet) {
    const double dv = inhomogeneous ? d.path(t1) - d.path(t0) : 0.0;
    const ComponentMask mask(std::vector<bool>{d.mask[0], d.mask[1], d.mask[2]});
    const DirichletField field(d, dv);
    VectorTools::interpolate_boundary_values(mapping, dof, static_cast<types::boundary_id>(d.face), field, c,
                                             mask);
  }
  for (size_t k = 0; k < pin_points.size(); ++k)
    for (unsigned comp = 0; comp < 3; ++comp)
      if (P.pins[k].mask[comp])
        for (auto i : vertex_dofs(pin_points[k], comp))
          if (!c.is_constrained(i)) c.add_line(i);
  if (P.plane_strain) {
    std::vector<types::global_dof_index> ids(fe.n_dofs_per_cell());
    for (const auto& cell : dof.active_cell_iterators()) {
      if (cell->is_artificial()) continue;
      cell->get_dof_indices(ids);
      for (unsigned a = 0; a < ids.size(); ++a)
        if (fe.system_to_component_index(a).first == 2 && !c.is_constrained(ids[a])) c.add_line(ids[a]);
    }
  }
  c.close();
  return c;
}

// @sect4{Assembly}
// Per cell and quadrature point: F = I + Grad u; the isochoric stress and
// tangent from neo_hookean.h; the volumetric part either pointwise
// (Displacement) or through the cell's J~ = v/V (ThreeField, p and J~
// condensed):
//   R_a  = int P_iso : G_a dV + p~ int J F^-T : G_a dV,
//   K_ab = int G_a : A_iso : G_b dV + p~ int G_a : d(J F^-T)/dF : G_b dV
//          + U''(J~) / V  b_a b_b,        b_a = int J F^-T : G_a dV.
Solver::Assembled Solver::assemble(const LA::MPI::Vector& u, double t, const AffineConstraints<double>& c,
                                   bool matrix) {
  const auto t_start = Clock::now();
  if (matrix) K = 0.0;
  rhs = 0.0;
  f_int_full = 0.0;
  f_ext_full = 0.0;
  contact_force.assign(P.contacts.size(), {{0, 0, 0}});
  contact_penetration.assign(P.contacts.size(), 0.0);
  AssemblyScratch scratch(mapping, fe, quad, face_quad, u, t, matrix);
  scratch.mu = P.material.mu;
  scratch.kappa = P.material.kappa;
  scratch.rho = P.material.density * P.gravity_path(t);
  scratch.three_field = P.formulation == Formulation::ThreeField;
  // Traction densities (nominal) per face.
  for (const auto& tr : active_tractions) {
    const double area = face_area[static_cast<size_t>(tr.face)];
    Tensor<1, 3> td;
    for (unsigned i = 0; i < 3; ++i) td[i] = tr.total_force[i] * tr.path(t) / area;
    scratch.traction[tr.face] += td;
  }
  CellAssembly data(fe.n_dofs_per_cell(), P.contacts.size());
  Assembled result;
  for (const auto& cell : dof.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    assemble_one_cell(cell, scratch, data);
    copy_local_to_global(data, c, matrix, result);
  }
  if (matrix) K.compress(VectorOperation::add);
  rhs.compress(VectorOperation::add);
  f_int_full.compress(VectorOperation::add);
  f_ext_full.compress(VectorOperation::add);
  result.valid = Utilities::MPI::min(result.valid ? 1 : 0, comm) == 1;
  result.min_J = Utilities::MPI::min(result.min_J, comm);
  result.strain_energy = Utilities::MPI::sum(result.strain_energy, comm);
  for (size_t k = 0; k < P.contacts.size(); ++k) {
    for (unsigned i = 0; i < 3; ++i) contact_force[k][i] = Utilities::MPI::sum(contact_force[k][i], comm);
    contact_penetration[k] = Utilities::MPI::max(contact_penetration[k], comm);
  }
  summary.assembly_seconds += seconds_since(t_start);
  return result;
}

void Solver::assemble_one_cell(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                               CellAssembly& data) const {
  data.reset();
  s.fv.reinit(cell);
  cell->get_dof_indices(data.dofs);
  add_volume_terms(s, data);
  add_dead_surface_loads(cell, s, data);
  add_cylinder_contact(cell, s, data);
  for (unsigned a = 0; a < fe.n_dofs_per_cell(); ++a) data.residual[a] = data.f_ext[a] - data.f_int[a];
}

// The volume terms at the cell's quadrature points: internal forces, weight,
// tangent and strain energy. The condensed volumetric state of the
// three-field formulation (P_{k-1} dilatation and pressure, dilatation.h)
// enters through p~ and B^T G B.
void Solver::add_volume_terms(AssemblyScratch& s, CellAssembly& data) const {
  const unsigned n = fe.n_dofs_per_cell(), nq = quad.size();
  const FEValuesExtractors::Vector disp(0);
  const FEValues<3>& fv = s.fv;
  const double mu = s.mu, kappa = s.kappa, rho = s.rho;
  const bool three_field = s.three_field, matrix = s.matrix;
  CellDilatation& dil = s.dil;
  FullMatrix<double>& Ke = data.K;
  fv[disp].get_function_gradients(s.u, s.grad);
  for (unsigned q = 0; q < nq; ++q) {
    s.Jq[q] = determinant(unit_symmetric_tensor<3>() + s.grad[q]);
    s.JxWq[q] = fv.JxW(q);
  }
  if (three_field) {
    dil.reinit(P.degree - 1, fv.get_quadrature_points(), s.JxWq);
    if (!dil.compute(s.Jq, kappa)) data.valid = false;
    data.energy.push_back(dil.energy());
    s.B.reinit(dil.size(), n);
  }
  for (unsigned q = 0; q < nq; ++q) {
    const Kinematics k(s.grad[q]);
    data.min_J = std::min(data.min_J, k.J);
    if (!(k.J > 0.0)) {
      data.valid = false;
      continue;
    }
    const double JxW = fv.JxW(q);
    const double p = three_field ? dil.pressure(q) : dU(kappa, k.J);
    data.energy.push_back((psi_iso(mu, k) + (three_field ? 0.0 : U(kappa, k.J))) * JxW);
    const Tensor<2, 3> Piso = P_iso(mu, k);
    for (unsigned a = 0; a < n; ++a) s.st[a] = shape_terms(k, fv.shape_grad_component(a, q, s.comp[a]), s.comp[a]);
    for (unsigned a = 0; a < n; ++a) {
      const auto& A = s.st[a];
      data.f_int[a] += ((Piso * A.g)[A.c] + p * k.J * A.h[A.c]) * JxW;
      data.f_ext[a] += rho * P.gravity[A.c] * fv.shape_value_component(a, q, A.c) * JxW;
      if (three_field)
        for (unsigned l = 0; l < dil.size(); ++l) s.B(l, a) += dil.phi(q, l) * k.J * A.h[A.c] * JxW;
      if (!matrix) continue;
      for (unsigned bb = 0; bb <= a; ++bb) {
        const auto& Bs = s.st[bb];
        double kab = iso_tangent(mu, k, A, Bs) + p * dJFinvT(k, A, Bs);
        if (!three_field) kab += ddU(kappa, k.J) * k.J * k.J * A.h[A.c] * Bs.h[Bs.c];
        Ke(a, bb) += kab * JxW;
      }
    }
  }
  if (!matrix) return;
  if (three_field) {
    // B^T G B (the condensed volumetric stiffness).
    s.GB.reinit(dil.size(), n);
    dil.G().mmult(s.GB, s.B);
    for (unsigned a = 0; a < n; ++a)
      for (unsigned bb = 0; bb <= a; ++bb) {
        double sum = 0.0;
        for (unsigned l = 0; l < dil.size(); ++l) sum += s.B(l, a) * s.GB(l, bb);
        Ke(a, bb) += sum;
      }
  }
  for (unsigned a = 0; a < n; ++a)
    for (unsigned bb = 0; bb < a; ++bb) Ke(bb, a) = Ke(a, bb);
}

// Dead surface loads: the nominal traction densities on the cell's boundary
// faces.
void Solver::add_dead_surface_loads(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                                    CellAssembly& data) const {
  if (s.traction.empty()) return;
  const unsigned n = fe.n_dofs_per_cell();
  for (unsigned f = 0; f < cell->n_faces(); ++f) {
    if (!cell->face(f)->at_boundary()) continue;
    const auto it = s.traction.find(cell->face(f)->boundary_id());
    if (it == s.traction.end()) continue;
    s.traction_fv.reinit(cell, f);
    for (unsigned q = 0; q < face_quad.size(); ++q)
      for (unsigned a = 0; a < n; ++a)
        data.f_ext[a] += it->second[s.comp[a]] * s.traction_fv.shape_value_component(a, q, s.comp[a]) *
                         s.traction_fv.JxW(q);
  }
}

// Penalty contact with rigid cylinders (fem.hpp, RigidCylinderContact): the
// traction enters f_int with a minus sign (it depends on u, unlike the dead
// loads), its energy the strain energy (the line search's merit).
void Solver::add_cylinder_contact(const DoFHandler<3>::active_cell_iterator& cell, AssemblyScratch& s,
                                  CellAssembly& data) const {
  const unsigned n = fe.n_dofs_per_cell();
  const FEValuesExtractors::Vector disp(0);
  FEFaceValues<3>& contact_fv = s.contact_fv;
  const std::vector<unsigned>& comp = s.comp;
  FullMatrix<double>& Ke = data.K;
  for (size_t k = 0; k < P.contacts.size(); ++k) {
    const RigidCylinderContact& rc = P.contacts[k];
    Tensor<1, 3> ax, centre;
    for (unsigned i = 0; i < 3; ++i) {
      ax[i] = rc.axis[i];
      centre[i] = rc.point[i] + rc.motion[i] * rc.path(s.t);
    }
    for (unsigned f = 0; f < cell->n_faces(); ++f) {
      if (!cell->face(f)->at_boundary()) continue;
      if (std::find(rc.faces.begin(), rc.faces.end(), static_cast<int>(cell->face(f)->boundary_id())) ==
          rc.faces.end())
        continue;
      contact_fv.reinit(cell, f);
      contact_fv[disp].get_function_values(s.u, s.face_u);
      for (unsigned q = 0; q < face_quad.size(); ++q) {
        const Tensor<1, 3> x = contact_fv.quadrature_point(q) + s.face_u[q];
        Tensor<1, 3> d = x - centre;
        d -= (d * ax) * ax;
        const double rr = d.norm(), g = rc.radius - rr;
        if (!(g > 0.0) || !(rr > 0.0)) continue;
        const Tensor<1, 3> nrm = d / rr;
        const double JxW = contact_fv.JxW(q), eps = rc.penalty;
        data.energy.push_back(0.5 * eps * g * g * JxW);
        Tensor<1, 3> force;
        for (unsigned i = 0; i < 3; ++i) force[i] = eps * g * nrm[i] * JxW;
        data.contact_force.emplace_back(k, force);
        data.contact_penetration[k] = std::max(data.contact_penetration[k], g);
        for (unsigned a = 0; a < n; ++a) {
          const double Na = contact_fv.shape_value_component(a, q, comp[a]);
          if (Na == 0.0) continue;
          data.f_int[a] -= eps * g * nrm[comp[a]] * Na * JxW;
          if (!s.matrix) continue;
          for (unsigned bb = 0; bb < n; ++bb) {
            const double Nb = contact_fv.shape_value_component(bb, q, comp[bb]);
            if (Nb == 0.0) continue;
            const unsigned i = comp[a], j = comp[bb];
            const double tang = (i == j ? 1.0 : 0.0) - ax[i] * ax[j] - nrm[i] * nrm[j];
            Ke(a, bb) += eps * (nrm[i] * nrm[j] - g / rr * tang) * Na * Nb * JxW;
          }
        }
      }
    }
  }
}

void Solver::copy_local_to_global(const CellAssembly& data, const AffineConstraints<double>& c, bool matrix,
                                  Assembled& result) {
  if (matrix) c.distribute_local_to_global(data.K, data.residual, data.dofs, K, rhs);
  else c.distribute_local_to_global(data.residual, data.dofs, rhs);
  no_constraints().distribute_local_to_global(data.f_int, data.dofs, f_int_full);
  no_constraints().distribute_local_to_global(data.f_ext, data.dofs, f_ext_full);
  result.valid = result.valid && data.valid;
  result.min_J = std::min(result.min_J, data.min_J);
  for (double e : data.energy) result.strain_energy += e;
  for (const auto& [k, force] : data.contact_force)
    for (unsigned i = 0; i < 3; ++i) contact_force[k][i] += force[i];
  for (size_t k = 0; k < data.contact_penetration.size(); ++k)
    contact_penetration[k] = std::max(contact_penetration[k], data.contact_penetration[k]);
}

// Consistent mass matrix M_ab = int rho N_a N_b dV (same component).
void Solver::assemble_mass_matrix() {
  const unsigned n = fe.n_dofs_per_cell(), nq = quad.size();
  FEValues<3> fv(mapping, fe, quad, update_values | update_JxW_values);
  FullMatrix<double> Me(n, n);
  std::vector<types::global_dof_index> ids(n);
  M = 0.0;
  for (const auto& cell : dof.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fv.reinit(cell);
    cell->get_dof_indices(ids);
    Me = 0.0;
    for (unsigned q = 0; q < nq; ++q)
      for (unsigned a = 0; a < n; ++a) {
        const unsigned ca = fe.system_to_component_index(a).first;
        for (unsigned bb = 0; bb < n; ++bb)
          if (fe.system_to_component_index(bb).first == ca)
            Me(a, bb) += P.material.density * fv.shape_value(a, q) * fv.shape_value(bb, q) * fv.JxW(q);
      }
    zero_constraints.distribute_local_to_global(Me, ids, M);
  }
  M.compress(VectorOperation::add);
}

// @sect4{Linear solves}
// Sparse direct (MUMPS through Trilinos Amesos) by default; CG with algebraic
// multigrid (Trilinos ML, rigid translations as near-null space) for large
// problems.
void Solver::prepare_solver(LA::SparseMatrix& A) {
  const auto t0 = Clock::now();
  if (P.linear_solver == LinearSolver::Direct) {
    direct = std::make_unique<LA::SolverDirect>(direct_control,
                                                LA::SolverDirect::AdditionalData(false, "Amesos_Mumps"));
    direct->initialize(A);
  } else {
    amg = std::make_unique<LA::PreconditionAMG>();
    LA::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = P.degree > 1;
    data.smoother_sweeps = 2;
    data.aggregation_threshold = 0.02;
    std::vector<std::vector<bool>> modes;
    DoFTools::extract_constant_modes(dof, ComponentMask(3, true), modes);
    data.constant_modes = modes;
    amg->initialize(A, data);
  }
  ++summary.factorizations;
  factorized = true;
  summary.linear_solver_seconds += seconds_since(t0);
}

void Solver::solve_prepared(LA::SparseMatrix& A, LA::MPI::Vector& x, const LA::MPI::Vector& b) {
  const auto t0 = Clock::now();
  if (P.linear_solver == LinearSolver::Direct) {
    direct->solve(x, b);
  } else {
    SolverControl control(5000, 1e-12 * b.l2_norm() + 1e-300);
    SolverCG<LA::MPI::Vector> cg(control);
    cg.solve(A, x, b, *amg);
  }
  summary.linear_solver_seconds += seconds_since(t0);
}

void Solver::solve_linear(LA::SparseMatrix& A, LA::MPI::Vector& x, const LA::MPI::Vector& b) {
  prepare_solver(A);
  solve_prepared(A, x, b);
}

// @sect4{Quasi-static loading}
// Each increment from t0 to t1 is solved by Newton's method. Convergence:
// |R_free| <= residual_tolerance * max(|f_int|, |f_ext|, 1e-3 mu V0^(2/3)) and the last
// correction |du| <= increment_tolerance * max(|u|, 1e-3 L). An increment whose
// Newton iteration fails (no convergence, a non-positive Jacobian, a linear
// solver failure) is halved, up to max_cuts times.
bool Solver::newton_increment(double t0, double t1, unsigned& iterations) {
  LA::MPI::Vector u(owned, comm), du(owned, comm), trial(owned, comm), u_ghost(owned, relevant, comm);
  u = u_owned;
  const AffineConstraints<double> first = make_constraints(t0, t1, true);
  // Whether the Dirichlet data move must be decided alike on every process
  // (each holds only the constraints of its own part of the mesh).
  const bool moving = Utilities::MPI::max(first.has_inhomogeneities() ? 1 : 0, comm) == 1;
  const double floor = 1e-3 * P.material.mu * std::pow(reference_volume, 2.0 / 3.0);
  const bool debug = std::getenv("TB_FEM_DEBUG") != nullptr;
  auto evaluate = [&](const LA::MPI::Vector& at, bool matrix, const AffineConstraints<double>& c) {
    u_ghost = at;
    return assemble(u_ghost, t1, c, matrix);
  };
  // Predictor: when the Dirichlet data move, one tangent step with the
  // increment imposed, so every later state satisfies them.
  // The tangent factorised in the previous increment is reused when there is
  // one (modified Newton across increments; the line search and the refresh
  // rule below take over if it has gone stale).
  if (moving) {
    if (!evaluate(u, true, first).valid) return false;  // the matrix enters the rhs correction
    du = 0.0;
    try {
      if (!factorized) prepare_solver(K);
      solve_prepared(K, du, rhs);
    } catch (const std::exception&) {
      return false;
    }
    first.distribute(du);
    u += du;
    ++iterations;
  }
  // Total potential energy (dead loads): the line search's merit function.
  auto potential = [&](const Assembled& a, const LA::MPI::Vector& at) { return a.strain_energy - (f_ext_full * at); };
  Assembled now = evaluate(u, false, zero_constraints);
  if (!now.valid) return false;
  double res = rhs.l2_norm(), last_du = 1e300, energy = potential(now, u);
  bool fresh = false, refresh = !moving;
  for (unsigned it = 1; it <= P.newton.max_iterations; ++it) {
    const double scale = std::max({f_int_full.l2_norm(), f_ext_full.l2_norm(), floor});
    const double u_scale = std::max(u.l2_norm(), 1e-3 * length);
    if (debug)
      std::fprintf(stderr, "newton t=%.9g it=%u res=%.3e scale=%.3e du=%.3e\n", t1, it, res, scale, last_du);
    if (!std::isfinite(res)) return false;
    if (res <= P.newton.residual_tolerance * scale &&
        (last_du <= P.newton.increment_tolerance * u_scale || res <= 1e-3 * P.newton.residual_tolerance * scale))
      break;
    if (refresh) {
      if (!evaluate(u, true, zero_constraints).valid) return false;
      try {
        prepare_solver(K);
      } catch (const std::exception&) {
        return false;
      }
      fresh = true;
    }
    du = 0.0;
    try {
      solve_prepared(K, du, rhs);
    } catch (const std::exception&) {
      return false;
    }
    zero_constraints.distribute(du);
    ++iterations;
    // Backtracking line search: accept a step that lowers the total potential
    // energy (Armijo), or - near convergence, where energy differences drown
    // in round-off - one that halves the residual.
    const double slope = -(rhs * du);  // d(energy)/d(step) at step 0
    double step = 1.0, res_trial = 1e300, energy_trial = 0.0;
    bool accepted = false;
    for (int ls = 0; ls < 8 && !accepted; ++ls, step *= 0.5) {
      trial = u;
      trial.add(step, du);
      const Assembled a = evaluate(trial, false, zero_constraints);
      res_trial = rhs.l2_norm();
      energy_trial = potential(a, trial);
      accepted = a.valid && std::isfinite(res_trial) && std::isfinite(energy_trial) &&
                 (energy_trial <= energy + 1e-4 * step * slope + 1e-13 * std::abs(energy) ||
                  res_trial < 0.5 * res);
      if (accepted) last_du = step * du.l2_norm();
    }
    if (!accepted) {
      if (fresh) return false;  // even a fresh tangent gives no descent
      if (!evaluate(u, false, zero_constraints).valid) return false;  // restore rhs at u
      energy = potential(now = evaluate(u, false, zero_constraints), u);
      refresh = true;
      continue;
    }
    // Modified Newton: keep the factorised tangent while it converges fast.
    refresh = res_trial > 0.1 * res;
    fresh = false;
    u = trial;
    res = res_trial;
    energy = energy_trial;
    if (it == P.newton.max_iterations) return false;
  }
  u_owned = u;
  return true;
}

std::vector<double> Solver::preload_times() const {
  std::vector<double> t;
  const double end = P.dynamics.release_time;
  const long n = std::max(1L, std::lround(end / P.report_interval));
  for (long k = 1; k <= n; ++k) t.push_back(end * static_cast<double>(k) / static_cast<double>(n));
  return t;
}

void Solver::run_quasi_static(const std::vector<double>& report_times) {
  double t = 0.0;
  {
    // The reference state, reported at t = 0 (nothing applied yet unless a
    // path starts away from zero).
    const Report r = measure(0.0, u_owned, nullptr);
    if (cb.on_report && Utilities::MPI::this_mpi_process(comm) == 0) cb.on_report(r);
  }
  double step = 0.0;
  for (double target : report_times) {
    if (target < t - 1e-12) throw Error("fem: report times must not decrease");
    while (t < target - 1e-14 * std::max(1.0, std::abs(target))) {
      double dt = target - t;
      if (P.max_increment > 0.0) dt = std::min(dt, P.max_increment);
      if (step > 0.0) dt = std::min(dt, step);
      unsigned cuts = 0;
      for (;;) {
        unsigned iterations = 0;
        const bool ok = newton_increment(t, t + dt, iterations);
        if (!ok) factorized = false;  // retry the halved increment with a fresh tangent
        summary.newton_iterations += iterations;
        newton_since_report += iterations;
        if (ok) break;
        if (++cuts > P.newton.max_cuts) {
          summary.wall_seconds = seconds_since(start);
          throw SolveError("fem: Newton did not converge from load time " + std::to_string(t) + " to " +
                               std::to_string(t + dt) + " after " + std::to_string(P.newton.max_cuts) +
                               " halvings of the increment (smallest J at the last converged state " +
                               std::to_string(last_min_J) + ")",
                           t, summary);
        }
        dt *= 0.5;
        ++summary.cuts;
        ++cuts_since_report;
      }
      t += dt;
      ++summary.increments;
      // Grow back after a success so one hard spot does not slow the rest.
      step = cuts > 0 ? dt : 0.0;
    }
    t = target;
    const Report r = measure(t, u_owned, nullptr);
    last_min_J = r.min_jacobian;
    if (cb.on_report && Utilities::MPI::this_mpi_process(comm) == 0) cb.on_report(r);
    if (cb.progress && Utilities::MPI::this_mpi_process(comm) == 0) cb.progress(t, report_times.back());
  }
}

// @sect4{Dynamics with SUNDIALS IDA}
// y = [u; v], F(t, y, y') = [u' - v ; M v' + C v + f_int(u) - f_ext(t)], with
// C = a M + b K0 (Rayleigh, K0 the tangent at the initial state). IDA's Newton
// matrix J = dF/dy + alpha dF/dy' is solved by eliminating dv = alpha du - r1:
//   (K + alpha C + alpha^2 M) du = r2 + (alpha M + C) r1.
// Constrained (fixed) components stay zero: their residual rows are u' and v'.
void Solver::run_dynamic() {
  using BV = LA::MPI::BlockVector;
  const std::vector<IndexSet> parts{owned, owned};
  LA::MPI::Vector u_ghost(owned, relevant, comm), tmp(owned, comm), du(owned, comm);

  // Initial displacement (a preload has already left its equilibrium in u_owned).
  const double L = P.mesh.shape == MeshSpec::Shape::Cylinder ? P.mesh.height : P.mesh.size[2];
  const double A = P.dynamics.amplitude;
  const auto initial = P.dynamics.initial;
  if (initial != Dynamics::Initial::Preload) {
    VectorFunctionFromScalarFunctionObject<3> field(
        [&](const Point<3>& p) {
          if (initial == Dynamics::Initial::AxialMode) return A * 2.0 * L / M_PI * std::sin(M_PI * p[2] / (2.0 * L));
          if (initial == Dynamics::Initial::AxialStretch) return A * p[2];
          return 0.0;
        },
        2, 3);
    VectorTools::interpolate(mapping, dof, field, u_owned);
    zero_constraints.distribute(u_owned);
  }
  const double t_start = initial == Dynamics::Initial::Preload ? P.dynamics.release_time : 0.0;

  assemble_mass_matrix();
  u_ghost = u_owned;
  assemble(u_ghost, t_start, zero_constraints, true);
  C.copy_from(M);
  C *= P.dynamics.rayleigh_mass;
  C.add(P.dynamics.rayleigh_stiffness, K);

  BV y(parts, comm), ydot(parts, comm);
  y.block(0) = u_owned;
  // Consistent start: u' = v0 = 0, M v' = f_ext - f_int (rhs holds it, zero on constraints).
  {
    LA::MPI::Vector a0(owned, comm);
    solve_linear(M, a0, rhs);
    zero_constraints.distribute(a0);
    ydot.block(1) = a0;
  }
  const IndexSet constrained = [&] {
    IndexSet s(dof.n_dofs());
    for (auto i : owned)
      if (zero_constraints.is_constrained(i)) s.add_index(i);
    s.compress();
    return s;
  }();

  SUNDIALS::IDA<BV>::AdditionalData data(t_start, P.dynamics.end_time, P.report_interval * 1e-2, P.report_interval,
                                         1e-14, 5, 10, 0.0, P.dynamics.absolute_tolerance,
                                         P.dynamics.relative_tolerance, false,
                                         SUNDIALS::IDA<BV>::AdditionalData::none,
                                         SUNDIALS::IDA<BV>::AdditionalData::none, 5);
  SUNDIALS::IDA<BV> ida(data, comm);
  double alpha_now = 0.0;
  ida.reinit_vector = [&](BV& v) { v.reinit(parts, comm); };
  ida.residual = [&](const double t, const BV& yy, const BV& yd, BV& res) -> int {
    u_ghost = yy.block(0);
    const Assembled a = assemble(u_ghost, t, zero_constraints, false);
    if (!a.valid) return 1;
    res.block(0) = yd.block(0);
    res.block(0) -= yy.block(1);
    // M v' + C v + f_int - f_ext; rhs = f_ext - f_int on free rows.
    M.vmult(res.block(1), yd.block(1));
    C.vmult(tmp, yy.block(1));
    res.block(1) += tmp;
    res.block(1) -= rhs;
    for (auto i : constrained) {
      res.block(0)[i] = yd.block(0)[i];
      res.block(1)[i] = yd.block(1)[i];
    }
    res.compress(VectorOperation::insert);
    return 0;
  };
  ida.setup_jacobian = [&](const double t, const BV& yy, const BV&, const double alpha) -> int {
    u_ghost = yy.block(0);
    const Assembled a = assemble(u_ghost, t, zero_constraints, true);
    if (!a.valid) return 1;
    alpha_now = alpha;
    K_eff.copy_from(K);
    K_eff.add(alpha, C);
    K_eff.add(alpha * alpha, M);
    try {
      prepare_solver(K_eff);
    } catch (const std::exception&) {
      return 1;
    }
    return 0;
  };
  ida.solve_with_jacobian = [&](const BV& r, BV& dst, const double) -> int {
    // tmp = r2 + (alpha M + C) r1
    M.vmult(tmp, r.block(0));
    tmp *= alpha_now;
    C.vmult_add(tmp, r.block(0));
    tmp += r.block(1);
    for (auto i : constrained) tmp[i] = 0.0;
    tmp.compress(VectorOperation::insert);
    du = 0.0;
    try {
      solve_prepared(K_eff, du, tmp);
    } catch (const std::exception&) {
      return 1;
    }
    dst.block(0) = du;
    dst.block(1) = du;
    dst.block(1) *= alpha_now;
    dst.block(1) -= r.block(0);
    for (auto i : constrained) dst.block(1)[i] = 0.0;
    dst.compress(VectorOperation::insert);
    return 0;
  };
  // deal.II's IDA loop ignores IDA errors in release builds and would then
  // report the same time for ever: a time that stops advancing is a failure.
  double last_output = -1e300;
  int stuck = 0;
  ida.output_step = [&](const double t, const BV& yy, const BV&, const unsigned) {
    stuck = t > last_output ? 0 : stuck + 1;
    last_output = std::max(last_output, t);
    if (stuck > 2) {
      summary.wall_seconds = seconds_since(start);
      throw SolveError("fem: SUNDIALS IDA could not advance past t = " + std::to_string(t) +
                           " s (step sizes collapsed; try looser tolerances or a smoother start)",
                       t, summary);
    }
    if (t <= t_start && initial == Dynamics::Initial::Preload) return;  // reported by the preload
    const Report r = measure(t, yy.block(0), &yy.block(1));
    if (cb.on_report && Utilities::MPI::this_mpi_process(comm) == 0) cb.on_report(r);
    if (cb.progress && Utilities::MPI::this_mpi_process(comm) == 0) cb.progress(t, P.dynamics.end_time);
  };
  try {
    summary.time_steps = ida.solve_dae(y, ydot);
  } catch (const ExceptionBase& e) {
    summary.wall_seconds = seconds_since(start);
    throw SolveError(std::string("fem: SUNDIALS IDA failed: ") + e.what(), 0.0, summary);
  }
}

// @sect4{Measurements}
Report Solver::measure(double t, const LA::MPI::Vector& u, const LA::MPI::Vector* velocity) {
  LA::MPI::Vector u_ghost(owned, relevant, comm);
  u_ghost = u;
  // f_int / f_ext at this state (the Newton loop's last assembly already was,
  // but dynamics and the initial state need it).
  const Assembled assembled = assemble(u_ghost, t, zero_constraints, false);
  Report r;
  r.stored_energy = assembled.strain_energy;
  r.time = t;
  r.newton_iterations = newton_since_report;
  r.cuts = cuts_since_report;
  newton_since_report = cuts_since_report = 0;
  r.contact_forces = contact_force;
  r.contact_penetrations = contact_penetration;
  for (size_t k = 0; k < face_dofs.size(); ++k) {
    std::array<double, 3> f{{0, 0, 0}};
    for (unsigned c = 0; c < 3; ++c)
      for (auto i : face_dofs[k][c]) f[c] += f_int_full[i] - f_ext_full[i];
    for (unsigned c = 0; c < 3; ++c) f[c] = Utilities::MPI::sum(f[c], comm);
    r.reactions.push_back(f);
    r.reaction_areas.push_back(face_area[static_cast<size_t>(P.reaction_faces[k])]);
  }
  for (const auto& p : probe_points) {
    std::array<double, 3> d{{0, 0, 0}};
    for (unsigned c = 0; c < 3; ++c) {
      double val = 0.0, found = 0.0;
      for (auto i : vertex_dofs(p, c))
        if (owned.is_element(i)) {
          val = u_ghost[i];
          found = 1.0;
          break;
        }
      const double total = Utilities::MPI::sum(found, comm);
      d[c] = total > 0 ? Utilities::MPI::sum(val, comm) / total : 0.0;
    }
    r.probe_displacements.push_back(d);
  }
  // Volume ratio, volume-averaged Cauchy stress and the smallest J.
  FEValues<3> fv(mapping, fe, quad, update_gradients | update_JxW_values | update_quadrature_points);
  std::vector<Tensor<2, 3>> grad(quad.size());
  std::vector<double> Jq(quad.size()), JxWq(quad.size());
  CellDilatation dil;
  const FEValuesExtractors::Vector disp(0);
  double vol = 0.0, minJ = 1e300;
  Tensor<2, 3> sigma_v;
  for (const auto& cell : dof.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fv.reinit(cell);
    fv[disp].get_function_gradients(u_ghost, grad);
    for (unsigned q = 0; q < quad.size(); ++q) {
      Jq[q] = determinant(unit_symmetric_tensor<3>() + grad[q]);
      JxWq[q] = fv.JxW(q);
    }
    if (P.formulation == Formulation::ThreeField) {
      dil.reinit(P.degree - 1, fv.get_quadrature_points(), JxWq);
      dil.compute(Jq, P.material.kappa);
    }
    for (unsigned q = 0; q < quad.size(); ++q) {
      const Kinematics k(grad[q]);
      minJ = std::min(minJ, k.J);
      const double p = P.formulation == Formulation::ThreeField ? dil.pressure(q) : dU(P.material.kappa, k.J);
      sigma_v += cauchy(P.material.mu, p, k) * k.J * fv.JxW(q);
      vol += k.J * fv.JxW(q);
    }
  }
  vol = Utilities::MPI::sum(vol, comm);
  sigma_v = Utilities::MPI::sum(sigma_v, comm);
  r.volume_ratio = vol / reference_volume;
  r.min_jacobian = Utilities::MPI::min(minJ, comm);
  const Tensor<2, 3> s = sigma_v / vol;
  r.mean_cauchy = {{s[0][0], s[1][1], s[2][2], s[1][2], s[0][2], s[0][1]}};
  if (velocity) {
    M.vmult(rhs, *velocity);
    r.kinetic_energy = 0.5 * (rhs * (*velocity));
  }
  if (t >= next_fields_time - 1e-12) {
    write_fields(t, u_ghost);
    next_fields_time = t + P.fields_interval;
  }
  return r;
}

// @sect4{Field output}
// VTU per process, a PVTU per frame and a PVD record for ParaView; the
// deformed boundary surface to the callbacks (rank 0) for the results file.
void Solver::write_fields(double t, const LA::MPI::Vector& u_ghost) {
  if (!P.vtu_directory.empty()) {
    DataOut<3> out;
    out.attach_dof_handler(dof);
    const std::vector<std::string> names(3, "displacement");
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> interp(
        3, DataComponentInterpretation::component_is_part_of_vector);
    out.add_data_vector(u_ghost, names, DataOut<3>::type_dof_data, interp);
    out.build_patches(mapping, P.degree);
    const std::string pvtu =
        out.write_vtu_with_pvtu_record(P.vtu_directory + "/", P.vtu_basename, frame, comm, 4, 0);
    pvd_records.emplace_back(t, pvtu);
    if (Utilities::MPI::this_mpi_process(comm) == 0) {
      std::ofstream pvd(P.vtu_directory + "/" + P.vtu_basename + ".pvd");
      DataOutBase::write_pvd_record(pvd, pvd_records);
      summary.vtu_files = {P.vtu_directory + "/" + P.vtu_basename + ".pvd"};
    }
  }
  if (cb.on_surface || cb.on_frame) gather_surface(u_ghost, !surface_sent, t);
  if (!P.field_probes.empty()) evaluate_field_probes(u_ghost, t);
  surface_sent = true;
  ++frame;
}

void Solver::gather_surface(const LA::MPI::Vector& u_ghost, bool topology, double t) {
  // Each boundary face of an owned cell contributes its (up to 4) vertices as
  // a quad split into two triangles. Rank 0 merges vertices by position.
  std::vector<std::array<double, 6>> corners;  // reference position, displacement
  for (const auto& cell : dof.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (unsigned f = 0; f < cell->n_faces(); ++f) {
      if (!cell->face(f)->at_boundary()) continue;
      const auto face = cell->face(f);
      for (unsigned v = 0; v < 4; ++v) {
        const Point<3> p = face->vertex(v);
        std::array<double, 6> e{{p[0], p[1], p[2], 0, 0, 0}};
        for (unsigned c = 0; c < 3; ++c) e[3 + c] = u_ghost[face->vertex_dof_index(v, c)];
        corners.push_back(e);
      }
    }
  }
  const auto all = Utilities::MPI::gather(comm, corners, 0);
  if (Utilities::MPI::this_mpi_process(comm) != 0) return;
  auto key = [&](const std::array<double, 6>& e) {
    return std::array<long long, 3>{{std::llround(e[0] / length * 1e9), std::llround(e[1] / length * 1e9),
                                     std::llround(e[2] / length * 1e9)}};
  };
  if (topology) {
    Surface s;
    for (const auto& part : all)
      for (size_t i = 0; i < part.size(); i += 4) {
        int idx[4];
        for (unsigned v = 0; v < 4; ++v) {
          const auto k = key(part[i + v]);
          auto [it, fresh] = surface_index.emplace(k, static_cast<int>(s.points.size()));
          if (fresh) s.points.push_back({{part[i + v][0], part[i + v][1], part[i + v][2]}});
          idx[v] = it->second;
        }
        // deal.II face vertex order is lexicographic: 0 1 / 2 3.
        s.triangles.push_back({{idx[0], idx[1], idx[3]}});
        s.triangles.push_back({{idx[0], idx[3], idx[2]}});
      }
    if (cb.on_surface) cb.on_surface(s);
  }
  std::vector<std::array<double, 3>> d(surface_index.size(), {{0, 0, 0}});
  for (const auto& part : all)
    for (const auto& e : part) {
      const auto it = surface_index.find(key(e));
      if (it != surface_index.end()) d[static_cast<size_t>(it->second)] = {{e[3], e[4], e[5]}};
    }
  if (cb.on_frame) cb.on_frame(t, d);
}

void Solver::locate_field_probes() {
  if (P.field_probes.empty()) return;
  const GridTools::Cache<3> cache(tria, mapping);
  const unsigned n = fe.n_dofs_per_cell();
  for (unsigned k = 0; k < P.field_probes.size(); ++k) {
    const Point<3> p(P.field_probes[k][0], P.field_probes[k][1], P.field_probes[k][2]);
    try {
      const auto found = GridTools::find_active_cell_around_point(cache, p);
      const auto& tcell = found.first;
      if (tcell.state() != IteratorState::valid || !tcell->is_locally_owned()) continue;
      const typename DoFHandler<3>::active_cell_iterator cell(&tria, tcell->level(), tcell->index(), &dof);
      LocatedProbe lp;
      lp.index = k;
      lp.dofs.resize(n);
      cell->get_dof_indices(lp.dofs);
      lp.shape.resize(n);
      for (unsigned i = 0; i < n; ++i) lp.shape[i] = fe.shape_value(i, found.second);
      located.push_back(std::move(lp));
    } catch (const std::exception&) {
      // outside the mesh (or not in this process's part): not evaluated here
    }
  }
}

void Solver::evaluate_field_probes(const LA::MPI::Vector& u_ghost, double t) {
  std::vector<std::array<double, 4>> local;  // index, ux, uy, uz
  for (const auto& lp : located) {
    std::array<double, 4> v{{static_cast<double>(lp.index), 0, 0, 0}};
    for (unsigned i = 0; i < lp.dofs.size(); ++i)
      v[1 + fe.system_to_component_index(i).first] += lp.shape[i] * u_ghost[lp.dofs[i]];
    local.push_back(v);
  }
  const auto all = Utilities::MPI::gather(comm, local, 0);
  if (Utilities::MPI::this_mpi_process(comm) != 0 || !cb.on_probe_frame) return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::array<double, 3>> d(P.field_probes.size(), {{nan, nan, nan}});
  for (const auto& part : all)
    for (const auto& v : part) {
      auto& slot = d[static_cast<size_t>(v[0])];
      if (std::isnan(slot[0])) slot = {{v[1], v[2], v[3]}};
    }
  cb.on_probe_frame(t, d);
}

Summary Solver::run() {
  start = Clock::now();
  check_problem();
  setup();
  active_tractions = P.tractions;
  if (P.dynamic && P.dynamics.initial == Dynamics::Initial::Preload) {
    // The preloaded equilibrium, reported like a quasi-static run.
    active_tractions = P.dynamics.preload;
    run_quasi_static(preload_times());
    active_tractions = P.tractions;
  }
  if (P.dynamic) run_dynamic();
  else run_quasi_static(P.report_times);
  summary.wall_seconds = seconds_since(start);
  return summary;
}

}  // namespace internal

Summary solve(const Problem& problem, const Callbacks& callbacks) {
  internal::Solver solver(problem, callbacks);
  try {
    return solver.run();
  } catch (const Error&) {
    throw;
  } catch (const dealii::ExceptionBase& e) {
    throw Error(std::string("fem: deal.II error: ") + e.what());
  }
}

}  // namespace fem
