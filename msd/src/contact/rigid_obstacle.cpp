#include "msd/contact/rigid_obstacle.hpp"

#include <cmath>

namespace msd {

ContactResponse parse_contact_response(const std::string& name) {
  if (name == "stick" || name == "thesis") return ContactResponse::Stick;
  if (name == "frictionless") return ContactResponse::Frictionless;
  throw Error("contact response '" + name + "' is not one of stick (the thesis), frictionless");
}

std::string to_string(ContactResponse response) {
  return response == ContactResponse::Stick ? "stick" : "frictionless";
}

CylinderGap cylinder_gap(const RigidCylinder& c, const Vec3& offset, const Vec3& x) {
  const Vec3 rel = x - (c.point + offset);
  const Vec3 d = rel - rel.dot(c.axis) * c.axis;
  const double r = d.norm();
  CylinderGap g;
  g.depth = c.radius - r;
  if (r > 0.0) {
    g.normal = d / r;
  } else {
    // On the axis: any direction normal to it will do; take the one closest to +z
    // (or +x when the axis is vertical).
    const Vec3 up = std::abs(c.axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
    g.normal = (up - up.dot(c.axis) * c.axis).normalized();
  }
  return g;
}

namespace {

// Projection to the closest surface point along the normal, then the velocity
// per the response (thesis 5.6.2).
bool respond(const ContactGap& g, ContactResponse response, const Vec3& velocity, Vec3& x, Vec3& v) {
  if (!(g.depth > 0.0)) return false;
  x += g.depth * g.normal;
  if (response == ContactResponse::Stick) {
    v = velocity;
  } else {
    const double vn = (v - velocity).dot(g.normal);
    if (vn < 0.0) v -= vn * g.normal;
  }
  return true;
}

}  // namespace

bool resolve_cylinder_contact(const RigidCylinder& c, ContactResponse response, const Vec3& offset,
                              const Vec3& velocity, Vec3& x, Vec3& v) {
  return respond(cylinder_gap(c, offset, x), response, velocity, x, v);
}

ContactGap plane_gap(const RigidPlane& p, const Vec3& offset, const Vec3& x) {
  return {-(x - p.point - offset).dot(p.normal), p.normal};
}

bool resolve_plane_contact(const RigidPlane& p, ContactResponse response, const Vec3& offset, const Vec3& velocity,
                           Vec3& x, Vec3& v) {
  return respond(plane_gap(p, offset, x), response, velocity, x, v);
}

void check_plane(const RigidPlane& p, const std::string& where) {
  if (!p.point.allFinite()) throw Error(where + ": the plane's point is not finite");
  if (!p.normal.allFinite() || std::abs(p.normal.norm() - 1.0) > 1e-9)
    throw Error(where + ": the plane's normal must be a unit vector");
}

void check_cylinder(const RigidCylinder& c, const std::string& where) {
  if (!c.point.allFinite()) throw Error(where + ": the cylinder's axis point is not finite");
  if (!c.axis.allFinite() || std::abs(c.axis.norm() - 1.0) > 1e-9)
    throw Error(where + ": the cylinder's axis must be a unit vector");
  if (!(c.radius > 0.0) || !std::isfinite(c.radius))
    throw Error(where + ": the cylinder's radius must be positive (got " + std::to_string(c.radius) + ")");
}

ContactGap obstacle_gap(const RigidObstacle& ob, const Vec3& offset, const Vec3& x) {
  return ob.shape == ObstacleShape::Plane ? plane_gap(ob.plane, offset, x) : cylinder_gap(ob.cylinder, offset, x);
}

bool resolve_obstacle_contact(const RigidObstacle& ob, const Vec3& offset, const Vec3& velocity, Vec3& x, Vec3& v) {
  return ob.shape == ObstacleShape::Plane ? resolve_plane_contact(ob.plane, ob.response, offset, velocity, x, v)
                                          : resolve_cylinder_contact(ob.cylinder, ob.response, offset, velocity, x, v);
}

void check_obstacle(const RigidObstacle& ob, const std::string& where) {
  if (ob.shape == ObstacleShape::Plane)
    check_plane(ob.plane, where);
  else
    check_cylinder(ob.cylinder, where);
}

}  // namespace msd
