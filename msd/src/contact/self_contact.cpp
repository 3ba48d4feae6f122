#include "msd/contact/self_contact.hpp"

#include "msd/geometry/inside_test.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace msd {

AabbTree::AabbTree(const Points& lo, const Points& hi) { rebuild(lo, hi); }

void AabbTree::rebuild(const Points& lo, const Points& hi) {
  lo_ = lo;
  hi_ = hi;
  const int n = static_cast<int>(lo.cols());
  order_.resize(static_cast<size_t>(n));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.clear();
  if (n == 0) return;
  centre_ = 0.5 * (lo + hi);
  nodes_.reserve(static_cast<size_t>(2 * n));
  build(0, n);
}

int AabbTree::build(int begin, int end) {
  const Points& centre = centre_;
  Node node;
  node.lo = lo_.col(order_[static_cast<size_t>(begin)]);
  node.hi = hi_.col(order_[static_cast<size_t>(begin)]);
  for (int i = begin; i < end; ++i) {
    node.lo = node.lo.cwiseMin(Vec3(lo_.col(order_[static_cast<size_t>(i)])));
    node.hi = node.hi.cwiseMax(Vec3(hi_.col(order_[static_cast<size_t>(i)])));
  }
  node.begin = begin;
  node.end = end;
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  if (end - begin > 4) {
    int axis;
    (node.hi - node.lo).maxCoeff(&axis);
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) { return centre(axis, a) < centre(axis, b); });
    const int left = build(begin, mid);
    const int right = build(mid, end);
    nodes_[static_cast<size_t>(index)].left = left;
    nodes_[static_cast<size_t>(index)].right = right;
  }
  return index;
}

void AabbTree::query(const Vec3& p, std::vector<int>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<size_t>(stack[--top])];
    if ((p.array() < n.lo.array()).any() || (p.array() > n.hi.array()).any()) continue;
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const int b = order_[static_cast<size_t>(i)];
        if ((p.array() >= lo_.col(b).array()).all() && (p.array() <= hi_.col(b).array()).all()) out.push_back(b);
      }
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
}

SelfContactRegion make_self_contact_region(const TetMesh& mesh, const std::string& name, const Vec3& lo,
                                           const Vec3& hi, const Vec3& split_point, const Vec3& split_normal,
                                           const std::vector<Tri>& surface) {
  SelfContactRegion r;
  r.name = name;
  auto in_box = [&](const Vec3& c) { return (c.array() >= lo.array()).all() && (c.array() <= hi.array()).all(); };
  auto side = [&](const Vec3& c) { return (c - split_point).dot(split_normal) >= 0.0 ? 0 : 1; };
  for (const Tri& f : surface.empty() ? boundary_faces(mesh.tets) : surface) {
    const Vec3 c = (mesh.nodes.col(f[0]) + mesh.nodes.col(f[1]) + mesh.nodes.col(f[2])) / 3.0;
    if (in_box(c)) r.faces[side(c)].push_back(f);
  }
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    Vec3 c = Vec3::Zero();
    for (int v : mesh.tets[e]) c += 0.25 * mesh.nodes.col(v);
    if (in_box(c)) r.tets[side(c)].push_back(static_cast<int>(e));
  }
  for (int s = 0; s < 2; ++s) {
    if (r.faces[s].empty())
      throw Error("self contact '" + name + "': side " + std::to_string(s) + " of the region has no surface face");
    for (const Tri& f : r.faces[s]) r.nodes[s].insert(r.nodes[s].end(), f.begin(), f.end());
    std::sort(r.nodes[s].begin(), r.nodes[s].end());
    r.nodes[s].erase(std::unique(r.nodes[s].begin(), r.nodes[s].end()), r.nodes[s].end());
  }
  std::vector<std::vector<int>> neighbours(static_cast<size_t>(mesh.num_nodes()));
  for (const Tet& t : mesh.tets)
    for (int a : t)
      for (int b : t)
        if (a != b) neighbours[static_cast<size_t>(a)].push_back(b);
  for (int s = 0; s < 2; ++s)
    for (int node : r.nodes[s]) {
      std::vector<int> n = neighbours[static_cast<size_t>(node)];
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
      r.ring[s].push_back(std::move(n));
    }
  return r;
}

