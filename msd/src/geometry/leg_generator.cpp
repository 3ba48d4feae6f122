#include "msd/geometry/leg_generator.hpp"

#include "msd/io/atomic_file.hpp"

#include "msd/geometry/implicit_surface.hpp"
#include "msd/mesh/limb_mesher.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

namespace msd {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Monotone piecewise-cubic interpolation (Fritsch & Carlson 1980) through
// (z_i, y_i), z increasing; constant beyond the ends. Monotone so a girth never
// overshoots between two measured sections.
class MonotoneCubic {
 public:
  MonotoneCubic(std::vector<double> z, std::vector<double> y) : z_(std::move(z)), y_(std::move(y)) {
    const size_t n = z_.size();
    std::vector<double> d(n - 1);
    for (size_t i = 0; i + 1 < n; ++i) d[i] = (y_[i + 1] - y_[i]) / (z_[i + 1] - z_[i]);
    m_.assign(n, 0.0);
    m_[0] = d[0];
    m_[n - 1] = d[n - 2];
    for (size_t i = 1; i + 1 < n; ++i) m_[i] = d[i - 1] * d[i] <= 0.0 ? 0.0 : 0.5 * (d[i - 1] + d[i]);
    for (size_t i = 0; i + 1 < n; ++i) {
      if (d[i] == 0.0) {
        m_[i] = m_[i + 1] = 0.0;
        continue;
      }
      const double a = m_[i] / d[i], b = m_[i + 1] / d[i], s = a * a + b * b;
      if (s > 9.0) {
        const double t = 3.0 / std::sqrt(s);
        m_[i] = t * a * d[i];
        m_[i + 1] = t * b * d[i];
      }
    }
  }
  double operator()(double z) const {
    if (z <= z_.front()) return y_.front();
    if (z >= z_.back()) return y_.back();
    const size_t i = static_cast<size_t>(std::upper_bound(z_.begin(), z_.end(), z) - z_.begin()) - 1;
    const double h = z_[i + 1] - z_[i], t = (z - z_[i]) / h, t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * y_[i] + (t3 - 2 * t2 + t) * h * m_[i] + (-2 * t3 + 3 * t2) * y_[i + 1] +
           (t3 - t2) * h * m_[i + 1];
  }

 private:
  std::vector<double> z_, y_, m_;
};

// The semi-minor axis b of an ellipse of perimeter `girth` and axis ratio
// r = a / b (Ramanujan's second approximation of the perimeter).
double semi_axis_for_girth(double girth, double r) {
  const double h = std::pow((r - 1.0) / (r + 1.0), 2);
  return girth / (kPi * (1.0 + r) * (1.0 + 3.0 * h / (10.0 + std::sqrt(4.0 - 3.0 * h))));
}

// Approximate signed distance to the ellipse of semi-axes (a, b) in a section.
double ellipse_field(double dx, double dy, double a, double b) {
  return (std::hypot(dx / a, dy / b) - 1.0) * std::min(a, b);
}

void require_range(double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream m;
    m << "leg: " << what << " = " << v << " is outside " << lo << " ... " << hi;
    throw Error(m.str());
  }
}

// The body's lengths, scaled from the reference body: lengths with stature,
// girths with sqrt(mass ratio / length ratio).
struct LegFrame {
  double ls, gs;                  // length and girth scales
  double z_top, z_knee, z_ankle;  // hip-joint, knee and ankle heights
  double L, B, Bh;                // foot length and breadth, heel breadth
  double T, S;                    // thigh and shank lengths
  double x_heel;                  // the heel's back
};

LegFrame leg_frame(const LegParameters& p) {
  const LegDimensions& d = p.dims;
  LegFrame f;
  f.ls = p.stature / d.reference_stature;
  f.gs = std::sqrt((p.mass / d.reference_mass) / f.ls);
  const double H = p.stature;
  f.z_top = d.hip_height_frac * H;
  f.z_knee = d.knee_height_frac * H;
  f.z_ankle = d.ankle_height * f.ls;
  f.L = d.foot_length * f.ls;
  f.B = d.foot_breadth * f.ls;
  f.Bh = d.heel_breadth * f.ls;
  f.T = f.z_top - f.z_knee;
  f.S = f.z_knee - f.z_ankle;
  f.x_heel = -d.heel_to_ankle_frac * f.L;
  return f;
}

