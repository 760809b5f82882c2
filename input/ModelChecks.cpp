// The checks of a built model that no single parameter shows (input/Deck.cpp runs them): every
// structure held against rigid-body motion, no beam given twice, and the model's memory estimate
// against the machine's.
#include "ModelChecks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "XmlDeck.hpp"
#include "core/PointGrid.hpp"

namespace bc::input {

using core::InputError;
using elements::Vec3d;

namespace {

// Eigenvalues (ascending) and eigenvectors (columns of V) of a symmetric 6 x 6 matrix, by cyclic
// Jacobi rotations.
void symmetricEigen6(std::array<std::array<double, 6>, 6> A, std::array<double, 6>& lambda,
                     std::array<std::array<double, 6>, 6>& V) {
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) V[i][j] = i == j ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0.0;
    for (int i = 0; i < 6; ++i)
      for (int j = i + 1; j < 6; ++j) off += A[i][j] * A[i][j];
    if (off < 1e-30) break;
    for (int p = 0; p < 6; ++p)
      for (int q = p + 1; q < 6; ++q) {
        if (std::abs(A[p][q]) < 1e-300) continue;
        const double theta = 0.5 * (A[q][q] - A[p][p]) / A[p][q];
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
        for (int k = 0; k < 6; ++k) {
          const double akp = A[k][p], akq = A[k][q];
          A[k][p] = c * akp - sn * akq;
          A[k][q] = sn * akp + c * akq;
        }
        for (int k = 0; k < 6; ++k) {
          const double apk = A[p][k], aqk = A[q][k];
          A[p][k] = c * apk - sn * aqk;
          A[q][k] = sn * apk + c * aqk;
        }
        for (int k = 0; k < 6; ++k) {
          const double vkp = V[k][p], vkq = V[k][q];
          V[k][p] = c * vkp - sn * vkq;
          V[k][q] = sn * vkp + c * vkq;
        }
      }
  }
  std::array<int, 6> order{0, 1, 2, 3, 4, 5};
  std::sort(order.begin(), order.end(), [&](int a, int b) { return A[a][a] < A[b][b]; });
  const auto W = V;
  for (int k = 0; k < 6; ++k) {
    lambda[k] = A[order[k]][order[k]];
    for (int i = 0; i < 6; ++i) V[i][k] = W[i][order[k]];
  }
}

std::string vectorText(const Vec3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3g, %.3g, %.3g)", std::abs(v[0]) < 5e-7 ? 0.0 : v[0],
                std::abs(v[1]) < 5e-7 ? 0.0 : v[1], std::abs(v[2]) < 5e-7 ? 0.0 : v[2]);
  return buf;
}

}  // namespace

// Each structure (a beam, or beams rigidly joined at shared nodes) must be held against all six
// rigid-body motions by the supports on its own nodes (contact, which acts only once beams touch,
// holds nothing at the start). The rigid motions of a structure, u = t + w x (X - c) and spin w,
// restricted to its fixed dofs form a matrix C (fixed dofs x 6); a motion in the null space of C^T C
// is free. Reports the first free motion found, as a translation direction or a rotation axis
// through a point.

namespace {

// The fixed components of every node: by the supports, and a pinned joint holds the translations of
// its two nodes (each structure is checked on its own: a beam pinned to another must be held against
// turning about the pin by its own supports).
std::vector<std::array<bool, 6>> fixedComponents(const Problem& p) {
  std::vector<std::array<bool, 6>> fixed(p.model.initial.numNodes(), std::array<bool, 6>{});
  for (const auto& sup : p.model.supports)
    for (int n : sup.nodes)
      for (int k = 0; k < 6; ++k) fixed[n][k] = fixed[n][k] || sup.fixed[k];
  for (const auto& [a, b] : p.pins)
    for (int k = 0; k < 3; ++k) fixed[a][k] = fixed[b][k] = true;
  return fixed;
}

// Structures: beams connected through shared nodes (union-find over the beams); root -> beams, in
// deck order.
std::map<int, std::vector<int>> structures(const Problem& p) {
  const auto& beams = p.beams->beams();
  std::vector<int> parent(beams.size()), nodeBeam(p.model.initial.numNodes(), -1);
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int b) { return parent[b] == b ? b : parent[b] = root(parent[b]); };
  for (std::size_t b = 0; b < beams.size(); ++b)
    for (int n : beams[b].nodes) {
      if (nodeBeam[n] >= 0) parent[root(static_cast<int>(b))] = root(nodeBeam[n]);
      nodeBeam[n] = static_cast<int>(b);
    }
  std::map<int, std::vector<int>> all;
  for (std::size_t b = 0; b < beams.size(); ++b) all[root(static_cast<int>(b))].push_back(static_cast<int>(b));
  return all;
}

