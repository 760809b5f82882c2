#include "ContactManager.hpp"

#include <algorithm>
#include <climits>
#include <functional>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Teuchos_CommHelpers.hpp>

#include "core/Checkpoint.hpp"
#include "core/Faults.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

using core::GlobalDof;

namespace {
// Gauss points of line contact that change sides within this fraction of the thinner section's inscribed
// radius of zero gap lie on the other beam: the cycling hint of acceptSolution.
constexpr double kLineCycleGap = 1e-3;
// A point that acts and went deeper within an increment by more than this many times its pair's thinner
// inscribed radius fails the increment (acceptSolution).
constexpr double kThroughSection = 1.0;
}  // namespace

ContactManager::ContactManager(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                               std::unique_ptr<ConstraintEnforcer> enforcer, ContactOptions options)
    : enforcer_(std::move(enforcer)),
      geometry_(std::move(beams), std::move(pairs), options,
                enforcer_->lineField() != ConstraintEnforcer::LineField::None && options.lineAngle > 0.0 &&
                    options.lineGaussPoints > 0),
      pointContact_(geometry_),
      lines_(geometry_, *enforcer_),
      search_(geometry_),
      set_(geometry_, *enforcer_, lines_),
      penalty_(*enforcer_, lines_),
      report_(geometry_, *enforcer_, lines_, penalty_) {
  geometry_.setNodalLineField(lines_.nodal());
}

std::map<PointKey, Candidate> ContactManager::detect(const core::State& s) const {
  return search_.detect(s, [&](int pi, int ea, int eb, long long visit, const CandidateOffer& offer) {
    if (geometry_.inLineContact(pi, ea, eb)) lines_.findPoints(pi, ea, eb, visit, s, set_.current(), offer);
    if (geometry_.inPointContact(pi, ea, eb)) pointContact_.findPoints(pi, ea, eb, visit, s, set_.current(), offer);
    pointContact_.findEndToEnd(pi, ea, eb, visit, s, set_.current(), offer);
  });
}

void ContactManager::initialize(core::State& state) {
  numNodes_ = state.numNodes();
  geometry_.setReference(state);
  lines_.setInitial(&state);
  const auto cands = detect(state);
  set_.current().clear();
  for (const auto& [key, c] : cands) {
    if (c.cp.gap < -1e-9 * std::max(1.0, c.cp.distance) && !geometry_.options().allowInitialPenetration) {
      const auto& pair = geometry_.pairs()[key.pair];
      const auto& beams = geometry_.beams().beams();
      std::ostringstream s;
      s << "beams \"" << beams[pair.beamA].name << "\" and \"" << beams[pair.beamB].name
        << "\" overlap at the start: gap " << c.cp.gap << " at (" << c.cp.pA[0] << ", " << c.cp.pA[1] << ", "
        << c.cp.pA[2] << "); move them apart or set \"Contact/Allow Initial Penetration\" to true";
      throw core::InputError(s.str());
    }
  }
  prepareIteration(state);
  search_.checkNoUnseenContact(state, true, enforcer_->type(),
                               [&](int pi, int ea, int eb) { return held(pi, ea, eb, state, false); });
  set_.commit();
}

bool ContactManager::prepareIteration(core::State& state) {
  ++iterate_;
  // A step starts from the refinement of the line field that its last converged points still need.
  if (resumeLevels_) lines_.resumeLevels(set_.current(), geometry_.reference());
  resumeLevels_ = false;
  const bool changed = set_.update(detect(state));
  giveUpIdle(state);
  // (Only a strategy with rows of its own at line nodes uses it: evaluateNode.)
  nodeCover_.clear();
  if (lines_.nodal() && enforcer_->lineNodeRows())
    for (const auto& [key, g] : lines_.nodeGaps(set_.current(), state)) nodeCover_[key] = g.full;
  penalty_.giveCompliance(set_.current(), geometry_,
                          [&](const Point& p) { return kinematics(p, state, Variations::First); });
  return set_.layoutMultipliers(state) || changed;
}

void ContactManager::giveUpIdle(const core::State& state) {
  // Multipliers whose rows carry nothing now have nothing to determine them: a line node whose Gauss
  // points left the other beam or carry no weight, a point contact whose blend weight is 0. They are
  // given up here (the state starts afresh); those that carry almost nothing are given up between
  // passes (acceptSolution), at the state the active set is judged at.
  const auto gaps =
      lines_.nodal() ? lines_.nodeGaps(set_.current(), state) : std::map<PointKey, LineContact::NodeGap>{};
  for (auto& [key, p] : set_.current()) {
    if (p.line() || enforcer_->multipliers(*p.state) == 0) continue;
    bool idle = false;
    if (p.node()) {
      const auto g = gaps.find(key);
      idle = g == gaps.end() || !(g->second.weight > 0.0);
    } else if (geometry_.blends(p.key.pair)) {
      idle = !(geometry_.blendWeightAt(p, state) > 0.0);
    }
    if (idle) p.state = PointStateHolder(p.node() ? enforcer_->newLineNodeState() : enforcer_->newPointState());
  }
}

std::vector<GlobalDof> ContactManager::blockDofs(const Point& p) const {
  const auto d = geometry_.pointDofs(p);
  std::vector<GlobalDof> dofs(d.begin(), d.end());
  for (int j = 0; j < p.extraCount; ++j) dofs.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + p.extraOffset + j);
  if (lines_.nodal() && p.line())
    for (const LineContact::FieldShare& n : lines_.fieldShares(p, p.xi, set_.current()))
      if (n.record)
        for (int j = 0; j < n.record->extraCount; ++j)
          dofs.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + n.record->extraOffset + j);
  return dofs;
}

const PointState* ContactManager::actingState(const Point& p) const {
  if (!(lines_.nodal() && p.line())) return &*p.state;
  return lines_.fieldState(p, set_.current());
}

ClosestPoints ContactManager::pointGeometry(const Point& p, const core::State& s, double* segment) const {
  return p.line() ? lines_.geometry(p, s, segment) : pointContact_.geometry(p, s);
}

