// The fast evaluation of the element terms (thesis eq. 5.4 and 5.5): the same
// forces as the per-tet reference loop (element_forces.hpp), computed in three
// passes over the model's ForcePlan (model.hpp):
//
//  1. edges (springs and dampers), once per unique edge, structure of arrays:
//       F_a = [ k_s (|l| - r) / |l| + k_d ((v_b - v_a) . l) / |l|^2 ] l,
//       l = x_b - x_a,  F_b = -F_a,
//     with k_s, k_d summed over the tets sharing the edge - equal to the
//     per-tet sum up to round-off because every tet sees the same rest length;
//  2. tets (face repulsion and volume preservation with their equalising
//     forces, thesis eq. 5.1-5.3, 5.5, and the continuum element,
//     stable_neo_hookean.hpp), once per tet into its four corners. For the
//     thesis' element the pass is vectorised across tets: in chunks of 64,
//     thesis 5.8's threshold is tested eight tets at a time, then the tets it
//     leaves on are gathered eight to a batch (structure of arrays on the
//     stack) and the element's formulas run lane by lane in the scalar
//     code's operations and order - the same bits as element_forces.cpp;
//  3. nodes: each node's force gathered from its edges and corners in a fixed
//     order.
// Every pass writes only its own entries, so the passes run on `model.threads`
// threads (OpenMP) without locks and the result is bit-identical for every
// thread count. The edge pass and the tet batches are compiled for AVX-512,
// AVX2 and the x86-64 baseline and the CPU picks at run time (GCC function
// multi-versioning); the file is compiled without floating-point contraction
// (and without errno for square roots, so they vectorise), so every variant
// gives the same bits.
#pragma once

#include "msd/model/model.hpp"

namespace msd {

/// The model's ForcePlan from its elements (build_model calls it); each
/// edge's spring law is its class's in its tets' region material. Throws
/// msd::Error when two tets sharing an edge give it different laws (regions
/// whose materials disagree on that edge class's exponents).
ForcePlan make_force_plan(const std::vector<Element>& elements, const std::vector<TissueMaterial>& materials,
                          int num_nodes);

/// Internal forces at x, v (3 x N) into f (resized, overwritten), using the
/// buffers in `buffers` (edge_force, corner_force; sized on first use, then
/// reused: no allocation after the first call). Returns the number of elements
/// whose non-linear terms ran.
long compute_forces_fast(const Model& model, const Points& x, const Points& v, Points& f, Scratch& buffers);

/// The instruction set the edge pass runs with on this CPU: "avx512f",
/// "avx2" or "baseline".
const char* force_engine_isa();

}  // namespace msd
