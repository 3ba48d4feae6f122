// The element force loop: for every element, gather its four vertices once, add
// the enabled terms (edge springs, edge dampers, face repulsion, volume
// preservation - thesis eq. 5.4 plus eq. 5.5 - and the continuum element of
// stable_neo_hookean.hpp) and scatter into one force buffer.
// Each term is its own function (edge_springs.hpp, ...); this loop only composes
// them so a model pays for the terms it uses and nothing else.
#pragma once

#include "msd/model/model.hpp"

namespace msd {

/// Internal forces of all elements at positions x and velocities v (3 x N) into
/// f (resized and overwritten). Returns the number of elements whose non-linear
/// terms were evaluated (all of them when the threshold is off). Runs the fast
/// engine (force_engine.hpp) with buffers of its own; a stepper passes its
/// Scratch to compute_forces_fast instead.
long compute_internal_forces(const Model& model, const Points& x, const Points& v, Points& f);

/// The same forces by the per-tet loop described above: the scalar reference
/// the fast engine is tested against (each spring once per tet side).
long compute_internal_forces_reference(const Model& model, const Points& x, const Points& v, Points& f);

/// Thesis 5.8's test: some vertex height of the tet at x[0..3] is below
/// `threshold` (> 0) times its rest height. With h_i = 6V / |m_i|
/// (tet_frame.hpp), h_i < c h0_i is 6V < c h0_i |m_i|; it is tested without
/// square roots or divisions: 6V <= 0 (flat or inverted: below), or
/// (6V)^2 < (c h0_i)^2 |m_i|^2 for some i. The forces and Jacobians use it alike.
bool nonlinear_terms_active(const Element& el, double threshold, const Vec3 x[4]);

/// The non-linear terms of one element (face repulsion and volume
/// preservation, whichever the model has, thesis eq. 5.1-5.3 and 5.5) added to
/// f[0..3] for vertices x[0..3]; nothing when the thesis 5.8 threshold leaves
/// the element out. Returns whether they ran. Shared by the reference loop and
/// the fast engine.
bool add_nonlinear_element_forces(const Model& model, const Element& el, const Vec3 x[4], Vec3 f[4]);

/// The pressure of volume group g at x, Pa: the continuum element's
/// lambda (Jbar - alpha) (msd/forces/stable_neo_hookean.hpp), or with the bulk
/// term its K (Jbar - 1) (msd/forces/bulk_volume.hpp).
double volume_group_pressure(const Model& model, int g, const Points& x);

/// The continuum element's forces on tet t (vertices x[0..3]) added to f: its
/// own volume term, or with volume groups the shear part and its group's
/// pressure from `group_pressure` (per group). Shared by the reference loop
/// and the fast engine.
void add_continuum_element_forces(const Model& model, size_t t, const Vec3 x[4],
                                  const std::vector<double>& group_pressure, Vec3 f[4]);

/// Forces of element e alone, for diagnostics and tests: f[i] is the force on
/// its local vertex i.
void element_forces(const Model& model, int e, const Points& x, const Points& v, Vec3 f[4]);

/// Elastic energy of the conservative terms (springs, face repulsion, the
/// neo-Hookean element) at x.
double conservative_energy(const Model& model, const Points& x);

/// Kinetic energy sum m |v|^2 / 2.
double kinetic_energy(const Model& model, const Points& v);

}  // namespace msd