// The thigh's elliptic sections by height: girth, AP/ML axis ratio, centre
// offset forward, interpolated between five measured heights. The ratios and
// offsets are modelling choices (docs/leg-geometry.md); the girths and
// heights are measurements.
class ThighSections {
 public:
  ThighSections(const LegDimensions& d, const LegFrame& f)
      : z_lo_(f.z_ankle),
        z_hi_(f.z_top),
        girth_(heights(f), {d.ankle_girth * f.gs, d.calf_girth * f.gs, d.knee_girth * f.gs,
                            d.lower_thigh_girth * f.gs, d.upper_thigh_girth * f.gs}),
        ratio_(heights(f), {0.85, 0.92, 0.90, 0.92, 0.95}),
        offset_(heights(f), {-0.005 * f.gs, -0.015 * f.gs, 0.005 * f.gs, 0.0, -0.010 * f.gs}) {}

  // The section at height z (clamped to ankle ... hip): centre offset cx,
  // semi-axes a (AP) and b (ML).
  void operator()(double z, double& cx, double& a, double& b) const {
    z = std::clamp(z, z_lo_, z_hi_);
    const double r = ratio_(z);
    b = semi_axis_for_girth(girth_(z), r);
    a = r * b;
    cx = offset_(z);
  }
  double girth(double z) const { return girth_(z); }

 private:
  static std::vector<double> heights(const LegFrame& f) {
    return {f.z_ankle + 0.12 * f.S, f.z_knee - 0.30 * f.S, f.z_knee, f.z_knee + 0.08 * f.T, f.z_top};
  }
  double z_lo_, z_hi_;
  MonotoneCubic girth_, ratio_, offset_;
};

// ---- Skin: a lofted tube of elliptic sections, a foot, blended. ----------

// The thigh and shank: the tube of sections, ending in the foot.
double tube_field(const LegFrame& f, const ThighSections& section, const Vec3& x) {
  double cx, a, b;
  section(x.z(), cx, a, b);
  double v = ellipse_field(x.x() - cx, x.y(), a, b);
  v = smooth_max(v, f.z_ankle - x.z(), 0.01);  // the tube ends in the foot
  return v;
}

// The foot: heel, midfoot and forefoot ellipsoids, blended.
double foot_field(const LegFrame& f, const Vec3& x) {
  const double L = f.L, B = f.B, Bh = f.Bh, x_heel = f.x_heel;
  const double heel = ellipsoid_field(x, Vec3(x_heel + 0.17 * L, 0.0, 0.14 * L), Vec3(0.17 * L, 0.5 * Bh, 0.16 * L));
  const double mid = ellipsoid_field(x, Vec3(x_heel + 0.50 * L, 0.0, 0.11 * L), Vec3(0.30 * L, 0.45 * B, 0.13 * L));
  const double fore = ellipsoid_field(x, Vec3(x_heel + 0.80 * L, 0.0, 0.07 * L), Vec3(0.20 * L, 0.50 * B, 0.09 * L));
  return smooth_min(smooth_min(heel, mid, 0.025 * f.ls), fore, 0.025 * f.ls);
}

// The skin: tube and foot blended, cut at hip-joint height and at the sole.
ScalarField skin_field(const LegFrame& f, const ThighSections& section) {
  return [f, &section](const Vec3& x) {
    double v = smooth_min(tube_field(f, section, x), foot_field(f, x), 0.03 * f.ls);
    v = smooth_max(v, x.z() - f.z_top, 0.01 * f.ls);  // cut at hip-joint height
    v = smooth_max(v, -x.z(), 0.008 * f.ls);          // the sole
    return v;
  };
}

// ---- Bones (sizes scale with stature). ----------------------------------

// Where the bones' landmarks lie in this body.
struct BoneLayout {
  double rf, rt, rfib;     // femur and tibia shaft radii, fibula radius
  double condyle_ap;       // the femur's condyles, AP semi-axis
  Vec3 patella_centre;
  double z_fib, z_dist;    // heights of the fibula's lower end and the tibia's distal end
  double y_fib, distal_y;  // the fibula's lower end, ML; the tibia's distal ML semi-axis
};

