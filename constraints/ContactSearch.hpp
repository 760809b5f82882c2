// The contact search: the elements' bounding boxes (inflated by "Search Margin", swept from the last
// converged state) are hashed into a uniform grid, so candidate element pairs are found without
// testing all pairs (the broad phase); elements that share a node (beams joined there) or whose nodes
// are pinned together are never a candidate pair. The narrow phase (point and line contact) finds
// the points of each candidate element pair; with several ranks each evaluates a share of the pairs
// and the ranks exchange their choices. The search also refuses overlaps no point can see and beams
// that passed through each other.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include "ContactGeometry.hpp"

namespace bc::constraints {

class ContactSearch {
 public:
  explicit ContactSearch(const ContactGeometry& geometry) : geometry_(geometry) {}
  // The ranks that share the narrow phase (detect).
  void useCommunicator(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) { comm_ = comm; }

  // Calls visit(pair, elementA, elementB) for the element pairs of the contact pairs whose bounding
  // boxes, swept from the last converged state to `s`, overlap.
  void forEachElementPair(const core::State& s, const std::function<void(int, int, int)>& visit) const;
  // The candidates at `s`: (pair, element of beam A, element of beam B), sorted.
  std::vector<std::tuple<int, int, int>> candidates(const core::State& s) const;
  // The narrow phase of one element pair (pair, element A, element B), the broad phase's `visit`-th.
  using NarrowPhase = std::function<void(int, int, int, long long, const CandidateOffer&)>;
  // The candidates of the state's element pairs: the narrow phase's offers for the pairs of the
  // broad phase, per key the one offered with the lowest (outside, order). With a communicator of
  // several ranks each rank evaluates a contiguous share of the pairs and the ranks exchange their
  // choices; the result is the same on every rank and the same as the whole search's on one.
  std::map<PointKey, Candidate> detect(const core::State& s, const NarrowPhase& narrow) const;

  // Overlaps no contact point can see (at a free beam end, or between nearly parallel beams; between
  // rectangular sections in line contact, unless seen(pair, element A, element B): an active point
  // of the pair on or next to those elements sees them): an error (InputError at the start, else the
  // increment fails). `strategy`: the enforcer's type.
  void checkNoUnseenContact(const core::State& state, bool atStart, const std::string& strategy,
                            const std::function<bool(int, int, int)>& seen) const;
  // Beams whose axes crossed since the last converged state, unless held(pair, element A, element B):
  // an active point of the pair near those elements holds them. The increment fails.
  void checkNoPassThrough(const core::State& state, const std::function<bool(int, int, int)>& held) const;

 private:
  // How deep the rectangular sections of elements ea and eb overlap across A's axis (negative: apart).
  double sectionOverlap(const core::State& state, int ea, int eb) const;
  const ContactGeometry& geometry_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
};

}  // namespace bc::constraints