ContactKinematics ContactManager::kinematics(const Point& p, const core::State& state, Variations order) const {
  return p.line() ? lines_.kinematics(p, state, order) : pointContact_.kinematics(p, state, order);
}

ContactKinematics ContactManager::judgedKinematics(const Point& p, const core::State& state) const {
  if (!p.line()) return kinematics(p, state, Variations::First);
  double segment = 0.0;
  const ClosestPoints cp = lines_.geometry(p, state, &segment);
  const PointState* acting = actingState(p);
  if (acting && enforcer_->contributes(cp.gap, *acting)) return kinematics(p, state, Variations::First);
  return lines_.values(p, cp, segment, state);
}

bool ContactManager::actsAt(const Point& p, const ContactKinematics& k) const {
  if (!p.line()) return true;
  const PointState* acting = actingState(p);
  return acting && enforcer_->contributes(k.normal.value, *acting);
}

bool ContactManager::evaluatesHere(const Point& p, const std::vector<GlobalDof>& dofs, const OwnsDof& owns) {
  // The rank of element A's first node or of element B's, alternating with the element pair: where
  // the two beams of a crossing lie on different ranks (layers, yarns), each rank takes about half
  // of the points. The choice depends only on the pair of elements, so a point keeps its rank (and
  // its rows in that rank's overlap of the matrix graph) while it lives.
  const unsigned mix = 2654435761u * static_cast<unsigned>(p.elementA) ^ static_cast<unsigned>(p.elementB);
  return owns(dofs[(mix >> 7) & 1u ? 12 : 0]);
}

std::vector<GlobalDof> ContactManager::nodeRows(const Point& p, const OwnsDof& owns) const {
  // A line node's own rows (a strategy's regularization of its multipliers), on the rank that owns
  // the node (connectivity and evaluate agree on it before and after the multipliers have owners).
  std::vector<GlobalDof> dofs;
  if (!(lines_.nodal() && p.node() && enforcer_->lineNodeRows())) return dofs;
  if (!owns(GlobalDof(core::kDofsPerNode) * lines_.fieldHome(p.key.node))) return dofs;
  for (int j = 0; j < p.extraCount; ++j) dofs.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + p.extraOffset + j);
  return dofs;
}

void ContactManager::connectivity(const OwnsDof& owns, std::vector<std::vector<GlobalDof>>& blocks) const {
  for (const auto& [key, p] : set_.current()) {
    if (p.node()) {
      const auto rows = nodeRows(p, owns);
      if (!rows.empty()) blocks.push_back(rows);
      continue;
    }
    const auto d = blockDofs(p);
    if (evaluatesHere(p, d, owns)) blocks.push_back(d);
  }
}

void ContactManager::evaluateNode(const Point& p, const std::vector<GlobalDof>& d, const core::State& state,
                                  core::AssemblySink& sink, bool tangent) const {
  const int n = static_cast<int>(d.size());
  std::vector<double> f(n, 0.0), K(tangent ? std::size_t(n) * n : 0, 0.0);
  const ContactKinematics none;
  // A strategy's own rows of a node (Augmented Lagrange's -L (lambda - lambda_hat) / eps_N) take the
  // length of line the node's Gauss points cover, int N_a ds over the pieces the other beam covers,
  // at the iterate (prepareIteration; held through its Newton step). With the node's whole share of
  // its beam instead, a node whose parts B covers over a fraction f had the law lambda = lambda_hat +
  // f eps_N g, and Augmented Lagrange ran out of passes (rectangles lying parallel, B's clamped end
  // 6e-6 of an element past A's node: 2e-4 deep after 50 passes).
  double length = lines_.fieldLength(p.key);
  const auto cover = nodeCover_.find(p.key);
  if (cover != nodeCover_.end() && cover->second > 0.0) length = std::min(length, cover->second);
  enforcer_->evaluateLineNode(lines_.nodeView(p, none, state), *p.state, length, f.data(),
                              tangent ? K.data() : nullptr);
  sink.add(d.data(), n, f.data(), tangent ? K.data() : nullptr);
}

void ContactManager::evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink,
                              bool tangent) const {
  std::vector<double> f, K;
  for (const auto& [key, p] : set_.current()) {
    // A line node's rows come from its Gauss points, and some strategies add rows of its own.
    if (p.node()) {
      const auto rows = nodeRows(p, owns);
      if (!rows.empty()) evaluateNode(p, rows, state, sink, tangent);
      continue;
    }
    const auto d = blockDofs(p);
    if (!evaluatesHere(p, d, owns)) continue;
    // The full kinematics (with their derivatives) only where the point acts.
    const PointState* acting = actingState(p);
    // (Whether it acts, against the last tangent assembly's: failureHint.)
    const bool acts =
        acting && enforcer_->contributes(pointGeometry(p, state).gap, *acting) && !geometry_.carriesNothing(p, state);
    penalty_.watchActive(key, acts, tangent && !quietEvaluation_);
    if (!acts) continue;
    // (A residual alone needs the first variations: the second ones, by nested AD for line points,
    // cost most of a line contact's evaluation.)
    const ContactKinematics k = kinematics(p, state, tangent ? Variations::Second : Variations::First);
    const int n = static_cast<int>(d.size());
    if (lines_.nodal() && p.line()) {
      if (!lines_.evaluateNodal(p, k, state, set_.current(), f, tangent ? &K : nullptr, nullptr)) continue;
    } else {
      f.assign(n, 0.0);
      K.assign(std::size_t(n) * n, 0.0);
      // (A slipping point's friction force is compared with the last tangent assembly's: failureHint.)
      // (Its secant while its friction force cycles, AutomaticPenalty::secant: not in the model's response
      // for a coupled step, quiet, which every rank computes for every point.)
      ContactPoint view = strategyView(p, k, state);
      view.secantFriction = !quietEvaluation_ && penalty_.secant(key);
      view.heldFriction = !quietEvaluation_ && enforcer_->holdsFriction() && penalty_.held(key);
      penalty_.watchFriction(key, enforcer_->evaluate(view, *p.state, f.data(), tangent ? K.data() : nullptr),
                             tangent && !quietEvaluation_);
    }
    // Weighted by the blend between point and line contact (w(u), its gradient in the tangent:
    // K <- w K + f (x) grad w) and, for a line point, by the length it stands for (which moves with
    // its segment's bounds).
    Vector24 gradient;
    double w = geometry_.blendWeight(p, k.axesCosine, k.axesCosineR.data(), &gradient);
    if (p.line()) {
      const double length = lines_.weight(p, k.segment), perSegment = lines_.weightRate(p);
      for (int i = 0; i < kPairDofs; ++i) gradient[i] = gradient[i] * length + w * perSegment * k.segmentR[i];
      w *= length;
    }
    if (tangent)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          K[std::size_t(n) * i + j] = w * K[std::size_t(n) * i + j] + (j < kPairDofs ? f[i] * gradient[j] : 0.0);
    for (double& v : f) v *= w;
    sink.add(d.data(), n, f.data(), tangent ? K.data() : nullptr);
  }
}

