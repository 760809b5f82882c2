#include "AutomaticPenalty.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Teuchos_CommHelpers.hpp>

#include "core/Faults.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

void AutomaticPenalty::giveCompliance(PointMap& points, const ContactGeometry& geometry, const Kinematics& kinematics) {
  if (!compliance_) return;
  std::vector<ContactPointRecord*> waiting;
  std::vector<core::SparseLoad> loads;
  std::vector<double> weights;
  for (auto& [key, p] : points) {
    // (A Gauss point of a nodal line field acts through its nodes' state: it needs none.)
    if (p.node() || (lines_.nodal() && p.line()) || !enforcer_.wantsCompliance(*p.state)) continue;
    const ContactKinematics k = kinematics(p);
    const auto d = geometry.pointDofs(p);
    for (const GapDerivatives* g : {&k.normal, &k.tangent1, &k.tangent2})
      loads.push_back(
          {std::vector<core::GlobalDof>(d.begin(), d.end()), std::vector<double>(g->R.begin(), g->R.end())});
    // The manager weights a line point's force by the length it stands for (a whole segment's share here).
    weights.push_back(p.line() ? lines_.weight(p, 1.0) : 1.0);
    waiting.push_back(&p);
  }
  if (waiting.empty()) return;
  std::vector<double> c;
  try {
    c = compliance_(geometry.reference(), loads);
  } catch (const std::runtime_error& e) {
    throw core::InputError(enforcer_.type() +
                           ": automatic penalty parameters need the beams' compliance at the "
                           "contact points, but " +
                           e.what() + "; give the penalty parameters as numbers");
  }
  for (std::size_t i = 0; i < waiting.size(); ++i) {
    for (int k = 0; k < 3; ++k) waiting[i]->compliance[k] = weights[i] * c[3 * i + k];
    handCompliance(*waiting[i]);
  }
}

void AutomaticPenalty::handCompliance(ContactPointRecord& p) const {
  if (relaxations_ == 0) enforcer_.setCompliance(*p.state, p.compliance);
  else enforcer_.relaxTangential(*p.state, p.compliance, relaxations_);
}

void AutomaticPenalty::watchFriction(const PointKey& key, const PointResult& r, bool tangent) const {
  if (!tangent || !r.active || !(r.slip[0] || r.slip[1])) return;
  FrictionWatch& w = frictionWatch_[key];
  ++w.since;
  if (w.force[0] * r.lambdaT[0] + w.force[1] * r.lambdaT[1] < 0.0) {
    ++w.reversals;
    w.since = 0;
    if (w.reversals >= kHoldReversals && !w.released) w.held = true;
  }
  w.force = {r.lambdaT[0], r.lambdaT[1]};
}

void AutomaticPenalty::watchActive(const PointKey& key, bool acts, bool tangent) const {
  if (!tangent) return;
  auto it = activeWatch_.find(key);
  if (it == activeWatch_.end()) {
    if (acts) activeWatch_[key].acts = true;
    return;
  }
  if (it->second.acts != acts) ++it->second.changes;
  it->second.acts = acts;
}

std::string AutomaticPenalty::failureHint(const Teuchos::Comm<int>& comm, const PointMap& points,
                                          bool frictional) const {
  std::string active = activeSetHint(comm, frictional);
  std::string friction = frictionHint(comm, points);
  if (active.empty() || friction.empty()) return active + friction;
  return active + "; " + friction;
}

std::string AutomaticPenalty::activeSetHint(const Teuchos::Comm<int>& comm, bool frictional) const {
  // Points that join and leave the active set back and forth within a Newton solve: many points
  // closing at once on beams soft against the contact's stiffness (generate grid's layers), where a
  // wrong active set makes Newton's steps far longer than the motion. Fixing the points that act for
  // each Newton solve, and changing them after it, as Lagrange multipliers do, gets through.
  // Or points that join and leave while the step bound (which stops a step where an open point
  // would pass its activation) shortens most steps to a crawl: the 32 x 32 layers, whose steps it cut
  // to 1e-4 of themselves.
  int local[3] = {static_cast<int>(activeWatch_.size()), 0, 0}, global[3] = {0, 0, 0};
  for (const auto& [key, w] : activeWatch_) {
    local[1] += w.changes >= kCyclingChanges;
    local[2] += w.changes >= 1;
  }
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 3, local, global);
  const bool cycling = global[1] >= 2 && global[1] >= global[0] / 8;
  const bool crawling = steps_ >= 10 && 2 * crawling_ >= steps_ && global[2] >= 2 && global[2] >= global[0] / 8;
  if (!cycling && !crawling) return "";
  std::ostringstream s;
  if (cycling)
    s << global[1] << " of " << global[0] << " contact points joined or left the active set " << kCyclingChanges
      << " times or more in this Newton solve (the active set changing within Newton's iterations)";
  else
    s << "the step bound shortened " << crawling_ << " of " << steps_ << " Newton steps to below " << kCrawlingBound
      << " of themselves while " << global[2] << " of " << global[0]
      << " contact points joined or left the active set (the active set changing within Newton's iterations)";
  const bool can = enforcer_.canFixActiveSet();
  if (cycling) ++cyclingFailures_;
  fixActive_ = can && (!frictional || cyclingFailures_ >= 2);
  if (fixActive_)
    s << "; the retry fixes the points that act for each Newton solve and changes them after it (as Penalty's "
         "Active Set = Between Solves does for a whole run)";
  else if (can)
    s << "; with friction the retry keeps Newton's own active set the first time and fixes the points that act for "
         "each Newton solve from the second (Active Set = Between Solves does it for a whole run)";
  return s.str();
}

