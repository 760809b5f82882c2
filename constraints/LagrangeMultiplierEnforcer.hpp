// Lagrange multiplier method (seed paper (3.2), (3.6), (3.9)-(3.10), (4.5), (4.11), (4.13),
// (4.16)-(4.29)): every active contact point adds the unknowns lambda_N, lambda_T1, lambda_T2, so
// the point's element has 24 + 3 = 27 dofs and the global system grows and shrinks with the active
// set. Rows of the multipliers:
//   normal:              g_N = 0
//   stick (line i):      g_Ti = 0                     (no slip since the last converged step)
//   slip  (line i):      s_i lambda_Ti + mu lambda_N = 0   (|lambda_Ti| = mu |lambda_N|, s_i fixed)
//   frictionless:        lambda_Ti = 0      (also along a direction without a measured slip)
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
// cone |lambda_T|_{M^-1} <= mu |lambda_N|, CoulombFriction.hpp): stick and slip and the slip direction are
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
  static const char* description() {
    return "exact constraints with multipliers (lambda_N, lambda_T1, lambda_T2) per active point and an active set";
  }
  static const core::ParameterSpec& spec();
  explicit LagrangeMultiplierEnforcer(const Teuchos::ParameterList& validated);
  // On lines: the multipliers interpolated linearly between the nodes of line A (mortar), with the
  // active set on the nodes' weighted gaps (docs/contact.md, "Lagrange multipliers on lines").
  LineField lineField() const override { return LineField::Nodal; }

  // The active set: whether the point is active (then it owns lambda_N, lambda_T1, lambda_T2) and,
  // for Per Line friction, each line's stick/slip state and slip direction.
  struct State : PointStateOf<State> {
    bool active = false;
    bool slip[2] = {false, false};
    double slipSign[2] = {1.0, 1.0};
    void fields(StateFields& v) override {
      v.flag("active", active);
      v.flag("slip_1", slip[0]);
      v.flag("slip_2", slip[1]);
      v.real("slip_sign_1", slipSign[0]);
      v.real("slip_sign_2", slipSign[1]);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<PointState> newPointState() const override { return std::make_unique<State>(); }
  int multipliers(const PointState& s) const override { return stateOf<State>(s).active ? 3 : 0; }
  bool addsMultiplierRows() const override { return true; }
  bool contributes(double, const PointState& s) const override { return stateOf<State>(s).active; }
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const override {
    return evaluate(p, s, f, K, Compliance{});
  }
  // The rows of springs instead of constraints (a perturbed Lagrangian, Penalty's Line Springs = Nodes):
  // the normal row g_N - normal lambda_N, a sticking line's row g_Ti - tangential (lambda_Ti -
  // committedT_i) (Isotropic Coulomb: M g_T - tangential (lambda_T - committedT) in the trial), so
  // that lambda_N = g_N / normal and a sticking lambda_T = committedT + M g_T / tangential.
  struct Compliance {
    double normal = 0.0, tangential = 0.0;
    double committedT[2] = {0.0, 0.0};
  };
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K, const Compliance& c) const;
  bool acceptNormal(const ContactPoint& p, PointState& s) const override;
  bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const override;
  int maximumPasses() const override { return maxPasses_; }
  bool discreteStates() const override { return true; }
  bool relaxesFrictionSteering() const override { return true; }

 private:
  // Isotropic Coulomb: adds the two friction rows; returns true when the point slips.
  bool isotropicFrictionRows(const ContactPoint& p, double* f, double* K, const Compliance& c) const;
  double tolerance_;
  int maxPasses_;
  double complementarity_;
};

}  // namespace bc::constraints