std::string ContactManager::failureHint(const Teuchos::Comm<int>& comm) const {
  const auto& pairs = geometry_.pairs();
  const bool frictional = std::any_of(pairs.begin(), pairs.end(), [](const auto& pair) { return pair.friction > 0.0; });
  return penalty_.failureHint(comm, set_.current(), frictional);
}

bool ContactManager::held(int pi, int ea, int eb, const core::State& state, bool penetrating) const {
  const auto& elems = geometry_.beams().elements();
  // (The pair's points only: every overlap check asks per element pair, and all the points' map
  // each time made the checks grow with the square of the points.)
  const PointMap& points = set_.current();
  for (auto it = points.lower_bound(PointKey::first(pi)); it != points.end() && it->first.pair == pi; ++it) {
    const Point& p = it->second;
    const auto [onA, onB] = geometry_.pairElements(p);
    if (std::abs(elems[onA].index - elems[ea].index) > 1 || std::abs(elems[onB].index - elems[eb].index) > 1) continue;
    if (p.node()) continue;
    // (A point of a blended pair whose weight is zero now carries nothing, as in the assembly: the
    // line points of a narrow rectangle whose elements turned by 2 degrees against the wide one's
    // in one Newton step, where no edges cross for point contact, held the overlap as "seen" while
    // the run ended "complete" with the narrow beam 2.1 inside the other and no force.)
    if (geometry_.carriesNothing(p, state)) continue;
    const PointState* acting = actingState(p);
    // (Seeing needs the gap's value only: a point that acts, or one that penetrates, whose strategy
    // has not taken it up yet, as Lagrange's points at the start.)
    if (!penetrating) {
      // (A line point deeper than kDeep of the thinner section's inscribed radius that no
      // multiplier or law takes up sees nothing: the active set accepted it, and the beams would pass
      // through each other with no force. Two face-to-face cantilevers loaded in one large increment
      // ended "complete" with the rod 29 % of its inscribed radius inside the other, no contact force.)
      const double gap = pointGeometry(p, state).gap;
      const bool takenUp = acting && enforcer_->contributes(gap, *acting);
      if (takenUp || (gap <= 0.0 && !(p.line() && gap < -kDeep * geometry_.thinner(pi)))) return true;
      continue;
    }
    if (!acting) continue;
    const ContactKinematics k = kinematics(p, state, Variations::First);
    if (enforcer_->contributes(k.normal.value, *acting) && k.normal.value < 0.0) return true;
  }
  return false;
}

ContactKinematics ContactManager::judge(const PointKey& key, const Point& p, const core::State& state,
                                        const std::map<PointKey, LineContact::NodeGap>& gaps, bool& carries) const {
  ContactKinematics k;
  if (p.node()) {
    const auto g = gaps.find(key);
    carries = g != gaps.end() && g->second.weight > kCarries * g->second.full;
    if (carries) {
      k.normal.value = g->second.weighted;
      k.tangent1.value = g->second.weightedAcross;
      k.tangent2.value = g->second.weightedSlip;
    }
    return k;
  }
  k = judgedKinematics(p, state);
  // (A line point on a sliver of a segment carries almost nothing either.)
  carries = !(lines_.nodal() && p.line()) && geometry_.blendWeight(p, k.axesCosine, nullptr, nullptr) > kCarries &&
            (!p.line() || k.segment > kCarries);
  return k;
}

