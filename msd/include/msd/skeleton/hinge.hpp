// The knee: a one-degree-of-freedom hinge with a fixed centre (thesis 5.4,
// "a simple one degree of freedom joint ... with a fixed center of rotation").
// The lower bone turns by the flexion angle theta about the axis n through the
// centre c; every node attached to it (its surface nodes and bone points)
// follows exactly,
//
//   x = c + R(theta) (X - c),   v = omega n x (x - c),
//
// with R Rodrigues' rotation. Dynamics: I theta'' = tau, I the bone's moment
// about the axis and tau the torques about it (tissue, tendons, gravity, an
// added joint torque), stepped by semi-implicit Euler; at the ends of the
// flexion range the angle is held and the velocity into the stop removed.
#pragma once

#include "msd/core/types.hpp"

#include <vector>

namespace msd {

struct Hinge {
  Vec3 centre{Vec3::Zero()};
  Vec3 axis{Vec3::UnitX()};  ///< unit; positive rotation = flexion
  double min_angle = 0.0;    ///< rad (0 = straight)
  double max_angle = 2.4;    ///< rad
  double inertia = 0.0;      ///< kg m^2 about the axis
};

struct HingeState {
  double angle = 0.0;     ///< rad
  double velocity = 0.0;  ///< rad/s
};

/// Throws msd::Error for a zero axis, an empty or inverted range, or a
/// non-positive inertia.
void check_hinge(const Hinge& hinge);

/// R(theta) about the hinge's axis.
Mat3 hinge_rotation(const Hinge& hinge, double angle);

/// Places the attached `nodes` (rest positions `rest`, 3 x N) at the hinge's
/// state: positions into x and velocities into v (3 x N).
void place_attached(const Hinge& hinge, const HingeState& s, const Points& rest, const std::vector<int>& nodes,
                    Points& x, Points& v);

/// The component along the hinge's axis of `torque` taken about its centre.
inline double axial_torque(const Hinge& hinge, const Vec3& torque) { return hinge.axis.normalized().dot(torque); }

/// One semi-implicit Euler step under the axial torque `tau` (N m), held
/// within the flexion range.
void step_hinge(const Hinge& hinge, double tau, double dt, HingeState& s);

}  // namespace msd
