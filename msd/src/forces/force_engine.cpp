#include "msd/forces/force_engine.hpp"

#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/edge_dampers.hpp"
#include "msd/forces/edge_springs.hpp"
#include "msd/forces/spring_law.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/stable_neo_hookean.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define TB_MULTIVERSION __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define TB_MULTIVERSION
#endif

namespace msd {

ForcePlan make_force_plan(const std::vector<Element>& elements, const std::vector<TissueMaterial>& materials,
                          int num_nodes) {
  ForcePlan p;
  std::map<std::pair<int, int>, int> index;
  bool laws = false;
  for (const TissueMaterial& m : materials)
    for (const SpringLaw& law : m.edge_laws) laws = laws || !law.linear();
  for (const Element& el : elements)
    for (int k = 0; k < 6; ++k) {
      int a = el.nodes[kTetEdges[k][0]], b = el.nodes[kTetEdges[k][1]];
      if (a > b) std::swap(a, b);
      const auto [it, fresh] = index.emplace(std::make_pair(a, b), p.num_edges());
      const size_t e = static_cast<size_t>(it->second);
      const SpringLaw& law = materials.at(static_cast<size_t>(el.region)).edge_laws[static_cast<size_t>(el.edge_class[k])];
      if (fresh) {
        p.edge_a.push_back(a);
        p.edge_b.push_back(b);
        p.edge_rest.push_back(el.rest_length[k]);
        p.edge_k_s.push_back(0.0);
        p.edge_k_d.push_back(0.0);
        if (laws) {
          p.edge_law_m.push_back(law.tension_exponent);
          p.edge_law_n.push_back(law.compression_exponent);
        }
      } else if (laws && (p.edge_law_m[e] != law.tension_exponent || p.edge_law_n[e] != law.compression_exponent)) {
        throw Error("the edge between nodes " + std::to_string(a) + " and " + std::to_string(b) +
                    " is shared by regions whose materials give its class (" + to_string(el.edge_class[k]) +
                    ") different spring laws; give the regions one law for it");
      }
      p.edge_k_s[e] += el.k.k_s[k];
      p.edge_k_d[e] += el.k.k_d[k];
    }
  // CSR by counting: offsets, then fill in increasing entry order.
  const auto csr = [num_nodes](size_t entries, auto node_of, std::vector<int>& offset, std::vector<int>& list) {
    offset.assign(static_cast<size_t>(num_nodes) + 1, 0);
    for (size_t r = 0; r < entries; ++r) ++offset[static_cast<size_t>(node_of(r)) + 1];
    for (size_t n = 0; n < static_cast<size_t>(num_nodes); ++n) offset[n + 1] += offset[n];
    list.assign(entries, 0);
    std::vector<int> next(offset.begin(), offset.end() - 1);
    for (size_t r = 0; r < entries; ++r) list[static_cast<size_t>(next[static_cast<size_t>(node_of(r))]++)] = static_cast<int>(r);
  };
  const size_t e2 = 2 * static_cast<size_t>(p.num_edges());
  csr(e2, [&](size_t r) { return (r & 1) ? p.edge_b[r / 2] : p.edge_a[r / 2]; }, p.node_edge_offset, p.node_edge);
  csr(4 * elements.size(), [&](size_t r) { return elements[r / 4].nodes[r % 4]; }, p.node_corner_offset,
      p.node_corner);
  return p;
}

namespace {

// Pass 1 over edges [begin, end): out(:, e) = force on edge_a[e]. x, v, out
// are 3 x N / 3 x E column-major arrays. kLaws: the springs follow their
// spring laws (ForcePlan::edge_law_m/n); without, the thesis' linear spring
// (a loop of its own, so the common case carries no per-edge branch).
template <bool kLaws>
TB_MULTIVERSION void edge_pass_impl(const ForcePlan& p, bool springs, bool dampers, const double* x, const double* v,
                                    double* out, long begin, long end) {
  const int* a = p.edge_a.data();
  const int* b = p.edge_b.data();
  const double* rest = p.edge_rest.data();
  const double* ks = p.edge_k_s.data();
  const double* kd = p.edge_k_d.data();
  const double* law_m = p.edge_law_m.data();
  const double* law_n = p.edge_law_n.data();
  for (long e = begin; e < end; ++e) {
    const long ia = 3L * a[e], ib = 3L * b[e];
    const double lx = x[ib] - x[ia], ly = x[ib + 1] - x[ia + 1], lz = x[ib + 2] - x[ia + 2];
    const double len = std::sqrt(lx * lx + ly * ly + lz * lz);
    const double inv = 1.0 / len;
    double s = 0.0;
    if (springs) {
      if constexpr (kLaws)
        s += spring_law_factor(ks[e], len, inv, rest[e], law_m[e], law_n[e]);
      else
        s += edge_spring_factor(ks[e], len, inv, rest[e]);
    }
    if (dampers) {
      const double rate = (v[ib] - v[ia]) * lx + (v[ib + 1] - v[ia + 1]) * ly + (v[ib + 2] - v[ia + 2]) * lz;
      s += edge_damper_factor(kd[e], rate, inv);
    }
    out[3 * e] = s * lx;
    out[3 * e + 1] = s * ly;
    out[3 * e + 2] = s * lz;
  }
}

void edge_pass(const ForcePlan& p, bool springs, bool dampers, const double* x, const double* v, double* out,
               long begin, long end) {
  if (p.edge_law_m.empty())
    edge_pass_impl<false>(p, springs, dampers, x, v, out, begin, end);
  else
    edge_pass_impl<true>(p, springs, dampers, x, v, out, begin, end);
}

// Pass 2, one tet: the continuum element and the non-linear terms into its
// four corners; returns whether the non-linear terms ran (thesis 5.8's threshold).
bool tet_terms(const Model& model, size_t t, const Points& x, const std::vector<double>& group_pressure,
               double* corner) {
  const Element& el = model.elements[t];
  Vec3 xe[4];
  for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[i]);
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  if (model.terms & kNeoHookean) add_continuum_element_forces(model, t, xe, group_pressure, f);
  if (model.terms & kBulk) add_bulk_forces(xe, group_pressure[static_cast<size_t>(model.volume_groups.of_tet[t])], f);
  const bool active = (model.terms & (kRepulsion | kVolume)) && add_nonlinear_element_forces(model, el, xe, f);
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) corner[3 * i + c] = f[i][c];
  return active;
}

}  // namespace

