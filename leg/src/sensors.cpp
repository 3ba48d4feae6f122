#include "leg/sensors.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/tendon.hpp"

#include <algorithm>
#include <cmath>

namespace leg {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kRegions[] = {msd::kPassiveTissue, msd::kFrontMuscle, msd::kBackMuscle};
const char* const kMuscleNames[] = {"front_muscle", "back_muscle"};

MuscleShape muscle_shape(const msd::LegModel& leg, const std::vector<int>& tet_region, int region,
                         const msd::Vec3& line) {
  const msd::Model& tm = leg.tissue;
  const int n = tm.num_nodes();
  MuscleShape m;
  std::vector<char> in(static_cast<size_t>(n), 0);
  for (size_t e = 0; e < leg.tets.size(); ++e)
    if (tet_region[e] == region)
      for (int v : leg.tets[e]) in[static_cast<size_t>(v)] = 1;
  for (int i = 0; i < n; ++i)
    if (in[static_cast<size_t>(i)]) m.nodes.push_back(i);
  m.line = line.normalized();
  if (!m.nodes.empty()) length_and_radius(tm.rest_positions, m, m.rest_length, m.rest_radius);
  return m;
}

// Where a point fixed on the femur at rest position p is now (a scripted hip
// moves it; at rest, p itself, bit for bit).
msd::Vec3 on_femur(const msd::LegState& state, const msd::Vec3& p) {
  const msd::RigidMotion& m = state.femur;
  return m.rotation == msd::Mat3::Identity() && m.offset == msd::Vec3::Zero() ? p : m.place(p);
}

// The same for a direction.
msd::Vec3 femur_direction(const msd::LegState& state, const msd::Vec3& d) {
  return state.femur.rotation == msd::Mat3::Identity() ? d : msd::Vec3(state.femur.rotation * d);
}

// The skin's largest outward displacement in an area, from where the skin
// would be if it moved rigidly with its bone (m).
double bulge(const Instruments& in, const Frame& f, size_t area) {
  const msd::LegModel& leg = *in.leg;
  double b = -1e300;
  for (int i : in.bulge_vertices[area]) {
    const msd::Vec3 X = in.skin->vertices.col(i);
    const bool lower = in.skin_lower[static_cast<size_t>(i)];
    const msd::Vec3 ref = on_femur(*f.state, lower ? msd::Vec3(leg.knee.centre + f.rotation * (X - leg.knee.centre)) : X);
    const msd::Vec3 nn = femur_direction(
        *f.state, lower ? msd::Vec3(f.rotation * in.skin_normals.col(i)) : msd::Vec3(in.skin_normals.col(i)));
    b = std::max(b, (msd::Vec3(f.skin_x.col(i)) - ref).dot(nn));
  }
  return b;
}

// Tissue elastic energy plus the tendons', the Hill muscles' passive element's
// and the skin's (J).
double elastic_energy(const msd::LegModel& leg, const Frame& f) {
  const msd::Points& x = f.state->tissue.x;
  const msd::LegControls& controls = *f.controls;
  double elastic = msd::conservative_energy(leg.tissue, x);
  for (const msd::Muscle& m : leg.tissue.muscles)  // a Hill muscle's passive element
    if (m.hill.enabled) elastic += msd::hill_muscle_passive_energy(x, m.units, m.unit_force, m.hill);
  if (!leg.tissue.skin.empty()) elastic += msd::membrane_energy(leg.tissue.skin, x);
  for (size_t si = 0; si < leg.strands.size(); ++si) {
    const msd::LegStrand& s = leg.strands[si];
    const double l0 = si < controls.strand_natural_length.size() ? controls.strand_natural_length[si] : s.natural_length;
    if (std::isfinite(l0))
      elastic += msd::leg_strand_energy(leg, s, x, f.state->knee.angle,
                                        controls.tendon_length_scale[static_cast<size_t>(s.tendon)] * l0,
                                        f.state->femur);
  }
  return elastic;
}

msd::Vec3 probe_displacement(const Instruments& in, const Frame& f) {
  msd::Vec3 d = msd::Vec3::Zero();
  for (int i : in.probe_nodes) d += f.state->tissue.x.col(i) - on_femur(*f.state, in.leg->tissue.rest_positions.col(i));
  d /= static_cast<double>(in.probe_nodes.size());
  // In the femur's axes (a scripted femur turns them).
  return f.state->femur.rotation == msd::Mat3::Identity() ? d : msd::Vec3(f.state->femur.rotation.transpose() * d);
}

}  // namespace