// The knee cap sits in front of the trochlea (the condyles' front) with a
// 4 mm gap; in a slim knee it keeps 3 mm of tissue under the skin and the
// trochlea gives way behind it. At the ankle the malleoli lie just under the
// skin: the fibula's lower end and the tibia's distal width keep 4 mm of
// tissue to the skin's section whatever the girth. Throws msd::Error where
// the knee or ankle is too slim for the bones.
BoneLayout place_bones(const LegParameters& p, const LegFrame& f, const ThighSections& section) {
  const LegDimensions& d = p.dims;
  const double ls = f.ls;
  BoneLayout b;
  b.rf = 0.5 * d.femur_shaft_diameter * ls;
  b.rt = 0.5 * d.tibia_shaft_diameter * ls;
  b.rfib = 0.5 * d.fibula_diameter * ls;
  const double tp = d.patella_thickness * ls, z_patella = f.z_knee + 0.03 * ls;
  double cx_k, a_k, b_k;
  section(z_patella, cx_k, a_k, b_k);
  const double patella_x = std::min(0.026 * ls + 0.004 * ls + 0.5 * tp, cx_k + a_k - 0.5 * tp - 0.003);
  b.condyle_ap = std::min(0.026 * ls, patella_x - 0.5 * tp - 0.003);
  b.patella_centre = Vec3(patella_x, 0.0, z_patella);
  b.z_fib = f.z_ankle + 0.015 * ls;
  b.z_dist = f.z_ankle + 0.012 * ls;
  double cx_a, a_a, b_fib, b_dist;
  section(b.z_fib, cx_a, a_a, b_fib);
  section(b.z_dist, cx_a, a_a, b_dist);
  b.y_fib = std::min(0.026 * ls, b_fib - b.rfib - 0.004);
  b.distal_y = std::min(0.025 * ls, b_dist - 0.004 * ls - 0.004);
  if (b.condyle_ap < 0.013 * ls || b.distal_y < 0.0125 * ls || b.y_fib < b.rt) {
    std::ostringstream m;
    m << "leg (stature " << p.stature << " m, mass " << p.mass << " kg): the knee and ankle girths ("
      << section.girth(z_patella) << " m, " << section.girth(b.z_dist)
      << " m) are too small for bones of this stature; raise the mass";
    throw Error(m.str());
  }
  return b;
}

// The upper bone: the femur's shaft, head and condyles.
ScalarField femur_field(const LegDimensions& d, const LegFrame& f, const BoneLayout& b) {
  return [&d, f, b](const Vec3& x) {
    const double ls = f.ls, z_knee = f.z_knee, z_top = f.z_top;
    const double shaft = capsule_field(x, Vec3(0, 0, z_knee + 0.06 * ls), Vec3(0, 0, z_top - 0.07 * ls), b.rf);
    const double head = ellipsoid_field(x, Vec3(-0.005 * ls, 0, z_top - 0.06 * ls), Vec3(0.022, 0.028, 0.035) * ls);
    const double condyles = ellipsoid_field(x, Vec3(0, 0, z_knee + 0.028 * ls),
                                            Vec3(b.condyle_ap, 0.5 * d.femur_bicondylar_breadth * ls, 0.024 * ls));
    return smooth_min(smooth_min(shaft, head, 0.02 * ls), condyles, 0.02 * ls);
  };
}

// What the quadriceps wrap: the femur's shaft and condyles with 4 mm around
// them (not its head: the wedge of muscle between the head and the cut folded
// the meshed surface, so there erosion separates them, regions.hpp), the shaft swept
// backwards 10 cm in the sagittal plane (the linea aspera and the septum
// behind it, where the vasti meet the hamstrings' compartment). An exact
// distance to a rounded rectangle. Without the sweep, the cut of the front
// compartment passed 3 mm behind the shaft and the thin wedge between them
// folded the meshed surface.
ScalarField femur_keep_out_field(const LegDimensions& d, const LegFrame& f, const BoneLayout& b) {
  return [femur = femur_field(d, f, b), f, b](const Vec3& x) {
    const double z0 = f.z_knee + 0.06 * f.ls, z1 = f.z_top - 0.07 * f.ls;
    const Vec3 q(std::clamp(x.x(), -0.10 * f.gs, 0.0), 0.0, std::clamp(x.z(), z0, z1));
    const double slot = (x - q).norm() - b.rf;
    return (x.z() < f.z_knee + 0.5 * f.T ? std::min(slot, femur(x)) : slot) - 0.004;
  };
}

