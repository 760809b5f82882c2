// How a contact constraint is enforced: the strategy interface. A strategy sees one contact point at
// a time: its kinematics (gaps g_N, g_T1, g_T2 with first variations R and linearized variations K,
// see ContactKinematics.hpp), the friction coefficient and the point's history, and adds the point's
// residual and tangent. The contact manager does search, bookkeeping and assembly; a strategy is only
// this local math plus what it does when Newton has converged (augment, change the active set).
//
// Sign conventions: lambda_N <= 0 is the normal contact force conjugate to g_N (paper's (3.2):
// F_N = lambda_N; the reported normal force is -lambda_N >= 0); lambda_Ti is the friction force
// conjugate to g_Ti. Coulomb friction by one of two laws (Contact/Friction Law):
//  - Isotropic Coulomb: the tangential force vector F_T in the contact plane obeys |F_T| <= mu |lambda_N|;
//    with the slip vector s = g_T1 a - g_T2 b (a, b unit line tangents, c = a . b) the force components
//    conjugate to (g_T1, g_T2) give |F_T|^2 = lambda_T^T M^-1 lambda_T, M = [1 -c; -c 1];
//  - Per Line: |lambda_Ti| <= mu |lambda_N| for each line independently (the seed paper's (4.3)); the
//    resultant may then reach sqrt(2) mu |lambda_N|.
#pragma once
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "ContactKinematics.hpp"

namespace bc::constraints {

// What is carried from one converged step to the next (and, for augmented Lagrange, between passes).
struct PointHistory {
  double lambdaN = 0.0;      // multiplier estimate (augmented Lagrange) or converged value (Lagrange)
  double lambdaT[2] = {0.0, 0.0};  // friction forces of the last converged step / estimates
  bool active = false;       // Lagrange: point is in the active set
  bool slip[2] = {false, false};   // Lagrange: slip state per line
  double slipSign[2] = {1.0, 1.0}; // Lagrange: direction of the friction force in slip
};

// The result of evaluating a point: forces and state, for output and for the progress line.
struct PointResult {
  bool active = false;
  double lambdaN = 0.0;
  double lambdaT[2] = {0.0, 0.0};
  bool slip[2] = {false, false};
};

enum class FrictionLaw { IsotropicCoulomb, PerLine };

class ConstraintEnforcer {
 public:
  virtual ~ConstraintEnforcer() = default;
  // The friction law the strategy enforces (set by the contact manager from the deck).
  void setFrictionLaw(FrictionLaw law) { law_ = law; }
  FrictionLaw frictionLaw() const { return law_; }
  virtual std::string type() const = 0;
  // Where the point's force switches on within Newton, as a gap: the point acts once g_N falls below
  // this (penalty: 0; augmented Lagrange: -lambda_hat_N / eps_N). Infinite for strategies whose
  // active set changes only between Newton solves (Lagrange multipliers).
  virtual double activationGap(const PointHistory& h) const { return -std::numeric_limits<double>::infinity(); }
  // Extra unknowns per active contact point (3 for Lagrange multipliers: lambda_N, lambda_T1, lambda_T2).
  virtual int multipliersPerPoint() const { return 0; }
  // True when a point whose kinematics are `k` takes part in the system now (penalty: g_N < 0).
  virtual bool contributes(const ContactKinematics& k, const PointHistory& h) const = 0;
  // Adds the point's residual f (size n = 24 + multipliersPerPoint) and tangent K (n x n,
  // row-major; may be null). `lambda` holds the point's current multipliers (null if none).
  virtual PointResult evaluate(const ContactKinematics& k, const PointHistory& h, double mu, const double* lambda,
                               double* f, double* K) const = 0;
  // Newton has converged for this increment. First stage, for every point: the normal active set
  // (activate, release); return false if it changed. Only when no point changed there, the second
  // stage (acceptPoint) runs: friction states, augmentation. Mixing both in one pass makes active
  // sets cycle, because slip directions would come from a configuration that no longer holds.
  virtual bool acceptNormal(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const {
    return true;
  }
  // Second stage. Update `h` (e.g. augment the multipliers, change stick/slip); return false if the
  // increment must be solved again with the updated history.
  // `worstViolation` collects the largest constraint violation (for the stopping test and output).
  virtual bool acceptPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda,
                           double& worstViolation) const = 0;
  // The forces of a point at a converged state, for output (called before commitPoint). By default
  // the evaluation without assembly.
  virtual PointResult reportedForces(const ContactKinematics& k, const PointHistory& h, double mu,
                                     const double* lambda) const {
    std::vector<double> f(kPairDofs + multipliersPerPoint(), 0.0);
    return contributes(k, h) ? evaluate(k, h, mu, lambda, f.data(), nullptr) : PointResult{};
  }
  // History at the end of a converged increment (friction forces carried to the next increment).
  virtual void commitPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const = 0;
  // Upper bound on the Newton solves of one increment the strategy may ask for (augmentation passes).
  virtual int maximumPasses() const { return 1; }

 private:
  FrictionLaw law_ = FrictionLaw::IsotropicCoulomb;
};

}  // namespace bc::constraints