void length_and_radius(const msd::Points& x, const MuscleShape& m, double& length, double& radius,
                       const msd::Vec3* line_now) {
  const msd::Vec3& line = line_now ? *line_now : m.line;
  double lo = 1e300, hi = -1e300;
  msd::Vec3 c = msd::Vec3::Zero();
  for (int i : m.nodes) {
    const double s = line.dot(x.col(i));
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    c += x.col(i);
  }
  c /= static_cast<double>(m.nodes.size());
  double r2 = 0.0;
  for (int i : m.nodes) {
    const msd::Vec3 d = msd::Vec3(x.col(i)) - c;
    r2 += (d - d.dot(line) * line).squaredNorm();
  }
  length = hi - lo;
  radius = std::sqrt(r2 / static_cast<double>(m.nodes.size()));
}

double region_volume(const msd::Points& x, const std::vector<msd::Tet>& tets, const std::vector<int>& region, int r) {
  double v = 0.0;
  for (size_t e = 0; e < tets.size(); ++e)
    if (region[e] == r) v += msd::tet_signed_volume(x, tets[e]);
  return v;
}

Instruments make_instruments(const msd::LegModel& leg, const LegScene& scene, const msd::TriangleMesh& skin,
                             const msd::Embedding& skin_embedding, const std::vector<msd::Tet>& embedding_tets) {
  Instruments in;
  in.leg = &leg;
  in.scene = &scene;
  in.skin = &skin;
  in.skin_embedding = &skin_embedding;
  in.embedding_tets = &embedding_tets;
  in.skin_normals = msd::vertex_normals(skin);
  for (size_t k = 0; k < leg.obstacles.size(); ++k) {
    const msd::TriangleMesh m = obstacle_surface(leg.obstacles[k]);
    const int offset = in.obstacles.num_vertices();
    in.obstacles.vertices.conservativeResize(3, offset + m.num_vertices());
    in.obstacles.vertices.rightCols(m.num_vertices()) = m.vertices;
    for (const msd::Tri& t : m.triangles) in.obstacles.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    in.obstacle_of.insert(in.obstacle_of.end(), static_cast<size_t>(m.num_vertices()), static_cast<int>(k));
  }
  const msd::Model& tm = leg.tissue;
  const int n = tm.num_nodes();
  for (const msd::Element& e : tm.elements) in.tet_region.push_back(e.region);
  for (int r = 0; r < 3; ++r) in.rest_volume[r] = region_volume(tm.rest_positions, leg.tets, in.tet_region, kRegions[r]);
  in.muscles[0] = muscle_shape(leg, in.tet_region, msd::kFrontMuscle, scene.model.front_line);
  in.muscles[1] = muscle_shape(leg, in.tet_region, msd::kBackMuscle, scene.model.back_line);
  in.bulge_vertices.resize(scene.bulge_areas.size());
  for (size_t a = 0; a < scene.bulge_areas.size(); ++a) {
    for (int i = 0; i < skin.num_vertices(); ++i)
      if (scene.bulge_areas[a].contains(skin.vertices.col(i))) in.bulge_vertices[a].push_back(i);
    if (in.bulge_vertices[a].empty())
      throw msd::Error(scene.file + ": analysis.bulge '" + scene.bulge_areas[a].name + "' holds no skin vertex");
  }
  in.skin_lower.resize(static_cast<size_t>(skin.num_vertices()));
  for (int i = 0; i < skin.num_vertices(); ++i)
    in.skin_lower[static_cast<size_t>(i)] =
        (msd::Vec3(skin.vertices.col(i)) - leg.knee.centre).dot(scene.model.leg_axis) < 0.0;
  if (scene.wobble_probe) {
    for (int i = 0; i < n; ++i)
      if (!leg.attached[static_cast<size_t>(i)] && scene.wobble_probe->contains(tm.rest_positions.col(i)))
        in.probe_nodes.push_back(i);
    if (in.probe_nodes.empty()) throw msd::Error(scene.file + ": analysis.wobble.probe holds no free tissue node");
  }
  in.shank_rest = (leg.lower_bone.mass > 0.0 ? leg.lower_bone.centre
                                             : msd::Vec3(tm.rest_positions.col(leg.lower_nodes.front()))) -
                  leg.knee.centre;
  for (int i = 0; i < n; ++i)
    if (!leg.attached[static_cast<size_t>(i)] &&
        (msd::Vec3(tm.rest_positions.col(i)) - leg.knee.centre).dot(scene.model.leg_axis) > 0.0)
      in.thigh_free.push_back(i);
  in.down = scene.model.gravity.norm() > 0.0 ? msd::Vec3(scene.model.gravity.normalized())
                                              : msd::Vec3(-msd::Vec3::UnitZ());
  return in;
}

