// Automatic penalty parameters: the points whose strategy state asks for it are handed the beams'
// compliance at the point (ConstraintEnforcer::setCompliance), from which the strategy chooses its
// parameters. When a Newton solve fails with slip directions cycling (friction forces reversing at
// many points, failureHint), the strategy is asked to relax its tangential law for the retry
// (ConstraintEnforcer::relaxTangential; the built-in strategies lower an automatic eps_T tenfold
// each time), at most kMaxRelaxations times; the run then warns.
#pragma once
#include <array>
#include <functional>
#include <map>
#include <string>

#include <Teuchos_Comm.hpp>

#include "ContactGeometry.hpp"
#include "LineContact.hpp"
#include "core/Checkpoint.hpp"
#include "core/Contribution.hpp"

namespace bc::constraints {

class AutomaticPenalty {
 public:
  AutomaticPenalty(const ConstraintEnforcer& enforcer, const LineContact& lines) : enforcer_(enforcer), lines_(lines) {}
  void useCompliance(core::ComplianceFunction compliance) { compliance_ = std::move(compliance); }

  // Hands the points whose strategy state waits for it the structure's compliance there (at the last
  // converged state `reference`, along the gaps' variations of `kinematics`); nothing before the
  // solver gave the compliance function.
  using Kinematics = std::function<ContactKinematics(const ContactPointRecord&)>;
  void giveCompliance(PointMap& points, const ContactGeometry& geometry, const Kinematics& kinematics);
  // Hands a point its compliance (setCompliance), or after relaxations the strategy relaxes its
  // tangential law from it (relaxTangential).
  void handCompliance(ContactPointRecord& p) const;

  // This rank's slipping points in the present Newton solve: compares a point's friction force at a
  // tangent assembly with the one before (a reversal counts); forgotten after a step or a failure.
  void watchFriction(const PointKey& key, const PointResult& r, bool tangent) const;
  void forgetFriction() {
    frictionWatch_.clear();
    activeWatch_.clear();
    steps_ = crawling_ = 0;
  }
  // The step bound of each Newton iteration (ContactManager::stepBound): how often it crawled.
  void watchBound(double bound) const {
    ++steps_;
    crawling_ += bound < kCrawlingBound;
  }
  // This rank's points in the present Newton solve: whether a point acts at a tangent assembly, against
  // the one before (a change counts; points that never acted are not kept).
  void watchActive(const PointKey& key, bool acts, bool tangent) const;
  // A point whose friction force reversed twice in the present Newton solve (a cycle) lets its strategy
  // take the secant of its friction in the tangent (ContactPoint::secantFriction) until
  // kSecantAssemblies tangent assemblies have passed without another reversal; then Newton's own
  // tangent finishes quadratically. (Measured on generate's layers and weave: after one reversal, the
  // 12 x 12 layers loaded in one increment with Automatic parameters stopped; after three, the 10 x 10
  // weave with Penalty; returning to Newton's tangent after 2 to 4 assemblies brought the reversals back
  // on the 16 x 16 layers; keeping the secant converged linearly, by 0.75 per iteration on 8 x 8.)
  // Whether a point takes it, and whether any of this rank's points does.
  bool secant(const PointKey& key) const {
    const auto it = frictionWatch_.find(key);
    return it != frictionWatch_.end() && it->second.secant();
  }
  // A point whose friction force reversed kHoldReversals times in the increment's Newton solves is
  // held in stick (ContactPoint::heldFriction) until release(key) (a converged state where its law
  // slips); once released it is not held again in the increment. Slip directions that cycle around
  // zero slip come from a stick zone (mu N / eps_T) far narrower than Newton's motions: a point with
  // a small normal force on soft beams, whose friction, applied, moves it further than the zone.
  bool held(const PointKey& key) const {
    const auto it = frictionWatch_.find(key);
    return it != frictionWatch_.end() && it->second.held;
  }
  void release(const PointKey& key) const {
    FrictionWatch& w = frictionWatch_[key];
    w.held = false;
    w.released = true;
  }
  bool anySecant() const {
    for (const auto& [key, w] : frictionWatch_)
      if (w.secant()) return true;
    return false;
  }
  // After a failed Newton solve: what the slip directions say, and whether the retry relaxes.
  // `frictional`: a pair has friction. The retry after the run's first failure whose points cycled
  // stays in Newton's own active set (measured: the 16 x 16 layers with friction 0.2, whose retries in
  // it complete, stopped with the points fixed); from the second such failure on, the retries fix them
  // (a rod pressed at its pinned ends onto a parallel one, its middle at gap 0: every cut in Newton's
  // own set failed).
  std::string failureHint(const Teuchos::Comm<int>& comm, const PointMap& points, bool frictional) const;
  // Its two parts: the active set, and the slip directions (each "" when they say nothing).
  std::string activeSetHint(const Teuchos::Comm<int>& comm, bool frictional) const;
  std::string frictionHint(const Teuchos::Comm<int>& comm, const PointMap& points) const;
  // Before the retry of a failed increment: lowers the automatic tangential parameters of the
  // committed points if failureHint found them cycling.
  void relaxAfterFailure(PointMap& committed);

  // The relaxation in checkpoints: its factor and count, and both read back (checked against each
  // other); then the count of failures whose points cycled.
  void save(core::CheckpointOut& out) const {
    out.real(tangentialRelaxationFactor(relaxations_)).integer(relaxations_).integer(cyclingFailures_);
  }
  void restore(core::CheckpointIn& in, double factor, int relaxations, int cyclingFailures);
  // The warning of a run whose parameters were lowered (empty: none).
  std::string warning() const;
  // Retries after slip directions cycled so far (each lowers automatic eps_T and the strategy's
  // friction steering tenfold).
  int relaxations() const { return relaxations_; }

 private:
  static constexpr int kMaxRelaxations = 6;
  static constexpr int kSecantReversals = 2;
  static constexpr int kSecantAssemblies = 6;
  static constexpr int kHoldReversals = 3;
  static constexpr int kCyclingReversals = 3;  // reversals of a point's friction force within a Newton solve
  static constexpr int kCyclingChanges = 2;  // changes of a point's acting within a Newton solve
  static constexpr double kCrawlingBound = 1e-2;  // a step bound this short crawls
  mutable int steps_ = 0, crawling_ = 0;
  struct ActiveWatch {
    bool acts = false;
    int changes = 0;
  };
  mutable std::map<PointKey, ActiveWatch> activeWatch_;
  mutable bool fixActive_ = false;  // failureHint: the retry fixes the active set for each Newton solve
  mutable int cyclingFailures_ = 0;  // failed Newton solves of the run whose points cycled (in checkpoints)
  struct FrictionWatch {
    std::array<double, 2> force{};
    int reversals = 0;
    int since = 0;  // tangent assemblies since the last reversal
    bool held = false, released = false;  // (released: not held again in the increment)
    bool secant() const { return reversals >= kSecantReversals && since < kSecantAssemblies; }
  };
  const ConstraintEnforcer& enforcer_;
  const LineContact& lines_;
  core::ComplianceFunction compliance_;
  int relaxations_ = 0;
  mutable bool cycling_ = false;
  mutable std::map<PointKey, FrictionWatch> frictionWatch_;
};

}  // namespace bc::constraints
