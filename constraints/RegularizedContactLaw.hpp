// The penalty-regularized contact law shared by the Penalty and Augmented Lagrange strategies, and by
// any strategy with its own normal law (e.g. a nonlinear penalty):
//   lambda_N  = phi(g_N)                        the normal law (active while < 0; penalty:
//                                               eps_N g_N, augmented: lambda_hat_N + eps_N g_N)
//   trial_T   = lambda_hat_T + eps_T M g_T      (Per Line: lambda_hat_Ti + eps_T g_Ti, each line)
//   lambda_T  = return mapping of trial_T onto mu |lambda_N|   (CoulombFriction.hpp)
// Residual: lambda_N R_N + sum_i lambda_Ti R_Ti. Tangent:
//   sum_a lambda_a K_a + sum_a R_a (x) sum_b (d lambda_a / d s_b) R_b,   s = (g_N, g_T1, g_T2, c),
// with the derivatives of the normal law and of the return mapping by forward AD (exact), so a new
// normal law needs no hand-derived tangent. Checked against central differences of the residual for
// every registered strategy (tests/unit/test_strategies.cpp).
#pragma once
#include <functional>

#include <Sacado.hpp>

#include "ConstraintEnforcer.hpp"

namespace bc::constraints {

// The scalar a normal law is written in: a value with its derivatives with respect to
// s = (g_N, g_T1, g_T2, c). Write the law as a function of g_N with ordinary arithmetic, and give a
// lambda its return type (`-> LawScalar`): Sacado's expression templates would otherwise return a
// reference to a temporary.
using LawScalar = Sacado::Fad::SFad<double, 4>;
using NormalLaw = std::function<LawScalar(const LawScalar& gapN)>;

// The linear law lambda_hat_N + eps_N g_N (penalty: lambda_hat_N = 0).
NormalLaw linearNormalLaw(double lambdaHatN, double epsN);
// The penalty law with a C1 onset over the first g0 of penetration: -eps_N g^2 / (2 g0) for
// -g0 < g < 0, then eps_N (g + g0 / 2) (linear, shifted by eps_N g0 / 2); g0 = 0: linear. A kink at
// first contact makes Newton cycle where many points touch at once (a line, a dense grid); the
// smooth onset removes it.
NormalLaw smoothedPenaltyLaw(double epsN, double g0);
// The augmented law lambda_hat_N + eps_N g_N with a C1 onset of width g0 centred on its kink: with
// x = g_N + lambda_hat_N / eps_N, eps_N x for x <= -g0 / 2, -eps_N (x - g0 / 2)^2 / (2 g0) up to
// x = g0 / 2, 0 beyond. Its linear branch is the unsmoothed law's, so the augmentations still close
// the gap (they converge to g_N = 0 wherever the force exceeds eps_N g0 / 2); g0 = 0: linear.
NormalLaw smoothedAugmentedLaw(double lambdaHatN, double epsN, double g0);

// A point held in or out of the active set for a Newton solve (its law linear and bilateral while in,
// ConstraintEnforcer::fixActiveSet): after the solve it joins where its linear law's force `trial`
// presses (below 0) and leaves where it pulls (above 0); at 0 it stays as it is. Returns whether it
// stayed.
inline bool settleEngaged(bool& engaged, double trial) {
  if (engaged == (trial < 0.0) || (engaged && trial == 0.0)) return true;
  engaged = trial < 0.0;
  return false;
}

// The friction part: estimates lambda_hat_T (the forces carried from the last converged step or
// augmentation) and the stick stiffness eps_T.
struct FrictionRegularization {
  double lambdaHat[2] = {0.0, 0.0};
  double penalty = 0.0;  // eps_T [force/length]
};

// The forces the law gives for a point (no assembly). `bilateral`: the law acts in tension too (a
// point held in the active set for a whole Newton solve; no friction while in tension).
PointResult regularizedForces(const ContactPoint& p, const NormalLaw& normal, const FrictionRegularization& t,
                              bool bilateral = false);
// Adds the residual (24) and tangent (24 x 24, may be null) of a point; returns its forces.
PointResult regularizedEvaluate(const ContactPoint& p, const NormalLaw& normal, const FrictionRegularization& t,
                                double* f, double* K, bool bilateral = false);

}  // namespace bc::constraints
