// The penalty parameters of the Penalty and Augmented Lagrange strategies: given by the user, or
// "Automatic", chosen per contact point from the structure's compliance there.
//
// Automatic (docs/contact.md, "Automatic penalty parameters"). Take one contact point of the
// linearized problem K u = f - G^T lambda, with its gap g = g0 + G u. Let c = G K^-1 G^T be the
// structure's compliance at the point along the gap's gradient G (K: the beams without contact; c:
// the diagonal Delassus entry). The exact constraint g = 0 gives lambda* = (g0 + G K^-1 f) / c. A
// penalty spring lambda = eps g gives lambda = lambda* eps c / (1 + eps c): the contact force, and
// every displacement it causes, is too small by the factor
//     e = 1 / (1 + eps c),   so   eps = (1 - e) / (e c)
// makes that relative error exactly e (the "Target Error"). The same holds for a sticking friction
// force along g_T1 or g_T2 with its own compliance; one eps_T serves both, so it is chosen for the
// stiffer of the two (the smaller c) and the error of the other is below e. For the Augmented
// Lagrange strategy e is the factor by which each augmentation reduces the force's error (Uzawa's
// contraction for one point), so the target sets the number of passes, not the result.
//
// The bound is exact for one point in the linear limit. Points that support each other (a grid
// pressed together) see a stiffer structure than the beams alone, and their error is larger; large
// rotations change c after the point was found (it is computed once, when the point appears).
#pragma once
#include <string>
#include <vector>

#include "ConstraintEnforcer.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

struct PointPenalties;

class PenaltyChoice {
 public:
  static constexpr const char* kAutomatic = "Automatic";
  // Adds "Normal Penalty Parameter", "Tangential Penalty Parameter" (each a number or "Automatic"),
  // "Normal Target Error" and "Tangential Target Error" to a strategy's spec; `role` says what the
  // parameters are in that strategy.
  static void addTo(core::ParameterSpec& spec, const std::string& role);
  explicit PenaltyChoice(const Teuchos::ParameterList& validated);

  bool automatic() const { return automatic_[0] || automatic_[1]; }
  // The point's (eps_N, eps_T): the given values, or from its compliance c = (c_N, c_T1, c_T2). After
  // `relaxations` tangential relaxations (ConstraintEnforcer::relaxTangential) the tangential
  // compliances count 10^relaxations times: an automatic eps_T is that much lower.
  void choose(const double compliance[3], double eps[2], int relaxations = 0) const;
  const double* given() const { return given_; }
  // The Normal (0) and Tangential (1) Target Error.
  double target(int i) const { return target_[i]; }
  // The (eps_N, eps_T) a point uses: the given values, kept here once for every point, or the point's
  // own when they are chosen automatically.
  const double* at(const PointPenalties& point) const;
  // The output columns of a strategy with penalty parameters (ConstraintEnforcer::outputValues).
  std::vector<double> outputValues(const PointPenalties& point) const;

 private:
  bool automatic_[2] = {false, false};
  double given_[2] = {0.0, 0.0};
  double target_[2] = {0.0, 0.0};
};

// A point's penalty parameters when they are chosen automatically, part of the strategy's point state
// (written to checkpoints then); with given parameters the point keeps nothing (PenaltyChoice::at).
struct PointPenalties {
  double eps[2] = {0.0, 0.0};  // eps_N, eps_T; 0 until chosen
  bool automatic = false;

  void start(const PenaltyChoice& choice) { automatic = choice.automatic(); }
  bool waiting() const { return automatic && !(eps[0] > 0.0); }
  void fields(StateFields& v) {
    if (!automatic) return;
    v.real("eps_N", eps[0]);
    v.real("eps_T", eps[1]);
  }
  // Throws when a point is evaluated before its parameters were chosen (no compliance given).
  void require() const;
};

inline const double* PenaltyChoice::at(const PointPenalties& point) const {
  return point.automatic ? point.eps : given_;
}

}  // namespace bc::constraints
