// The identity of a contact point: its beam pair and what it is on that pair. A point contact joins
// two contact lines; a Gauss point of line contact lies on the segment of an element of beam A (its
// edge against a face of B for rectangular sections) that projects onto an element of beam B; a line
// node carries a strategy's multiplier field on line A (ConstraintEnforcer::LineField::Nodal).
//
// Points live in maps ordered by their keys, and that order decides the order of the rows of
// contact_points.csv, of the VTK arrays, of the multipliers and of every sum over points. Keys
// therefore compare as the three numbers of their code (pair, line A, line B) did when they were the
// key themselves (see code()): by pair; then line nodes (by edge, descending, then node), Gauss points
// (by element of B, face, edge, Gauss point, all descending, then element of A), point contacts (by
// line A, then line B).
//
// The code is what checkpoints, the extra unknowns' keys and the table's line_A and line_B columns
// hold: a point contact (lineA, lineB); a Gauss point (-1 - (gauss + 4096 (edge + 4 face + 16 elementB)),
// elementA); a line node (kLineNode - edge, node). Gauss codes that would reach the line nodes' codes
// (more than about 3 x 10^4 elements of B, which the packed numbers could not hold) skip below them, so
// every key has its own code; there the keys keep their order (line nodes first) while such a Gauss
// point's code compares below the line nodes' (nothing depends on the codes' order: the extra
// unknowns of line nodes and of Gauss points never coexist, and points are found by key).
#pragma once
#include <array>
#include <limits>
#include <ostream>
#include <tuple>

namespace bc::constraints {

struct PointKey {
  enum class Kind { LineNode, Gauss, Contact };  // in the order of their codes
  int pair = 0;
  Kind kind = Kind::Contact;
  int lineA = 0, lineB = 0;  // a point contact's lines
  int elementA = 0, elementB = 0;  // a Gauss point's elements
  int edge = 0, face = 0;  // a Gauss point's (a line node's: edge) edge of A and face of B
  int gauss = 0;  // a Gauss point's index in its segment
  int node = 0;  // a line node's node

  static PointKey contact(int pair, int lineA, int lineB) {
    PointKey k;
    k.pair = pair;
    k.lineA = lineA;
    k.lineB = lineB;
    return k;
  }
  static PointKey gaussPoint(int pair, int elementA, int elementB, int edge, int face, int gauss) {
    PointKey k;
    k.pair = pair;
    k.kind = Kind::Gauss;
    k.elementA = elementA;
    k.elementB = elementB;
    k.edge = edge;
    k.face = face;
    k.gauss = gauss;
    return k;
  }
  static PointKey lineNode(int pair, int edge, int node) {
    PointKey k;
    k.pair = pair;
    k.kind = Kind::LineNode;
    k.edge = edge;
    k.node = node;
    return k;
  }

  // The least key of a pair (a line node of the largest edge and least node: line nodes come first,
  // by edge descending, then node): a map of points from lower_bound(first(pair)) holds the pair's
  // points until the pair changes.
  static PointKey first(int pair) {
    return lineNode(pair, std::numeric_limits<int>::max(), std::numeric_limits<int>::min());
  }

