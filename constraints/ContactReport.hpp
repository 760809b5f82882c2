// What the contact reports of the committed points: the rows of contact_points.csv, the VTK arrays
// of the active points, the progress line, and the warnings of the run (penetrations deeper than
// the sections allow, line contact that did not resolve its zone, frictionless line contact,
// lowered automatic parameters).
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "AutomaticPenalty.hpp"
#include "ContactGeometry.hpp"
#include "LineContact.hpp"
#include "core/Contribution.hpp"

namespace bc::constraints {

// A penetration deeper than this fraction of the thinner section's inscribed radius: the sections
// overlap visibly there. An active point that deep is reported (a penalty law is far from contact);
// a line point that deep which nothing takes up sees no contact (ContactManager::held).
constexpr double kDeep = 0.05;
// Two closest points of a point contact's lines on the chords across a node whose normals lie further
// apart than this (radians) make the force lean across the beams by up to half of it, a side of the
// chords' kink the mesh picks (ContactReport::noteRival).
constexpr double kRivalAngle = 0.02;
// How close a rival's gap must be to the point's, of the thinner section's inscribed radius.
constexpr double kRivalGap = 0.01;

class ContactReport {
 public:
  ContactReport(const ContactGeometry& geometry, const ConstraintEnforcer& enforcer, const LineContact& lines,
                const AutomaticPenalty& penalty)
      : geometry_(geometry), enforcer_(enforcer), lines_(lines), penalty_(penalty) {}

  // The common columns, then the strategy's own (ConstraintEnforcer::outputColumns).
  std::string tableHeader() const;
  std::vector<std::string> tableRows(const PointMap& committed) const;
  void appendVtk(const PointMap& committed, core::VtkMesh& mesh) const;
  // `lastPasses`: the passes of the increment solved last.
  std::string progressSummary(const PointMap& committed, int lastPasses) const;
  std::vector<std::string> warnings() const;
  // Notes a committed active point at its closest points `cp` (penetrations beyond kDeep).
  void noteDepth(const ContactPointRecord& p, const ClosestPoints& cp);
  // Notes a committed active line point (or point contact under Isotropic Coulomb) whose applied
  // force (normalForce, tangentialForce) lies outside the Coulomb cone by more than kOutsideCone |F_N|.
  void noteCone(const ContactPointRecord& p, double friction);
  // Notes a committed active point contact on the chords with a rival as close across a node
  // (PointContact::rivalAngle: the angle between their normals) beyond kRivalAngle.
  // `initialKink`: the angle at which the beam's elements met there in its initial shape, which
  // Hermite axes keep (PointContact::rivalAngle).
  void noteRival(const ContactPointRecord& p, double angle, double initialKink);

 private:
  // The line-contact warnings: overlaps between Gauss points, unresolved Lagrange fields, gaps that
  // supports hold, forces outside the Coulomb cone.
  void lineWarnings(std::vector<std::string>& w) const;
  const ContactGeometry& geometry_;
  const ConstraintEnforcer& enforcer_;
  const LineContact& lines_;
  const AutomaticPenalty& penalty_;
  std::map<int, std::pair<double, Vec3d>> deepPoints_;  // pair -> deepest active point beyond kDeep, where
  std::map<int, std::pair<double, Vec3d>> rivals_;  // pair -> largest rival angle beyond kRivalAngle, where
  std::map<int, double> rivalKinks_;  // pair -> the initial kink at that point
  std::map<int, std::pair<double, Vec3d>> outsideCone_;  // pair -> largest |F_T| / (mu |F_N|) beyond 1, where
  std::map<int, std::pair<double, Vec3d>> pointsOutsideCone_;  // the same of point contacts (Isotropic Coulomb)
};

}  // namespace bc::constraints