// The lower bone: tibia, fibula, the foot's talus and metatarsals, and the
// knee cap.
ScalarField lower_bone_field(const LegDimensions& d, const LegFrame& f, const BoneLayout& b) {
  return [&d, f, b](const Vec3& x) {
    const double ls = f.ls, z_knee = f.z_knee, z_ankle = f.z_ankle, L = f.L, B = f.B, x_heel = f.x_heel;
    const double k = 0.01 * ls;
    const double plateau = ellipsoid_field(x, Vec3(0, 0, z_knee - 0.026 * ls),
                                           Vec3(0.028 * ls, 0.5 * d.tibia_plateau_breadth * ls, 0.02 * ls));
    const double shaft = capsule_field(x, Vec3(0, 0, z_knee - 0.03 * ls), Vec3(0, 0, z_ankle + 0.03 * ls), b.rt);
    const double distal =
        ellipsoid_field(x, Vec3(0, -0.004 * ls, b.z_dist), Vec3(0.020 * ls, b.distal_y, 0.018 * ls));
    const double fibula = capsule_field(x, Vec3(-0.008 * ls, 0.028 * ls, z_knee - 0.035 * ls),
                                        Vec3(-0.008 * ls, b.y_fib, b.z_fib), b.rfib);
    const double talus = ellipsoid_field(x, Vec3(x_heel + 0.20 * L, 0, 0.13 * L), Vec3(0.16 * L, 0.22 * B, 0.09 * L));
    const double metatarsals =
        ellipsoid_field(x, Vec3(x_heel + 0.58 * L, 0, 0.075 * L), Vec3(0.25 * L, 0.30 * B, 0.04 * L));
    const double patella = ellipsoid_field(
        x, b.patella_centre, Vec3(0.5 * d.patella_thickness, 0.5 * d.patella_width, 0.5 * d.patella_height) * ls);
    double v = smooth_min(plateau, shaft, k);
    v = smooth_min(v, fibula, k);
    v = smooth_min(v, distal, 1.5 * k);
    v = smooth_min(v, talus, 1.5 * k);
    v = smooth_min(v, metatarsals, k);
    return std::min(v, patella);  // the knee cap: its own piece of the same rigid body
  };
}

// ---- Muscles: spindles lofted from the thigh's sections. -----------------
// At height z a muscle's section is an ellipse placed and sized as fractions
// of the skin's section there (centre at cx + u a, semi-axes (p a, q b)),
// tapered along the thigh like an ellipsoid between z_lo and z_hi - so it
// stays inside the skin and off the other muscle for any body.
struct Spindle {
  double u, p, q, z_lo, z_hi;
};

Spindle front_spindle(const LegFrame& f) { return {0.45, 0.30, 0.55, f.z_knee + 0.16 * f.T, f.z_knee + 0.90 * f.T}; }
Spindle back_spindle(const LegFrame& f) { return {-0.45, 0.32, 0.58, f.z_knee + 0.14 * f.T, f.z_knee + 0.86 * f.T}; }

// The muscle's field.
ScalarField spindle_field(const ThighSections& section, const Spindle& m) {
  return [&section, m](const Vec3& x) {
    double cx, a, b;
    section(x.z(), cx, a, b);
    const double zc = 0.5 * (m.z_lo + m.z_hi), hz = 0.5 * (m.z_hi - m.z_lo);
    const double A = m.p * a, Bm = m.q * b;
    return (std::sqrt(std::pow((x.x() - cx - m.u * a) / A, 2) + std::pow(x.y() / Bm, 2) +
                      std::pow((x.z() - zc) / hz, 2)) -
            1.0) *
           std::min(A, Bm);
  };
}

// The muscle's centre line at height z (x; y = 0).
double muscle_x(const ThighSections& section, const Spindle& m, double z) {
  double cx, a, b;
  section(z, cx, a, b);
  return cx + m.u * a;
}

// ---- Anatomical muscles: the compartment split front and back. ----------
// The thigh's muscle compartment at height z is the skin's section scaled by
// k (LegDimensions::compartment_scale), tapered along the thigh like an
// ellipsoid between z_lo and z_hi: semi-axes (A s, B s) with A = k a,
// B = k b, s = sqrt(1 - zeta^2), zeta = (z - z_mid) / half-length. A group
// takes the part of it on its side (side = +1 front, -1 back) beyond a plane
// at the fraction t of the untapered AP semi-axis: side (x - cx) >= t A.
// That part's area is A B s^2 g(t / s), with g(u) = acos(u) - u sqrt(1 - u^2)
// the area of a unit circle's segment (g = pi for u <= -1, 0 for u >= 1), so
// the volume V(t) = integral of A B s^2 g(t / s) dz falls monotonically with
// t, and t is found by bisection. A group ends where s = max(t, s_end) (a cap
// of the ellipsoid or a flat end, blended; s_end = 0.35), not in a needle: a
// needle's tip beside the femur's condyles folded the meshed surface.
struct Compartment {
  int side;
  double k, t, z_lo, z_hi;
};

constexpr double kEndTaper = 0.35;  // s_end

double segment_area(double u) {
  u = std::clamp(u, -1.0, 1.0);
  return std::acos(u) - u * std::sqrt(1.0 - u * u);
}

double compartment_taper(const Compartment& c, double z) {
  const double zeta = (z - 0.5 * (c.z_lo + c.z_hi)) / (0.5 * (c.z_hi - c.z_lo));
  return std::sqrt(std::max(0.0, 1.0 - zeta * zeta));
}

