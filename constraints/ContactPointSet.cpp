#include "ContactPointSet.hpp"

#include <algorithm>
#include <string>

namespace bc::constraints {

ContactPointRecord ContactPointSet::newPoint(const PointKey& key, const Candidate& c) const {
  ContactPointRecord p;
  p.key = key;
  p.state = PointStateHolder(enforcer_.newPointState());
  p.sigma = c.cp.sigma;
  p.xiPrev = geometry_.beamCoordinate(c.elementA, c.cp.xi);
  p.etaPrev = geometry_.beamCoordinate(c.elementB, c.cp.eta);
  p.etaRate = c.cp.etaRate;
  p.across2 = c.cp.across2;
  return p;
}

void ContactPointSet::inherit(ContactPointRecord& p, Donors& donors, bool& donorsFound) const {
  // A new Gauss point of a segment (its segment appeared, or moved so that the point left its
  // neighbour's): its material point of A had its history at the nearest line point of the
  // same element and line of A at the last converged state. It takes that point's strategy
  // state and normal, and its projection then, extrapolated along B by the donor's d eta / d xi.
  if (!donorsFound) {
    for (const auto& [k, d] : committed_)
      if (d.line()) donors[{d.key.pair, d.key.elementA, d.edge(), d.face()}].push_back(&d);
    donorsFound = true;
  }
  const auto list = donors.find({p.key.pair, p.key.elementA, p.edge(), p.face()});
  const ContactPointRecord* donor = nullptr;
  if (list != donors.end())
    for (const ContactPointRecord* d : list->second)
      if (!donor || std::abs(d->xiPrev - p.xiPrev) < std::abs(donor->xiPrev - p.xiPrev)) donor = d;
  if (donor) {
    p.state = donor->state;
    std::copy(donor->compliance, donor->compliance + 3, p.compliance);
    p.normal = donor->normal;
    p.etaRate = donor->etaRate;
    p.etaPrev = LineHistory{donor->xiPrev, donor->etaPrev, donor->etaRate}.etaPrevAt(p.xiPrev);
  }
}

bool ContactPointSet::update(const std::map<PointKey, Candidate>& candidates) {
  PointMap next;
  bool changed = false;
  // Line points of the last converged state by (pair, element of A, edge, face): the donors of the
  // history of new line points.
  Donors donors;
  bool donorsFound = false;
  for (const auto& [key, c] : candidates) {
    auto it = points_.find(key);
    ContactPointRecord p;
    if (it != points_.end()) {
      p = it->second;
      changed = changed || p.elementA != c.elementA || p.elementB != c.elementB;
    } else {
      changed = true;
      p = newPoint(key, c);
      if (p.line()) inherit(p, donors, donorsFound);
    }
    p.elementA = c.elementA;
    p.elementB = c.elementB;
    p.xi = c.cp.xi;
    p.endCut = c.endCut;
    // A new line point's side: its normal at the last converged state (where the beams had not
    // passed through each other), so a point found after they did has a deeply negative gap.
    if (p.line() && dot(p.normal, p.normal) == 0.0) p.normal = lines_.geometry(p, geometry_.reference()).normal;
    next[key] = p;
  }
  if (lines_.nodal()) addLineNodes(next, changed);
  changed = changed || next.size() != points_.size();
  points_ = std::move(next);
  return changed;
}

void ContactPointSet::addLineNodes(PointMap& next, bool& changed) const {
  for (const auto& [key, p] : next)
    if (p.line())
      for (const LineContact::FieldShare& share : lines_.fieldShares(p, p.xi, next))
        if (!next.count(PointKey::lineNode(p.key.pair, p.edge(), share.node))) {
          const PointKey nk = PointKey::lineNode(p.key.pair, p.edge(), share.node);
          const auto it = points_.find(nk);
          ContactPointRecord q;
          if (it != points_.end()) {
            q = it->second;
          } else {
            changed = true;
            q.key = nk;
            q.elementA = q.elementB = p.elementA;
            q.state = PointStateHolder(enforcer_.newLineNodeState());
          }
          next[nk] = q;
        }
}

bool ContactPointSet::layoutMultipliers(core::State& state) {
  std::map<core::ExtraUnknowns::Key, int> wanted;
  for (const auto& [key, p] : points_)
    wanted[extraKey(p)] = lines_.nodal() && p.line() ? 0 : enforcer_.multipliers(*p.state);
  const bool changed = state.extra.request(kContactExtraOwner, wanted);
  for (auto& [key, p] : points_) {
    const auto* block = state.extra.find(kContactExtraOwner, extraKey(p));
    p.extraOffset = block ? block->offset : -1;
    p.extraCount = block ? block->size : 0;
  }
  return changed;
}

void ContactPointSet::save(core::CheckpointOut& out) const {
  // The strategy's point state, field by field (name and value).
  struct Writer : StateFields {
    core::CheckpointOut& out;
    explicit Writer(core::CheckpointOut& o) : out(o) {}
    void real(const char* name, double& v) override { out.word(name).real(v); }
    void flag(const char* name, bool& v) override { out.word(name).integer(v ? 1 : 0); }
  } writer(out);
  for (const auto& [key, p] : committed_) {
    const auto code = p.key.code();
    out.label("point").integer(code[0]).integer(code[1]).integer(code[2]).integer(p.elementA).integer(p.elementB);
    out.real(p.sigma).real(p.xiPrev).real(p.etaPrev).real(p.etaRate).real(p.across2).real(p.length);
    for (int a = 0; a < 3; ++a) out.real(p.normal[a]);
    for (int a = 0; a < 3; ++a) out.real(p.compliance[a]);
    (*p.state).fields(writer);
  }
}

ContactPointRecord ContactPointSet::readPoint(core::CheckpointIn& in, long long i, StateFields& reader) {
  const auto& pairs = geometry_.pairs();
  const int elements = static_cast<int>(geometry_.beams().elements().size());
  in.label("point");
  ContactPointRecord p;
  const int pair = static_cast<int>(in.integer());
  const long long lineA = in.integer();
  p.key = PointKey::fromCode(pair, lineA, static_cast<int>(in.integer()));
  p.elementA = static_cast<int>(in.integer());
  p.elementB = static_cast<int>(in.integer());
  if (p.key.pair < 0 || p.key.pair >= static_cast<int>(pairs.size()) || p.elementA < 0 || p.elementA >= elements ||
      p.elementB < 0 || p.elementB >= elements)
    in.fail("contact point " + std::to_string(i + 1) + " refers to a pair or element the deck does not have (pair " +
            std::to_string(p.key.pair) + " of " + std::to_string(pairs.size()) + ", elements " +
            std::to_string(p.elementA) + " and " + std::to_string(p.elementB) + " of " + std::to_string(elements) +
            ")");
  // Its elements belong to the beams of its pair.
  const auto onPair = [&](int e) {
    const int beam = geometry_.beams().elements()[e].beam;
    return beam == pairs[p.key.pair].beamA || beam == pairs[p.key.pair].beamB;
  };
  if (!onPair(p.elementA) || !onPair(p.elementB))
    in.fail("contact point " + std::to_string(i + 1) + " joins elements " + std::to_string(p.elementA) + " and " +
            std::to_string(p.elementB) + ", which are not on the beams of its contact pair \"" +
            pairs[p.key.pair].name + "\"");
  if (committed_.count(p.key)) in.fail("contact point " + std::to_string(i + 1) + " is there twice (it is damaged)");
  p.sigma = in.real();
  if (p.sigma != 1.0 && p.sigma != -1.0)
    in.fail("contact point " + std::to_string(i + 1) + " has the normal orientation " + core::shortest(p.sigma) +
            " (it is +1 or -1)");
  p.xiPrev = in.real();
  p.etaPrev = in.real();
  p.etaRate = in.real();
  p.across2 = in.real();
  p.length = in.real();
  for (int a = 0; a < 3; ++a) p.normal[a] = in.real();
  for (int a = 0; a < 3; ++a) p.compliance[a] = in.real();
  p.xi = p.xiPrev - geometry_.beams().elements()[p.elementA].index;
  p.state = PointStateHolder(p.node() ? enforcer_.newLineNodeState() : enforcer_.newPointState());
  (*p.state).fields(reader);
  return p;
}

void ContactPointSet::load(core::CheckpointIn& in, long long n, const core::State& committed) {
  struct Reader : StateFields {
    core::CheckpointIn& in;
    explicit Reader(core::CheckpointIn& i) : in(i) {}
    void name(const char* expected) {
      if (in.word() != core::CheckpointOut::token(expected))
        in.fail(std::string("a contact point's state lacks \"") + expected + "\" (another strategy version?)");
    }
    void real(const char* n, double& v) override {
      name(n);
      v = in.real();
    }
    void flag(const char* n, bool& v) override {
      name(n);
      v = in.integer() != 0;
    }
  } reader(in);
  committed_.clear();
  for (long long i = 0; i < n; ++i) {
    ContactPointRecord p = readPoint(in, i, reader);
    const auto* block = committed.extra.find(kContactExtraOwner, extraKey(p));
    p.extraOffset = block ? block->offset : -1;
    p.extraCount = block ? block->size : 0;
    if (p.extraCount != enforcer_.multipliers(*p.state))
      in.fail("a contact point's multipliers do not match its state");
    committed_[p.key] = p;
  }
  // Every contact multiplier in the state belongs to one of these points.
  std::size_t blocks = 0, withBlock = 0;
  for (const auto& [id, block] : committed.extra.blocks()) blocks += id.first == kContactExtraOwner ? 1 : 0;
  for (const auto& [key, p] : committed_) withBlock += p.extraOffset >= 0 ? 1 : 0;
  if (blocks != withBlock)
    in.fail("its state holds contact multipliers of " + std::to_string(blocks) + " points, its contact history " +
            std::to_string(withBlock) + " points with multipliers");
  points_ = committed_;
  marked_ = committed_;
}

}  // namespace bc::constraints
