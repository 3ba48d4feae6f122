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

// Pass 2 for the thesis' element (no continuum or bulk term): the tets whose
// non-linear terms are on (thesis 5.8's threshold; all at threshold 0), in
// batches of kLanes, each batch gathered into lane arrays and every formula
// of add_nonlinear_element_forces (tet_frame, face_repulsion_magnitude,
// volume_force_magnitude, add_balanced_normal_forces) evaluated lane by lane
// in the same operations and order, so the compiler vectorises across tets
// (eight doubles per AVX-512 register) and every lane gives the scalar
// path's bits (no contraction in this file; the floor's branch is a select
// of two values both computed as the scalar code computes the one it takes).
constexpr int kLanes = 8;

template <bool kRep, bool kVol>
TB_MULTIVERSION void nonlinear_batch_pass(const Model& model, const double* x, double* corner, const int* tets,
                                          int count) {
  for (int b0 = 0; b0 < count; b0 += kLanes) {
    const int w = std::min(kLanes, count - b0);
    double X[4][3][kLanes], h0[4][kLanes], kr[4][kLanes], kv[4][kLanes], v0[kLanes], fl[kLanes];
    for (int k = 0; k < kLanes; ++k) {
      const Element& el = model.elements[static_cast<size_t>(tets[b0 + (k < w ? k : 0)])];  // (spare lanes repeat the first tet)
      for (int i = 0; i < 4; ++i) {
        const double* p = x + 3L * el.nodes[static_cast<size_t>(i)];
        X[i][0][k] = p[0];
        X[i][1][k] = p[1];
        X[i][2][k] = p[2];
        h0[i][k] = el.rest_height[i];
        kr[i][k] = el.k.k_r[i];
        kv[i][k] = el.k.k_v[i];
      }
      v0[k] = el.rest_volume;
      fl[k] = el.floor;
    }
    double F[4][3][kLanes];
#pragma omp simd
    for (int k = 0; k < kLanes; ++k) {
      // tet_frame
      const double e1x = X[1][0][k] - X[0][0][k], e1y = X[1][1][k] - X[0][1][k], e1z = X[1][2][k] - X[0][2][k];
      const double e2x = X[2][0][k] - X[0][0][k], e2y = X[2][1][k] - X[0][1][k], e2z = X[2][2][k] - X[0][2][k];
      const double e3x = X[3][0][k] - X[0][0][k], e3y = X[3][1][k] - X[0][1][k], e3z = X[3][2][k] - X[0][2][k];
      double m[4][3];
      m[1][0] = e2y * e3z - e2z * e3y, m[1][1] = e2z * e3x - e2x * e3z, m[1][2] = e2x * e3y - e2y * e3x;
      m[2][0] = e3y * e1z - e3z * e1y, m[2][1] = e3z * e1x - e3x * e1z, m[2][2] = e3x * e1y - e3y * e1x;
      m[3][0] = e1y * e2z - e1z * e2y, m[3][1] = e1z * e2x - e1x * e2z, m[3][2] = e1x * e2y - e1y * e2x;
      #pragma GCC unroll 4
      for (int c = 0; c < 3; ++c) m[0][c] = -((m[1][c] + m[2][c]) + m[3][c]);
      const double six_v = (e1x * m[1][0] + e1y * m[1][1]) + e1z * m[1][2];
      const double volume = six_v / 6.0;
      double inv[4], mag[4];
      #pragma GCC unroll 4
      for (int i = 0; i < 4; ++i) {
        inv[i] = 1.0 / std::sqrt((m[i][0] * m[i][0] + m[i][1] * m[i][1]) + m[i][2] * m[i][2]);
        const double h = six_v * inv[i];
        mag[i] = 0.0;
        if constexpr (kRep) {
          const double x0 = h0[i][k], xc = fl[k] * x0;
          const double above = kr[i][k] * (x0 * x0 / h - h);
          const double fc = kr[i][k] * (x0 * x0 / xc - xc);
          const double slope = -kr[i][k] * (x0 * x0 / (xc * xc) + 1.0);
          mag[i] += h >= xc ? above : fc + slope * (h - xc);
        }
        if constexpr (kVol) mag[i] += kv[i][k] * 6.0 * (v0[k] - volume) * inv[i];
      }
      // add_balanced_normal_forces
      double pp[4], ss[4], d[4][4];
      #pragma GCC unroll 4
      for (int i = 0; i < 4; ++i) {
        pp[i] = mag[i] * inv[i];
        ss[i] = pp[i] * inv[i] * inv[i];
      }
      #pragma GCC unroll 4
      for (int i = 0; i < 4; ++i)
        #pragma GCC unroll 4
        for (int j = i + 1; j < 4; ++j)
          d[i][j] = d[j][i] = (m[i][0] * m[j][0] + m[i][1] * m[j][1]) + m[i][2] * m[j][2];
      #pragma GCC unroll 4
      for (int j = 0; j < 4; ++j)
        #pragma GCC unroll 4
        for (int c = 0; c < 3; ++c) {
          double acc = pp[j] * m[j][c];
          #pragma GCC unroll 4
          for (int i = 0; i < 4; ++i)
            if (i != j) acc += (ss[i] * d[i][j]) * m[i][c];
          F[j][c][k] = 0.0 + acc;
        }
    }
    for (int k = 0; k < w; ++k)
      for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) corner[12L * tets[b0 + k] + 3 * i + c] = F[i][c][k];
  }
}

