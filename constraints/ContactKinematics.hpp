// Kinematics of one contact point between two straight contact lines, one on each of two beam
// elements (seed paper sec. 2-4; Litewka & Wriggers 2002):
//  - A contact line of an element runs between the points x_a + R_a o and x_b + R_b o of its two
//    nodes, where o is the line's offset from the beam axis in the reference configuration: a
//    section edge for rectangles (o = +-b/2 e2 +- h/2 e3), the axis itself for circles (o = 0).
//  - Closest points (xi on line A, eta on line B, in [0, 1]) from the orthogonality conditions (2.1)
//    t_A . (p_B - p_A) = 0, t_B . (p_B - p_A) = 0; for straight lines they are linear in (xi, eta),
//    so one Newton step solves them exactly, also in the AD types below.
//  - Normal: the cross-product form of (3.4), n = sigma (t_B x t_A) / |t_B x t_A|, stable as the gap
//    goes to zero; sigma = +-1 is fixed so that n points from beam A's axis towards beam B's.
//  - Normal gap g_N = (p_B - p_A) . n - (r_A + r_B) (radii for circular sections, else 0).
//  - Tangential gaps (4.7) along each line from the previous converged contact point mapped on the
//    current configuration: g_T1 = (xi - xi_p) |p_A2 - p_A1|, g_T2 = (eta - eta_p) |p_B2 - p_B1|.
//  - The cosine c of the angle between the lines (value and first variation), the metric of the
//    tangential gaps for the isotropic Coulomb law.
// The 24 dofs are [u_A1, phi_A1, u_A2, phi_A2, u_B1, phi_B1, u_B2, phi_B2] (displacement and spin
// increments). For each gap g the kernel returns its value, its first variation R (delta g = R . du,
// the paper's R1, R2, R3) and its linearized variation K (Delta delta g = du^T K Du, K1, K2, K3), by
// nested forward AD of the formulas above, including the implicit dependence of xi and eta.
#pragma once
#include <array>

#include "core/SmallMath.hpp"

