// Penalty method (seed paper (3.1), (3.7)-(3.8), (4.4), (4.10), (4.12)): normal force eps_N g_N while
// penetrating, tangential forces eps_T times the elastic slip, return-mapped onto the Coulomb limit.
// Parameters (sublist "Penalty"): "Normal Penalty Parameter" eps_N, "Tangential Penalty Parameter"
// eps_T [force/length].
#pragma once
#include "ConstraintEnforcer.hpp"
#include "RegularizedContactLaw.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

class PenaltyEnforcer : public ConstraintEnforcer {
 public:
  static const char* name() { return "Penalty"; }
  static const core::ParameterSpec& spec();
  explicit PenaltyEnforcer(const Teuchos::ParameterList& validated);

  std::string type() const override { return name(); }
  double activationGap(const PointHistory&) const override { return 0.0; }
  bool contributes(const ContactKinematics& k, const PointHistory& h) const override;
  PointResult evaluate(const ContactKinematics& k, const PointHistory& h, double mu, const double* lambda, double* f,
                       double* K) const override;
  bool acceptPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda,
                   double& worstViolation) const override;
  void commitPoint(const ContactKinematics& k, PointHistory& h, double mu, const double* lambda) const override;

 private:
  RegularizedParameters parameters() const {
    RegularizedParameters p = p_;
    p.law = frictionLaw();
    return p;
  }
  RegularizedParameters p_;
};

}  // namespace bc::constraints