bool ContactManager::acceptSolution(core::State& state) {
  ++passes_;
  worstViolation_ = 0.0;
  bool all = true;
  // A point whose blend weight is at most kCarries carries (almost) nothing: the strategy does not judge it.
  // With a nodal line field the line nodes are judged, on their weighted gaps, not the Gauss points.
  std::vector<bool> carries;
  const auto gaps =
      lines_.nodal() ? lines_.nodeGaps(set_.current(), state) : std::map<PointKey, LineContact::NodeGap>{};
  const auto judged = [&](const PointKey& key, const Point& p, bool& carriesHere) {
    return judge(key, p, state, gaps, carriesHere);
  };
  const auto view = [&](const Point& p, const ContactKinematics& k) {
    return p.node() ? lines_.nodeView(p, k, state) : strategyView(p, k, state);
  };
  carries.reserve(set_.current().size());
  // Gauss points of line contact with a law of their own whose normal state changed in this pass: how
  // many, per pair, and the largest of their gaps against the pair's thinner inscribed radius.
  std::map<int, std::pair<int, double>> switchedLine;
  // Passes that cycle (a strategy of discrete states: the same points changing as in an earlier pass
  // of the increment, e.g. the edge points of Example 1's rectangles with friction 1.0 sliding one way,
  // sticking, sliding the other way across B's edges, each change of all of them at once driving
  // the next) change one point's stick or slip per pass from then on, the first in key order (the
  // least-index rule that ends cycling in pivoting methods). The normal stage still changes every
  // point at once: one activation per pass let a column's end pushed through a beam in one increment
  // end "complete" with its end point gone.
  if (passes_ == 1) {
    changeSets_.clear();
    cycleFrom_ = 0;
  }
  const bool oneAtATime = cycleFrom_ > 0 && enforcer_->discreteStates();
  std::pair<double, const Point*> deepest{kThroughSection, nullptr};
  std::vector<PointKey> changed;
  int stage = 0;
  for (auto& [key, p] : set_.current()) {
    bool carriesHere = false;
    const ContactKinematics k = judged(key, p, carriesHere);
    carries.push_back(carriesHere);
    if (carriesHere) {
      // (the point that acts and went deepest within the increment, against its pair's thinner section)
      if (!p.node() && -k.normal.value > deepest.first * geometry_.thinner(key.pair)) {
        const auto c = set_.committed().find(key);
        const double before =
            c != set_.committed().end() && c->second.result.active ? std::max(0.0, -c->second.gap) : 0.0;
        const double deeper = (-k.normal.value - before) / geometry_.thinner(key.pair);
        if (deeper > deepest.first && enforcer_->contributes(k.normal.value, *p.state)) deepest = {deeper, &p};
      }
      const bool settled = enforcer_->acceptNormal(view(p, k), *p.state);
      if (!settled) changed.push_back(key);
      if (!settled && p.line() && !lines_.nodal()) {
        auto& [count, largest] = switchedLine[key.pair];
        ++count;
        largest = std::max(largest, std::abs(k.normal.value) / geometry_.thinner(key.pair));
      }
      all = settled && all;
    } else if (!p.line() && enforcer_->multipliers(*p.state) > 0) {
      // Multipliers of a point or line node that carries (almost) nothing: given up.
      p.state = PointStateHolder(p.node() ? enforcer_->newLineNodeState() : enforcer_->newPointState());
      all = false;
    }
  }
  if (all) {
    stage = 1;
    std::size_t i = 0;
    for (auto& [key, p] : set_.current()) {
      if (carries[i] && !(oneAtATime && !changed.empty())) {
        bool carriesHere = false;
        const ContactKinematics k = judged(key, p, carriesHere);
        const bool settled = enforcer_->acceptPoint(view(p, k), *p.state, worstViolation_);
        if (!settled) changed.push_back(key);
        all = settled && all;
      }
      ++i;
    }
  }
  if (!changed.empty() && cycleFrom_ == 0 && enforcer_->discreteStates() && !changeSets_.emplace(stage, changed).second)
    cycleFrom_ = passes_ + 1;
  // Friction held in stick (AutomaticPenalty::held) where the law slips at this converged state: let go,
  // and Newton goes on; such a pass does not count against the strategy's limit (each point is held
  // once per increment).
  if (all && releaseHeld(state)) {
    all = false;
    ++gatePasses_;
  }
  // Element pairs whose angle at this converged state calls for line points or point contacts that
  // their angle at the last converged state did not (turned past the margins within the increment)
  // get them for the rest of the increment (ContactGeometry::openGates), and Newton goes on from here
  // with them; such a pass does not count against the strategy's limit (Penalty's is 1). (Opened at
  // every iterate instead, the rod pressed at its pinned ends onto a parallel ground, rectangles with
  // Penalty's springs on the nodes, gathered point contacts from the iterates' passing angles and its
  // passes cycled.)
  if (all && geometry_.lineContact() && geometry_.openGates(search_.candidates(state), state) > 0) {
    all = false;
    ++gatePasses_;
  }
  // An end point of a blended pair whose closest point lies beyond its element's node at a converged
  // state (kept there by the search's hysteresis, found there at an earlier iterate) goes to the
  // neighbour that holds it, once per increment, and Newton goes on: its blend weight is its
  // element's angle, which differs on the two sides of a bent node, so the side it was found on
  // decided the answer. (B's clamped ends 0.02 past A's node pressing on the parallel 2 x 1 rectangles:
  // Penalty 0.35019 with 10 increments, 0.34558 with 1 and 5.)
  if (all && geometry_.lineContact()) {
    bool handed = false;
    for (const auto& [key, p] : set_.current()) {
      if (!key.end() || key.endToEnd() || !geometry_.blends(key.pair) || pointContact_.handedOver(key)) continue;
      const double eta = pointGeometry(p, state).eta;
      const auto& e = geometry_.beams().elements()[p.elementB];
      const int last = static_cast<int>(geometry_.beams().beams()[e.beam].nodes.size()) - 2;
      if (!((eta < 0.0 && e.index > 0) || (eta > 1.0 && e.index < last))) continue;
      pointContact_.handOver(key);
      handed = true;
    }
    if (handed) {
      all = false;
      ++gatePasses_;
    }
  }
  // A point that acts and went deeper within the increment than its pair's thinner section reaches (a
  // step that carried one beam into the other, held there by the normal its point keeps) is not where
  // the load path leads: the increment fails and is cut. (Example 1 with 20 elements per beam,
  // frictionless, Penalty on 5 increments ended "complete" with beam 2 7.5 into beam 1, three times
  // its section's inscribed radius, and a contact force of 6e5 against 907 with 10 increments: warned
  // only.) A soft penalty that lets the beams in that deep over several increments is the law's
  // answer: warned (ContactReport::noteDepth).
  if (all && deepest.second) {
    const Point& p = *deepest.second;
    const auto& pair = geometry_.pairs()[p.key.pair];
    const ClosestPoints cp = pointGeometry(p, state);
    const Vec3d at = geometry_.touching(p, cp);
    std::ostringstream s;
    s << "beams \"" << geometry_.beams().beams()[pair.beamA].name << "\" and \""
      << geometry_.beams().beams()[pair.beamB].name << "\" penetrated each other by " << -cp.gap << " near (" << at[0]
      << ", " << at[1] << ", " << at[2] << "), " << deepest.first
      << " times the thinner section's inscribed radius deeper than at the last converged step, where a contact point "
         "acts: a step that carried one beam into the other (smaller increments help; if it persists, raise the "
         "Normal Penalty Parameter)";
    throw std::runtime_error(s.str());
  }
  if (all) {
    search_.checkNoPassThrough(state, [&](int pi, int ea, int eb) { return held(pi, ea, eb, state); });
    search_.checkNoUnseenContact(state, false, enforcer_->type(),
                                 [&](int pi, int ea, int eb) { return held(pi, ea, eb, state, false); });
  }
  // On a converged active set, a nodal field that does not resolve a contact zone (the beams
  // penetrate between its nodes) is refined there, and Newton goes on with the finer field.
  if (all && lines_.nodal() && lines_.refineField(set_.current(), state)) all = false;
  if (passes_ == 1) violations_.clear();
  violations_.push_back(worstViolation_);
  if (!all && passes_ - gatePasses_ >= enforcer_->maximumPasses()) {
    std::ostringstream s;
    // (The violation can be 0 here: a pass ends on any change, of the active set, of stick and slip,
    // of an augmentation or of the field's refinement, so the last pass may have met every gap and
    // still changed a state: the states cycle.)
    s << enforcer_->type() << ": constraints not met after " << passes_
      << " passes (the strategy's limit): the last pass still changed the active set, stick and slip, an "
         "augmentation or the line field's refinement (largest gap violation "
      << worstViolation_ << (worstViolation_ > 0.0 ? ")" : ": the states cycle)");
    if (!changed.empty())
      s << "; the last pass changed " << changed.size() << (changed.size() == 1 ? " point's " : " points' ")
        << (stage == 0                    ? "contact state (active or not)"
            : enforcer_->discreteStates() ? "stick or slip"
                                          : "stick, slip or augmentation");
    if (cycleFrom_ > 0)
      s << "; the passes repeated an earlier pass's changes, and from pass " << cycleFrom_
        << " one point's stick or slip changed per pass";
    // Springs at Gauss points on beams lying on each other: their gaps sit near 0 along the line, and
    // more springs per element than the elements' bending can follow (a penalty's bending wavelength
    // shorter than the elements) over-constrain it, so which of them act cycles from pass to pass.
    for (const auto& [pair, changed] : switchedLine)
      if (changed.second <= kLineCycleGap)
        s << "; " << changed.first << " Gauss points of line contact of pair \"" << geometry_.pairs()[pair].name
          << "\" changed sides in the last pass at gaps within " << changed.second
          << " of the thinner section's inscribed radius of zero (the beams lie on each other along the line, and a "
             "spring at every Gauss point over-constrains elements that bend less finely): use Lagrange Multiplier "
             "or Augmented Lagrange (a constraint per node of the line), fewer Contact/Line Gauss Points or a "
             "smaller Normal Penalty Parameter, or springs on the line's nodes "
             "(Contact/Enforcement/Penalty/Line Springs = Nodes: a force concentrated at a beam's end is then "
             "resolved only as finely as the elements there)";
    throw std::runtime_error(s.str());
  }
  return all;
}