// C^T C of a structure's nodes `nodes` (centre c, size L): the rigid motions restricted to the fixed dofs.
std::array<std::array<double, 6>, 6> heldMotions(const std::vector<int>& nodes, const std::vector<Vec3d>& X,
                                                 const std::vector<std::array<bool, 6>>& fixed, const Vec3d& c,
                                                 double L) {
  std::array<std::array<double, 6>, 6> G{};
  for (int n : nodes) {
    const Vec3d r = (1.0 / L) * (X[n] - c);
    for (int k = 0; k < 6; ++k) {
      if (!fixed[n][k]) continue;
      std::array<double, 6> row{};
      if (k < 3) {
        row[k] = 1.0;
        for (int a = 0; a < 3; ++a) {
          Vec3d e{};
          e[a] = 1.0;
          row[3 + a] = cross(e, r)[k];
        }
      } else {
        row[k] = 1.0;
      }
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) G[i][j] += row[i] * row[j];
    }
  }
  return G;
}

// The error for a structure (beams `members`) free to move along the first column of V.
InputError notHeld(const std::vector<elements::Beam>& beams, const std::vector<int>& members,
                   const std::array<double, 6>& lambda, const std::array<std::array<double, 6>, 6>& V, const Vec3d& c,
                   double L) {
  const Vec3d t{{V[0][0], V[1][0], V[2][0]}}, w{{V[3][0], V[4][0], V[5][0]}};
  std::string motion;
  if (norm(w) < 1e-6) {
    motion = "it can translate along " + vectorText((1.0 / norm(t)) * t);
  } else {
    // u(X) = t + w x (X - c) / L vanishes on the axis through c + L (w x t) / |w|^2.
    const Vec3d through = c + (L / dot(w, w)) * cross(w, t);
    motion = "it can rotate about the axis " + vectorText((1.0 / norm(w)) * w) + " through " + vectorText(through);
  }
  int free = 0;
  for (double l : lambda) free += l <= 1e-9;
  std::string who = "beam \"" + beams[members[0]].name + "\"";
  if (members.size() > 1) {
    who = "the beams joined to \"" + beams[members[0]].name + "\" (" + std::to_string(members.size()) +
          " beams sharing nodes)";
  }
  return InputError(who + " is not held by its supports: " + motion +
                    (free > 1 ? " (and " + std::to_string(free - 1) + " more free rigid motions)" : "") +
                    "; fix more components (Supports/.../Fixed) on its nodes");
}

}  // namespace

void checkRigidBodyMotions(const Problem& p) {
  const core::State& s = p.model.initial;
  const auto fixed = fixedComponents(p);
  const auto& beams = p.beams->beams();
  for (const auto& [r, members] : structures(p)) {
    std::vector<int> nodes;
    for (int b : members) nodes.insert(nodes.end(), beams[b].nodes.begin(), beams[b].nodes.end());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    Vec3d c{};
    for (int n : nodes) c = c + (1.0 / nodes.size()) * s.reference[n];
    double L = 0.0;
    for (int n : nodes) L = std::max(L, norm(s.reference[n] - c));
    std::array<double, 6> lambda;
    std::array<std::array<double, 6>, 6> V;
    symmetricEigen6(heldMotions(nodes, s.reference, fixed, c, L), lambda, V);
    if (lambda[0] > 1e-9) continue;
    throw notHeld(beams, members, lambda, V, c, L);
  }
}

