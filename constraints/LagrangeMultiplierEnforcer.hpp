// Lagrange multiplier method (seed paper (3.2), (3.6), (3.9)-(3.10), (4.5), (4.11), (4.13),
// (4.16)-(4.29)): every active contact point adds the unknowns lambda_N, lambda_T1, lambda_T2, so
// the point's element has 24 + 3 = 27 dofs and the global system grows and shrinks with the active
// set. Rows of the multipliers:
//   normal:              g_N = 0
//   stick (line i):      g_Ti = 0                     (no slip since the last converged step)
//   slip  (line i):      s_i lambda_Ti + mu lambda_N = 0   (|lambda_Ti| = mu |lambda_N|, s_i fixed)
//   frictionless:        lambda_Ti = 0
// and the displacement rows get lambda_N R_N + sum_i lambda_Ti R_Ti with tangent
// lambda_N K_N + sum_i lambda_Ti K_Ti and the R vectors as the coupling columns. (The paper writes the
// slip force as mu lambda_N R_T with its own signs and indices, some misprinted; this form gives
// the same solution and is checked against finite differences.)
// Active set, updated when Newton has converged (then the increment is solved again):
//   an active point whose lambda_N > 0 (tension) is released; an inactive one with g_N < -"Gap
//   Tolerance" is activated, sliding in the direction it moved since the last converged step; a
//   sticking line with |lambda_T| > mu |lambda_N| slips in the direction of lambda_T; a slipping
//   line whose slip g_T opposes its force sticks.
// That is the "Per Line" friction law. With "Isotropic Coulomb" the two friction rows are the
// semismooth complementarity function lambda_T - P(lambda_T + c_T M g_T) = 0 (P the projection on the
// cone |lambda_T|_{M^-1} <= mu |lambda_N|, CoulombCone.hpp): stick and slip and the slip direction are
// found by Newton itself, the active set only handles the normal contact.
// Parameters (sublist "Lagrange Multiplier"): "Gap Tolerance" [length], "Maximum Active Set
// Iterations", "Friction Complementarity Parameter" c_T [force/length].
#pragma once
#include "ConstraintEnforcer.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

class LagrangeMultiplierEnforcer : public ConstraintEnforcer {
 public:
  static const char* name() { return "Lagrange Multiplier"; }
  static const core::ParameterSpec& spec();
  explicit LagrangeMultiplierEnforcer(const Teuchos::ParameterList& validated);

  std::string type() const override { return name(); }
  int multipliersPerPoint() const override { return 3; }
  bool contributes(const ContactKinematics& k, const PointHistory& h) const override { return h.active; }
  PointResult evaluate(const ContactKinematics& k, const PointHistory& h, double mu, const double* lambda, double* f,
                       double* K) const override;
  bool acceptNormal(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const override;
  bool acceptPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda,
                   double& worstViolation) const override;
  void commitPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const override;
  int maximumPasses() const override { return maxPasses_; }

 private:
  // Isotropic Coulomb: adds the two friction rows; returns true when the point slips.
  bool isotropicFrictionRows(const ContactKinematics& k, double mu, const double* lambda, double* f, double* K) const;
  double tolerance_;
  int maxPasses_;
  double complementarity_;
};

}  // namespace bc::constraints
