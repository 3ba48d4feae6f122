// A parametric human leg (thesis 4.2): the skin (thigh, knee, calf, ankle,
// foot), the femur, one lower bone combining tibia, fibula, patella and the
// foot's bones, a front (quadriceps-like) and a back (hamstrings-like) muscle,
// and four tendon paths joining each muscle to both bones - closed, outward
// surfaces built as implicit solids (implicit_surface.hpp) from published
// anthropometry, scaled by stature and mass. The muscles are the thesis'
// spindles or, with MuscleShape::Anatomical, the quadriceps and hamstrings
// sized to their published volumes for the body (Handsfield et al. 2014).
//
// Frame: z up from the floor (the sole at z = 0), x forward (anterior), y to
// the side (lateral: the fibula lies at +y). The skin is cut flat at hip-joint
// height. The knee's hinge centre is at (0, 0, knee height), its axis along y.
//
// Scaling: lengths (segment lengths, bone sizes) scale with stature H / H0;
// girths with sqrt((M / M0) / (H / H0)), so the limb's volume scales with mass
// at a given stature. H0 and M0 are the reference body the dimensions describe.
// Every dimension and its source: docs/leg-geometry.md.
#pragma once

#include "msd/geometry/triangle_mesh.hpp"
#include "msd/mesh/limb_mesher.hpp"
#include "msd/mesh/tendon_paths.hpp"

#include <string>
#include <vector>

