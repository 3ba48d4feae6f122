#include "msd/mesh/embedding.hpp"

#include "msd/geometry/inside_test.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace msd {

namespace {

Vec3 tet_node(const Points& x, const Tet& t, int k) { return x.col(t[static_cast<size_t>(k)]); }

}  // namespace

TetLocator::TetLocator(const Points& nodes, const std::vector<Tet>& tets) : nodes_(nodes), tets_(tets) {
  if (tets_.empty()) throw Error("embedding: the tet mesh is empty");
  if (!nodes_.allFinite()) throw Error("embedding: the tet mesh has non-finite node coordinates");
  const int n = nodes_.cols();
  for (size_t e = 0; e < tets_.size(); ++e)
    for (int k : tets_[e])
      if (k < 0 || k >= n) throw Error("embedding: tet " + std::to_string(e) + " has an invalid node index");

  // Per-tet inverse edge frames and bounding boxes.
  inverse_.resize(tets_.size());
  std::vector<Vec3> blo(tets_.size()), bhi(tets_.size());
  lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo_;
  double extent = 0.0;
  for (size_t e = 0; e < tets_.size(); ++e) {
    const Tet& t = tets_[e];
    const Vec3 a = tet_node(nodes_, t, 0);
    Mat3 m;
    m.col(0) = tet_node(nodes_, t, 1) - a;
    m.col(1) = tet_node(nodes_, t, 2) - a;
    m.col(2) = tet_node(nodes_, t, 3) - a;
    if (!(std::abs(m.determinant()) > 0.0))
      throw Error("embedding: tet " + std::to_string(e) + " is degenerate (zero volume)");
    inverse_[e] = m.inverse();
    blo[e] = a;
    bhi[e] = a;
    for (int k = 1; k < 4; ++k) {
      blo[e] = blo[e].cwiseMin(tet_node(nodes_, t, k));
      bhi[e] = bhi[e].cwiseMax(tet_node(nodes_, t, k));
    }
    lo_ = lo_.cwiseMin(blo[e]);
    hi = hi.cwiseMax(bhi[e]);
    extent += (bhi[e] - blo[e]).maxCoeff();
  }
  // Cells about the size of a tet's bounding box, at most ~4 cells per tet.
  h_ = extent / static_cast<double>(tets_.size());
  const Vec3 size = (hi - lo_).cwiseMax(Vec3::Constant(1e-300));
  const double max_cells = 4.0 * static_cast<double>(tets_.size()) + 64.0;
  while ((size / h_).array().ceil().prod() > max_cells) h_ *= 1.25;
  for (int d = 0; d < 3; ++d) n_[d] = std::max(1, static_cast<int>(std::ceil(size[d] / h_)));

  // Counting sort of (cell, tet) pairs into a compressed list.
  auto range = [&](const Vec3& p, int c[3]) {
    for (int d = 0; d < 3; ++d)
      c[d] = std::clamp(static_cast<int>(std::floor((p[d] - lo_[d]) / h_)), 0, n_[d] - 1);
  };
  start_.assign(static_cast<size_t>(cells()) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
      items_.resize(static_cast<size_t>(start_.back()));
      fill.assign(start_.begin(), start_.end() - 1);
    }
    for (size_t e = 0; e < tets_.size(); ++e) {
      int a[3], b[3];
      range(blo[e], a);
      range(bhi[e], b);
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i) {
            const long c = i + static_cast<long>(n_[0]) * (j + static_cast<long>(n_[1]) * k);
            if (pass == 0)
              ++start_[static_cast<size_t>(c) + 1];
            else
              items_[static_cast<size_t>(fill[static_cast<size_t>(c)]++)] = static_cast<int>(e);
          }
    }
  }
  stamp_.assign(tets_.size(), 0);
}

long TetLocator::cell_index(const Vec3& p, int c[3]) const {
  for (int d = 0; d < 3; ++d)
    c[d] = std::clamp(static_cast<int>(std::floor((p[d] - lo_[d]) / h_)), 0, n_[d] - 1);
  return c[0] + static_cast<long>(n_[0]) * (c[1] + static_cast<long>(n_[1]) * c[2]);
}

Vec3 TetLocator::local_coordinates(int e, const Vec3& p) const {
  return inverse_[static_cast<size_t>(e)] * (p - tet_node(nodes_, tets_[static_cast<size_t>(e)], 0));
}

