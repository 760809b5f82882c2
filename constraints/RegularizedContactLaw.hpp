// The penalty-regularized contact and Coulomb friction law shared by the Penalty and the Augmented
// Lagrange strategies (with multiplier estimates lambda_hat = 0 for the normal part in the penalty
// method):
//   lambda_N  = lambda_hat_N + eps_N g_N            (active while < 0)
//   trial_i   = lambda_hat_Ti + eps_T g_Ti          (g_Ti: slip along line i since the last step)
//   stick:  |trial_i| <= mu |lambda_N|  ->  lambda_Ti = trial_i
//   slip:   otherwise                   ->  lambda_Ti = sign(trial_i) mu |lambda_N|   (return mapping)
// Residual: lambda_N R_N + sum_i lambda_Ti R_Ti. Tangent (consistent with the return mapping):
//   eps_N R_N (x) R_N + lambda_N K_N
//   + stick: eps_T R_Ti (x) R_Ti + lambda_Ti K_Ti
//   + slip:  -sign_i mu eps_N R_Ti (x) R_N + lambda_Ti K_Ti
// (the paper's (3.7), (4.14)-(4.15), (4.22)-(4.23), here derived and checked by finite differences).
// That is the "Per Line" law. With "Isotropic Coulomb" the friction trial is the vector
//   trial = lambda_hat_T + eps_T M g_T      (M the metric of the gaps, CoulombCone.hpp)
// return-mapped onto |lambda_T|_{M^-1} <= mu |lambda_N|; its tangent is
//   sum_a lambda_a K_a + sum_a R_a (x) sum_b (d lambda_a / d s_b) R_b,   s = (g_N, g_T1, g_T2, c),
// with the derivatives of the return mapping by forward AD (exact).
#pragma once
#include "ConstraintEnforcer.hpp"

namespace bc::constraints {

struct RegularizedParameters {
  double normalPenalty = 0.0;      // eps_N
  double tangentialPenalty = 0.0;  // eps_T
  FrictionLaw law = FrictionLaw::IsotropicCoulomb;
};

// The multipliers the law gives for a point (no assembly).
PointResult regularizedForces(const ContactKinematics& k, const PointHistory& h, double mu,
                              const RegularizedParameters& p);
// Residual and tangent (24 / 24 x 24) of a point; returns its forces.
PointResult regularizedEvaluate(const ContactKinematics& k, const PointHistory& h, double mu,
                                const RegularizedParameters& p, double* f, double* K);

}  // namespace bc::constraints