namespace msd {

/// One muscle of a group: its MRI volume regressed on height x mass
/// (Handsfield et al. 2014, J Biomech 47:631-638, supplementary table 3:
/// V = slope (h m) + intercept, cm^3 with h in m and m in kg) and its optimal
/// fibre length (Ward et al. 2009, Clin Orthop Relat Res 467:1074-1082,
/// table 3, cadavers). PCSA = V / fibre length.
struct MuscleAnatomy {
  std::string name;
  double slope = 0.0;         ///< cm^3 per (m kg)
  double intercept = 0.0;     ///< cm^3
  double fibre_length = 0.0;  ///< m
};

/// A muscle group the parametric leg meshes as one region.
struct MuscleGroupAnatomy {
  std::string name;
  std::vector<MuscleAnatomy> muscles;
};

/// The group's volume (m^3) for a body of stature `h` (m) and mass `m` (kg):
/// the sum of its muscles' regressions. Throws msd::Error naming the group and
/// muscle when a muscle's volume or fibre length is not positive.
double group_volume(const MuscleGroupAnatomy& group, double h, double m);
/// The group's physiological cross-section (m^2): sum of V_i / l_i.
double group_pcsa(const MuscleGroupAnatomy& group, double h, double m);

/// The reference body and its leg: the mean US Army male of ANSUR II (2012)
/// unless noted; every number's source is in docs/leg-geometry.md. Lengths in
/// m at the reference stature; `*_girth` are circumferences (m); `*_frac` are
/// fractions of stature.
struct LegDimensions {
  double reference_stature = 1.756;  ///< H0 (m), ANSUR II male mean
  double reference_mass = 85.5;      ///< M0 (kg), ANSUR II male mean
  // Heights above the floor, foot size.
  double hip_height_frac = 0.530;    ///< hip joint, Drillis & Contini (Winter 2009, fig. 4.1)
  double knee_height_frac = 0.285;   ///< knee joint, same
  double ankle_height = 0.0729;      ///< lateral malleolus
  double foot_length = 0.2712;
  double foot_breadth = 0.1019;
  double heel_breadth = 0.0725;
  double heel_to_ankle_frac = 0.25;  ///< of the foot's length, heel to the ankle's vertical (a modelling choice)
  // Girths (m).
  double upper_thigh_girth = 0.625;  ///< at the gluteal furrow
  double lower_thigh_girth = 0.409;  ///< just above the knee
  double knee_girth = 0.3915;        ///< Heinz et al. 2003 (0.372 m), rescaled to this body
  double calf_girth = 0.392;         ///< maximum
  double ankle_girth = 0.229;        ///< minimum, above the malleoli
  // Bones (m).
  double femur_shaft_diameter = 0.0287;      ///< midshaft perimeter / pi (N. Greece femora, 2019)
  double femur_bicondylar_breadth = 0.0820;  ///< same sample
  double tibia_plateau_breadth = 0.0760;     ///< MRI, Egyptian knees (2021)
  double tibia_shaft_diameter = 0.024;       ///< no source found: a modelling choice
  double fibula_diameter = 0.013;            ///< no source found: a modelling choice
  double patella_height = 0.0344;            ///< Iranpour et al., Caucasians
  double patella_width = 0.0448;
  double patella_thickness = 0.0224;
  // Muscle groups (the anatomical muscles, MuscleShape::Anatomical).
  MuscleGroupAnatomy quadriceps{"quadriceps",
                                {{"rectus femoris", 1.71, 56.9, 0.076},
                                 {"vastus lateralis", 5.89, 102.0, 0.099},
                                 {"vastus medialis", 3.03, 57.6, 0.097},
                                 {"vastus intermedius", 1.29, 111.0, 0.099}}};
  MuscleGroupAnatomy hamstrings{"hamstrings",
                                {{"biceps femoris, long head", 1.24, 53.0, 0.098},
                                 {"biceps femoris, short head", 0.738, 8.64, 0.110},
                                 {"semitendinosus", 1.27, 29.1, 0.193},
                                 {"semimembranosus", 1.54, 54.5, 0.069}}};
  /// The thigh's muscle compartment: the skin's section scaled by this about
  /// the section's centre (the rest is subcutaneous fat and skin). No source
  /// found: a modelling choice (about 8 mm of fat at mid-thigh).
  double compartment_scale = 0.90;
};

/// The two muscles' shapes. Thesis: the thesis' "loosely based" spindles (a
/// quadriceps of about 740 cm^3 and hamstrings of about 790 cm^3 at the
/// reference body, scaling with the skin's sections). Anatomical: the thigh's muscle compartment (the skin's
/// sections scaled by `compartment_scale`, tapered to both ends) split by two
/// planes into a front and a back part, each sized to its group's published
/// volume for this stature and mass (LegDimensions::quadriceps, hamstrings);
/// the quadriceps wrap the femur's shaft and condyles (4 mm clear) and the
/// septum behind the shaft. make_leg throws, naming the body, when the groups
/// do not fit in the compartment or their planes cross.
enum class MuscleShape { Thesis, Anatomical };

struct LegParameters {
  double stature = 1.756;  ///< H (m)
  double mass = 85.5;      ///< M (kg)
  LegDimensions dims;
  /// Marching-tetrahedra cell of the skin (m); the inner surfaces use half of
  /// it. 0.016 m gives about 15.7k skin triangles at the reference size, like
  /// the thesis' scan (15,338 triangles, about 1.2 cm).
  double skin_cell = 0.016;
  MuscleShape muscles = MuscleShape::Thesis;
};

struct LegGeometry {
  TriangleMesh skin, upper_bone, lower_bone, front_muscle, back_muscle;
  /// Tendon paths, the limb mesher's routing input: back-upper (8 strands),
  /// back-lower, front-upper, front-lower (6 each), thesis 4.5.
  std::vector<TendonPathSpec> tendons;
  Vec3 knee_centre{Vec3::Zero()};
  Vec3 knee_axis{Vec3::UnitY()};
  double hip_height = 0.0, knee_height = 0.0, ankle_height = 0.0, foot_length = 0.0;
  double girth_scale = 1.0;  ///< sqrt((M / M0) / (H / H0))
  /// The muscle groups' published volumes and cross-sections for this body
  /// (group_volume, group_pcsa), m^3 and m^2, whatever the shape.
  double front_target_volume = 0.0, back_target_volume = 0.0;
  double front_pcsa = 0.0, back_pcsa = 0.0;
};

/// Builds the leg. Throws msd::Error naming the parameter for a stature outside
/// 1.2-2.3 m, a mass outside 30-200 kg, a cell outside 2-30 mm, or a body
/// whose bones or muscles would leave the skin or overlap (the surfaces are
/// checked by validate_limb before they are returned). Whatever the shape, it
/// throws (group_volume) for a muscle in `dims.quadriceps` or `hamstrings`
/// without a positive volume or fibre length, since their published volumes
/// are reported; with MuscleShape::Anatomical also for a compartment_scale
/// outside 0.5-0.99 and for groups that do not fit in the compartment.
LegGeometry make_leg(const LegParameters& params);

/// Writes skin.obj, upper_bone.obj, lower_bone.obj, front_muscle.obj,
/// back_muscle.obj and leg.yaml - the `tissuebench mesh` scene with the tendon
/// paths, the grid spacing `spacing` (m) and the pull area behind the knee -
/// into `dir` (created if missing). Each file is written under a temporary
/// name and moved into place.
void write_leg(const LegGeometry& leg, const LegParameters& params, double spacing, const std::string& dir);

/// Reads the five surfaces write_leg writes (skin.obj, upper_bone.obj, ...)
/// from `dir` as a limb, each region's source naming its file.
LimbSurfaces read_leg_surfaces(const std::string& dir);

/// A leg meshed with its tendons routed through the mesh.
struct MeshedLeg {
  LimbMesh mesh;
  std::vector<TendonStrands> tendons;  ///< in the order of LegGeometry::tendons
};

/// The surfaces in `dir` (read_leg_surfaces) meshed with `options`, and the
/// tendon paths of make_leg(params) routed through that mesh - for the shipped
/// leg (msd/data/leg, written by write_leg with the default parameters), the
/// leg the scenes, tests and benchmarks move.
MeshedLeg mesh_leg(const std::string& dir, const LimbMeshOptions& options, const LegParameters& params = {});

}  // namespace msd
