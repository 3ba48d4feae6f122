// Binds a Spec to the FEM reference (reference_fem, namespace fem): geometry and
// mesh, material, boundary conditions and loading per loading type, and the
// results file in the shared layout (plus /fields and VTU/PVD output).
#pragma once

#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"
#include "fem/fem.hpp"

#include <string>

namespace bench {

/// Shear and bulk moduli of the spec's material (from E and nu, or given).
/// Throws msd::Error naming the spec when neither pair is present.
fem::NeoHookean fem_material(const Spec& spec);

/// The spec as an FEM problem; `vtu_directory` empty disables VTU output.
fem::Problem make_fem_problem(const Spec& spec, const std::string& vtu_directory = "");

/// Runs the spec with the FEM solver on every MPI process; rank 0 writes
/// `out_path` (HDF5 + CSV) and the VTU/PVD files beside it (FILE_vtu/). Bad
/// input throws before any file exists; a solve that fails after retries is
/// recorded in the file (status "failed") and in the summary.
RunSummary run_fem(const Spec& spec, const std::string& out_path, const Progress& progress = {});

/// The FEM reference of `spec` in `out_path`: an existing complete file written
/// from the identical spec text is reused (returns true); otherwise the FEM runs
/// (collectively under MPI) and a failure throws msd::Error naming the spec.
bool ensure_fem_reference(const Spec& spec, const std::string& out_path, const Progress& progress = {});

}  // namespace bench