bool ContactManager::releaseHeld(const core::State& state) {
  if (!enforcer_->holdsFriction()) return false;
  int released = 0;
  for (const auto& [key, p] : set_.current()) {
    if (!penalty_.held(key)) continue;
    const ContactKinematics k = kinematics(p, state, Variations::First);
    const PointResult r = enforcer_->reportedForces(strategyView(p, k, state), *p.state);
    if (!(r.active && (r.slip[0] || r.slip[1]))) continue;
    penalty_.release(key);
    ++released;
  }
  if (comm_) {
    int any = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, 1, &released, &any);
    released = any;
  }
  return released > 0;
}

namespace {
// Solves the m x m system D x = b (row-major D, b overwritten by x) by Gaussian elimination with
// partial pivoting; false when D is not regular enough: a pivot below 1e-12 of the largest diagonal
// entry, a diagonal entry not positive, or x not finite.
bool solvePositiveDiagonal(std::vector<double>& D, std::vector<double>& b) {
  const std::size_t m = b.size();
  double scale = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    if (!(D[j * m + j] > 0.0) || !std::isfinite(D[j * m + j])) return false;
    scale = std::max(scale, D[j * m + j]);
  }
  for (std::size_t c = 0; c < m; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < m; ++r)
      if (std::abs(D[r * m + c]) > std::abs(D[pivot * m + c])) pivot = r;
    if (!(std::abs(D[pivot * m + c]) > 1e-12 * scale)) return false;
    if (pivot != c) {
      for (std::size_t j = 0; j < m; ++j) std::swap(D[c * m + j], D[pivot * m + j]);
      std::swap(b[c], b[pivot]);
    }
    for (std::size_t r = c + 1; r < m; ++r) {
      const double f = D[r * m + c] / D[c * m + c];
      for (std::size_t j = c; j < m; ++j) D[r * m + j] -= f * D[c * m + j];
      b[r] -= f * b[c];
    }
  }
  for (std::size_t c = m; c-- > 0;) {
    for (std::size_t j = c + 1; j < m; ++j) b[c] -= D[c * m + j] * b[j];
    b[c] /= D[c * m + c];
    if (!std::isfinite(b[c])) return false;
  }
  return true;
}
}  // namespace

