// A benchmark specification: one YAML file read by every solver (design notes:
// "one spec, one result schema"). Field reference: benchmarks/specs/README.md.
// Parsing is strict - unknown fields, wrong types and unphysical values are
// errors naming the file, line and field - and happens before anything runs.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

struct GeometrySpec {
  std::string shape;                 ///< cylinder | box | obj
  double radius = 0.0, height = 0.0; ///< cylinder, m
  int segments = 64;                 ///< cylinder polygon
  Eigen::Vector3d size{Eigen::Vector3d::Zero()};  ///< box, m (lowest corner at 0)
  std::string file;                  ///< obj, resolved against the spec's folder
};

struct MeshSpec {
  double spacing = 0.0;              ///< cube edge h, m
  std::string rule = "centre";       ///< centre | inside | overlap
  std::optional<Eigen::Vector3d> origin;
  long max_cubes = 20'000'000;
};

struct MaterialSpec {
  std::string name;
  double density = 0.0;                   ///< kg/m^3
  std::optional<double> youngs_modulus;   ///< Pa
  std::optional<double> poisson_ratio;    ///< used by continuum solvers
  std::optional<double> damping_time;     ///< s, stiffness-proportional damping
};

struct MsdSpec {
  std::string constants = "physical";     ///< raw | physical
  // raw
  double k_s = 0.0, k_d = 0.0, k_r = 0.0, k_v = 0.0;
  // physical
  double stiffness_scale = 1.0, repulsion_factor = 0.0, volume_factor = 0.0;
  double repulsion_floor = 0.01;
  std::string mass_lumping = "per_tet";   ///< per_tet | equal
  std::vector<std::string> terms{"springs", "dampers", "repulsion", "volume"};
  double nonlinear_threshold = 0.0;       ///< 0 = off
  std::string integrator = "symplectic_euler";
  double dt = 0.0;
};

struct LoadingSpec {
  std::string type = "uniaxial";
  std::string platens = "bonded";         ///< bonded | frictionless
  std::vector<std::pair<double, double>> path;  ///< (time s, nominal strain)
  Eigen::Vector3d gravity{Eigen::Vector3d::Zero()};
};

struct OutputSpec {
  double interval = 0.01;                 ///< s between samples
};

struct Spec {
  std::string name, description;
  std::string path;   ///< file it was read from ("" for text)
  std::string text;   ///< the YAML text, stored verbatim in every results file
  GeometrySpec geometry;
  MeshSpec mesh;
  MaterialSpec material;
  MsdSpec msd;
  LoadingSpec loading;
  OutputSpec output;
};

/// Reads and validates a spec file. Throws msd::Error with file:line context.
Spec load_spec(const std::string& path);

/// Parses spec text; `source` names it in messages and resolves relative paths.
Spec parse_spec(const std::string& text, const std::string& source);

}  // namespace bench