namespace {

bool inside_tet(const Points& x, const Tet& t, const Vec3& p) {
  const Vec3 a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]), d = x.col(t[3]);
  Mat3 m;
  m << b - a, c - a, d - a;
  const Eigen::FullPivLU<Mat3> lu(m);
  if (!lu.isInvertible()) return false;
  const Vec3 w = lu.solve(p - a);
  return w.minCoeff() >= 0.0 && w.sum() <= 1.0;
}

}  // namespace

SelfContactReport resolve_self_contact(const SelfContactRegion& r, const std::vector<Tet>& tets, Points& x,
                                       Points& v, const std::vector<char>& held) {
  SelfContactWorkspace w;
  return resolve_self_contact(r, tets, x, v, held, w);
}

SelfContactReport resolve_self_contact(const SelfContactRegion& r, const std::vector<Tet>& tets, Points& x,
                                       Points& v, const std::vector<char>& held, SelfContactWorkspace& buffers) {
  SelfContactReport report;
  std::vector<int>& candidates = buffers.candidates;
  for (int s = 0; s < 2; ++s) {
    const int other = 1 - s;
    const std::vector<int>& other_tets = r.tets[other];
    if (other_tets.empty()) continue;
    Points& lo = buffers.lo[s];
    Points& hi = buffers.hi[s];
    if (lo.cols() != static_cast<Eigen::Index>(other_tets.size())) {
      lo.resize(3, static_cast<Eigen::Index>(other_tets.size()));
      hi.resize(3, static_cast<Eigen::Index>(other_tets.size()));
    }
    for (size_t k = 0; k < other_tets.size(); ++k) {
      const Tet& t = tets[static_cast<size_t>(other_tets[k])];
      Vec3 l = x.col(t[0]), h = x.col(t[0]);
      for (int i = 1; i < 4; ++i) {
        l = l.cwiseMin(Vec3(x.col(t[i])));
        h = h.cwiseMax(Vec3(x.col(t[i])));
      }
      lo.col(static_cast<Eigen::Index>(k)) = l;
      hi.col(static_cast<Eigen::Index>(k)) = h;
    }
    AabbTree& tree = buffers.tree[s];
    tree.rebuild(lo, hi);
    for (size_t ni = 0; ni < r.nodes[s].size(); ++ni) {
      const int node = r.nodes[s][ni];
      if (!held.empty() && held[static_cast<size_t>(node)]) continue;
      const Vec3 p = x.col(node);
      tree.query(p, candidates);
      const std::vector<int>* ring = r.ring[s].empty() ? nullptr : &r.ring[s][ni];
      auto near = [&](const Tet& t) {  // its own tet, or one touching its neighbours
        for (int w : t) {
          if (w == node) return true;
          if (ring && std::binary_search(ring->begin(), ring->end(), w)) return true;
        }
        return false;
      };
      bool inside = false;
      for (int k : candidates) {
        const Tet& t = tets[static_cast<size_t>(other_tets[static_cast<size_t>(k)])];
        if (near(t)) continue;
        if (inside_tet(x, t, p)) {
          inside = true;
          break;
        }
      }
      if (!inside) continue;
      // The closest boundary face of the other side; out along its normal.
      double best = std::numeric_limits<double>::infinity();
      const Tri* face = nullptr;
      for (const Tri& f : r.faces[other]) {
        const Vec3 q = closest_point_on_triangle(p, x.col(f[0]), x.col(f[1]), x.col(f[2]));
        const double d = (q - p).squaredNorm();
        if (d < best) {
          best = d;
          face = &f;
        }
      }
      const Vec3 a = x.col((*face)[0]), b = x.col((*face)[1]), c = x.col((*face)[2]);
      const Vec3 area = (b - a).cross(c - a);
      if (!(area.norm() > 0.0)) continue;  // a collapsed face has no normal
      const Vec3 n = area.normalized();
      const double depth = (a - p).dot(n);
      // A node resting on the other side's surface is touching, not penetrating.
      if (!(depth > 1e-12 * std::sqrt((b - a).cross(c - a).norm()))) continue;
      if (depth > r.max_correction) {
        ++report.too_deep;
        continue;
      }
      x.col(node) = p + depth * n;
      v.col(node).setZero();
      ++report.contacts;
      report.max_depth = std::max(report.max_depth, depth);
      for (const Tri& f : r.faces[s])
        if (f[0] == node || f[1] == node || f[2] == node)
          report.area += 0.5 / 3.0 * (Vec3(x.col(f[1]) - x.col(f[0]))).cross(Vec3(x.col(f[2]) - x.col(f[0]))).norm();
    }
  }
  return report;
}

}  // namespace msd