bool ContactManager::coupleStep(core::State& state, std::vector<double>& du, bool near) {
  const int limit = enforcer_->maximumCoupledConstraints();
  if (limit <= 0 || !response_ || responseFailed_) return false;
  // The constraints (ConstraintEnforcer::coupledConstraints) of the points that act, with their
  // signature (point, gap, sliding directions); near the solution also each constraint's gap
  // predicted after the step (g + gradient . du), its gradient (row) and the residual's derivative
  // with respect to its estimate (column).
  struct Entry {
    PointState* state;
    ConstraintEnforcer::CoupledConstraint c[3];
    int n;
  };
  std::vector<Entry> entries;
  std::vector<std::array<long long, 5>> signature;
  std::vector<core::SparseLoad> rows, columns;
  std::vector<double> delta;
  for (auto& [key, p] : set_.current()) {
    if (p.line() || p.node()) return false;  // line contact's field: unknowns of the system already
    const PointState* acting = actingState(p);
    if (!acting || !enforcer_->contributes(pointGeometry(p, state).gap, *acting)) continue;
    const ContactKinematics k = kinematics(p, state, Variations::First);
    const ContactPoint view = strategyView(p, k, state);
    if (!(view.weight > 0.0)) continue;  // a blended point that carries nothing now
    Entry e{&*p.state, {}, 0};
    e.n = enforcer_->coupledConstraints(view, *p.state, e.c);
    if (e.n == 0) continue;
    if (static_cast<int>(signature.size()) + e.n > limit) return false;
    entries.push_back(e);
    const auto code = key.code();
    const auto dofs = geometry_.pointDofs(p);
    const GapDerivatives* gaps[3] = {&k.normal, &k.tangent1, &k.tangent2};
    for (int j = 0; j < e.n; ++j) {
      const auto sign = [&](int l) { return (e.c[j].force[l] > 0.0) - (e.c[j].force[l] < 0.0); };
      signature.push_back({code[0], code[1], code[2], e.c[j].gap, sign(1) + 3 * sign(2)});
      if (!near) continue;
      const GapDerivatives& g = *gaps[e.c[j].gap];
      core::SparseLoad row, column;
      row.dofs.assign(dofs.begin(), dofs.end());
      column.dofs = row.dofs;
      column.values.assign(dofs.size(), 0.0);
      double predicted = g.value;
      // The gap moves along its gradient; the estimate's force acts along the variations R (they differ
      // where a point's place or slip metric is held: ends, ContactKinematics.hpp).
      for (std::size_t d = 0; d < dofs.size(); ++d) {
        row.values.push_back(g.gradient[d]);
        predicted += g.gradient[d] * du[dofs[d]];
        // The manager weights the point's residual by its blend weight: so does the estimate's share.
        for (int l = 0; l < 3; ++l) column.values[d] += view.weight * e.c[j].force[l] * gaps[l]->R[d];
      }
      rows.push_back(std::move(row));
      columns.push_back(std::move(column));
      delta.push_back(predicted);
    }
  }
  if (signature.empty()) return false;
  // Only once the constraints have settled: the same points, gaps and sliding directions at the last
  // iterate (while contacts still open, close, stick or slip, a step coupled on this iterate's set
  // moves estimates the next iterate drops or lacks; measured: the 16 x 16 grid's first contact
  // stalled).
  const bool settled = signatureIterate_ == iterate_ - 1 && signature == signature_;
  signature_ = std::move(signature);
  signatureIterate_ = iterate_;
  if (!settled || !near) return false;
  // Not while a sliding point takes its friction's secant in Newton's tangent (its force cycled in
  // this solve): the response below would differ from Newton's matrix there, and each rank knows only
  // its own points' reversals.
  int reversed = penalty_.anySecant() ? 1 : 0;
  if (comm_) {
    int any = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, 1, &reversed, &any);
    reversed = any;
  }
  if (reversed) return false;
  // The model's response, the same on every rank (each factors its own copy on several ranks: they
  // decide together, and the evaluation does not count as a Newton iterate's for the friction watch).
  core::ModelResponse response;
  int ok = 1;
  try {
    quietEvaluation_ = true;
    response = response_(state, rows, columns);
  } catch (const std::runtime_error&) {
    ok = 0;
  }
  quietEvaluation_ = false;
  if (comm_) {
    int all = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, 1, &ok, &all);
    ok = all;
  }
  if (!ok) {
    responseFailed_ = true;  // a singular tangent: the augmentations wait for the passes in this increment
    return false;
  }
  // D delta = g + gradient . du, D_ij = gradient_i^T K^-1 F_j: each estimate must move its own gap
  // (D_jj > 0) and D must be regular.
  if (!solvePositiveDiagonal(response.D, delta)) return false;
  // The estimates move by delta, the motion by -K^-1 F delta.
  std::size_t j = 0;
  for (const Entry& e : entries) {
    enforcer_->coupledUpdate(*e.state, e.c, e.n, &delta[j]);
    j += e.n;
  }
  for (std::size_t c = 0; c < delta.size(); ++c)
    for (std::size_t d = 0; d < du.size() && d < response.motion[c].size(); ++d)
      du[d] -= delta[c] * response.motion[c][d];
  return true;
}

