// Indentation: a rigid cylinder (axis horizontal, across the sample) pressed
// into the top face of a block whose bottom face is bonded (clamped), the
// contact case of the leg. The cylinder starts touching the top face above the
// centre of the block's footprint and moves straight down by depth(t) =
// max_depth * path(t). Contact is the thesis' position constraint
// (msd/contact/rigid_obstacle.hpp); the indentation force is the sum of the
// contact nodes' reaction constraints along the indenting direction,
//     F = sum_i lambda_i (n_i . e),   lambda_i = max(0, -(f_i + f_ext,i) . n_i),
// with e = -z the indenting direction and n_i the cylinder's outward normal
// at node i (nodes within 1e-9 R of its surface).
#pragma once

#include "msd/contact/rigid_obstacle.hpp"
#include "msd/experiments/loading_path.hpp"
#include "msd/experiments/rig.hpp"

namespace msd {

struct IndenterOptions {
  double radius = 0.0;          ///< m
  int axis = 1;                 ///< 0 = x, 1 = y: the horizontal axis it lies along
  double max_depth = 0.0;       ///< m, reached where path = 1
  ContactResponse response = ContactResponse::Stick;
};

struct IndentationSetup {
  int clamp_group = -1;
  int obstacle = -1;
  double max_depth = 0.0;
  double height = 0.0;          ///< block height, m
  double volume = 0.0;          ///< rest volume, m^3
};

/// Clamps the bottom face and adds the cylinder, touching the top face at rest,
/// to `options` (tested against the top-face nodes).
IndentationSetup add_indenter(const TetMesh& mesh, const IndenterOptions& indenter, ModelOptions& options);

/// The cylinder's offset (0, 0, -max_depth path(t)) and velocity.
Controls indentation_controls(const Model& model, const IndentationSetup& setup, const LoadingPath& path, double t);

struct IndentationSample {
  double time = 0.0;
  double depth = 0.0;            ///< prescribed indenter depth, m
  double force = 0.0;            ///< indentation force, N (positive pressing in)
  int contact_nodes = 0;
  double base_reaction = 0.0;    ///< z reaction of the clamped base, N (= F when static)
  double volume_ratio = 1.0;
  int inverted_elements = 0;
  double kinetic_energy = 0.0;
};

IndentationSample measure_indentation(const Model& model, const IndentationSetup& setup, const LoadingPath& path,
                                      const State& state, Scratch& scratch);

}  // namespace msd