// V(t) (m^3) by Simpson's rule on 400 intervals.
double compartment_volume(const ThighSections& section, const Compartment& c) {
  const int n = 400;
  const double h = (c.z_hi - c.z_lo) / n;
  double sum = 0.0;
  for (int i = 1; i < n; ++i) {  // s = 0 at both ends
    double cx, a, b;
    const double z = c.z_lo + i * h, s = compartment_taper(c, z);
    if (s < kEndTaper) continue;
    section(z, cx, a, b);
    sum += (i % 2 ? 4.0 : 2.0) * c.k * c.k * a * b * s * s * segment_area(c.t / s);
  }
  return sum * h / 3.0;
}

// The plane t that gives the group `volume` (m^3); throws when the
// compartment cannot hold it.
Compartment size_compartment(const ThighSections& section, Compartment c, double volume, double published,
                             const std::string& group, const LegParameters& p) {
  c.t = -1.0;
  const double whole = compartment_volume(section, c);
  if (!(volume > 0.0) || !(volume < 0.95 * whole)) {
    std::ostringstream m;
    m << "leg (stature " << p.stature << " m, mass " << p.mass << " kg): the " << group << " (" << 1e6 * published
      << " cm^3) do not fit in the thigh's muscle compartment (" << 1e6 * whole << " cm^3)";
    throw Error(m.str());
  }
  double lo = -1.0, hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    c.t = 0.5 * (lo + hi);
    (compartment_volume(section, c) > volume ? lo : hi) = c.t;
  }
  c.t = 0.5 * (lo + hi);
  return c;
}

// The group's field: the tapered compartment, the plane and the flat ends,
// blended over 1 cm, less `keep_out` (when given) blended over 5 mm: the
// quadriceps wrap the femur (a muscle overlapping the bone would, on a fine
// grid, erode the shaft away, regions.hpp).
ScalarField compartment_field(const ThighSections& section, const Compartment& c, const ScalarField* keep_out) {
  return [&section, c, keep_out](const Vec3& x) {
    double cx, a, b;
    section(x.z(), cx, a, b);
    const double A = c.k * a, B = c.k * b;
    const double zeta = (x.z() - 0.5 * (c.z_lo + c.z_hi)) / (0.5 * (c.z_hi - c.z_lo));
    const double ellipsoid = (std::sqrt(std::pow((x.x() - cx) / A, 2) + std::pow(x.y() / B, 2) + zeta * zeta) - 1.0) *
                             std::min(A, B);
    const double plane = c.t * A - c.side * (x.x() - cx);
    const double ends = (std::abs(zeta) - std::sqrt(1.0 - kEndTaper * kEndTaper)) * 0.5 * (c.z_hi - c.z_lo);
    const double v = smooth_max(smooth_max(ellipsoid, plane, 0.01), ends, 0.01);
    return keep_out ? smooth_max(v, -(*keep_out)(x), 0.005) : v;
  };
}

// The group's ends: where the taper s reaches max(t, s_end).
std::pair<double, double> compartment_ends(const Compartment& c) {
  const double zc = 0.5 * (c.z_lo + c.z_hi), hz = 0.5 * (c.z_hi - c.z_lo);
  const double s_end = std::max(c.t, kEndTaper), zeta = std::sqrt(1.0 - s_end * s_end);
  return {zc - zeta * hz, zc + zeta * hz};
}

// The group's centre line at height z: halfway between its inner bound - the
// plane, or `inner` (a distance from the femur's axis on the group's side)
// when that lies further out - and the compartment's edge on its side.
double compartment_x(const ThighSections& section, const Compartment& c, double inner, double z) {
  double cx, a, b;
  section(z, cx, a, b);
  const double from = std::max(c.side * cx + c.t * c.k * a, inner), to = c.side * cx + compartment_taper(c, z) * c.k * a;
  return c.side * 0.5 * (from + to);
}

// A muscle's surface field and centre line, whichever shape.
struct MuscleBody {
  TriangleMesh surface;
  std::function<double(double)> centre_x;
  double z_lower_tendon, z_upper_tendon;  // where the tendons leave it
};

// Sizes and meshes an anatomical group. The blend of the plane rounds the
// crease and takes a little volume, so the sharp shape's target is corrected
// twice by the ratio of the wanted volume to the one the surface encloses.
// Raw marching tetrahedra, without relaxation: relaxing folded the surface
// where the blends meet (the cut, the flat ends, the femur) on several
// bodies, and an isosurface of the piecewise-linear field cannot cross itself.
std::pair<Compartment, TriangleMesh> mesh_compartment(const ThighSections& section, Compartment c, double volume,
                                                      const std::string& group, const LegParameters& p,
                                                      const ScalarField* keep_out, ImplicitMeshOptions o) {
  o.relax_iterations = 0;
  double target = volume;
  c = size_compartment(section, c, target, volume, group, p);
  TriangleMesh m = mesh_implicit_surface(compartment_field(section, c, keep_out), o);
  for (int i = 0; i < 2; ++i) {
    const double got = enclosed_volume(m);
    if (!(got > 0.0)) throw Error("leg: the " + group + "' surface encloses no volume");
    target *= volume / got;
    c = size_compartment(section, c, target, volume, group, p);
    m = mesh_implicit_surface(compartment_field(section, c, keep_out), o);
  }
  return {c, std::move(m)};
}