void ContactManager::commitPoint(Point& p, const core::State& state) {
  ContactKinematics k = judgedKinematics(p, state);
  if (lines_.nodal() && p.line()) {
    const ContactPoint view = strategyView(p, k, state);
    std::vector<double> f;
    p.result = PointResult{};
    lines_.evaluateNodal(p, k, state, set_.current(), f, nullptr, &p.result);
    // (As its field node's, whose view carries the field's compliance there.)
    const ContactPointRecord* host = lines_.fieldHost(p, set_.current());
    ContactPoint hosted = view;
    if (host) hosted.fieldCompliance = lines_.fieldCompliance(host->key);
    p.outputs = host ? enforcer_->outputValues(hosted, *host->state)
                     : std::vector<double>(enforcer_->outputColumns().size(), 0.0);
  } else {
    // The forces the residual applied at this state, so that the table and VTK report them. A point
    // the strategy judged in the last pass reports what the strategy says it applied (Augmented
    // Lagrange: its multipliers, updated to the applied force by that pass); a point it did not judge
    // (one that carries almost nothing: judge()) kept its state, and its force is its evaluation
    // (before: Augmented Lagrange reported such a point's stale multipliers, 0 for a new one). A line
    // point of a per-point strategy judged by its values alone (its strategy's contributes() false at
    // its gap now) may still have applied a force: a law with an estimate per point, updated by the
    // last pass, acts at a small positive gap (lambda_hat + eps_N g_N < 0 before that update); it
    // reports it and gets its first variations too, so its force vectors below are the applied ones
    // (before: zero vectors).
    const bool judged =
        geometry_.blendWeight(p, k.axesCosine, nullptr, nullptr) > kCarries && (!p.line() || k.segment > kCarries);
    const auto applied = [&] {
      const ContactPoint view = strategyView(p, k, state);
      if (judged) return enforcer_->reportedForces(view, *p.state);
      if (!enforcer_->contributes(k.normal.value, *p.state)) return PointResult{};
      std::vector<double> f(kPairDofs + enforcer_->multipliers(*p.state), 0.0);
      return enforcer_->evaluate(view, *p.state, f.data(), nullptr);
    };
    p.result = applied();
    if (p.line() && p.result.active && !actsAt(p, k)) {
      k = kinematics(p, state, Variations::First);
      p.result = applied();
    }
    const ContactPoint view = strategyView(p, k, state);
    p.outputs = enforcer_->outputValues(view, *p.state);
    enforcer_->commitPoint(view, *p.state);
  }
  // Reported as applied: times the blend weight and, for a line point, its length.
  p.length = p.line() ? lines_.weight(p, k.segment) : 0.0;
  const double w = geometry_.blendWeight(p, k.axesCosine, nullptr, nullptr) * (p.line() ? p.length : 1.0);
  p.result.lambdaN *= w;
  for (double& t : p.result.lambdaT) t *= w;
  if (w == 0.0) p.result.active = false;
  lines_.noteCommitted(p, k, state);
  p.gap = k.normal.value;
  const ClosestPoints cp = pointGeometry(p, state);
  if (p.result.active) report_.noteDepth(p, cp);
  p.position = geometry_.touching(p, cp);
  if (p.result.active && !p.line() && !p.end()) {
    double initialKink = 0.0;
    const double rival =
        pointContact_.rivalAngle(p, cp, state, kRivalGap * geometry_.thinner(p.key.pair), &initialKink);
    report_.noteRival(p, rival, initialKink);
  }
  // A point with swapped roles (an edge of the pair's B on A's face) reports as the pair's: its normal
  // from the pair's A to B, its force on the pair's B (the gaps do not change under a rigid
  // translation, so the translations' rows of its residual sum to zero: the force on its own beam A,
  // the pair's B, is minus that on its own B).
  const double roles = geometry_.swapped(p) ? -1.0 : 1.0;
  p.normal = roles * cp.normal;
  // The force on beam B is what the multipliers apply through the residual lambda_q R_q on B's
  // nodal translations (dofs 12-14 and 18-20), with the opposite sign (the residual holds the
  // internal side): the normal force lambda_N R_N, the tangential one lambda_T1 R_T1 + lambda_T2 R_T2.
  // (Each kernel's unit multipliers apply the normal and two tangent vectors on B. Split along the
  // normal of the converged projection instead, a rectangle's face point leaked up to 5.3e-6 of its
  // normal force into the tangential part where the beams bend: 1.0000053 mu N reported on the cone.)
  const GapDerivatives* g[3] = {&k.normal, &k.tangent1, &k.tangent2};
  const double lam[3] = {p.result.lambdaN, p.result.lambdaT[0], p.result.lambdaT[1]};
  Vec3d parts[2] = {};
  for (int q = 0; q < 3; ++q)
    for (int a = 0; a < 3; ++a) parts[q > 0][a] -= roles * lam[q] * (g[q]->R[12 + a] + g[q]->R[18 + a]);
  p.normalForce = parts[0];
  p.tangentialForce = parts[1];
  // (Under the per-line law each line's force is bounded, and their vector sum may reach sqrt(2) mu N.)
  if (p.result.active && (p.line() || geometry_.options().frictionLaw == FrictionLaw::IsotropicCoulomb))
    report_.noteCone(p, geometry_.pairs()[p.key.pair].friction);
  p.xiPrev = geometry_.beamCoordinate(p.elementA, k.xi);
  p.etaPrev = geometry_.beamCoordinate(p.elementB, k.eta);
  if (p.line() || p.end()) p.etaRate = cp.etaRate;
  if (p.key.endToEnd()) p.across2 = cp.across2;
}

void ContactManager::commitStep(const core::State& state) {
  penalty_.forgetFriction();
  enforcer_->fixActiveSet(false);  // (a failed increment's retries only: AutomaticPenalty::relaxAfterFailure)
  responseFailed_ = false;
  const auto gaps =
      lines_.nodal() ? lines_.nodeGaps(set_.current(), state) : std::map<PointKey, LineContact::NodeGap>{};
  for (auto& [key, p] : set_.current()) {
    if (!p.node()) {
      commitPoint(p, state);
      continue;
    }
    // A line node: its multipliers (reported through its Gauss points).
    ContactKinematics k;
    const auto g = gaps.find(key);
    if (g != gaps.end()) {
      k.normal.value = g->second.weighted;
      k.tangent1.value = g->second.weightedAcross;
      k.tangent2.value = g->second.weightedSlip;
    }
    const ContactPoint view = lines_.nodeView(p, k, state);
    p.result = enforcer_->reportedForces(view, *p.state);
    p.outputs = enforcer_->outputValues(view, *p.state);
    enforcer_->commitPoint(view, *p.state);
    p.gap = k.normal.value;
    p.position = lines_.fieldPosition(p.key.node, state);
  }
  lines_.checkResolution(set_.current(), state);
  lines_.stepCommitted();
  set_.commit();
  // The next step's field: at its first iteration (until then the field stays as the matrix graph
  // has it), whose update of the points drops the interior nodes no longer needed.
  resumeLevels_ = true;
  geometry_.setReference(state);
  lastPasses_ = passes_;
  passes_ = 0;
  gatePasses_ = 0;
  pointContact_.clearHandedOver();
}

void ContactManager::saveCommitted(core::CheckpointOut& out) const {
  out.label("contact")
      .word(enforcer_->type())
      .integer(static_cast<long long>(set_.committed().size()))
      .integer(lastPasses_);
  penalty_.save(out);
  set_.save(out);
}

void ContactManager::loadCommitted(core::CheckpointIn& in, const core::State& committed) {
  in.label("contact");
  if (in.word() != core::CheckpointOut::token(enforcer_->type()))
    in.fail("it was written with another enforcement strategy");
  const long long n = in.integer();
  const long long lastPasses = in.integer();
  const double relaxation = in.real();
  const long long relaxations = in.integer();
  const long long cycling = in.integer();
  if (n < 0 || lastPasses < 0 || lastPasses > INT_MAX || relaxations < 0 || relaxations > INT_MAX || cycling < 0 ||
      cycling > INT_MAX)
    in.fail("its contact counters are negative or too large (points " + std::to_string(n) + ", passes " +
            std::to_string(lastPasses) + ", relaxations " + std::to_string(relaxations) + ", cycling failures " +
            std::to_string(cycling) + ")");
  lastPasses_ = static_cast<int>(lastPasses);
  penalty_.restore(in, relaxation, static_cast<int>(relaxations), static_cast<int>(cycling));
  geometry_.setFrictionRelaxation(tangentialRelaxationFactor(penalty_.relaxations()));
  set_.load(in, n, committed);
  geometry_.setReference(committed);
  // (The line-contact warnings are not in the checkpoint: they are renewed from the steps that
  // follow, and the frictionless one also from the restored points.)
  lines_.noteRestored(set_.committed());
  lines_.clearLevels();
  resumeLevels_ = true;
  passes_ = 0;
  gatePasses_ = 0;
  pointContact_.clearHandedOver();
}

