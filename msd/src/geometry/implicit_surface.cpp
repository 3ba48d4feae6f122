#include "msd/geometry/implicit_surface.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace msd {

double smooth_min(double a, double b, double k) {
  if (!(k > 0.0)) return std::min(a, b);
  const double s = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * k * s * s;
}

double smooth_max(double a, double b, double k) { return -smooth_min(-a, -b, k); }

double ellipsoid_field(const Vec3& x, const Vec3& c, const Vec3& s) {
  return ((x - c).cwiseQuotient(s).norm() - 1.0) * s.minCoeff();
}

double capsule_field(const Vec3& x, const Vec3& a, const Vec3& b, double r) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (x - (a + t * ab)).norm() - r;
}

Vec3 field_gradient(const ScalarField& f, const Vec3& x, double h) {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 up = x, down = x;
    up[a] += h;
    down[a] -= h;
    g[a] = (f(up) - f(down)) / (2.0 * h);
  }
  return g;
}

namespace {

// Newton steps along grad f onto f = 0, each step at most one cell long.
Vec3 project(const ScalarField& f, Vec3 x, double cell) {
  const double h = 1e-3 * cell;
  for (int it = 0; it < 4; ++it) {
    const double v = f(x);
    const Vec3 g = field_gradient(f, x, h);
    const double g2 = g.squaredNorm();
    if (!(g2 > 0.0)) break;
    Vec3 step = -v * g / g2;
    if (step.norm() > cell) step *= cell / step.norm();
    x += step;
    if (std::abs(v) < 1e-9 * cell) break;
  }
  return x;
}

// Whether triangle t at positions x faces along grad f at its centroid (the
// outward side). A triangle that faces the other way is folded over its
// neighbours: the surface passes through itself there.
bool faces_out(const ScalarField& f, const Tri& t, const std::vector<Vec3>& x, double cell) {
  const Vec3& a = x[static_cast<size_t>(t[0])];
  const Vec3& b = x[static_cast<size_t>(t[1])];
  const Vec3& c = x[static_cast<size_t>(t[2])];
  return (b - a).cross(c - a).dot(field_gradient(f, (a + b + c) / 3.0, 1e-3 * cell)) > 0.0;
}

// A relaxation pass may not fold the surface: every vertex of a triangle that
// faced outwards before the pass (at `old`) and would face inwards after it
// (at `next`) keeps its old position, repeated until no such triangle is left
// (each round puts back at least one vertex, so it ends).
void keep_orientation(const ScalarField& f, const std::vector<Tri>& tris, const std::vector<Vec3>& old,
                      std::vector<Vec3>& next, double cell) {
  std::vector<char> was_out(tris.size());
  for (size_t t = 0; t < tris.size(); ++t) was_out[t] = faces_out(f, tris[t], old, cell);
  for (bool reverted = true; reverted;) {
    reverted = false;
    for (size_t t = 0; t < tris.size(); ++t) {
      if (!was_out[t] || faces_out(f, tris[t], next, cell)) continue;
      for (int v : tris[t]) {
        const size_t i = static_cast<size_t>(v);
        if (next[i] != old[i]) {
          next[i] = old[i];
          reverted = true;
        }
      }
    }
  }
}

}  // namespace