// ---- Surfaces. -------------------------------------------------------------

// The box the surfaces are meshed in, with the skin's cell size.
ImplicitMeshOptions surface_box(const LegParameters& p, const LegFrame& f) {
  const double margin = 0.03 * f.ls;
  const double half_width =
      std::max({0.5 * p.dims.upper_thigh_girth * f.gs / kPi, 0.6 * f.B, 0.06 * f.ls}) + margin;
  ImplicitMeshOptions o;
  o.cell = p.skin_cell;
  o.lo = Vec3(f.x_heel - half_width, -half_width, -margin);
  o.hi = Vec3(f.x_heel + f.L + margin, half_width, f.z_top + margin);
  o.lo.x() = std::min(o.lo.x(), -half_width);
  o.hi.x() = std::max(o.hi.x(), half_width);
  return o;
}

// ---- Tendon paths (muscle end first), strands as in thesis 4.5. ----------
// The hamstrings' lower tendon passes 3.3 cm (scaled by girth) behind the
// knee's centre, near the straight line from muscle to insertion: with a
// deeper bow (4.5 cm) the taut tendon cut through the soft flesh behind the
// knee instead of turning the lower bone, and the activated back muscle
// flexed the knee no further than about 40 degrees (issue 6, measured).
// The quadriceps' tendon ends on the knee cap, which is part of the lower
// bone here: the patellar tendon is rigid. Routed on past the knee cap to
// the tibia, the tendon wrapped over the front of the knee through the
// flesh, and in a flexed knee its pull dragged that flesh through the
// femur's condyles (the leg blew up at 70-90 degrees, issue 6, measured).
std::vector<TendonPathSpec> leg_tendons(const LegFrame& f, const MuscleBody& front, const MuscleBody& back,
                                        const Vec3& patella_centre) {
  const double ls = f.ls, gs = f.gs, z_knee = f.z_knee, z_top = f.z_top;
  auto tendon = [](const char* name, int muscle, int bone, int strands, std::vector<Vec3> path) {
    TendonPathSpec t;
    t.name = name;
    t.muscle = muscle;
    t.bone = bone;
    t.strands = strands;
    t.path = std::move(path);
    return t;
  };
  auto mx = [](const MuscleBody& m, double z) { return m.centre_x(z); };
  return {
      tendon("back_upper", kBackMuscle, kUpperBone, 8,
             {Vec3(mx(back, back.z_upper_tendon), 0, back.z_upper_tendon), Vec3(-0.012 * ls, 0, z_top - 0.06 * ls)}),
      tendon("back_lower", kBackMuscle, kLowerBone, 6,
             {Vec3(mx(back, back.z_lower_tendon), 0, back.z_lower_tendon), Vec3(-0.033 * gs, 0, z_knee),
              Vec3(-0.008 * ls, 0, z_knee - 0.05 * ls)}),
      tendon("front_upper", kFrontMuscle, kUpperBone, 6,
             {Vec3(mx(front, front.z_upper_tendon), 0, front.z_upper_tendon), Vec3(0.012 * ls, 0, z_top - 0.07 * ls)}),
      tendon("front_lower", kFrontMuscle, kLowerBone, 6,
             {Vec3(mx(front, front.z_lower_tendon), 0, front.z_lower_tendon), patella_centre}),
  };
}

