// What a leg run measures (thesis 6.2's observations, and the ones our scenes
// add). Three parts: the instruments, set up once from the model and the scene
// (regions' rest volumes, the muscles' shapes, skin areas, the probe); a frame,
// the quantities derived from one state that several sensors share (the
// embedded skin, the hinge rotation, muscle length and radius, tendon
// straightness); and the sensor table, one {name, unit, read} entry per column
// of /series, so the columns and each recorded row come from one list.
#pragma once

#include "leg/scene.hpp"

#include "msd/geometry/triangle_mesh.hpp"
#include "msd/mesh/embedding.hpp"
#include "msd/scene/leg_model.hpp"

#include <functional>
#include <string>
#include <vector>

namespace leg {

/// A muscle's nodes and the line its length is measured along.
struct MuscleShape {
  std::vector<int> nodes;
  msd::Vec3 line{msd::Vec3::UnitZ()};
  double rest_length = 0.0, rest_radius = 0.0;
};

/// Extent of the nodes along `line` (or `line_now`, the line turned with a
/// scripted femur) and their RMS distance from the line through their
/// centroid (m).
void length_and_radius(const msd::Points& x, const MuscleShape& m, double& length, double& radius,
                       const msd::Vec3* line_now = nullptr);

/// Sum of the signed volumes of the tets labelled `r` (m^3).
double region_volume(const msd::Points& x, const std::vector<msd::Tet>& tets, const std::vector<int>& region, int r);

/// Set up once per scene. Refers to (does not own) the model, scene and skin.
struct Instruments {
  const msd::LegModel* leg = nullptr;
  const LegScene* scene = nullptr;
  const msd::TriangleMesh* skin = nullptr;
  const msd::Embedding* skin_embedding = nullptr;
  const std::vector<msd::Tet>* embedding_tets = nullptr;  ///< the tets the skin is embedded in
  msd::Points skin_normals;                               ///< 3 x skin vertices, at rest
  std::vector<int> tet_region;
  double rest_volume[3] = {0.0, 0.0, 0.0};  ///< passive, front muscle, back muscle
  MuscleShape muscles[2];                   ///< front, back
  std::vector<std::vector<int>> bulge_vertices;  ///< per scene.bulge_areas: skin vertices
  std::vector<char> skin_lower;                  ///< skin vertex below the knee (moves with the shank)
  std::vector<int> probe_nodes;                  ///< the wobble probe's free nodes
  std::vector<int> thigh_free;                   ///< free tissue nodes above the knee
  msd::Vec3 shank_rest{msd::Vec3::Zero()}, down{-msd::Vec3::UnitZ()};
  /// The femur's and the lower bone's surfaces as one mesh (empty when the
  /// limb has no bone surfaces), and per vertex whether it is the lower bone's
  /// (turns with the hinge) or the femur's (fixed). Owned: set by add_bone_surfaces.
  msd::TriangleMesh bones;
  std::vector<char> bone_lower;
  /// The rigid obstacles drawn (empty without obstacles): each cylinder a
  /// 40 cm piece of its axis, each plane a 40 cm square about its point; per
  /// vertex its obstacle (moved by that obstacle's offset). Set by make_instruments.
  msd::TriangleMesh obstacles;
  std::vector<int> obstacle_of;
};

/// Throws msd::Error naming the scene file when a bulge area holds no skin
/// vertex or the wobble probe no free node.
Instruments make_instruments(const msd::LegModel& leg, const LegScene& scene, const msd::TriangleMesh& skin,
                             const msd::Embedding& skin_embedding, const std::vector<msd::Tet>& embedding_tets);

/// A surface to draw for `ob`: a cylinder as a 16-sided prism `length` long
/// centred on its axis point, a plane as a square of side `length` about its point.
msd::TriangleMesh obstacle_surface(const msd::RigidObstacle& ob, double length = 0.4);

/// Adds the limb's upper and lower bone surfaces (those it has) to `in.bones`.
void add_bone_surfaces(Instruments& in, const msd::TriangleMesh* upper_bone, const msd::TriangleMesh* lower_bone);

/// One recorded state and what several sensors derive from it.
struct Frame {
  const msd::LegState* state = nullptr;
  const msd::LegScratch* scratch = nullptr;   ///< of the step that led to `state`
  const msd::LegControls* controls = nullptr;
  msd::Points skin_x;                          ///< embedded skin positions
  msd::Points bones_x;                         ///< the bone surfaces, rigidly placed (3 x in.bones vertices)
  msd::Points obstacles_x;                     ///< the obstacles drawn, at their offsets (3 x in.obstacles vertices)
  msd::Mat3 rotation{msd::Mat3::Identity()};   ///< the knee hinge's rotation (relative to the femur, LegState::femur)
  double length_ratio[2] = {1.0, 1.0}, radius_ratio[2] = {1.0, 1.0};  ///< front, back muscle
  std::vector<double> straightness;            ///< per tendon: mean chord / path length of its strands
  msd::Points strand_points;                   ///< buffer
};

/// Fills `frame` for the current state (buffers reused; no allocation after the first frame).
void observe(const Instruments& in, const msd::LegState& state, const msd::LegScratch& scratch,
             const msd::LegControls& controls, Frame& frame);

struct Sensor {
  std::string name, unit;
  std::function<double(const Frame&)> read;
};

/// The sensor table for a scene: time, knee, joint, activations, tendons,
/// volumes, muscle shape, contacts, obstacles, bulges, posture, energies and
/// the wobble probe (docs/leg-scenes.md lists them). `in` must outlive it.
std::vector<Sensor> leg_sensors(const Instruments& in);

}  // namespace leg