std::string AutomaticPenalty::frictionHint(const Teuchos::Comm<int>& comm, const PointMap& points) const {
  // Slip directions that flip back and forth at many points: the friction force's jump across zero
  // slip is steeper than the beams can follow, and Newton cycles between mirror images.
  int local[2] = {static_cast<int>(frictionWatch_.size()), 0}, global[2] = {0, 0};
  for (const auto& [key, w] : frictionWatch_) local[1] += w.reversals >= kCyclingReversals;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 2, local, global);
  if (global[1] < 2 || global[1] < global[0] / 4) return "";
  std::ostringstream s;
  s << global[1] << " of " << global[0] << " slipping contact points reversed their friction force "
    << kCyclingReversals << " times or more in this Newton solve (slip directions cycling): the strategy's "
    << "tangential stiffness (Tangential Penalty Parameter, or Friction Complementarity Parameter with Lagrange "
       "multipliers) may be too stiff for these beams; a smaller value helps";
  // Points with parameters chosen from the compliance: relaxAfterFailure lowers them for the retry.
  const bool automatic =
      std::any_of(points.begin(), points.end(), [](const auto& kv) { return kv.second.compliance[0] > 0.0; });
  const bool steering = enforcer_.relaxesFrictionSteering();
  if ((automatic || steering) && relaxations_ < kMaxRelaxations) {
    cycling_ = true;
    if (automatic) s << "; the automatic Tangential Penalty Parameters are lowered tenfold for the retry";
    if (steering)
      s << "; the Friction Complementarity Parameter is lowered tenfold for the retry (it steers Newton's stick and "
           "slip guesses only: the solution does not depend on it)";
  }
  return s.str();
}

void AutomaticPenalty::relaxAfterFailure(PointMap& committed) {
  if (fixActive_) {
    enforcer_.fixActiveSet(true);
    for (auto& [key, p] : committed)
      if (!p.node()) enforcer_.engage(*p.state, p.result.active);
  }
  fixActive_ = false;
  if (cycling_) {
    ++relaxations_;
    for (auto& [key, p] : committed)
      if (p.compliance[0] > 0.0) handCompliance(p);
  }
  cycling_ = false;
}

void AutomaticPenalty::restore(core::CheckpointIn& in, double factor, int relaxations, int cyclingFailures) {
  relaxations_ = relaxations;
  cyclingFailures_ = cyclingFailures;
  // The tangential penalties are relaxed by a factor 10 each time (relaxAfterFailure), from 1.
  if (factor != tangentialRelaxationFactor(relaxations_))
    in.fail("its tangential relaxation factor " + core::shortest(factor) + " is not 10^" +
            std::to_string(relaxations_) + " (its count of relaxations)");
}

std::string AutomaticPenalty::warning() const {
  // (A strategy that relaxes its friction steering instead, Lagrange multipliers, has no penalties to
  // warn of: its solution does not depend on what was lowered.)
  if (relaxations_ == 0 || enforcer_.relaxesFrictionSteering()) return "";
  std::ostringstream s;
  s << "the automatic Tangential Penalty Parameters were lowered by a factor "
    << tangentialRelaxationFactor(relaxations_)
    << " after Newton solves failed with slip directions cycling: a sticking friction force may be off by more "
       "than the Tangential Target Error (by 1 / (1 + eps_T c_T) of it with the lowered eps_T, contact_points.csv "
       "gives each point's eps_T)";
  return s.str();
}

}  // namespace bc::constraints