// The two muscles of the chosen shape. Anatomical: the quadriceps' compartment
// from 10 % to 96 % of the thigh's length above the knee, the hamstrings' from
// 4 % to 98 % (modelling choices: the vasti end a few centimetres above the
// knee cap; the hamstrings, cut off where their plane meets the tapered
// compartment, span about 9-93 %); the two planes must not cross.
std::pair<MuscleBody, MuscleBody> muscle_bodies(const LegParameters& p, const LegFrame& f,
                                                const ThighSections& section, const LegGeometry& leg,
                                                const BoneLayout& bones, const ImplicitMeshOptions& o) {
  const ScalarField femur = femur_keep_out_field(p.dims, f, bones);
  const double zk = f.z_knee, T = f.T;
  if (p.muscles == MuscleShape::Thesis) {
    const Spindle front = front_spindle(f), back = back_spindle(f);
    return {{mesh_implicit_surface(spindle_field(section, front), o),
             [&section, front](double z) { return muscle_x(section, front, z); }, zk + 0.18 * T, zk + 0.88 * T},
            {mesh_implicit_surface(spindle_field(section, back), o),
             [&section, back](double z) { return muscle_x(section, back, z); }, zk + 0.16 * T, zk + 0.84 * T}};
  }
  const double k = p.dims.compartment_scale;
  require_range(k, 0.5, 0.99, "compartment_scale");
  auto [front, front_surface] = mesh_compartment(section, {+1, k, 0.0, zk + 0.10 * T, zk + 0.96 * T},
                                                 leg.front_target_volume, "quadriceps", p, &femur, o);
  auto [back, back_surface] = mesh_compartment(section, {-1, k, 0.0, zk + 0.04 * T, zk + 0.98 * T},
                                               leg.back_target_volume, "hamstrings", p, nullptr, o);
  if (front.t + back.t < 0.0) {
    std::ostringstream m;
    m << "leg (stature " << p.stature << " m, mass " << p.mass << " kg): the quadriceps and hamstrings ("
      << 1e6 * leg.front_target_volume << " and " << 1e6 * leg.back_target_volume
      << " cm^3) overlap in the thigh's muscle compartment";
    throw Error(m.str());
  }
  const auto [front_lo, front_hi] = compartment_ends(front);
  const auto [back_lo, back_hi] = compartment_ends(back);
  const double inset = 0.10 * T;  // the tendons leave 10 % of the thigh's length inside the muscle's ends
  const double clear = bones.rf + 0.009;  // the keep-out's radius and its blend: the quadriceps lie beyond
  return {{std::move(front_surface),
           [&section, front = front, clear](double z) { return compartment_x(section, front, clear, z); },
           front_lo + inset, front_hi - inset},
          {std::move(back_surface),
           [&section, back = back](double z) { return compartment_x(section, back, -1.0, z); },
           back_lo + inset, back_hi - inset}};
}

// The surfaces checked as a limb (validate_limb), named after this body.
void validate_leg(const LegGeometry& leg, const LegParameters& p) {
  LimbSurfaces check;
  check.skin = leg.skin;
  check.inner = {{kUpperBone, leg.upper_bone},
                 {kLowerBone, leg.lower_bone},
                 {kFrontMuscle, leg.front_muscle},
                 {kBackMuscle, leg.back_muscle}};
  std::ostringstream who;
  who << "leg (stature " << p.stature << " m, mass " << p.mass << " kg)";
  for (int r : {kPassiveTissue, kUpperBone, kLowerBone, kFrontMuscle, kBackMuscle})
    check.source[r] = who.str();
  validate_limb(check);
}

}  // namespace

double group_volume(const MuscleGroupAnatomy& group, double h, double m) {
  double v = 0.0;
  for (const MuscleAnatomy& mu : group.muscles) {
    const double vi = mu.slope * h * m + mu.intercept;
    if (!std::isfinite(vi) || vi <= 0.0 || !std::isfinite(mu.fibre_length) || mu.fibre_length <= 0.0) {
      std::ostringstream msg;
      msg << "leg: " << group.name << ": " << mu.name << ": volume " << vi << " cm^3 (slope " << mu.slope
          << ", intercept " << mu.intercept << ") and fibre length " << mu.fibre_length
          << " m must both be positive";
      throw Error(msg.str());
    }
    v += 1e-6 * vi;
  }
  if (group.muscles.empty()) throw Error("leg: " + group.name + ": no muscles");
  return v;
}

double group_pcsa(const MuscleGroupAnatomy& group, double h, double m) {
  group_volume(group, h, m);  // checks every muscle
  double a = 0.0;
  for (const MuscleAnatomy& mu : group.muscles) a += 1e-6 * (mu.slope * h * m + mu.intercept) / mu.fibre_length;
  return a;
}