void observe(const Instruments& in, const msd::LegState& state, const msd::LegScratch& scratch,
             const msd::LegControls& controls, Frame& f) {
  const msd::LegModel& leg = *in.leg;
  const msd::Points& x = state.tissue.x;
  f.state = &state;
  f.scratch = &scratch;
  f.controls = &controls;
  f.straightness.assign(leg.tendon_names.size(), 0.0);
  std::vector<int> count(leg.tendon_names.size(), 0);
  for (const msd::LegStrand& s : leg.strands) {
    msd::leg_strand_points(leg, s, x, state.knee.angle, f.strand_points, state.femur);
    const double chord = (f.strand_points.col(f.strand_points.cols() - 1) - f.strand_points.col(0)).norm();
    f.straightness[static_cast<size_t>(s.tendon)] += chord / msd::leg_strand_length(leg, s, x, state.knee.angle, state.femur);
    ++count[static_cast<size_t>(s.tendon)];
  }
  for (size_t k = 0; k < f.straightness.size(); ++k) f.straightness[k] /= std::max(1, count[k]);
  for (int k = 0; k < 2; ++k) {
    f.length_ratio[k] = f.radius_ratio[k] = 1.0;
    const MuscleShape& m = in.muscles[k];
    if (m.nodes.empty()) continue;
    const msd::Vec3 line = femur_direction(state, m.line);  // the line turns with a scripted femur
    length_and_radius(x, m, f.length_ratio[k], f.radius_ratio[k], &line);
    f.length_ratio[k] /= m.rest_length;
    f.radius_ratio[k] /= m.rest_radius;
  }
  f.skin_x.resize(3, in.skin->num_vertices());
  msd::embedded_positions(x, *in.embedding_tets, *in.skin_embedding, f.skin_x);
  f.rotation = msd::hinge_rotation(leg.knee, state.knee.angle);
  f.obstacles_x.resize(3, in.obstacles.num_vertices());
  for (int i = 0; i < in.obstacles.num_vertices(); ++i) {
    const size_t k = static_cast<size_t>(in.obstacle_of[static_cast<size_t>(i)]);
    f.obstacles_x.col(i) = in.obstacles.vertices.col(i);
    if (k < controls.obstacle_offset.size()) f.obstacles_x.col(i) += controls.obstacle_offset[k];
  }
  f.bones_x.resize(3, in.bones.num_vertices());
  for (int i = 0; i < in.bones.num_vertices(); ++i) {
    const msd::Vec3 p = in.bones.vertices.col(i);
    f.bones_x.col(i) =
        on_femur(state, in.bone_lower[static_cast<size_t>(i)] ? msd::Vec3(leg.knee.centre + f.rotation * (p - leg.knee.centre)) : p);
  }
}