// Thesis 5.8's test (nonlinear_terms_active, element_forces.hpp) for tets
// [begin, begin + count), count <= 64, into on[]: eight lanes at a time, the
// predicate's operations in its order (so the same answer bit for bit).
TB_MULTIVERSION void threshold_flags(const Model& model, const double* x, double threshold, long begin, int count,
                                     bool* on) {
  for (int b0 = 0; b0 < count; b0 += kLanes) {
    const int w = std::min(kLanes, count - b0);
    double X[4][3][kLanes], c[4][kLanes];
    for (int k = 0; k < kLanes; ++k) {
      const Element& el = model.elements[static_cast<size_t>(begin + b0 + (k < w ? k : 0))];
      for (int i = 0; i < 4; ++i) {
        const double* p = x + 3L * el.nodes[static_cast<size_t>(i)];
        X[i][0][k] = p[0];
        X[i][1][k] = p[1];
        X[i][2][k] = p[2];
        c[i][k] = threshold * el.rest_height[i];
      }
    }
    long lane[kLanes];
#pragma omp simd
    for (int k = 0; k < kLanes; ++k) {
      const double e1x = X[1][0][k] - X[0][0][k], e1y = X[1][1][k] - X[0][1][k], e1z = X[1][2][k] - X[0][2][k];
      const double e2x = X[2][0][k] - X[0][0][k], e2y = X[2][1][k] - X[0][1][k], e2z = X[2][2][k] - X[0][2][k];
      const double e3x = X[3][0][k] - X[0][0][k], e3y = X[3][1][k] - X[0][1][k], e3z = X[3][2][k] - X[0][2][k];
      const double m1x = e2y * e3z - e2z * e3y, m1y = e2z * e3x - e2x * e3z, m1z = e2x * e3y - e2y * e3x;
      const double m2x = e3y * e1z - e3z * e1y, m2y = e3z * e1x - e3x * e1z, m2z = e3x * e1y - e3y * e1x;
      const double m3x = e1y * e2z - e1z * e2y, m3y = e1z * e2x - e1x * e2z, m3z = e1x * e2y - e1y * e2x;
      const double m0x = -((m1x + m2x) + m3x), m0y = -((m1y + m2y) + m3y), m0z = -((m1z + m2z) + m3z);
      const double six_v = (e1x * m1x + e1y * m1y) + e1z * m1z;
      const double s2 = six_v * six_v;
      // (| not ||: no branch in the lane loop, the same truth value)
      const long below = static_cast<long>(s2 < c[0][k] * c[0][k] * ((m0x * m0x + m0y * m0y) + m0z * m0z)) |
                         static_cast<long>(s2 < c[1][k] * c[1][k] * ((m1x * m1x + m1y * m1y) + m1z * m1z)) |
                         static_cast<long>(s2 < c[2][k] * c[2][k] * ((m2x * m2x + m2y * m2y) + m2z * m2z)) |
                         static_cast<long>(s2 < c[3][k] * c[3][k] * ((m3x * m3x + m3y * m3y) + m3z * m3z));
      lane[k] = static_cast<long>(!(six_v > 0.0)) | below;
    }
    for (int k = 0; k < w; ++k) on[b0 + k] = lane[k] != 0;
  }
}

// Tets [begin, end) (at most 64): those thesis 5.8's threshold leaves on
// (every one at threshold 0) in batches, the others' corners zero. Returns
// how many ran.
long nonlinear_batches(const Model& model, const double* x, double* corner, long begin, long end) {
  int tets[64];
  bool on[64];
  int count = 0;
  const double threshold = model.nonlinear_threshold;
  if (threshold > 0.0)
    threshold_flags(model, x, threshold, begin, static_cast<int>(end - begin), on);
  else
    std::fill(on, on + (end - begin), true);
  for (long t = begin; t < end; ++t) {
    if (on[t - begin])
      tets[count++] = static_cast<int>(t);
    else
      std::fill(corner + 12 * t, corner + 12 * t + 12, 0.0);
  }
  const bool rep = model.terms & kRepulsion, vol = model.terms & kVolume;
  if (rep && vol)
    nonlinear_batch_pass<true, true>(model, x, corner, tets, count);
  else if (rep)
    nonlinear_batch_pass<true, false>(model, x, corner, tets, count);
  else
    nonlinear_batch_pass<false, true>(model, x, corner, tets, count);
  return count;
}

// Whether pass 2 runs the batches: the thesis' element terms only (no
// continuum or bulk term in the tets).
bool batched_tets(const Model& model) {
  return !(model.terms & (kNeoHookean | kBulk)) && (model.terms & (kRepulsion | kVolume));
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
  const bool batched = tets && batched_tets(model) && !model.reference_forces;
  const long tet_batches = batched ? (tet_count + 63) / 64 : 0;
  long active = 0;
#pragma omp parallel num_threads(threads) if (threads > 1) reduction(+ : active)
  {
#pragma omp for schedule(static)
    for (long block = 0; block < edge_blocks; ++block)
      edge_pass(p, springs, dampers, x.data(), v.data(), ef, block * 1024, std::min(ne, block * 1024 + 1024));
#pragma omp for schedule(static)
    for (long g = 0; g < group_count; ++g) pressure[static_cast<size_t>(g)] = volume_group_pressure(model, static_cast<int>(g), x);
    if (batched) {
#pragma omp for schedule(static)
      for (long b = 0; b < tet_batches; ++b)
        active += nonlinear_batches(model, x.data(), cf, b * 64, std::min(tet_count, b * 64 + 64));
    } else {
#pragma omp for schedule(static)
      for (long t = 0; t < tet_count; ++t)
        active += tet_terms(model, static_cast<size_t>(t), x, pressure, cf + 12 * t);
    }
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
