// MPI for the whole process, through deal.II (which also initialises PETSc and
// Trilinos' needs); one thread per process so timings are comparable.
#include "fem/fem.hpp"

#include <deal.II/base/config.h>
#include <deal.II/base/mpi.h>

#include <unistd.h>

#include <memory>
#include <string>

namespace fem {

namespace {
std::unique_ptr<dealii::Utilities::MPI::MPI_InitFinalize> g_mpi;
}

Session::Session(int& argc, char**& argv) {
  if (g_mpi) throw Error("fem::Session created twice");
  g_mpi = std::make_unique<dealii::Utilities::MPI::MPI_InitFinalize>(argc, argv, 1);
}

Session::~Session() { g_mpi.reset(); }

int Session::rank() { return static_cast<int>(dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD)); }
int Session::size() { return static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)); }
void Session::barrier() { MPI_Barrier(MPI_COMM_WORLD); }

std::string Session::broadcast(const std::string& text) {
  unsigned long long n = text.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  std::string out = rank() == 0 ? text : std::string(n, '\0');
  if (n > 0) MPI_Bcast(out.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  return out;
}

long Session::root_pid() {
  long pid = static_cast<long>(getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  return pid;
}

std::string library_version() { return DEAL_II_PACKAGE_VERSION; }

NeoHookean neo_hookean_from(double E, double nu, double density) {
  if (!(E > 0.0)) throw Error("material: Young's modulus must be positive");
  if (!(nu > -1.0 && nu < 0.5)) throw Error("material: Poisson's ratio must lie in (-1, 0.5)");
  return {E / (2.0 * (1.0 + nu)), E / (3.0 * (1.0 - 2.0 * nu)), density};
}

double Path::operator()(double t) const {
  if (points.empty()) return 1.0;
  if (t <= points.front().first) return points.front().second;
  for (size_t i = 1; i < points.size(); ++i)
    if (t <= points[i].first) {
      const auto& [t0, v0] = points[i - 1];
      const auto& [t1, v1] = points[i];
      return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
    }
  return points.back().second;
}

}  // namespace fem