double ContactManager::stepBound(const core::State& state, const std::vector<double>& du) const {
  // A point open at this iterate whose gap would cross its activation gap at the full step: the step
  // stops where it has crossed by a tenth of its present distance, so the point is active, with a
  // small force, at the next iterate and the next Newton step sees its stiffness. Without this a
  // stiff penalty spring that the linearized step ignores meets a penetration of the whole step and
  // Newton cycles. The place: the gap interpolated linearly along the step, checked at the step it
  // gives, and interpolated again from there while no such point has crossed (an end face that turns
  // along the step closes its gap nonlinearly: the first interpolation stopped short by a factor ~4
  // each iteration, and Newton crawled towards contact without reaching it). Line points have a
  // bound of their own (lineStepBound).
  double bound = 1.0;
  std::unique_ptr<core::State> next;
  const auto stepped = [&]() -> const core::State& {
    if (!next) {
      next = std::make_unique<core::State>(state);
      next->applyIncrement(du);
    }
    return *next;
  };
  // The gap above activation at step s0 (open) and at the full step; the target beyond activation: a
  // tenth of the present distance, or as deep as the deepest active point at this iterate where that
  // is deeper. (A tenth alone let only a few of many points closing together in per iteration, each
  // cutting the step to 1e-5 of itself: 24 x 24 layers 3 apart crawled and stopped at first contact.)
  struct Crossing {
    const Point* p;
    double activation, s0, a0, a1, target;
  };
  struct Open {
    const Point* p;
    double activation, a0;
  };
  std::vector<Open> open;
  bool pointBound = true;
  double deepest = 0.0;  // the deepest active point contact at this iterate, beyond its activation
  for (const auto& [key, p] : set_.current()) {
    if (p.node()) continue;
    if (p.line()) {
      bound = std::min(bound, lineStepBound(p, state, stepped));
      continue;
    }
    if (!pointBound) continue;
    const double activation = enforcer_->activationGap(*p.state);
    if (!std::isfinite(activation)) {
      pointBound = false;  // (the strategy's active set changes only between Newton solves)
      continue;
    }
    const double a0 = pointGeometry(p, state).gap - activation;
    if (a0 > 0.0) open.push_back({&p, activation, a0});
    else if (a0 < 0.0) deepest = std::max(deepest, -a0);
  }
  std::vector<Crossing> crossing;
  if (!pointBound) open.clear();
  for (const Open& o : open) {
    const ClosestPoints then = pointGeometry(*o.p, stepped());
    if (then.sinAngle < geometry_.options().minimumSinAngle) continue;
    const double a1 = then.gap - o.activation, target = -std::max(0.1 * o.a0, deepest);
    if (a1 >= target) continue;
    crossing.push_back({o.p, o.activation, 0.0, o.a0, a1, target});
  }
  const auto interpolated = [](const Crossing& c) { return c.s0 + (1.0 - c.s0) * (c.a0 - c.target) / (c.a0 - c.a1); };
  constexpr int kRounds = 8;
  for (int round = 0; round < kRounds && !crossing.empty(); ++round) {
    double s = 1.0;
    for (const Crossing& c : crossing) s = std::min(s, interpolated(c));
    if (s >= 1.0 || round == kRounds - 1) {
      bound = std::min(bound, s);
      break;
    }
    core::State at(state);
    std::vector<double> part(du);
    for (double& v : part) v *= s;
    at.applyIncrement(part);
    bool crossed = false;
    for (Crossing& c : crossing) {
      const double a = pointGeometry(*c.p, at).gap - c.activation;
      if (a <= 0.0) crossed = true;
      if (a > 0.0 && s > c.s0) c.s0 = s, c.a0 = a;
    }
    if (crossed) {
      bound = std::min(bound, s);
      break;
    }
  }
  penalty_.watchBound(bound);
  return bound;
}

double ContactManager::lineStepBound(const Point& p, const core::State& state,
                                     const std::function<const core::State&()>& stepped) const {
  // A line point whose gap the full step would take more than kLineStepDepth times the thinner
  // section's inscribed radius below min(gap now, 0): the step stops where the point has gone half
  // as deep (linear interpolation of the gap). That is a step that jumps a contact zone into, or
  // through, the other beam (a line point keeps its side, so beyond the other axis its gap is below
  // -(r_A + r_B)), which the linearized contact does not follow: open points the tangent does not
  // see, and points whose gap the step moves by more than the linearization holds. A point hovering
  // at zero gap at a zone's edge, which a full step moves by a small fraction of the section, never
  // bounds the step; bounding on every crossing of zero made Newton crawl (two parallel rods pressed
  // together: 10 steps with, 15 with cuts, without). (The weighted gaps of a Lagrange field's line
  // nodes are averages of these points' gaps.)
  if (geometry_.carriesNothing(p, state)) return 1.0;
  const double g0 = pointGeometry(p, state).gap;
  const double depth = kLineStepDepth * geometry_.thinner(p.key.pair), from = std::min(g0, 0.0);
  const double g1 = pointGeometry(p, stepped()).gap;
  if (!(g1 < from - depth)) return 1.0;
  return (g0 - (from - 0.5 * depth)) / (g0 - g1);
}

void ContactManager::restoreStep() {
  responseFailed_ = false;
  geometry_.closeGates();
  penalty_.relaxAfterFailure(set_.committed());
  geometry_.setFrictionRelaxation(tangentialRelaxationFactor(penalty_.relaxations()));
  set_.restore();
  lines_.clearLevels(true);
  resumeLevels_ = true;
  passes_ = 0;
  gatePasses_ = 0;
  pointContact_.clearHandedOver();
  penalty_.forgetFriction();
}

void ContactManager::appendVtk(const core::State&, core::VtkMesh& mesh) const {
  report_.appendVtk(set_.committed(), mesh);
}

}  // namespace bc::constraints
