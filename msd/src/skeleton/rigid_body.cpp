#include "msd/skeleton/rigid_body.hpp"

#include <string>

namespace msd {

MassProperties region_mass_properties(const TetMesh& mesh, int region, double density) {
  if (!(density > 0.0)) throw Error("rigid body: density must be positive, got " + std::to_string(density));
  MassProperties p;
  Mat3 second = Mat3::Zero();  // integral of x x^T
  Vec3 first = Vec3::Zero();   // integral of x
  double volume = 0.0;
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    if (mesh.region[e] != region) continue;
    const Tet& t = mesh.tets[e];
    const double v = tet_signed_volume(mesh.nodes, t);
    Vec3 s = Vec3::Zero();
    Mat3 vv = Mat3::Zero();
    for (int k = 0; k < 4; ++k) {
      const Vec3 x = mesh.nodes.col(t[static_cast<size_t>(k)]);
      s += x;
      vv += x * x.transpose();
    }
    volume += v;
    first += v * s / 4.0;
    second += v / 20.0 * (vv + s * s.transpose());
  }
  if (!(volume > 0.0)) throw Error("rigid body: region " + std::to_string(region) + " has no tets");
  p.mass = density * volume;
  p.centre = first / volume;
  const Mat3 c = density * second - p.mass * p.centre * p.centre.transpose();  // about the centre
  p.inertia = c.trace() * Mat3::Identity() - c;
  return p;
}

double moment_about_axis(const MassProperties& body, const Vec3& point, const Vec3& axis) {
  const Vec3 n = axis.normalized();
  const Vec3 d = body.centre - point;
  const Vec3 r = d - d.dot(n) * n;  // offset of the centre from the axis
  return n.dot(body.inertia * n) + body.mass * r.squaredNorm();
}

std::pair<Vec3, Vec3> force_and_torque(const Points& x, const Points& f, const std::vector<int>& nodes,
                                       const Vec3& centre) {
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  for (int i : nodes) {
    const Vec3 fi = f.col(i);
    force += fi;
    torque += (Vec3(x.col(i)) - centre).cross(fi);
  }
  return {force, torque};
}

}  // namespace msd
