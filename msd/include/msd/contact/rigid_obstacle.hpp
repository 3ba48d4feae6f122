// Contact of the tissue's surface nodes with rigid external objects (thesis
// 5.6: "skin against rigid external objects"), by position constraints as in
// the thesis (5.6.2): a node found inside the object after a step is moved to
// the object's surface along the surface normal, and its velocity is set to
// the object's (the thesis set it to zero; its objects did not move).
//
// The object here is a circular cylinder of unbounded length (a rod longer
// than the sample), with axis line {c + s a}, unit direction a and radius R.
// For a point x, with d = (x - c) - ((x - c) . a) a and r = |d|:
//     inside    <=>  r < R,
//     normal    n = d / r           (outward from the axis),
//     depth     g = R - r           (> 0 inside),
//     projected x' = x + g n        (the closest surface point).
//
// The force the object exerts (Platt & Barr's reaction constraint, thesis
// 5.6.2) is not part of the step - the projection does its work - but is
// measured afterwards: a node resting on the surface with internal plus
// external force f needs lambda n, lambda = max(0, -f . n), to stay there.
#pragma once

#include "msd/core/types.hpp"

#include <string>
#include <vector>

namespace msd {

struct RigidCylinder {
  Vec3 point{Vec3::Zero()};       ///< a point of the axis at rest, m
  Vec3 axis{Vec3::UnitY()};       ///< unit direction of the axis
  double radius = 0.0;            ///< m
};

/// What a node that entered the object keeps of its velocity relative to it:
/// Stick (the thesis: none) or Frictionless (the tangential part; only the
/// inward normal part is removed).
enum class ContactResponse { Stick, Frictionless };
ContactResponse parse_contact_response(const std::string& name);
std::string to_string(ContactResponse response);

/// Where a point lies relative to an object's surface.
struct ContactGap {
  double depth = 0.0;          ///< > 0 inside (cylinder: R - r), m
  Vec3 normal{Vec3::Zero()};   ///< outward unit normal at the closest surface point
};
using CylinderGap = ContactGap;

/// Where x lies relative to the cylinder moved by `offset`.
CylinderGap cylinder_gap(const RigidCylinder& c, const Vec3& offset, const Vec3& x);

/// The thesis' response for one node: if x is inside the cylinder (moved by
/// `offset`, moving with `velocity`), moves it to the closest surface point and
/// sets its velocity per `response`. Returns whether it was inside.
bool resolve_cylinder_contact(const RigidCylinder& c, ContactResponse response, const Vec3& offset,
                              const Vec3& velocity, Vec3& x, Vec3& v);

/// Throws msd::Error naming `where` unless the cylinder is usable (finite
/// point, unit-normalisable axis, positive radius).
void check_cylinder(const RigidCylinder& c, const std::string& where);

/// A rigid half-space - a table, a wall, the floor: solid where
/// (x - point) . normal < 0; `normal` is the unit outward normal. For x inside,
/// depth g = -(x - point) . normal and the closest surface point is x + g n.
struct RigidPlane {
  Vec3 point{Vec3::Zero()};
  Vec3 normal{Vec3::UnitZ()};
};

/// Where x lies relative to the plane moved by `offset`.
ContactGap plane_gap(const RigidPlane& p, const Vec3& offset, const Vec3& x);

/// The thesis' response against a plane, as resolve_cylinder_contact.
bool resolve_plane_contact(const RigidPlane& p, ContactResponse response, const Vec3& offset, const Vec3& velocity,
                           Vec3& x, Vec3& v);

/// Throws msd::Error naming `where` unless the plane is usable (finite point,
/// unit normal).
void check_plane(const RigidPlane& p, const std::string& where);

enum class ObstacleShape { Cylinder, Plane };

/// A rigid object and the nodes tested against it (surface nodes only: the
/// model tests only what a scene can bring into contact).
struct RigidObstacle {
  std::string name;
  ObstacleShape shape = ObstacleShape::Cylinder;
  RigidCylinder cylinder;  ///< when shape is Cylinder
  RigidPlane plane;        ///< when shape is Plane
  ContactResponse response = ContactResponse::Stick;
  std::vector<int> nodes;
};

/// What an obstacle did in the last step.
struct ObstacleContact {
  int contacts = 0;           ///< nodes found inside and put back on its surface
  double max_depth = 0.0;     ///< deepest of them, m
  Vec3 force{Vec3::Zero()};   ///< on the tissue: sum of lambda n, lambda = max(0, -f . n)
};

/// Where x lies relative to the obstacle moved by `offset`.
ContactGap obstacle_gap(const RigidObstacle& ob, const Vec3& offset, const Vec3& x);
/// The thesis' response against the obstacle's shape (resolve_cylinder_contact
/// or resolve_plane_contact).
bool resolve_obstacle_contact(const RigidObstacle& ob, const Vec3& offset, const Vec3& velocity, Vec3& x, Vec3& v);
/// check_cylinder or check_plane, by shape.
void check_obstacle(const RigidObstacle& ob, const std::string& where);

}  // namespace msd