msd::TriangleMesh obstacle_surface(const msd::RigidObstacle& ob, double length) {
  // A frame (u, w, n) with n the cylinder's axis or the plane's normal.
  const msd::Vec3 n = (ob.shape == msd::ObstacleShape::Cylinder ? ob.cylinder.axis : ob.plane.normal).normalized();
  const msd::Vec3 u = (std::abs(n.x()) < 0.9 ? msd::Vec3::UnitX() : msd::Vec3::UnitY()).cross(n).normalized();
  const msd::Vec3 w = n.cross(u);
  msd::Mat3 frame;
  frame << u, w, n;
  msd::TriangleMesh m;
  msd::Vec3 centre;
  if (ob.shape == msd::ObstacleShape::Cylinder) {
    m = msd::make_cylinder(ob.cylinder.radius, length, 16);
    m.vertices.row(2).array() -= 0.5 * length;
    centre = ob.cylinder.point;
  } else {
    m = msd::make_box(msd::Vec3(-0.5 * length, -0.5 * length, -0.002), msd::Vec3(0.5 * length, 0.5 * length, 0.0));
    centre = ob.plane.point;
  }
  for (int i = 0; i < m.num_vertices(); ++i) m.vertices.col(i) = centre + frame * msd::Vec3(m.vertices.col(i));
  return m;
}

void add_bone_surfaces(Instruments& in, const msd::TriangleMesh* upper_bone, const msd::TriangleMesh* lower_bone) {
  in.bones = msd::TriangleMesh{};
  in.bone_lower.clear();
  int total = 0;
  for (const msd::TriangleMesh* m : {upper_bone, lower_bone})
    if (m) total += m->num_vertices();
  in.bones.vertices.resize(3, total);
  int offset = 0;
  for (const msd::TriangleMesh* m : {upper_bone, lower_bone}) {
    if (!m) continue;
    in.bones.vertices.middleCols(offset, m->num_vertices()) = m->vertices;
    for (const msd::Tri& t : m->triangles) in.bones.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    in.bone_lower.insert(in.bone_lower.end(), static_cast<size_t>(m->num_vertices()), m == lower_bone ? 1 : 0);
    offset += m->num_vertices();
  }
}

