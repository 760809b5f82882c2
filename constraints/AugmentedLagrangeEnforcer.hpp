// Augmented Lagrange method, Uzawa type: within an increment the multipliers are fixed estimates
// lambda_hat and the contact law is the penalty-regularized one around them
// (RegularizedContactLaw.hpp); when Newton has converged, lambda_hat <- lambda (normal and friction)
// and the increment is solved again, until every active point has |g_N| <= "Gap Tolerance" and every
// sticking line |g_T| <= "Gap Tolerance". The converged result therefore does not depend on the
// penalty parameters beyond that tolerance; they only change how many passes it takes.
// Parameters (sublist "Augmented Lagrange"): "Normal Penalty Parameter", "Tangential Penalty
// Parameter" [force/length], "Gap Tolerance" [length], "Maximum Augmentations".
#pragma once
#include "ConstraintEnforcer.hpp"
#include "RegularizedContactLaw.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

class AugmentedLagrangeEnforcer : public ConstraintEnforcer {
 public:
  static const char* name() { return "Augmented Lagrange"; }
  static const core::ParameterSpec& spec();
  explicit AugmentedLagrangeEnforcer(const Teuchos::ParameterList& validated);

  std::string type() const override { return name(); }
  double activationGap(const PointHistory& h) const override { return -h.lambdaN / p_.normalPenalty; }
  bool contributes(const ContactKinematics& k, const PointHistory& h) const override;
  PointResult evaluate(const ContactKinematics& k, const PointHistory& h, double mu, const double* lambda, double* f,
                       double* K) const override;
  bool acceptPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda,
                   double& worstViolation) const override;
  // acceptPoint has already set the estimates to the converged forces: report and keep those
  // (recomputing lambda_hat + eps g would count the last augmentation twice).
  PointResult reportedForces(const ContactKinematics& k, const PointHistory& h, double mu,
                             const double* lambda) const override;
  void commitPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const override {}
  int maximumPasses() const override { return maxPasses_; }

 private:
  RegularizedParameters parameters() const {
    RegularizedParameters p = p_;
    p.law = frictionLaw();
    return p;
  }
  RegularizedParameters p_;
  double tolerance_;
  int maxPasses_;
};

}  // namespace bc::constraints