long compute_forces_fast(const Model& model, const Points& x, const Points& v, Points& f, Scratch& buffers) {
  const ForcePlan& p = model.plan;
  const long n = x.cols(), ne = p.num_edges(), nt = model.num_elements();
  if (p.node_edge_offset.size() != static_cast<size_t>(n) + 1 || p.node_corner_offset.size() != static_cast<size_t>(n) + 1)
    throw Error("compute_forces_fast: the model's force plan has " + std::to_string(p.node_edge_offset.size()) +
                " - 1 nodes, the state " + std::to_string(n) + " (a model not made by build_model?)");
  const bool springs = model.terms & kSprings, dampers = model.terms & kDampers;
  const bool edges = (springs || dampers) && ne > 0;
  const bool tets = (model.terms & (kRepulsion | kVolume | kNeoHookean | kBulk)) && nt > 0;
  if (f.cols() != n) f.resize(3, n);
  if (edges && buffers.edge_force.cols() != ne) buffers.edge_force.resize(3, ne);
  if (tets && buffers.corner_force.cols() != 4 * nt) buffers.corner_force.resize(3, 4 * nt);
  const int threads = std::max(1, model.threads);
  double* ef = buffers.edge_force.data();
  double* cf = buffers.corner_force.data();
  // A pass a model does not have runs no iterations.
  const long edge_blocks = edges ? (ne + 1023) / 1024 : 0, tet_count = tets ? nt : 0;
  const long group_count = (model.terms & (kNeoHookean | kBulk)) ? model.volume_groups.size() : 0;
  if (buffers.group_pressure.size() != static_cast<size_t>(group_count)) buffers.group_pressure.resize(static_cast<size_t>(group_count));
  std::vector<double>& pressure = buffers.group_pressure;
  long active = 0;
#pragma omp parallel num_threads(threads) if (threads > 1) reduction(+ : active)
  {
#pragma omp for schedule(static)
    for (long block = 0; block < edge_blocks; ++block)
      edge_pass(p, springs, dampers, x.data(), v.data(), ef, block * 1024, std::min(ne, block * 1024 + 1024));
#pragma omp for schedule(static)
    for (long g = 0; g < group_count; ++g) pressure[static_cast<size_t>(g)] = volume_group_pressure(model, static_cast<int>(g), x);
#pragma omp for schedule(static)
    for (long t = 0; t < tet_count; ++t)
      active += tet_terms(model, static_cast<size_t>(t), x, pressure, cf + 12 * t);
#pragma omp for schedule(static)
    for (long node = 0; node < n; ++node) {
      double s0 = 0.0, s1 = 0.0, s2 = 0.0;
      if (edges)
        for (int k = p.node_edge_offset[static_cast<size_t>(node)]; k < p.node_edge_offset[static_cast<size_t>(node) + 1]; ++k) {
          const int r = p.node_edge[static_cast<size_t>(k)];
          const double* fe = ef + 3L * (r >> 1);
          if (r & 1) {
            s0 -= fe[0], s1 -= fe[1], s2 -= fe[2];
          } else {
            s0 += fe[0], s1 += fe[1], s2 += fe[2];
          }
        }
      if (tets)
        for (int k = p.node_corner_offset[static_cast<size_t>(node)]; k < p.node_corner_offset[static_cast<size_t>(node) + 1]; ++k) {
          const double* fc = cf + 3L * p.node_corner[static_cast<size_t>(k)];
          s0 += fc[0], s1 += fc[1], s2 += fc[2];
        }
      f(0, node) = s0;
      f(1, node) = s1;
      f(2, node) = s2;
    }
  }
  return active;
}

const char* force_engine_isa() {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return "avx512f";
  if (__builtin_cpu_supports("avx2")) return "avx2";
#endif
  return "baseline";
}

}  // namespace msd