namespace bc::constraints {

using namespace bc::math;  // Vec3, Mat3 and the SO(3) maps

constexpr int kPairDofs = 24;
using Vector24 = std::array<double, kPairDofs>;
using Matrix24 = std::array<double, kPairDofs * kPairDofs>;  // row-major

struct LinePairInput {
  Vec3d xA1{}, xA2{}, xB1{}, xB2{};  // current nodal positions
  Mat3d RA1{}, RA2{}, RB1{}, RB2{};  // current nodal rotations
  Vec3d oA{}, oB{};  // reference offsets of the two lines from their axes
  double radiusSum = 0.0;  // r_A + r_B for circular sections
  // The elements' reference axis vectors X_2 - X_1 (length L0). The axis of an element is then the
  // cubic Hermite curve through the two nodes with the nodal tangents R_m (X_2 - X_1) (it is the
  // straight chord while the nodes have not turned, and follows the beam's bending between the
  // nodes), a line of it the curve through x_m + R_m o with the same tangents; a zero vector gives the
  // straight chord x_1 + u (x_2 - x_1). Line contact, and point contact with Point Contact Axes =
  // Hermite (PointContact zeroes them for the chords).
  Vec3d dA{}, dB{};
  // Node 2's reference tangent where it differs from node 1's: smoothed axes (Point Contact Axes =
  // Hermite) give each interior node of a beam one tangent shared by its two elements, so the curves
  // meet at the node with one direction. Zero: dA (dB) at both nodes.
  Vec3d dA2{}, dB2{};
  // Face contact of rectangular sections (line contact of an edge of A on a face of B): B's line is
  // then the centre line of its face (oB its offset), nB the face's outward unit normal and
  // halfWidthB its half width, all in the reference configuration. face false: circular sections.
  bool face = false;
  Vec3d nB{};
  double halfWidthB = 0.0;
  // Segments of line contact: the normals, in the reference configuration, of the planes through
  // B's two nodes that bound the part of A's line projecting onto B's element (at a node between
  // two elements the mean of their unit axis vectors, so neighbouring segments share the plane and
  // tile A's line; at a beam end the end element's). They turn with the nodes: tau_m = R_m sB_m.
  Vec3d sB1{}, sB2{};
  // Circular sections in line contact: the slip of the two surfaces, where A's section turns
  // against B's (turnSlip, setTurnSlip). The slip g_T2 = (eta - eta_p) m is the motion of A's axis
  // point along B's surface, whose variation turns A's contact point with B's section; A's own turn
  // adds -r_A (theta_A - theta_B) . b, b = n x t_B (n from B's axis towards A's), theta the sections'
  // turns since the last converged state: about the axes' normals from the Hermite tangents,
  // t_p x (t - t_p) (the bending the axes show), about the axes from the nodes' rotations,
  // (q - e) . (t_p x e) t_p with e a unit vector across the axis at the last converged state (n_p
  // made normal to t_p) and q = R_m R_m,p^T e interpolated between the nodes (the twist, which a
  // tangent does not show; it counts where the axes are apart). prev: the line points and Hermite
  // tangents (P_A1, P_A2, P_B1, P_B2, V_A1, V_A2, V_B1, V_B2) at the last converged state; turnRef:
  // R_m,p^T e of the nodes A1, A2 (e = across[0]), B1, B2 (across[1]); radiusA: A's radius.
  // With it the slip across the axes, g_T1 (surfaceSlips): the motion along b of A's material point at
  // the contact point of the last converged state against B's, (p_A - x_B - rho_A q_A - rho_B q_B) . b
  // + acrossStart, q the sections' vectors that were e, rho = r + g_N / 2 (the contact point midway
  // between the surfaces); acrossStart = (rho_A e_A + rho_B e_B) . b_p makes it zero there.
  // acrossSlip: g_T1 measured (set by setTurnSlip; LineContact clears it where the pair has no
  // friction across the axes, ContactGeometry::acrossFriction: g_T1 = 0 then, no variation).
  bool turnSlip = false, acrossSlip = false;
  double radiusA = 0.0, acrossStart = 0.0;
  Vec3d prev[8]{}, turnRef[4]{}, across[2]{};
  // End contact (endNode 0 or 1: A's node whose free end face is in contact; -1: none). The end face
  // is a disc of radius endRadius, or (endRectangle) a rectangle of half sizes endHalf along the
  // section's e2 and e3; endAxes the end's reference triad (e1 along the axis, e2, e3), outward +1 at
  // A's node 2 and -1 at node 1 (the axis leaves the beam along outward e1). B's surface: its
  // circular section of radius radiusB about its axis (oB = 0; acrossB a reference vector across B's
  // axis, the origin of the angle around it), or with `face` the face of nB (as above).
  // endCorner 0..3: not the whole end face but its corner (+-endHalf[0] e2, +-endHalf[1] e3; bit 0:
  // minus e2, bit 1: minus e3) against B's face (PointKey::cornerPoint); -1: the face.
  int endNode = -1, endCorner = -1;
  bool endRectangle = false;
  double endRadius = 0.0, endHalf[2] = {0.0, 0.0}, outward = 1.0, radiusB = 0.0;
  Vec3d endAxes[3]{};
  Vec3d acrossB{};
  // End-to-end contact (otherEnd 0 or 1: B's node whose free end face is the plane A's end face
  // presses on; -1: none): that face, a disc of radius otherRadius or (otherRectangle) a rectangle of
  // half sizes otherHalf along its e2 and e3, with its reference triad otherAxes (e1 outward).
  int otherEnd = -1;
  bool otherRectangle = false;
  double otherRadius = 0.0, otherHalf[2] = {0.0, 0.0};
  Vec3d otherAxes[3]{};
};

// The part [lo, hi] of A's element (parameters in [0, 1]) whose points lie between the planes of B's
// element (LinePairInput::sB1, sB2): bounded by A's element ends (kind -1) or by the plane of B's
// node 1 or 2 (kind 0, 1). Empty (hi = lo = 0) where A's element does not reach B's.
struct LineSegment {
  double lo = 0.0, hi = 0.0;
  int loKind = -1, hiKind = -1;
  double length() const { return hi - lo; }
};
LineSegment lineSegment(const LinePairInput& in);

// A line point's history: its parameters on A's and B's elements at the last converged state and
// d eta / d xi there, so that a material point of A that has moved along its segment (the segment's
// bounds move with the dofs) is measured from its own projection then: etaPrev(xi) = etaPrev +
// etaRate (xi - xiPrev).
struct LineHistory {
  double xiPrev = 0.0, etaPrev = 0.0, etaRate = 0.0;
  template <class T> T etaPrevAt(const T& xi) const { return etaPrev + etaRate * (xi - xiPrev); }
};

struct ClosestPoints {
  double xi = 0.0, eta = 0.0;  // line parameters in [0, 1] when inside both segments
  double distance = 0.0;  // |p_B - p_A|
  double sinAngle = 0.0;  // |t_A x t_B| / (|t_A| |t_B|)
  Vec3d pA{}, pB{}, cA{}, cB{};  // points on the lines and on the axes at xi, eta
  Vec3d normal{};  // unit normal with sigma applied
  double sigma = 1.0;
  double gap = 0.0;
  double lateral = 0.0;  // face contact: p_A's offset across B's face from its centre line
  double etaRate = 0.0;  // line contact: d eta / d xi of the projection
  double slipMetric = 0.0;  // line contact: the slip along B per unit eta (lineGaps' slipMetric)
  double across2 = 0.0;  // end-to-end contact: the end's offset along the other face's e3 (etaRate: e2)
};

// Closest points in double precision (for the search and for choosing sigma). Lines closer to
// parallel than sinAngle < 1e-12 return sinAngle and nothing else. With dA or dB set, the closest
// points of the Hermite curves (Newton on the two orthogonality conditions from the chords'), the
// normal from their tangents there and sinAngle of those tangents; a solution that does not converge
// returns sinAngle 0 (no point).
ClosestPoints closestPoints(const LinePairInput& in);

// Switches on the surfaces' slip of circles in line contact (LinePairInput::turnSlip): `converged`
// the same elements' input at the last converged state, `normal` the point's normal there (from B's
// axis towards A's), xi and eta its parameters there.
void setTurnSlip(LinePairInput& in, const LinePairInput& converged, const Vec3d& normal, double xi, double eta);
// The surfaces' slips of circles (LinePairInput::turnSlip; 0 without it) at A's parameter xi, B's
// material point etaPrev and A's projection eta on B, n from B's axis towards A's: the slip across
// the axes (g_T1; 0 without acrossSlip) and the turn part of the slip along B (added to g_T2).
std::array<double, 2> surfaceSlips(const LinePairInput& in, double xi, double etaPrev, double eta, const Vec3d& n);

// A gap's value, its first variation R (the direction of the force a unit multiplier applies: the
// residual is lambda R), the linearized variation K (the derivative of R) and the gradient of the value
// (what linearizes a law lambda(g): dlambda = lambda'(g) gradient . du). For point contact R is the
// gradient. A Gauss point of line contact varies at its place on A and with its slip metric held
// (segmentKinematics): R differs from the gradient by the motion of the Gauss point with B's segment
// and by the slip times the metric's change.
struct GapDerivatives {
  double value = 0.0;
  Vector24 R{};
  Matrix24 K{};
  Vector24 gradient{};
};

// Which variations of the gaps a kinematics call computes: First (values and R; K left zero) serves
// the passes that read no tangent (active set, commit, output); Second adds K.
enum class Variations { First, Second };

struct ContactKinematics {
  double xi = 0.0, eta = 0.0;
  GapDerivatives normal, tangent1, tangent2;
  // c = t_A . t_B / (|t_A| |t_B|) and its first variation: the tangential gaps are lengths along two
  // lines at an angle, so the slip vector s = g_T1 a - g_T2 b has |s|^2 = g^T M g, M = [1 -c; -c 1].
  double cosine = 0.0;
  Vector24 cosineR{};
  // The cosine of the two elements' axes (chords) and its first variation: what all-angle contact
  // blends by. For a point contact it is `cosine`; for a line Gauss point `cosine` is 0 (its two
  // tangential gaps, across and along the axes, are orthogonal) and this holds the axes' angle.
  double axesCosine = 0.0;
  Vector24 axesCosineR{};
  // Line contact on a segment: the Gauss point's parameter xi on A's element and the segment's
  // length (a fraction of A's element) move with the dofs; their first variations.
  Vector24 xiR{};
  double segment = 1.0;
  Vector24 segmentR{};
};

// The cubic Hermite curve through P1, P2 with end tangents V1, V2 (per unit parameter) at u: line
// contact's axis of an element, with V_m = R_m (X_2 - X_1).
Vec3d hermitePoint(const Vec3d& P1, const Vec3d& V1, const Vec3d& P2, const Vec3d& V2, double u);

// Line contact (circular sections, nearly parallel axes) at the Gauss point xi of axis A: its
// projection on axis B (the point of B's Hermite axis where t_B(eta) . (p_B - p_A) = 0, by Newton's
// method from the chord's projection), in double precision (sinAngle of the chords, xi, eta, pA, pB,
// cA = pA, cB = pB, distance, normal along p_B - p_A, gap = distance - (r_A + r_B); sigma unused).
ClosestPoints lineProjection(const LinePairInput& in, double xi);
// The gaps of that Gauss point with their derivatives: g_N = |p_B - p_A| - (r_A + r_B) with eta from
// the projection (its dependence included), g_T1 = 0 (no slip is measured across the axes; circles
// with LinePairInput::turnSlip: the surfaces' slip across, surfaceSlips), g_T2 =
// (eta - etaPrev) m (slip along B, m the slip metric: the length A's point travels relative to B per
// unit eta, so that the variation of g_T2 is B's unit tangent); cosine 0 (the two tangential directions
// are orthogonal), axesCosine the chords'. The variations R (and K) are taken with the Gauss point's
// parameter xi on A and the metric m held: a Gauss point applies lambda_N n and lambda_T t_B on B
// (unit normal and tangent), so Coulomb's |lambda_T| <= mu |lambda_N| is the applied force's cone.
// The gradients of the values (GapDerivatives::gradient) include both.
// `keptNormal` (zero: none) orients the circular sections' gap: g_N = side |p_B - p_A| - (r_A + r_B),
// side = lineSide(projection, keptNormal). A Gauss point whose axes have passed through each other
// since the last converged step (p_B - p_A against the normal it had then) has side -1, so its gap is
// deeply negative instead of positive again.
ContactKinematics lineKinematics(const LinePairInput& in, double xi, double etaPrev, const Vec3d& keptNormal = {},
                                 Variations order = Variations::Second);
// The same at the Gauss point s (in [0, 1]) of a segment: xi = lo + s (hi - lo) with the bounds as
// functions of the dofs (planeRoot), the slip along B from the history's etaPrev(xi); the segment's
// length and xi with their first variations in ContactKinematics (their second variations are not
// needed: the length weights the point's residual, K <- w K + f (x) grad w).
ContactKinematics segmentKinematics(const LinePairInput& in, const LineSegment& segment, double s,
                                    const LineHistory& history, const Vec3d& keptNormal = {},
                                    Variations order = Variations::Second);
// The same two by nested forward AD of the gaps with the held quantities frozen (the held variations
// are written out in lineKinematics and segmentKinematics): the reference of the tests.
ContactKinematics lineKinematicsFromGaps(const LinePairInput& in, double xi, double etaPrev,
                                         const Vec3d& keptNormal = {}, Variations order = Variations::Second);
ContactKinematics segmentKinematicsFromGaps(const LinePairInput& in, const LineSegment& segment, double s,
                                            const LineHistory& history, const Vec3d& keptNormal = {},
                                            Variations order = Variations::Second);
// -1 where the projection's p_B - p_A points against keptNormal (a nonzero normal of circular
// sections' line contact), else +1 (face contact's gap carries its own sign).
double lineSide(const LinePairInput& in, const ClosestPoints& projection, const Vec3d& keptNormal);
// With in.face (rectangular sections, an edge of A on a face of B): the point of A's edge projected on
// the centre line of B's face (the same orthogonality), the gap along the face's normal n (the nodal
// normals R_m nB interpolated linearly and normalized), g_N = (p_A - x_B) . n, positive outside the
// face; lateral = (p_A - x_B) . (t_B x n) / |t_B x n|. lineProjection and lineKinematics dispatch on
// in.face.

// End contact: the free end face of A's beam at its node in.endNode against B's surface.
//  - eta: the projection of the end face's centre p_E on B's axis (circles) or on the centre line of
//    B's face (rectangles), x_B'(eta) . (x_B(eta) - p_E) = 0, in [0, 1] when on B's element.
//  - The direction u from the end towards B: across B's axis, the one along which the end face lies
//    furthest from the axis (circles: a maximum over the angle about B's axis, so a face pressed
//    flat on B has u along its own axis), minus the face's outward normal (rectangles); the gap is
//    the distance along u less B's radius and less how far the end face reaches towards B along u
//    (its support function: a disc r sin of
//    the angle between u and the axis, a rectangle b/2 |u . e2| + h/2 |u . e3|, each |x| smoothed
//    as (sqrt(x^2 + delta^2) - delta) / (sqrt(1 + delta^2) - delta), delta = kEndSmoothing, so that a
//    face pressed flat rocks smoothly; the smoothing makes the gap of a tilted face larger by at most
//    1.64 % of the face's half size). The distance of the end face from B's axis (circles) or from
//    the face's plane (rectangles), up to that smoothing.
//  - Slip along B: g_T2 = (eta - etaPrev) m (m the slip metric, as for line points); across B: g_T1 =
//    |p_E - x_B| (phi - acrossPrev) with phi the angle of p_E around B's axis from B's rotated acrossB
//    (circles), or (rectangles) the offset of p_E across the face less acrossPrev. The two are
//    orthogonal (cosine 0); axesCosine is the chords' (the all-angle blend, as for point contacts).
//  - The variations R are the relative motion of the two bodies' material points at one place, the
//    end face's support point (its point farthest towards B; the centre when the face is flat on B),
//    along three held orthonormal directions (-u, across B, along B): a unit multiplier applies a
//    unit force on B and its opposite on the end at that point, so the forces' moments balance and
//    the multipliers' Coulomb cone is the applied force's. The gradients of the values include
//    everything.
// `side` -1 when the end has passed B's axis since its point was found (circles: the gap is then
// deeply negative). endProjection returns the geometry in double precision (xi the end's parameter,
// eta, pA = p_E (with endCorner the corner), pB = x_B, normal u, gap, sinAngle of the chords) with etaRate holding the
// across coordinate (phi or the offset): the history an end point keeps.
constexpr double kEndSmoothing = 0.02;
ClosestPoints endProjection(const LinePairInput& in, double side);
ContactKinematics endKinematics(const LinePairInput& in, double side, double etaPrev, double acrossPrev,
                                Variations order = Variations::Second);

// End-to-end contact: A's end face (as in end contact, at in.endNode) against the plane of B's end
// face at B's node in.otherEnd (its outward normal n = R otherAxes[0]).
//  - gap: the distance of A's end centre from that plane along n, less how far A's end face reaches
//    towards it (its support function along -n, |x| smoothed as in end contact);
//  - slips: the centre's offsets in the plane along B's end e2 and e3, less offset1Prev and
//    offset2Prev (the offsets at the last converged state);
//  - the variations: the relative motion of the two ends' material points at A's support point along
//    n, e2, e3 held (orthonormal; the forces' moments balance, a unit multiplier applies a unit force).
// endToEndProjection returns the geometry in double precision (xi, eta the two ends' parameters, pA
// the support point, pB its projection on the plane, normal -n, etaRate and across2 the offsets).
ClosestPoints endToEndProjection(const LinePairInput& in);
ContactKinematics endToEndKinematics(const LinePairInput& in, double offset1Prev, double offset2Prev,
                                     Variations order = Variations::Second);

// All gaps and their derivatives at the current state; `sigma` from closestPoints (or the history),
// `xiPrev`, `etaPrev` the previous converged contact point (for the tangential gaps). The gaps'
// gradients in the end points' coordinates are written out (the orthogonality conditions' implicit
// derivatives), their Hessians by one level of forward AD of those gradients. With dA or dB set, on
// the Hermite curves: g_N along the curves' normal, g_T1 = (xi - xiPrev) |x_A'(xi)|, g_T2 = (eta -
// etaPrev) |x_B'(eta)|, the cosine of the tangents, gradients in the coordinates of the four line
// points and the four nodal tangents.
ContactKinematics contactKinematics(const LinePairInput& in, double sigma, double xiPrev, double etaPrev,
                                    Variations order = Variations::Second);
// The same by nested forward AD of the gaps alone (about five times the cost): the reference of the
// tests.
ContactKinematics contactKinematicsFromGaps(const LinePairInput& in, double sigma, double xiPrev, double etaPrev,
                                            Variations order = Variations::Second);

}  // namespace bc::constraints
