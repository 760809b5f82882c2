// Kinematic state of the model: nodal positions and nodal rotations (finite, multiplicative), plus
// the values of extra unknowns (e.g. Lagrange multipliers) that constraint contributions may add.
// The state is replicated on every rank: it is small (12 numbers a node) and contact search needs the
// global geometry anyway. Element work, the matrix and the vectors are distributed (see Assembler).
//
// Global dof numbering: node n owns dofs 6n..6n+5 = (ux, uy, uz, spin x, spin y, spin z); extra
// unknowns follow after 6 * numNodes.
#pragma once
#include <cmath>
#include <vector>

#include "elements/SmallMath.hpp"

namespace bc::core {

using elements::Mat3d;
using elements::Vec3d;
using GlobalDof = long long;

constexpr int kDofsPerNode = 6;

struct State {
  std::vector<Vec3d> reference;   // X: initial nodal positions
  std::vector<Vec3d> position;    // x: current nodal positions
  std::vector<Mat3d> rotation;    // R: current nodal rotation (maps reference triads to current ones)
  std::vector<Vec3d> rotationVector;  // unwrapped total rotation vector, updated at converged steps
  std::vector<double> extra;      // extra unknowns, numbered from 6 * numNodes()

  int numNodes() const { return static_cast<int>(position.size()); }
  GlobalDof numDofs() const { return GlobalDof(kDofsPerNode) * numNodes() + GlobalDof(extra.size()); }
  Vec3d displacement(int n) const { return position[n] - reference[n]; }

  void resize(int nodes);
  // Adds an increment over all dofs: positions additively, rotations R <- exp(skew(dphi)) R.
  void applyIncrement(const std::vector<double>& du);
  // Applies one node's increment (6 values).
  void applyNodeIncrement(int node, const double* du6);
  // Chooses, for each node, the rotation vector of R closest to the previous one (so that a beam
  // rolled into a full circle reports 2 pi, not 0).
  void updateRotationVectors();
};

inline void State::resize(int nodes) {
  reference.assign(nodes, Vec3d{});
  position.assign(nodes, Vec3d{});
  rotation.assign(nodes, elements::identity3<double>());
  rotationVector.assign(nodes, Vec3d{});
}

inline void State::applyNodeIncrement(int n, const double* du) {
  for (int k = 0; k < 3; ++k) position[n][k] += du[k];
  const Vec3d w{{du[3], du[4], du[5]}};
  if (w[0] != 0.0 || w[1] != 0.0 || w[2] != 0.0) rotation[n] = elements::expSO3(w) * rotation[n];
}

inline void State::applyIncrement(const std::vector<double>& du) {
  const int nn = numNodes();
  for (int n = 0; n < nn; ++n) applyNodeIncrement(n, &du[std::size_t(kDofsPerNode) * n]);
  for (std::size_t k = 0; k < extra.size(); ++k) extra[k] += du[std::size_t(kDofsPerNode) * nn + k];
}

inline void State::updateRotationVectors() {
  const double twoPi = 2.0 * std::acos(-1.0);
  for (int n = 0; n < numNodes(); ++n) {
    const Vec3d psi = elements::logSO3(rotation[n]);
    const double angle = norm(psi);
    const Vec3d& prev = rotationVector[n];
    if (angle < 1e-14) {
      // Identity: the candidates are 2 pi k along the previous axis.
      const double pa = norm(prev);
      if (pa < 1e-14) { rotationVector[n] = psi; continue; }
      const double k = std::round(pa / twoPi);
      rotationVector[n] = (k * twoPi / pa) * prev;
      continue;
    }
    const Vec3d axis = (1.0 / angle) * psi;
    // Candidates (angle + 2 pi k) * axis; pick k nearest to the previous vector's projection.
    const double along = dot(prev, axis);
    const double k = std::round((along - angle) / twoPi);
    rotationVector[n] = (angle + k * twoPi) * axis;
  }
}

}  // namespace bc::core
