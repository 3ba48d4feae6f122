// The forces of a model's moving parts besides the tissue (Model::strands and
// Model::muscles; thesis 5.3, 5.2.7), evaluated by evaluate_forces after the
// element terms, and where a strand's anchor is.
//
//  - A strand through nodes p_0 ... p_{m-1} (and its anchor a, when it has
//    one) pulls with T = k_t (L - L0) for L > L0 (msd/forces/tendon.hpp); the
//    force on the anchor, -T u_last, is kept per strand (Scratch::anchor_force)
//    for the joint that carries it. L0 is Controls::strand_natural_length[s]
//    when given, else the model's.
//    Its toe region (Strand::toe_strain) makes the tension rise
//    quadratically first. Scratch::strand_strain records (L - L0) / L0.
//  - A muscle's units pull with activation * unit_force (times f_L)
//    (msd/forces/muscle_units.hpp); activation 0 adds nothing. A Hill
//    muscle's units pull with the Hill law's tension at their length and
//    lengthening rate (its passive element also at activation 0).
//  - The skin membrane (Model::skin, msd/forces/skin_membrane.hpp) pulls its
//    surface triangles back towards their rest shape.
#pragma once

#include "msd/model/model.hpp"

namespace msd {

/// Group g's rigid motion in `controls` (Controls::group_motion), or null.
const RigidMotion* group_motion(const Controls& controls, int group);

/// The rigid motion carrying joint j's hinge (its parent's), or null: fixed.
const RigidMotion* joint_frame(const Model& model, const Controls& controls, int joint);

/// Where a point fixed on kinematic group g (at `rest` when the group is at
/// rest) is: turned by the group's joint, x = c + R(theta) (rest - c) (then
/// carried by the joint's frame, when it has one), placed by the group's rigid
/// motion, or translated with the group's first node.
Vec3 group_point(const Model& model, int group, const Vec3& rest, const Points& x,
                 const std::vector<HingeState>& joints, const Controls& controls);

/// The natural length of strand s under `controls`.
double strand_natural_length(const Model& model, size_t strand, const Controls& controls);

/// Adds the strands', muscles' and skin's forces at positions x and velocities v
/// (3 x N) to scratch.f and records scratch.strand_tension, strand_strain and
/// anchor_force (sized to the strands; no allocation once sized).
void add_part_forces(const Model& model, const Points& x, const Points& v, const std::vector<HingeState>& joints,
                     const Controls& controls, Scratch& scratch);

}  // namespace msd