int TetLocator::containing(const Vec3& p, double tolerance) const {
  int c[3];
  const long cell = cell_index(p, c);
  int best = -1;
  double best_min = -tolerance;
  for (int k = start_[static_cast<size_t>(cell)]; k < start_[static_cast<size_t>(cell) + 1]; ++k) {
    const int e = items_[static_cast<size_t>(k)];
    const Vec3 l = local_coordinates(e, p);
    const double smallest = std::min({1.0 - l.sum(), l[0], l[1], l[2]});
    if (smallest >= best_min) {
      best_min = smallest;
      best = e;
    }
  }
  return best;
}

double TetLocator::distance_to_tet(int e, const Vec3& p) const {
  const Vec3 l = local_coordinates(e, p);
  if (std::min({1.0 - l.sum(), l[0], l[1], l[2]}) >= 0.0) return 0.0;
  const Tet& t = tets_[static_cast<size_t>(e)];
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : kFaces) {
    const Vec3 q = closest_point_on_triangle(p, tet_node(nodes_, t, f[0]), tet_node(nodes_, t, f[1]),
                                             tet_node(nodes_, t, f[2]));
    best = std::min(best, (q - p).norm());
  }
  return best;
}

std::pair<int, double> TetLocator::nearest(const Vec3& p) const {
  if (const int e = containing(p, 0.0); e >= 0) return {e, 0.0};
  if (++epoch_ == 0) {  // wrapped: clear the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    epoch_ = 1;
  }
  int c0[3];
  cell_index(p, c0);
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  const int max_ring = std::max({n_[0], n_[1], n_[2]});
  for (int r = 0; r <= max_ring; ++r) {
    // The shell of cells at Chebyshev index distance exactly r from c0.
    for (int k = c0[2] - r; k <= c0[2] + r; ++k) {
      if (k < 0 || k >= n_[2]) continue;
      for (int j = c0[1] - r; j <= c0[1] + r; ++j) {
        if (j < 0 || j >= n_[1]) continue;
        const bool face_jk = std::abs(k - c0[2]) == r || std::abs(j - c0[1]) == r;
        for (int i = c0[0] - r; i <= c0[0] + r; i += (face_jk || r == 0) ? 1 : 2 * r) {
          if (i < 0 || i >= n_[0]) continue;
          const long c = i + static_cast<long>(n_[0]) * (j + static_cast<long>(n_[1]) * k);
          for (int q = start_[static_cast<size_t>(c)]; q < start_[static_cast<size_t>(c) + 1]; ++q) {
            const int e = items_[static_cast<size_t>(q)];
            if (stamp_[static_cast<size_t>(e)] == epoch_) continue;
            stamp_[static_cast<size_t>(e)] = epoch_;
            const double d = distance_to_tet(e, p);
            if (d < best_d) {
              best_d = d;
              best = e;
            }
          }
        }
      }
    }
    // A tet not yet visited lies in cells more than r cells away along some
    // axis from c0, whose slab holds p or lies beyond the grid on p's side:
    // it is at least r * h away.
    if (best >= 0 && best_d <= r * h_) break;
  }
  return {best, best_d};
}

Embedding embed_vertices(const TetMesh& mesh, const Points& vertices) {
  const TetLocator locator(mesh.nodes, mesh.tets);
  Embedding out;
  out.vertices.resize(static_cast<size_t>(vertices.cols()));
  for (Eigen::Index i = 0; i < vertices.cols(); ++i) {
    const Vec3 p = vertices.col(i);
    if (!p.allFinite()) throw Error("embedding: vertex " + std::to_string(i) + " has non-finite coordinates");
    EmbeddedVertex& v = out.vertices[static_cast<size_t>(i)];
    v.tet = locator.containing(p);
    if (v.tet < 0) {
      const auto [e, d] = locator.nearest(p);
      v.tet = e;
      v.distance = d;
      ++out.outside;
      out.max_outside_distance = std::max(out.max_outside_distance, d);
    }
    const Vec3 l = locator.local_coordinates(v.tet, p);
    v.u = l[0];
    v.v = l[1];
    v.w = l[2];
  }
  return out;
}

void embedded_positions(const Points& x, const std::vector<Tet>& tets, const Embedding& embedding, Points& out) {
  out.resize(3, static_cast<Eigen::Index>(embedding.vertices.size()));
  for (size_t i = 0; i < embedding.vertices.size(); ++i) {
    const EmbeddedVertex& v = embedding.vertices[i];
    const Tet& t = tets[static_cast<size_t>(v.tet)];
    const Vec3 a = x.col(t[0]);
    out.col(static_cast<Eigen::Index>(i)) =
        a + v.u * (x.col(t[1]) - a) + v.v * (x.col(t[2]) - a) + v.w * (x.col(t[3]) - a);
  }
}

}  // namespace msd