// Two beams in the same place are a beam given twice (and would overlap along their whole length).
// Found through the cells (of the largest tolerance) of the beams' ends, each beam against the
// earlier beams with an end near one of its own: not every pair of beams (10^4 beams: 5 x 10^7 pairs).
void checkDuplicateBeams(const Problem& p) {
  const auto& beams = p.beams->beams();
  const auto& X = p.model.initial.reference;
  double longest = 0.0;
  for (const auto& b : beams) longest = std::max(longest, norm(X[b.nodes.back()] - X[b.nodes.front()]));
  core::PointGrid ends(longest > 0.0 && std::isfinite(longest) ? 1e-9 * longest : 1.0);  // the beams' ends
  for (std::size_t b = 0; b < beams.size(); ++b) {
    const Vec3d b0 = X[beams[b].nodes.front()], b1 = X[beams[b].nodes.back()];
    for (const int a : ends.near(b0)) {
      const Vec3d a0 = X[beams[a].nodes.front()], a1 = X[beams[a].nodes.back()];
      const double tol = 1e-9 * std::max(norm(a1 - a0), norm(b1 - b0));
      if ((norm(a0 - b0) <= tol && norm(a1 - b1) <= tol) || (norm(a0 - b1) <= tol && norm(a1 - b0) <= tol))
        throw InputError("beams \"" + beams[a].name + "\" and \"" + beams[b].name +
                         "\" have the same Start and End: a beam given twice?");
    }
    ends.insert(b0, static_cast<int>(b));
    ends.insert(b1, static_cast<int>(b));
  }
}

// What a model needs, against the memory this process may use. Measured (bench/bench_memory.py,
// docs/scale.md "Memory per element and per contact point"): the peak resident memory of a run on one
// rank with the default Direct solver (KLU2) grows by 16.5 kB per beam element (Example 1 with 2.5e4
// to 1e5 elements: 466 to 1646 MB) and, over the crossed layers' contact points (32 x 32 to 128 x 128,
// every point active), by 76 kB per point with Penalty and, with Lagrange multipliers, 170 kB from
// 32 x 32 to 64 x 64, 195 kB from 64 x 64 to 100 x 100 and at least 267 kB on average at 128 x 128
// (4.8 GB before KLU2's first factorization of the saddle point had ended, after 18 min: its factors
// grow faster than the points), above 74 MB for the program. Augmented Lagrange has Penalty's matrix; a plug-in's
// strategy is counted as Lagrange. A pair of All Pairs costs 100 bytes (its entry and the search's index: a network of
// 4000 fibres, 8e6 pairs, 791 MB above the same deck without contact). The estimate is checked before anything of the
// solver is allocated: while the beams are read (elements only), before All Pairs makes its pairs, and once the contact
// points at the start are known.
void checkModelSize(std::size_t elements, std::size_t points, double bytesPerPoint, double pairs) {
  const double bytes =
      kBaseBytes + kBytesPerElement * double(elements) + bytesPerPoint * double(points) + kBytesPerPair * pairs;
  std::string limited;
  const double usable = usableMemory(&limited), physical = physicalMemory();
  if (elements > 5000000 || (usable > 0 && bytes > 0.8 * usable)) {
    char buf[500];
    if (pairs > 0)
      std::snprintf(buf, sizeof buf,
                    "All Pairs of the deck's beams makes %.0f contact pairs (with %zu elements), which needs about "
                    "%.1f GB; this machine has %.1f GB (the limit is 80 %% of the memory, at %.0f bytes per pair)",
                    pairs, elements, bytes / 1e9, physical / 1e9, kBytesPerPair);
    else if (points > 0)
      std::snprintf(buf, sizeof buf,
                    "the model has %zu elements and %zu contact points at the start, which needs about %.1f GB; "
                    "this machine has %.1f GB (the limit is 5e6 elements and 80 %% of the memory, at %.0f kB per "
                    "element and %.0f kB per contact point)",
                    elements, points, bytes / 1e9, physical / 1e9, kBytesPerElement / 1e3, bytesPerPoint / 1e3);
    else
      std::snprintf(buf, sizeof buf,
                    "the beams have %zu elements in all, which needs about %.1f GB; this machine has %.1f GB (the "
                    "limit is 5e6 elements and 80 %% of the memory, at %.0f kB per element)",
                    elements, bytes / 1e9, physical / 1e9, kBytesPerElement / 1e3);
    throw InputError(buf + limited);
  }
}

}  // namespace bc::input