  // An end point (end contact: a free beam end's face on the other beam) is a point contact whose
  // line A is kEndLine + 2 (the end is the pair's beam B's) + end (0: the beam's first node, 1: its
  // last), line B the face of the other beam it presses on (rectangles; circles 0).
  static constexpr int kEndLine = 1000;
  static PointKey endPoint(int pair, bool ofB, int end, int face) {
    return contact(pair, kEndLine + 2 * (ofB ? 1 : 0) + end, face);
  }
  // Two ends against each other (end-to-end contact): line B is kEndLine + the other end (0, 1 as
  // above), whose end face is the plane the first end presses on.
  static PointKey endToEndPoint(int pair, bool ofB, int end, int otherEnd) {
    return contact(pair, kEndLine + 2 * (ofB ? 1 : 0) + end, kEndLine + otherEnd);
  }
  // A corner of a rectangular end on the other beam's face (where the end hangs over that face's
  // side or its axis does not point into the face: end contact, "End corners"): line B is the face +
  // 4 (1 + corner), corner 0..3 at (+e2, +e3), (-e2, +e3), (+e2, -e3), (-e2, -e3) of the end's half
  // sizes.
  static PointKey cornerPoint(int pair, bool ofB, int end, int face, int corner) {
    return contact(pair, kEndLine + 2 * (ofB ? 1 : 0) + end, face + 4 * (1 + corner));
  }
  bool end() const { return kind == Kind::Contact && lineA >= kEndLine; }
  bool endToEnd() const { return end() && lineB >= kEndLine; }
  bool corner() const { return end() && !endToEnd() && lineB >= 4; }
  int cornerIndex() const { return corner() ? lineB / 4 - 1 : -1; }
  int endFace() const { return lineB % 4; }  // an end or corner point's face of the other beam
  int otherEnd() const { return lineB - kEndLine; }
  bool endOfB() const { return (lineA - kEndLine) / 2 == 1; }
  int endIndex() const { return (lineA - kEndLine) % 2; }

  static constexpr long long kLineNode = -2000000000;
  static constexpr long long kGaussSlots = 4096;  // Gauss points per segment (32 in each of 127 parts)

  // (pair, line A, line B) as described above.
  std::array<long long, 3> code() const {
    switch (kind) {
      case Kind::LineNode: return {pair, kLineNode - edge, node};
      case Kind::Gauss: {
        long long c = -1 - (gauss + kGaussSlots * (edge + 4 * (face + 4 * static_cast<long long>(elementB))));
        if (c <= kLineNode) c -= 4;  // below the line nodes' codes
        return {pair, c, elementA};
      }
      case Kind::Contact: break;
    }
    return {pair, lineA, lineB};
  }
  static PointKey fromCode(long long pair, long long a, long long b) {
    const int p = static_cast<int>(pair), n = static_cast<int>(b);
    if (a >= 0) return contact(p, static_cast<int>(a), n);
    if (a <= kLineNode && a > kLineNode - 4) return lineNode(p, static_cast<int>(kLineNode - a), n);
    const long long slots = -1 - (a < kLineNode ? a + 4 : a);
    return gaussPoint(p, n, static_cast<int>(slots / (16 * kGaussSlots)), static_cast<int>((slots / kGaussSlots) % 4),
                      static_cast<int>((slots / (4 * kGaussSlots)) % 4), static_cast<int>(slots % kGaussSlots));
  }

  // In the order of the codes (a Gauss point's larger slots: a lower code).
  bool operator<(const PointKey& o) const {
    if (pair != o.pair) return pair < o.pair;
    if (kind != o.kind) return kind < o.kind;
    switch (kind) {
      case Kind::LineNode: return edge != o.edge ? edge > o.edge : node < o.node;
      case Kind::Gauss:
        return std::tie(o.elementB, o.face, o.edge, o.gauss, elementA) <
               std::tie(elementB, face, edge, gauss, o.elementA);
      case Kind::Contact: break;
    }
    return std::tie(lineA, lineB) < std::tie(o.lineA, o.lineB);
  }
  bool operator==(const PointKey& o) const {
    return std::tie(pair, kind, lineA, lineB, elementA, elementB, edge, face, gauss, node) ==
           std::tie(o.pair, o.kind, o.lineA, o.lineB, o.elementA, o.elementB, o.edge, o.face, o.gauss, o.node);
  }
  bool operator!=(const PointKey& o) const { return !(*this == o); }
};

inline std::ostream& operator<<(std::ostream& s, const PointKey& k) {
  const auto c = k.code();
  return s << "(" << c[0] << ", " << c[1] << ", " << c[2] << ")";
}

}  // namespace bc::constraints
