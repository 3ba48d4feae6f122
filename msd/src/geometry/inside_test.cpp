#include "msd/geometry/inside_test.hpp"

#include <algorithm>
#include <cmath>

namespace msd {

namespace {

// Edge function of the directed edge u -> w at query q in the yz plane
// (positive when q lies to the left), made antisymmetric in (u, w) bit for bit
// by always evaluating from the lower-numbered vertex, with the
// simulation-of-simplicity tie-break for q on the edge's line: q is read as
// (y + e, z + e^2).
int edge_sign(const TriangleMesh& m, int iu, int iw, double qy, double qz) {
  const bool flip = iu > iw;
  if (flip) std::swap(iu, iw);
  const double uy = m.vertices(1, iu), uz = m.vertices(2, iu);
  const double wy = m.vertices(1, iw), wz = m.vertices(2, iw);
  const double e = (wy - uy) * (qz - uz) - (wz - uz) * (qy - uy);
  int s = 0;
  if (e > 0) s = 1;
  else if (e < 0) s = -1;
  else {
    const double dy = -(wz - uz);  // d e / d qy
    const double dz = wy - uy;     // d e / d qz
    s = dy > 0 ? 1 : dy < 0 ? -1 : (dz > 0 ? 1 : dz < 0 ? -1 : 0);
  }
  return flip ? -s : s;
}

double edge_value(const TriangleMesh& m, int iu, int iw, double qy, double qz) {
  const double uy = m.vertices(1, iu), uz = m.vertices(2, iu);
  const double wy = m.vertices(1, iw), wz = m.vertices(2, iw);
  return (wy - uy) * (qz - uz) - (wz - uz) * (qy - uy);
}

}  // namespace

InsideTest::InsideTest(const TriangleMesh& surface) : surface_(surface) {
  const Aabb box = bounding_box(surface);
  y0_ = box.lo.y();
  z0_ = box.lo.z();
  const double wy = box.hi.y() - box.lo.y(), wz = box.hi.z() - box.lo.z();
  const double n = std::max(1.0, std::sqrt(static_cast<double>(surface.num_triangles())));
  cell_size_ = std::max({wy, wz, 1e-300}) / n;
  ny_ = std::max(1, static_cast<int>(std::ceil(wy / cell_size_)) + 1);
  nz_ = std::max(1, static_cast<int>(std::ceil(wz / cell_size_)) + 1);
  bins_.assign(static_cast<size_t>(ny_) * nz_, {});
  for (int t = 0; t < surface.num_triangles(); ++t) {
    const Tri& tri = surface.triangles[t];
    double ylo = 1e300, yhi = -1e300, zlo = 1e300, zhi = -1e300;
    for (int k = 0; k < 3; ++k) {
      ylo = std::min(ylo, surface.vertices(1, tri[k]));
      yhi = std::max(yhi, surface.vertices(1, tri[k]));
      zlo = std::min(zlo, surface.vertices(2, tri[k]));
      zhi = std::max(zhi, surface.vertices(2, tri[k]));
    }
    const int j0 = std::clamp(static_cast<int>(std::floor((ylo - y0_) / cell_size_)), 0, ny_ - 1);
    const int j1 = std::clamp(static_cast<int>(std::floor((yhi - y0_) / cell_size_)), 0, ny_ - 1);
    const int k0 = std::clamp(static_cast<int>(std::floor((zlo - z0_) / cell_size_)), 0, nz_ - 1);
    const int k1 = std::clamp(static_cast<int>(std::floor((zhi - z0_) / cell_size_)), 0, nz_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int k = k0; k <= k1; ++k) bins_[static_cast<size_t>(j) * nz_ + k].push_back(t);
  }
}

const std::vector<int>& InsideTest::cell(double y, double z) const {
  const double fj = std::floor((y - y0_) / cell_size_), fk = std::floor((z - z0_) / cell_size_);
  if (!(fj >= 0 && fj < ny_ && fk >= 0 && fk < nz_)) return empty_;
  return bins_[static_cast<size_t>(fj) * nz_ + static_cast<size_t>(fk)];
}

std::vector<double> InsideTest::crossings(double y, double z) const {
  std::vector<double> xs;
  const TriangleMesh& m = surface_;
  for (int t : cell(y, z)) {
    const Tri& tri = m.triangles[t];
    const int s0 = edge_sign(m, tri[1], tri[2], y, z);
    const int s1 = edge_sign(m, tri[2], tri[0], y, z);
    const int s2 = edge_sign(m, tri[0], tri[1], y, z);
    if (s0 == 0 || s1 == 0 || s2 == 0) continue;  // projection has zero area
    if (!(s0 == s1 && s1 == s2)) continue;
    // Barycentric interpolation of x at the unperturbed (y, z).
    const double w0 = edge_value(m, tri[1], tri[2], y, z);
    const double w1 = edge_value(m, tri[2], tri[0], y, z);
    const double w2 = edge_value(m, tri[0], tri[1], y, z);
    const double sum = w0 + w1 + w2;
    if (sum == 0.0) continue;  // parallel to the ray
    xs.push_back((w0 * m.vertices(0, tri[0]) + w1 * m.vertices(0, tri[1]) +
                  w2 * m.vertices(0, tri[2])) /
                 sum);
  }
  std::sort(xs.begin(), xs.end());
  return xs;
}

std::vector<char> InsideTest::inside_on_line(double y, double z,
                                             const std::vector<double>& xs) const {
  const std::vector<double> cross = crossings(y, z);
  std::vector<char> result(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) {
    const auto beyond = cross.end() - std::upper_bound(cross.begin(), cross.end(), xs[i]);
    result[i] = static_cast<char>(beyond % 2 == 1);
  }
  return result;
}

bool InsideTest::inside(const Vec3& p, double surface_tolerance) const {
  const std::vector<double> cross = crossings(p.y(), p.z());
  const auto beyond = cross.end() - std::upper_bound(cross.begin(), cross.end(), p.x());
  if (beyond % 2 == 1) return true;
  return surface_tolerance > 0.0 && distance(p, surface_tolerance) < surface_tolerance;
}

double InsideTest::distance(const Vec3& p, double max_distance) const {
  double best = max_distance;
  const TriangleMesh& m = surface_;
  for (const Tri& tri : m.triangles) {
    const Vec3 a = m.vertices.col(tri[0]), b = m.vertices.col(tri[1]), c = m.vertices.col(tri[2]);
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c).array() - best;
    const Vec3 hi = a.cwiseMax(b).cwiseMax(c).array() + best;
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    best = std::min(best, (closest_point_on_triangle(p, a, b, c) - p).norm());
  }
  return best;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

bool triangle_box_overlap(const Vec3& lo, const Vec3& hi, const Vec3& a, const Vec3& b,
                          const Vec3& c) {
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 v[3] = {a - centre, b - centre, c - centre};
  // Box face normals.
  for (int i = 0; i < 3; ++i) {
    const double mn = std::min({v[0][i], v[1][i], v[2][i]});
    const double mx = std::max({v[0][i], v[1][i], v[2][i]});
    if (mn > half[i] || mx < -half[i]) return false;
  }
  // Triangle normal.
  const Vec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const Vec3 n = e[0].cross(e[1]);
  const double r = half.cwiseProduct(n.cwiseAbs()).sum();
  if (std::abs(n.dot(v[0])) > r) return false;
  // Cross products of edges and box axes.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Vec3 axis = Vec3::Zero();
      axis[j] = 1.0;
      axis = axis.cross(e[i]);
      const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
      const double rad = half.cwiseProduct(axis.cwiseAbs()).sum();
      if (std::min({p0, p1, p2}) > rad || std::max({p0, p1, p2}) < -rad) return false;
    }
  }
  return true;
}

}  // namespace msd