TriangleMesh mesh_implicit_surface(const ScalarField& f, const ImplicitMeshOptions& o) {
  if (!(o.cell > 0.0) || !std::isfinite(o.cell)) throw Error("implicit surface: the cell size must be positive");
  if (!o.lo.allFinite() || !o.hi.allFinite() || !((o.hi - o.lo).minCoeff() > 0.0))
    throw Error("implicit surface: the box must have hi > lo along every axis");
  const Eigen::Vector3i n = ((o.hi - o.lo) / o.cell).array().ceil().cast<int>() + 1;
  const double total = static_cast<double>(n[0]) * n[1] * n[2];
  if (total > 2e7) throw Error("implicit surface: the box needs more than 2e7 grid nodes; use a larger cell");
  auto id = [&](int i, int j, int k) { return (static_cast<long>(k) * n[1] + j) * n[0] + i; };
  auto node = [&](int i, int j, int k) { return Vec3(o.lo + o.cell * Vec3(i, j, k)); };

  // Sample; values on the surface count as outside.
  std::vector<double> value(static_cast<size_t>(total));
  const double nudge = 1e-9 * o.cell;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        double v = f(node(i, j, k));
        if (!std::isfinite(v)) throw Error("implicit surface: the field is not finite at a grid node");
        if (std::abs(v) < nudge) v = nudge;
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        if (boundary && v < 0.0) throw Error("implicit surface: the solid reaches the boundary of the sampled box");
        value[static_cast<size_t>(id(i, j, k))] = v;
      }

  TriangleMesh out;
  std::vector<Vec3> verts;
  std::unordered_map<long long, int> on_edge;  // grid edge (two node ids) -> vertex
  const long long stride = static_cast<long long>(total);
  auto crossing = [&](long a, long b, const Vec3& xa, const Vec3& xb) {
    const long lo = std::min(a, b), hi = std::max(a, b);
    const long long key = static_cast<long long>(lo) * stride + hi;
    const auto it = on_edge.find(key);
    if (it != on_edge.end()) return it->second;
    const double fa = value[static_cast<size_t>(a)], fb = value[static_cast<size_t>(b)];
    const double t = std::clamp(fa / (fa - fb), 1e-3, 1.0 - 1e-3);
    verts.push_back(xa + t * (xb - xa));
    const int v = static_cast<int>(verts.size()) - 1;
    on_edge.emplace(key, v);
    return v;
  };
  auto emit = [&](int a, int b, int c, const Vec3& outward) {
    const Vec3 nrm = (verts[static_cast<size_t>(b)] - verts[static_cast<size_t>(a)])
                         .cross(verts[static_cast<size_t>(c)] - verts[static_cast<size_t>(a)]);
    if (nrm.dot(outward) < 0.0) std::swap(b, c);
    out.triangles.push_back({a, b, c});
  };

  // Kuhn's six tets of a cube: the paths 000 -> 111 along the axes in each order.
  static const int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i)
        for (const auto& order : kOrders) {
          Eigen::Vector3i c(i, j, k);
          long ids[4];
          Vec3 xs[4];
          for (int v = 0; v < 4; ++v) {
            if (v > 0) c[order[v - 1]] += 1;
            ids[v] = id(c[0], c[1], c[2]);
            xs[v] = node(c[0], c[1], c[2]);
          }
          int in[4], out_[4], ni = 0, no = 0;
          for (int v = 0; v < 4; ++v) (value[static_cast<size_t>(ids[v])] < 0.0 ? in[ni++] : out_[no++]) = v;
          if (ni == 0 || no == 0) continue;
          Vec3 outward = Vec3::Zero();
          for (int v = 0; v < no; ++v) outward += xs[out_[v]] / no;
          for (int v = 0; v < ni; ++v) outward -= xs[in[v]] / ni;
          auto cut = [&](int a, int b) { return crossing(ids[a], ids[b], xs[a], xs[b]); };
          if (ni == 1) {
            emit(cut(in[0], out_[0]), cut(in[0], out_[1]), cut(in[0], out_[2]), outward);
          } else if (ni == 3) {
            emit(cut(out_[0], in[0]), cut(out_[0], in[1]), cut(out_[0], in[2]), outward);
          } else {  // a quad, in cyclic order
            const int p00 = cut(in[0], out_[0]), p01 = cut(in[0], out_[1]);
            const int p11 = cut(in[1], out_[1]), p10 = cut(in[1], out_[0]);
            emit(p00, p01, p11, outward);
            emit(p00, p11, p10, outward);
          }
        }
  if (out.triangles.empty()) throw Error("implicit surface: the field has no surface in the box");

  // Tangential relaxation, then projection onto f = 0.
  std::vector<std::vector<int>> nbrs(verts.size());
  for (const Tri& t : out.triangles)
    for (int e = 0; e < 3; ++e) {
      nbrs[static_cast<size_t>(t[e])].push_back(t[(e + 1) % 3]);
      nbrs[static_cast<size_t>(t[(e + 1) % 3])].push_back(t[e]);
    }
  for (auto& l : nbrs) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  for (int it = 0; it < o.relax_iterations; ++it) {
    std::vector<Vec3> next(verts.size());
    for (size_t v = 0; v < verts.size(); ++v) {
      Vec3 mean = Vec3::Zero();
      for (int w : nbrs[v]) mean += verts[static_cast<size_t>(w)];
      mean /= static_cast<double>(nbrs[v].size());
      Vec3 g = field_gradient(f, verts[v], 1e-3 * o.cell);
      Vec3 move = 0.5 * (mean - verts[v]);
      if (g.squaredNorm() > 0.0) {
        g.normalize();
        move -= move.dot(g) * g;
      }
      next[v] = project(f, verts[v] + move, o.cell);
    }
    keep_orientation(f, out.triangles, verts, next, o.cell);
    verts.swap(next);
  }

  out.vertices.resize(3, static_cast<Eigen::Index>(verts.size()));
  for (size_t v = 0; v < verts.size(); ++v) out.vertices.col(static_cast<Eigen::Index>(v)) = verts[v];
  return out;
}

}  // namespace msd