LegGeometry make_leg(const LegParameters& p) {
  require_range(p.stature, 1.2, 2.3, "stature (m)");
  require_range(p.mass, 30.0, 200.0, "mass (kg)");
  require_range(p.skin_cell, 0.002, 0.03, "skin_cell (m)");
  const LegDimensions& d = p.dims;
  const LegFrame f = leg_frame(p);

  LegGeometry leg;
  leg.girth_scale = f.gs;
  leg.hip_height = f.z_top;
  leg.knee_height = f.z_knee;
  leg.ankle_height = f.z_ankle;
  leg.foot_length = f.L;
  leg.knee_centre = Vec3(0.0, 0.0, f.z_knee);

  const ThighSections section(d, f);
  const BoneLayout bones = place_bones(p, f, section);
  leg.front_target_volume = group_volume(d.quadriceps, p.stature, p.mass);
  leg.back_target_volume = group_volume(d.hamstrings, p.stature, p.mass);
  leg.front_pcsa = group_pcsa(d.quadriceps, p.stature, p.mass);
  leg.back_pcsa = group_pcsa(d.hamstrings, p.stature, p.mass);

  ImplicitMeshOptions o = surface_box(p, f);
  leg.skin = mesh_implicit_surface(skin_field(f, section), o);
  o.cell = 0.5 * p.skin_cell;
  leg.upper_bone = mesh_implicit_surface(femur_field(d, f, bones), o);
  leg.lower_bone = mesh_implicit_surface(lower_bone_field(d, f, bones), o);
  auto [front, back] = muscle_bodies(p, f, section, leg, bones, o);
  leg.front_muscle = std::move(front.surface);
  leg.back_muscle = std::move(back.surface);

  leg.tendons = leg_tendons(f, front, back, bones.patella_centre);
  validate_leg(leg, p);
  return leg;
}

LimbSurfaces read_leg_surfaces(const std::string& dir) {
  LimbSurfaces s;
  const std::pair<int, const char*> files[] = {{kPassiveTissue, "skin.obj"},
                                               {kUpperBone, "upper_bone.obj"},
                                               {kLowerBone, "lower_bone.obj"},
                                               {kFrontMuscle, "front_muscle.obj"},
                                               {kBackMuscle, "back_muscle.obj"}};
  for (const auto& [region, name] : files) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    s.source[region] = path;
    (region == kPassiveTissue ? s.skin : s.inner[region]) = read_obj(path);
  }
  return s;
}

void write_leg(const LegGeometry& leg, const LegParameters& p, double spacing, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  auto put = [&](const std::string& name, const TriangleMesh& m) { write_obj((fs::path(dir) / name).string(), m); };
  put("skin.obj", leg.skin);
  put("upper_bone.obj", leg.upper_bone);
  put("lower_bone.obj", leg.lower_bone);
  put("front_muscle.obj", leg.front_muscle);
  put("back_muscle.obj", leg.back_muscle);

  const double z = leg.knee_height, ls = p.stature / p.dims.reference_stature;
  std::ostringstream y;
  y << std::setprecision(6);
  y << "# Generated by `tissuebench leg-geometry --stature " << p.stature << " --mass " << p.mass
    << (p.muscles == MuscleShape::Anatomical ? " --muscles anatomical" : "") << "` (msd/geometry/leg_generator.hpp);\n# dimensions and sources: docs/leg-geometry.md. "
    << "Mesh it: tissuebench mesh THIS_FILE --out DIR\n";
  y << "name: leg\n";
  y << "description: parametric leg, stature " << p.stature << " m, mass " << p.mass << " kg; knee centre [0, 0, "
    << z << "], axis +y\n";
  y << "leg:\n  skin: skin.obj\n  upper_bone: upper_bone.obj\n  lower_bone: lower_bone.obj\n"
    << "  front_muscle: front_muscle.obj\n  back_muscle: back_muscle.obj\n";
  y << "mesh:\n  spacing: " << spacing << "\n  rule: centre\n";
  y << "  pull:\n    - {name: behind_knee, lo: [" << -0.12 * ls << ", " << -0.10 * ls << ", " << z - 0.08 * ls
    << "], hi: [" << -0.02 * ls << ", " << 0.10 * ls << ", " << z + 0.08 * ls << "]}\n";
  y << "tendons:\n";
  for (const TendonPathSpec& t : leg.tendons) {
    y << "  - {name: " << t.name << ", muscle: " << region_name(t.muscle) << ", bone: " << region_name(t.bone)
      << ", strands: " << t.strands
      << ",\n     path: [";
    for (size_t k = 0; k < t.path.size(); ++k)
      y << (k ? ", " : "") << "[" << t.path[k].x() << ", " << t.path[k].y() << ", " << t.path[k].z() << "]";
    y << "]}\n";
  }
  write_file_atomically((fs::path(dir) / "leg.yaml").string(), [&](std::ostream& out) { out << y.str(); });
}

MeshedLeg mesh_leg(const std::string& dir, const LimbMeshOptions& options, const LegParameters& params) {
  MeshedLeg leg{mesh_limb(read_leg_surfaces(dir), options), {}};
  for (const TendonPathSpec& t : make_leg(params).tendons) leg.tendons.push_back(route_tendon(leg.mesh, t));
  return leg;
}

}  // namespace msd
