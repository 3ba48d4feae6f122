// Every field of a leg scene, declared once: path, unit, default, range, doc.
// The scene reader (scene.cpp) reads through these; docs/leg-scenes.md's field
// table is generated from them (tests/leg/scene_parameters_test.cpp holds it
// to them). Defaults that the model owns come from msd::LegModelOptions and
// msd::TissueMaterial, not restated here.
#include "leg/scene.hpp"

#include "msd/material/tissue_material.hpp"

#include <cmath>

namespace leg {

namespace {

using tbio::Kind;
using tbio::Parameter;
using tbio::Range;

using namespace tbio::declare;
using tbio::number_text;

std::string degrees_text(double lo, double hi) {
  return "[" + number_text(lo * 180.0 / M_PI) + ", " + number_text(hi * 180.0 / M_PI) + "]";
}

std::vector<Parameter> declare() {
  const msd::LegModelOptions model;
  const msd::TissueMaterial material;
  const Range any = Range::any(), positive = Range::positive(), non_negative = Range::non_negative();
  return {
      other("name", Kind::Text, "", "the file's stem", "the scene's name"),
      other("description", Kind::Text, "", "empty", "one line on what the scene shows"),
      other("geometry", Kind::Text, "", "msd/data/leg/leg.yaml", "a mesh scene (`tissuebench mesh`), relative to this file"),
      flag("mesh_pull", true, "apply the geometry's pull areas (thesis 4.6)"),
      number("duration", "s", std::nullopt, positive, "simulated time"),
      number("dt", "s", std::nullopt, positive, "time step"),
      choice("integrator", {"symplectic_euler", "explicit_euler", "velocity_verlet", "imex_euler", "backward_euler", "bdf2"}, "symplectic_euler",
             "the tissue's integrator (msd/integrate/step.hpp); imex_euler: symplectic Euler with the tendon strands' stiffness implicit, for real tendons at the tissue's explicit step; backward_euler, bdf2: implicit (first, second order), for stiff tendons and large steps (docs/msd-model.md); the knee is stepped semi-implicitly with any of them"),
      number("newton.tolerance", "1", model.newton.tolerance, Range::open(0, 1), "backward_euler and bdf2 only: Newton's residual relative to the balance's largest term"),
      integer("newton.max_iterations", model.newton.max_iterations, Range::closed(1, 1000), "backward_euler and bdf2 only: Newton iterations before the step is halved"),
      integer("newton.max_step_cuts", model.newton.max_step_cuts, Range::closed(0, 30), "backward_euler and bdf2 only: halvings of a step whose Newton solve failed before the run fails"),
      flag("newton.reuse_factorization", model.newton.reuse_factorization, "backward_euler and bdf2 only: modified Newton - try an earlier step's LU factorisation first (false: factorise every iteration)"),
      choice("newton.linear_solver", {"sparse_lu", "symmetric_ldlt"}, msd::to_string(model.newton.linear_solver), "backward_euler and bdf2 only: sparse_lu factorises Newton's matrix (exact Newton); symmetric_ldlt its symmetric part (approximate Newton, cheaper factorisations)"),
      flag("newton.keep_orientation", model.newton.keep_orientation, "backward_euler and bdf2 only: every iterate Newton accepts keeps every tet's orientation"),
      integer("newton.anderson_depth", model.newton.anderson_depth, Range::closed(0, 8), "backward_euler and bdf2 with reuse_factorization only: Anderson acceleration of the chord steps, mixing in this many earlier ones (0: plain chord steps)"),
      number("output_interval", "s", 0.04, positive, "time between recorded frames (the thesis' 1/25 s); a whole number of steps"),
      vector3("gravity", "m/s^2", model.gravity, "in the leg's frame (z up the leg, x forward)"),
      other("terms", Kind::List, "", "all", "force terms: springs, dampers, repulsion, volume, gravity, neo_hookean (the continuum element, one volume ratio per cube of the mesh; needs materials.*.poisson_ratio)"),
      number("nonlinear_threshold", "1", model.nonlinear_threshold, Range::closed(0, 1), "thesis 5.8: the non-linear element forces act below this fraction of rest"),
      integer("threads", model.threads, Range::closed(1, 256), "threads of the force evaluation; the results are bit-identical for every count"),
      choice("forces", {"engine", "reference"}, "engine", "engine: each edge once, threaded; reference: the per-tet loop (same forces up to round-off; docs/msd-model.md 2.5)"),
      number("materials.*.density", "kg/m^3", std::nullopt, positive, "of `passive` and `muscle` tissue"),
      number("materials.*.youngs_modulus", "Pa", std::nullopt, positive, "Young's modulus"),
      number("materials.*.damping_time", "s", 0.0, non_negative, "k_d = damping_time k_s"),
      number("materials.*.stiffness_scale", "1", 1.0, any, "calibration factor on k_s, k_r, k_v"),
      number("materials.*.repulsion_factor", "1", 0.5, non_negative, "k_r relative to the reference stiffness"),
      number("materials.*.volume_factor", "1", 1.6, non_negative, "k_v relative to the reference stiffness"),
      optional_number("materials.*.poisson_ratio", "1", Range::open(-1, 0.5), "read only by the continuum element (terms: neo_hookean): its mu and lambda are E's, nu's and stiffness_scale's; benchmarks/materials.yaml: 0.495 for flesh and muscle"),
      number("materials.*.repulsion_floor", "1", material.repulsion_floor, any, "tangent continuation of the repulsion below floor x0"),
      number("materials.skin.youngs_modulus", "Pa", std::nullopt, positive, "the skin: a membrane on the leg's outer surface (msd/forces/skin_membrane.hpp), incompressible neo-Hookean, mu = E/3; in vivo 129 +- 88 kPa (Diridollou et al. 2000; benchmarks/materials.yaml's skin)"),
      number("materials.skin.thickness", "m", std::nullopt, positive, "the skin's thickness, epidermis and dermis (the thigh's 1.55 mm, Laurent et al. 2007); the membrane carries E x thickness"),
      vector3("knee.centre", "m", std::nullopt, "the hinge's centre"),
      vector3("knee.axis", "1", msd::Vec3::UnitY(), "hinge axis; positive rotation = flexion"),
      other("knee.range_deg", Kind::List, "deg", degrees_text(model.min_flexion, model.max_flexion), "[min, max]: the hard stops"),
      number("knee.initial_angle_deg", "deg", 0.0, any, "within range_deg"),
      number("knee.initial_velocity_deg", "deg/s", 0.0, any, "initial flexion rate"),
      other("knee.angle_deg", Kind::List, "deg", "none", "kinematic override: [t, deg] keyframes, linear"),
      optional_number("knee.release", "s", non_negative, "the override ends here and the knee moves dynamically"),
      other("knee.torque", Kind::List, "N m", "none", "added joint torque: [t, N m] keyframes"),
      number("knee.damping", "N m s/rad", model.joint_damping, non_negative, "the knee's passive structures, viscous"),
      number("knee.limit_stiffness", "N m/rad", model.limit_stiffness, non_negative, "elastic end-range torque beyond passive_range_deg"),
      other("knee.passive_range_deg", Kind::List, "deg", "range_deg", "[lo, hi]: where the end-range torque starts"),
      number("knee.joint_space_radius", "m", 0.0, non_negative, "also leave out tets squeezed between the bones"),
      vector3("hip.pivot", "m", std::nullopt, "a scripted hip: the femur's point the keyframes place (the hip's centre), at rest"),
      other("hip.keyframes", Kind::List, "m, 1", "none", "[t, x, y, z, qw, qx, qy, qz]: where the pivot is and the femur's orientation (a unit quaternion from the rest pose); a C1 spline (Catmull-Rom) through them, at rest at the first and last, held outside; the knee rides on the femur"),
      number("tendons.modulus", "Pa", model.tendon_modulus, positive, "every strand's modulus"),
      other("tendons.moduli", Kind::List, "Pa", "none", "per-tendon overrides, by tendon name"),
      number("tendons.strand_area", "m^2", model.strand_area, positive, "cross-section per strand"),
      number("tendons.toe_strain", "1", model.tendon_toe_strain, Range::closed_open(0, 0.2), "the toe region's end: tension rises quadratically to it, then at the modulus (0: linear, the thesis; real tendon about 0.02-0.03, Maganaris & Paul 1999)"),
      number("tendons.failure_strain", "1", 0.1, Range::open(0, 1), "the summary warns when a strand's strain passes it (tendon fails at about 8-10 % strain, Butler et al. 1978; Wren et al. 2001)"),
      choice("tendons.insertions", {"path", "nodes"}, "path", "bone ends at the paths' last points, or at the bone node the route reached (the thesis)"),
      choice("tendons.route", {"tissue", "direct"}, "tissue", "tissue: each strand runs through the tissue nodes its path snapped to and drags them (the thesis, 4.5); direct: straight from its muscle node to its bone end - a tendon slides in its sheath and bears on no flesh it passes"),
      choice("tendons.attach", {"patch", "fibre_ends"}, "patch", "patch: each tendon's strands leave the muscle nodes nearest its path's start (the thesis); fibre_ends: an aponeurosis - one strand from every end of the muscle's fibres on the tendon's side, sharing the tendon's section (strands x strand_area); needs route: direct"),
      optional_number("tendons.engage_at", "s", non_negative, "slack until then; then natural length = the path's length"),
      number("tendons.pretension.fraction", "1", std::nullopt, Range::closed_open(0, 1), "L0 -> (1 - fraction) L0"),
      number("tendons.pretension.start", "s", 0.0, non_negative, "when the pre-tension ramp starts"),
      number("tendons.pretension.duration", "s", 0.0, non_negative, "the ramp's length (0: a step)"),
      number("muscles.max_stress", "Pa", model.max_muscle_stress, positive, "maximum isometric stress (with law: hill, the specific tension: F_max = it x the cross-section)"),
      optional_number("muscles.pcsa.front", "m^2", positive, "F_max = max_stress x this cross-section (the published PCSA: docs/leg-geometry.md, 225 cm^2 for this leg's quadriceps) instead of the mesh's section"),
      optional_number("muscles.pcsa.back", "m^2", positive, "the same for the back muscle (the hamstrings: 88 cm^2)"),
      number("muscles.optimal_at_deg.front", "deg", model.front_optimal_angle * 180.0 / M_PI, any, "the knee angle at which the front muscle is at its mesh length (with law: hill, its fibres' optimum) and its tendons just taut: their natural lengths are taken there (0: the straight knee of the mesh, the thesis); within knee.range_deg; needs tendons.route: direct and tendons.insertions: path; not with tendons.engage_at"),
      number("muscles.optimal_at_deg.back", "deg", model.back_optimal_angle * 180.0 / M_PI, any, "the same for the back muscle"),
      choice("muscles.law", {"thesis", "hill"}, "thesis", "thesis: units pull with activation x F (times force_length_zero's limb); hill: Zajac 1989's Hill-type law (msd/forces/muscle_units.hpp)"),
      number("muscles.hill.rest_fibre_stretch", "1", model.hill.rest_fibre_stretch, positive, "the fibres' length in the mesh's posture over their optimal length"),
      number("muscles.hill.active_width", "1", model.hill.active_width, Range::open(0, 1), "the active force-length curve is zero at 1 +- this (Zajac 1989: 0.5)"),
      number("muscles.hill.passive_strain", "1", model.hill.passive_strain, positive, "fibre strain at which the passive element carries F_max (Thelen 2003: 0.6)"),
      number("muscles.hill.passive_shape", "1", model.hill.passive_shape, Range::open(0, 50), "the passive curve's exponential shape (Thelen 2003: 4)"),
      flag("muscles.hill.force_velocity", model.hill.force_velocity, "the force-velocity relation (needs integrator: backward_euler or bdf2)"),
      number("muscles.hill.max_velocity", "1/s", model.hill.max_velocity, positive, "maximum shortening velocity, optimal lengths per second (Zajac 1989: 10)"),
      number("muscles.hill.curvature", "1", model.hill.curvature, positive, "Hill's constant a / F_max (Hill 1938, Zajac 1989: 0.25)"),
      number("muscles.hill.eccentric_max", "1", model.hill.eccentric_max, Range::open(1, 10), "the lengthening plateau of f_V (1.8)"),
      number("muscles.activation_time", "s", model.activation_time, non_negative, "activation dynamics: rise time constant (Zajac 1989: 0.01); 0 with deactivation_time 0: the activation is the script's value"),
      number("muscles.deactivation_time", "s", model.deactivation_time, non_negative, "activation dynamics: fall time constant (Zajac 1989: 0.04)"),
      other("muscles.force_length_zero", Kind::Number, "1", number_text(model.force_length.zero_at), "lambda_0 of the force-length relation in [0, 1); `none`: the thesis' constant force"),
      number("muscles.unit_angle_deg", "deg", model.unit_angle_deg, Range::open(0, 90), "the contractile units' angle tolerance"),
      vector3("muscles.front_line", "1", model.front_line, "the front muscle's line of action"),
      vector3("muscles.back_line", "1", model.back_line, "the back muscle's line of action"),
      other("muscles.script", Kind::Text, "", "none", "activation script (thesis 5.7 format; FRONT_MUSCLE, BACK_MUSCLE)"),
      number("muscles.activation.front", "1", 0.0, Range::closed(0, 1), "constant activation (no script)"),
      number("muscles.activation.back", "1", 0.0, Range::closed(0, 1), "constant activation (no script)"),
      other("contact.knee", Kind::List, "m", "none", "{lo, hi}: skin against skin behind the knee in this box"),
      other("contact.obstacles", Kind::List, "", "none", "rigid objects: {name, shape: cylinder or plane, point, axis, radius, normal, response, box, motion}"),
      number("contact.obstacles[].radius", "m", std::nullopt, positive, "a cylinder's radius"),
      number("analysis.from", "s", 0.0, non_negative, "the summary's extremes from here on"),
      other("analysis.bulge", Kind::List, "m", "none", "skin areas {name, lo, hi} whose bulge is reported"),
      number("analysis.drop.release", "s", 0.0, non_negative, "pendulum metrics of the knee angle after this"),
      other("analysis.wobble.probe", Kind::List, "m", "none", "{lo, hi}: the flesh whose wobble is measured"),
      number("analysis.wobble.after", "s", 0.0, non_negative, "the wobble's ring-down from here on"),
      other("variants", Kind::List, "", "none", "runs differing in constant activation: {name, activation: {front, back}}"),
      integer("outputs.obj_every", 1.0, non_negative, "an OBJ of the skin every n-th frame (0: none)"),
  };
}

}  // namespace

const std::vector<tbio::Parameter>& leg_scene_parameters() {
  static const std::vector<tbio::Parameter> all = declare();
  return all;
}

const tbio::Parameter& leg_scene_parameter(const std::string& path) {
  return tbio::find_parameter(leg_scene_parameters(), path, "leg scene");
}

}  // namespace leg
