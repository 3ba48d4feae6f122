// One step of the leg in motion (msd/scene/leg_model.hpp) at the thesis'
// resolution, with the work a scene can ask for switched on one at a time:
// nothing but tissue, tendons and muscles; skin-against-skin contact in the
// box behind the knee (the scenes' region) or over the whole leg; a rigid
// cylinder tested against the skin nodes in its box or against every skin
// node (the rod held clear of the leg, so what differs is the testing); or the
// skin membrane on the leg's outer surface (msd/forces/skin_membrane.hpp, at
// benchmarks/materials.yaml's skin), no contact. The knee is held bent at 95 degrees (scripted), where the crease
// touches, so the contact tests do their real work. The ratios in
// benchmarks/results/2026-12-01-kernels-and-leg.md ("collisions only where a scene says") are of these
// figures, measured in one run. The second argument picks the force path:
// 0 the per-tet reference loop, 1 or 2 the engine on that many threads
// (msd/forces/force_engine.hpp), wall time per step.
#include "msd/geometry/leg_generator.hpp"
#include "msd/mesh/limb_mesher.hpp"
#include "msd/scene/leg_model.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

const msd::MeshedLeg& leg() {
  static const msd::MeshedLeg l = [] {
    msd::LimbMeshOptions o;
    o.spacing = 0.0245;
    return msd::mesh_leg(std::string(TISSUEBENCH_DATA_DIR) + "/leg", o);
  }();
  return l;
}

msd::LegModelOptions options(double tendon_modulus) {
  msd::LegModelOptions o;  // the scenes' materials (msd/data/scenes/*.yaml)
  o.passive.density = 920;
  o.passive.mode = msd::ConstantsMode::Physical;
  o.passive.youngs_modulus = 15000;
  o.passive.damping_time = 4.2e-3;
  o.passive.repulsion_factor = 0.5;
  o.passive.volume_factor = 1.6;
  o.muscle = o.passive;
  o.muscle.density = 1040;
  o.muscle.youngs_modulus = 75000;
  o.knee_centre = msd::Vec3(0, 0, 0.50046);
  o.joint_space_radius = 0.09;
  o.max_muscle_stress = 1e6;
  o.tendon_modulus = tendon_modulus;
  return o;
}

enum Contact { kNone, kKneeBox, kKneeWholeLeg, kRodBox, kRodAllSkin, kSkinMembrane };

void BM_LegStep(benchmark::State& state) {
  msd::LegModelOptions o = options(36.4e6);
  const auto contact = static_cast<Contact>(state.range(0));
  if (contact == kKneeBox) o.knee_contact_box = std::make_pair(msd::Vec3(-0.15, -0.12, 0.38), msd::Vec3(0.0, 0.12, 0.62));
  if (contact == kKneeWholeLeg) o.knee_contact_box = std::make_pair(msd::Vec3(-1, -1, -1), msd::Vec3(1, 1, 2));
  if (contact == kRodBox || contact == kRodAllSkin) {
    msd::LegModelOptions::Obstacle rod;
    rod.object.name = "rod";
    rod.object.cylinder.point = msd::Vec3(0.3, 0, 0.17);  // clear of the leg: the cost of the test alone
    rod.object.cylinder.axis = msd::Vec3::UnitY();
    rod.object.cylinder.radius = 0.04;
    if (contact == kRodBox) rod.box = std::make_pair(msd::Vec3(0.0, -0.08, 0.08), msd::Vec3(0.12, 0.08, 0.3));
    o.obstacles = {rod};
  }
  if (contact == kSkinMembrane) o.skin = msd::LegModelOptions::Skin{129e3, 1.55e-3};
  msd::LegModel model = msd::build_leg_model(leg().mesh, leg().tendons, o);
  // Second argument: 0 the per-tet reference forces, n > 0 the engine on n threads.
  model.tissue.reference_forces = state.range(1) == 0;
  model.tissue.threads = std::max<int>(1, static_cast<int>(state.range(1)));
  // Bent there by a scripted ramp at 50 degrees/s (as the scenes' lead-ins).
  msd::LegState s = msd::leg_rest_state(model, 0.0);
  msd::LegScratch scratch;
  msd::LegControls c;
  const double dt = 2e-4, rate = 50.0 * kDeg;
  for (double t = dt; t < 95.0 * kDeg / rate + 0.2; t += dt) {
    c.scripted_knee = msd::HingeState{std::min(rate * t, 95.0 * kDeg), rate * t < 95.0 * kDeg ? rate : 0.0};
    msd::step_leg(model, s, c, dt, scratch);
  }
  c.scripted_knee = msd::HingeState{95.0 * kDeg, 0.0};
  c.back_activation = 0.3;
  for (auto _ : state) msd::step_leg(model, s, c, dt, scratch);
  state.counters["tested_nodes"] =
      static_cast<double>(model.knee_contact ? model.knee_contact->nodes[0].size() + model.knee_contact->nodes[1].size()
                                             : (model.obstacles.empty() ? 0 : model.obstacles[0].nodes.size()));
  state.counters["contacts"] = static_cast<double>(scratch.knee_contact.contacts);
}
BENCHMARK(BM_LegStep)
    ->ArgNames({"contact", "threads"})
    ->Args({kNone, 0})
    ->Args({kNone, 1})
    ->Args({kNone, 2})
    ->Args({kKneeBox, 0})
    ->Args({kKneeBox, 1})
    ->Args({kKneeBox, 2})
    ->Args({kKneeWholeLeg, 1})
    ->Args({kRodBox, 1})
    ->Args({kRodAllSkin, 1})
    ->Args({kSkinMembrane, 0})
    ->Args({kSkinMembrane, 1})
    ->Args({kSkinMembrane, 2})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
