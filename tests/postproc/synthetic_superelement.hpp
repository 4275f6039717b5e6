#pragma once
// A superelement file for the surface analyses' tests (erp, animate): `modes` coordinates and the given
// exported surface; the other fields are placeholders of the right shapes (the analyses read only the surface
// and the coordinate count).
#include <string>

#include "common/superelement.hpp"

namespace nvh::testing {

inline SuperelementFile superelement_with(const SurfaceExport& surface, int modes) {
  SuperelementFile se;
  se.name = "synthetic-surface";
  se.kind = "volume";
  se.method = "modal";
  se.orthonormalized = true;
  se.frequency_hz = Eigen::VectorXd::LinSpaced(modes, 100.0, 100.0 * modes);
  for (int j = 0; j < modes; ++j) se.coordinates.push_back("mode " + std::to_string(j + 1));
  se.mass = Eigen::MatrixXd::Identity(modes, modes);
  se.stiffness = Eigen::MatrixXd::Identity(modes, modes);
  se.damping = Eigen::MatrixXd::Zero(modes, modes);
  se.surface = surface;
  se.inertia.mass = 1.0;
  se.inertia.center_of_mass.setZero();
  se.inertia.inertia.setIdentity();
  se.inertia.inertia_origin.setIdentity();
  se.inertia.second_moment.setIdentity();
  se.invariants.translational = Eigen::MatrixXd::Zero(3, modes);
  se.invariants.rotational = Eigen::MatrixXd::Zero(3, modes);
  for (int kl = 0; kl < 9; ++kl) {
    se.invariants.position.push_back(Eigen::VectorXd::Zero(modes));
    se.invariants.quadratic.push_back(Eigen::MatrixXd::Zero(modes, modes));
  }
  return se;
}

}  // namespace nvh::testing
