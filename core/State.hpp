// Kinematic state of the model: nodal positions and nodal rotations (finite, multiplicative), plus
// the values of extra unknowns (e.g. Lagrange multipliers) that any contribution may own
// (ExtraUnknowns: each owner asks for its blocks by key; the layout travels with the values, so a
// copy of the state is a consistent snapshot).
// The state is replicated on every rank: it is small (12 numbers a node) and contact search needs the
// global geometry anyway. Element work, the matrix and the vectors are distributed (see Assembler).
//
// Global dof numbering: node n owns dofs 6n..6n+5 = (ux, uy, uz, spin x, spin y, spin z); extra
// unknowns follow after 6 * numNodes.
#pragma once
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "SmallMath.hpp"

namespace bc::core {

using math::Mat3d;
using math::Vec3d;
using GlobalDof = long long;

constexpr int kDofsPerNode = 6;

// Extra unknowns beyond the nodal dofs, numbered after them. Owners (contributions, by name) ask for
// blocks identified by a key of their choosing (e.g. a contact point, a segment, an element); the
// blocks are laid out by (owner, key), so every rank that makes the same requests gets the same
// numbering.
class ExtraUnknowns {
 public:
  using Key = std::vector<long long>;
  struct Block {
    int offset = 0;
    int size = 0;
  };
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  double& operator[](std::size_t i) { return values_[i]; }
  const double& operator[](std::size_t i) const { return values_[i]; }
  const std::vector<double>& values() const { return values_; }

  // Sets `owner`'s blocks to `wanted` (key -> number of unknowns). A block whose key was there before
  // with the same size keeps its values, a new one starts at zero; other owners' blocks keep theirs.
  // Returns true when the layout changed. `owner` is one word (it is written to checkpoints).
  bool request(const std::string& owner, const std::map<Key, int>& wanted) {
    for (char c : owner)
      if (std::isspace(static_cast<unsigned char>(c)))
        throw std::logic_error("extra-unknown owner \"" + owner + "\" is not one word");
    std::map<std::pair<std::string, Key>, Block> next;
    for (const auto& [k, b] : blocks_)
      if (k.first != owner) next.emplace(k, b);
    for (const auto& [key, n] : wanted)
      if (n > 0) next.emplace(std::make_pair(owner, key), Block{0, n});
    std::vector<double> values;
    bool changed = next.size() != blocks_.size();
    for (auto& [k, b] : next) {
      const auto old = blocks_.find(k);
      b.offset = static_cast<int>(values.size());
      const bool kept = old != blocks_.end() && old->second.size == b.size;
      changed = changed || !kept || old->second.offset != b.offset;
      for (int j = 0; j < b.size; ++j) values.push_back(kept ? values_[old->second.offset + j] : 0.0);
    }
    blocks_ = std::move(next);
    values_ = std::move(values);
    return changed;
  }
  // The block of `owner` under `key`, or null.
  const Block* find(const std::string& owner, const Key& key) const {
    const auto it = blocks_.find({owner, key});
    return it == blocks_.end() ? nullptr : &it->second;
  }
  // Every block, for checkpoints: (owner, key) -> block, in numbering order.
  const std::map<std::pair<std::string, Key>, Block>& blocks() const { return blocks_; }
  // Restores a layout and its values (checkpoint); the blocks must tile the values.
  void assign(std::map<std::pair<std::string, Key>, Block> blocks, std::vector<double> values) {
    blocks_ = std::move(blocks);
    values_ = std::move(values);
  }

 private:
  std::map<std::pair<std::string, Key>, Block> blocks_;
  std::vector<double> values_;
};

struct State {
  std::vector<Vec3d> reference;  // X: initial nodal positions
  std::vector<Vec3d> position;  // x: current nodal positions
  std::vector<Mat3d> rotation;  // R: current nodal rotation (maps reference triads to current ones)
  std::vector<Vec3d> rotationVector;  // unwrapped total rotation vector, updated at converged steps
  ExtraUnknowns extra;  // extra unknowns, numbered from 6 * numNodes()

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
  rotation.assign(nodes, math::identity3<double>());
  rotationVector.assign(nodes, Vec3d{});
}

inline void State::applyNodeIncrement(int n, const double* du) {
  for (int k = 0; k < 3; ++k) position[n][k] += du[k];
  const Vec3d w{{du[3], du[4], du[5]}};
  if (w[0] != 0.0 || w[1] != 0.0 || w[2] != 0.0) rotation[n] = math::expSO3(w) * rotation[n];
}

inline void State::applyIncrement(const std::vector<double>& du) {
  const int nn = numNodes();
  for (int n = 0; n < nn; ++n) applyNodeIncrement(n, &du[std::size_t(kDofsPerNode) * n]);
  for (std::size_t k = 0; k < extra.size(); ++k) extra[k] += du[std::size_t(kDofsPerNode) * nn + k];
}

inline void State::updateRotationVectors() {
  const double twoPi = 2.0 * std::acos(-1.0);
  for (int n = 0; n < numNodes(); ++n) {
    const Vec3d psi = math::logSO3(rotation[n]);
    const double angle = norm(psi);
    const Vec3d& prev = rotationVector[n];
    if (angle < 1e-14) {
      // Identity: the candidates are 2 pi k along the previous axis.
      const double pa = norm(prev);
      if (pa < 1e-14) {
        rotationVector[n] = psi;
        continue;
      }
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