std::vector<Sensor> leg_sensors(const Instruments& in) {
  const msd::LegModel& leg = *in.leg;
  const LegScene& scene = *in.scene;
  std::vector<Sensor> s = {
      {"time", "s", [](const Frame& f) { return f.state->tissue.t; }},
      {"knee_angle", "deg", [](const Frame& f) { return f.state->knee.angle / kDeg; }},
      {"knee_velocity", "deg/s", [](const Frame& f) { return f.state->knee.velocity / kDeg; }},
      {"knee_torque", "N m", [](const Frame& f) { return f.scratch->knee_torque; }},
      {"passive_joint_torque", "N m", [](const Frame& f) { return f.scratch->passive_joint_torque; }},
      {"joint_reaction_x", "N", [](const Frame& f) { return f.scratch->joint_reaction.x(); }},
      {"joint_reaction_y", "N", [](const Frame& f) { return f.scratch->joint_reaction.y(); }},
      {"joint_reaction_z", "N", [](const Frame& f) { return f.scratch->joint_reaction.z(); }},
      // The muscles' activations: the state's under activation dynamics, else the controls'.
      {"front_activation", "1", [](const Frame& f) {
         return f.state->activation.size() == 2 ? f.state->activation[0] : f.controls->front_activation;
       }},
      {"back_activation", "1", [](const Frame& f) {
         return f.state->activation.size() == 2 ? f.state->activation[1] : f.controls->back_activation;
       }}};
  for (size_t k = 0; k < leg.tendon_names.size(); ++k)
    s.push_back({"tension_" + leg.tendon_names[k], "N", [k](const Frame& f) {
                   return k < f.scratch->tendon_tension.size() ? f.scratch->tendon_tension[k] : 0.0;
                 }});
  for (size_t k = 0; k < leg.tendon_names.size(); ++k)
    s.push_back({"strain_" + leg.tendon_names[k], "1", [k](const Frame& f) {
                   return k < f.scratch->tendon_strain.size() ? f.scratch->tendon_strain[k] : 0.0;
                 }});
  for (size_t k = 0; k < leg.tendon_names.size(); ++k)
    s.push_back({"straightness_" + leg.tendon_names[k], "1", [k](const Frame& f) { return f.straightness[k]; }});
  const char* const volume_names[] = {"volume_ratio_passive", "volume_ratio_front_muscle", "volume_ratio_back_muscle"};
  for (int r = 0; r < 3; ++r)
    s.push_back({volume_names[r], "1", [&in, r](const Frame& f) {
                   return in.rest_volume[r] > 0.0 ? region_volume(f.state->tissue.x, in.leg->tets, in.tet_region,
                                                                  kRegions[r]) /
                                                        in.rest_volume[r]
                                                  : 1.0;
                 }});
  for (int k = 0; k < 2; ++k)
    s.push_back({std::string("length_ratio_") + kMuscleNames[k], "1", [k](const Frame& f) { return f.length_ratio[k]; }});
  for (int k = 0; k < 2; ++k)
    s.push_back({std::string("radius_ratio_") + kMuscleNames[k], "1", [k](const Frame& f) { return f.radius_ratio[k]; }});
  s.push_back({"knee_contact_area", "m^2", [](const Frame& f) { return f.scratch->knee_contact.area; }});
  s.push_back({"knee_contacts", "1",
               [](const Frame& f) { return static_cast<double>(f.scratch->knee_contact.contacts); }});
  for (size_t k = 0; k < leg.obstacles.size(); ++k) {
    s.push_back({"obstacle_force_" + leg.obstacles[k].name, "N", [k](const Frame& f) {
                   return k < f.scratch->obstacles.size() ? f.scratch->obstacles[k].force.norm() : 0.0;
                 }});
    s.push_back({"obstacle_contacts_" + leg.obstacles[k].name, "1", [k](const Frame& f) {
                   return k < f.scratch->obstacles.size() ? f.scratch->obstacles[k].contacts : 0.0;
                 }});
  }
  for (size_t a = 0; a < scene.bulge_areas.size(); ++a)
    s.push_back({"bulge_" + scene.bulge_areas[a].name, "m", [&in, a](const Frame& f) { return bulge(in, f, a); }});
  if (scene.hip)  // the scripted femur's turn about the knee's axis (hip extension +, flexion -)
    s.push_back({"femur_angle", "deg", [&leg](const Frame& f) {
                   return msd::rotation_vector(Eigen::Quaterniond(f.state->femur.rotation)).dot(leg.knee.axis) / kDeg;
                 }});
  s.push_back({"lower_leg_below_horizontal", "deg", [&in](const Frame& f) {
                 const msd::Vec3 shank = femur_direction(*f.state, f.rotation * in.shank_rest);
                 return std::asin(std::clamp(shank.normalized().dot(in.down), -1.0, 1.0)) / kDeg;
               }});
  s.push_back({"thigh_flesh_sag", "m", [&in](const Frame& f) {
                 double sag = 0.0;
                 for (int i : in.thigh_free)
                   sag += (f.state->tissue.x.col(i) - on_femur(*f.state, in.leg->tissue.rest_positions.col(i))).dot(in.down);
                 return in.thigh_free.empty() ? 0.0 : sag / static_cast<double>(in.thigh_free.size());
               }});
  s.push_back({"kinetic_energy", "J", [&leg](const Frame& f) { return msd::leg_kinetic_energy(leg, *f.state); }});
  s.push_back({"elastic_energy", "J", [&leg](const Frame& f) { return elastic_energy(leg, f); }});
  s.push_back({"max_node_speed", "m/s", [](const Frame& f) { return f.state->tissue.v.colwise().norm().maxCoeff(); }});
  if (!in.probe_nodes.empty())
    for (int c = 0; c < 3; ++c)
      s.push_back({std::string("probe_") + "xyz"[c], "m",
                   [&in, c](const Frame& f) { return probe_displacement(in, f)[c]; }});
  return s;
}

}  // namespace leg
