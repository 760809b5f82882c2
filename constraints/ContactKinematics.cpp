#include "ContactKinematics.hpp"

#include <cmath>
#include <type_traits>

namespace bc::constraints {

using namespace bc::math;

namespace {

// Whether an element's lines are its Hermite curves (a nonzero reference axis vector) or chords.
bool cubic(const Vec3d& d) { return dot(d, d) > 0.0; }
bool smoothPoint(const LinePairInput& in) { return cubic(in.dA) || cubic(in.dB); }
// Node 2's reference tangent of A and of B (LinePairInput::dA2, dB2).
const Vec3d& tangentA2(const LinePairInput& in) { return cubic(in.dA2) ? in.dA2 : in.dA; }
const Vec3d& tangentB2(const LinePairInput& in) { return cubic(in.dB2) ? in.dB2 : in.dB; }

// Closest points of the lines pA1 + xi (pA2 - pA1) and pB1 + eta (pB2 - pB1): the orthogonality
// conditions are linear in (xi, eta) for straight lines; Cramer's rule.
template <class T>
void solveClosest(const Vec3<T>& pA1, const Vec3<T>& pA2, const Vec3<T>& pB1, const Vec3<T>& pB2, T& xi, T& eta) {
  const Vec3<T> a = pA2 - pA1, b = pB2 - pB1, d = pB1 - pA1;
  const T aa = dot(a, a), ab = dot(a, b), bb = dot(b, b), ad = dot(a, d), bd = dot(b, d);
  // a.(d + eta b - xi a) = 0, b.(d + eta b - xi a) = 0
  const T det = aa * bb - ab * ab;
  xi = (ad * bb - ab * bd) / det;
  eta = (ab * ad - aa * bd) / det;
}

template <class T> struct Gaps {
  T gN, gT1, gT2, xi, eta;
  T cosine;  // t_A . t_B / (|t_A| |t_B|): the metric of the tangential gaps (isotropic friction)
  T length;  // line contact on a segment: its length as a fraction of A's element (else 1)
};

// The three gaps as functions of the four line end points alone.
template <class T>
Gaps<T> gaps(const Vec3<T>& pA1, const Vec3<T>& pA2, const Vec3<T>& pB1, const Vec3<T>& pB2, double radiusSum,
             double sigma, double xiPrev, double etaPrev) {
  using std::sqrt;
  Gaps<T> g;
  solveClosest(pA1, pA2, pB1, pB2, g.xi, g.eta);
  const Vec3<T> tA = pA2 - pA1, tB = pB2 - pB1;
  const Vec3<T> pA = pA1 + g.xi * tA, pB = pB1 + g.eta * tB;
  const Vec3<T> c = cross(tB, tA);
  const T nc = sqrt(dot(c, c));
  const T s = sigma / nc;
  const Vec3<T> n = s * c;
  g.gN = dot(pB - pA, n) - radiusSum;
  g.gT1 = (g.xi - xiPrev) * sqrt(dot(tA, tA));
  g.gT2 = (g.eta - etaPrev) * sqrt(dot(tB, tB));
  g.cosine = dot(tA, tB) / (sqrt(dot(tA, tA)) * sqrt(dot(tB, tB)));
  g.length = T(1.0);
  return g;
}

// The cubic Hermite curve through P1, P2 with end tangents V1, V2 (per unit parameter) at u, and its
// first and second derivatives in u.
template <class T> struct Same { using type = T; };
template <class T, class U>
void hermite(const Vec3<T>& P1, const Vec3<T>& V1, const Vec3<T>& P2, const Vec3<T>& V2, const U& u,
             typename Same<Vec3<T>>::type* x, typename Same<Vec3<T>>::type* dx, typename Same<Vec3<T>>::type* ddx) {
  const U u2 = u * u, u3 = u2 * u;
  if (x) *x = (1.0 - 3.0 * u2 + 2.0 * u3) * P1 + (u - 2.0 * u2 + u3) * V1 + (3.0 * u2 - 2.0 * u3) * P2 + (u3 - u2) * V2;
  if (dx)
    *dx = (6.0 * u2 - 6.0 * u) * P1 + (1.0 - 4.0 * u + 3.0 * u2) * V1 + (6.0 * u - 6.0 * u2) * P2 +
          (3.0 * u2 - 2.0 * u) * V2;
  if (ddx) *ddx = (12.0 * u - 6.0) * P1 + (6.0 * u - 4.0) * V1 + (6.0 - 12.0 * u) * P2 + (6.0 * u - 2.0) * V2;
}

// A point of an element's axis at u (and its derivatives): the Hermite curve when the element has a
// reference axis vector (cubic), else the straight chord P1 + u (P2 - P1).
template <class T, class U>
void axisPoint(const Vec3<T>& P1, const Vec3<T>& V1, const Vec3<T>& P2, const Vec3<T>& V2, bool cubic, const U& u,
               typename Same<Vec3<T>>::type* x, typename Same<Vec3<T>>::type* dx, typename Same<Vec3<T>>::type* ddx) {
  if (cubic) return hermite(P1, V1, P2, V2, u, x, dx, ddx);
  if (x) *x = P1 + u * (P2 - P1);
  if (dx) *dx = P2 - P1;
  if (ddx) *ddx = 0.0 * (P2 - P1);
}

// The parameter eta of the point of the curve (P1, V1, P2, V2) (axisPoint) nearest to p, in double
// precision: the chord's projection, then Newton on x'(eta) . (x(eta) - p) = 0 to round-off.
double projectionParameter(const Vec3d& P1, const Vec3d& V1, const Vec3d& P2, const Vec3d& V2, bool cubic,
                           const Vec3d& p) {
  const Vec3d t = P2 - P1;
  double eta = dot(t, p - P1) / dot(t, t);
  for (int it = 0; it < 50; ++it) {
    Vec3d x, dx, ddx;
    axisPoint(P1, V1, P2, V2, cubic, eta, &x, &dx, &ddx);
    const Vec3d d = x - p;
    const double step = dot(dx, d) / (dot(ddx, d) + dot(dx, dx));
    eta -= step;
    if (std::abs(step) < 1e-15 * (1.0 + std::abs(eta))) break;
  }
  return eta;
}

// A's point at xi and its projection x_B(eta) on B's line (f(eta) = x_B'(eta) . (x_B(eta) - p_A) = 0),
// by Newton steps from etaStart, the solution in double precision: each step makes one more order of
// the AD derivatives exact (two are needed, three are taken). Sets g.xi, g.eta.
template <class T>
void projectOnB(const Vec3<T>* P, const Vec3<T>* V, bool cubicA, bool cubicB, const T& xi, double etaStart, Gaps<T>& g,
                Vec3<T>& pA, Vec3<T>& xB) {
  Vec3<T> dB, ddB;
  axisPoint(P[0], V[0], P[1], V[1], cubicA, xi, &pA, nullptr, nullptr);
  g.xi = xi;
  g.eta = T(etaStart);
  for (int it = 0; it < 3; ++it) {
    axisPoint(P[2], V[2], P[3], V[3], cubicB, g.eta, &xB, &dB, &ddB);
    const Vec3<T> d = xB - pA;
    g.eta -= dot(dB, d) / (dot(ddB, d) + dot(dB, dB));
  }
  axisPoint(P[2], V[2], P[3], V[3], cubicB, g.eta, &xB, nullptr, nullptr);
}

// The slip metric of line contact at B's parameter eta, projection of A's point pA: the length that
// A's point travels relative to B per unit of eta, m = (|x_B'|^2 + x_B'' . (x_B - p_A)) / |x_B'|. From
// the orthogonality x_B'(eta) . (x_B(eta) - p_A) = 0, a motion v of A's point relative to B moves the
// projection by d eta = x_B' . v / (|x_B'|^2 + x_B'' . (x_B - p_A)), so m d eta = t_B . v (t_B the unit
// tangent): the slip g_T2 = (eta - etaPrev) m has a unit variation along t_B, and a friction force
// lambda_T conjugate to it acts on B as lambda_T t_B, of length |lambda_T|. (The chord's length
// |x_B2 - x_B1|, used before, differs from |x_B'| where B's element bends, and leaves out the offset of
// A's point from B's curved axis, 1 - kappa (r_A + r_B) on the inside of a bend: strands 1.02-1.04.)
// x with its first variations (the inner AD level) removed and its increments (the outer level, with
// second variations) kept: a quantity held in the variation but not in the linearization.
template <class T> T frozen(const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    return x;
  } else {
    using V = std::decay_t<decltype(x.val())>;
    if constexpr (std::is_same_v<V, double>) {
      return T(x.val());
    } else {
      T y(V(x.val().val()));
      for (int l = 0; l < x.size(); ++l) y.fastAccessDx(l) = V(x.dx(l).val());
      return y;
    }
  }
}

template <class T> T slipMetric(const Vec3<T>* P, const Vec3<T>* V, bool cubicB, const T& eta, const Vec3<T>& pA) {
  using std::sqrt;
  Vec3<T> xB, dB, ddB;
  axisPoint(P[2], V[2], P[3], V[3], cubicB, eta, &xB, &dB, &ddB);
  const T speed2 = dot(dB, dB);
  return (speed2 + dot(ddB, xB - pA)) / sqrt(speed2);
}

// The unit tangent of the axis (P1, V1, P2, V2) at u.
template <class T>
Vec3<T> unitTangent(const Vec3<T>& P1, const Vec3<T>& V1, const Vec3<T>& P2, const Vec3<T>& V2, bool cubic,
                    const T& u) {
  using std::sqrt;
  Vec3<T> d;
  axisPoint(P1, V1, P2, V2, cubic, u, static_cast<Vec3<T>*>(nullptr), &d, static_cast<Vec3<T>*>(nullptr));
  return (1.0 / sqrt(dot(d, d))) * d;
}

template <class T> Vec3<T> lifted(const Vec3d& v) { return Vec3<T>{{T(v[0]), T(v[1]), T(v[2])}}; }

// The unit tangents of A's axis at xi and of B's at etaPrev at the last converged state
// (LinePairInput::prev).
template <class T>
void previousTangents(const LinePairInput& in, bool cubicA, bool cubicB, const T& xi, const T& etaPrev, Vec3<T>& tAp,
                      Vec3<T>& tBp) {
  Vec3<T> p[8];
  for (int k = 0; k < 8; ++k) p[k] = lifted<T>(in.prev[k]);
  tAp = unitTangent(p[0], p[4], p[1], p[5], cubicA, xi);
  tBp = unitTangent(p[2], p[6], p[3], p[7], cubicB, etaPrev);
}

// A section's turn since the last converged state, dotted with b (LinePairInput::turnSlip): t_p x (t -
// t_p) . b + (q - e) . (t_p x e) (t_p . b), t (t_p) the unit tangent now (then), q the section's
// vector that was e (across the axis).
template <class T>
T sectionTurn(const Vec3<T>& t, const Vec3<T>& tp, const Vec3<T>& q, const Vec3d& across, const Vec3<T>& b) {
  const Vec3<T> e = lifted<T>(across);
  return dot(cross(tp, t - tp), b) + dot(q - e, cross(tp, e)) * dot(tp, b);
}

// The sections' vectors q that were e at the last converged state (LinePairInput::turnSlip), from the
// nodes' turn vectors Q = R_m turnRef[m] (A1, A2, B1, B2): A's at xi, B's at etaPrev.
template <class T> std::array<Vec3<T>, 2> sectionVectors(const Vec3<T>* Q, const T& xi, const T& etaPrev) {
  return {(1.0 - xi) * Q[0] + xi * Q[1], (1.0 - etaPrev) * Q[2] + etaPrev * Q[3]};
}

// The contact point's distances from A's and B's axes, rho = r + g_N / 2 (midway between the surfaces).
template <class T> std::array<T, 2> contactArms(const LinePairInput& in, const T& gap) {
  return {in.radiusA + 0.5 * gap, (in.radiusSum - in.radiusA) + 0.5 * gap};
}

// The turn part of circles' slip (LinePairInput::turnSlip): -r_A (theta_A(xi) - theta_B(etaPrev)) . b,
// P, V the axes' points and tangents now, q the sections' vectors (sectionVectors).
// Its variation with xi, etaPrev and b held applies the moment r_A lambda_T about A's axis that a
// friction force lambda_T along B's surface exerts on A (where the axis point's slip puts it on B's
// section); a rigid turn of the pair gives theta_A = theta_B.
template <class T>
T turnSlipOf(const LinePairInput& in, const Vec3<T>* P, const Vec3<T>* V, const std::array<Vec3<T>, 2>& q, bool cubicA,
             bool cubicB, const T& xi, const T& etaPrev, const Vec3<T>& b) {
  Vec3<T> tAp, tBp;
  previousTangents(in, cubicA, cubicB, xi, etaPrev, tAp, tBp);
  const Vec3<T> tA = unitTangent(P[0], V[0], P[1], V[1], cubicA, xi);
  const Vec3<T> tB = unitTangent(P[2], V[2], P[3], V[3], cubicB, etaPrev);
  return -in.radiusA * (sectionTurn(tA, tAp, q[0], in.across[0], b) - sectionTurn(tB, tBp, q[1], in.across[1], b));
}

// The slip of circles across their axes (LinePairInput::turnSlip): (p_A - x_B - rho_A q_A(xi) -
// rho_B q_B(etaPrev)) . b + acrossStart, the motion along b = n x t_B of A's material point at the
// contact point at the last converged state against B's (each the axis point less rho along the
// section's vector q that was the normal e then, sectionVectors; rho = r + g_N / 2, contactArms, the
// contact point midway between the surfaces, so that the two bodies' forces act at one
// point and their moments balance where a penalty lets the surfaces overlap); p_A - x_B lies along n,
// so its part is zero in value, and its variation with b held is the axes' relative motion across.
// acrossStart makes it zero at the last converged state (e_A, made normal to A's axis, is not quite
// normal to b where the axes lie at an angle). Its variation with xi, etaPrev, b and rho held,
// (dp_A - dx_B) . b + rho_A dtheta_A . t + rho_B dtheta_B . t (q = n), is a unit force along b on each
// body at the contact point with its moment about the axis; a rigid motion of the pair gives 0.
template <class T>
T acrossSlipOf(const LinePairInput& in, const std::array<Vec3<T>, 2>& q, const Vec3<T>& fromB, const Vec3<T>& b,
               const T& gap) {
  const std::array<T, 2> rho = contactArms(in, gap);
  return dot(fromB - rho[0] * q[0] - rho[1] * q[1], b) + in.acrossStart;
}

// Line contact at a Gauss point of axis A (fixed parameter xi, a material point) against axis B:
// P = (x_A1, x_A2, x_B1, x_B2), V = their Hermite tangents R_m d; the point projected on B's curve
// (projectOnB). The normal is along p_B - p_A, the gap |p_B - p_A| - (r_A + r_B), the slip along B from
// etaPrev. Axis A's own tangential gap is zero (the point is material on A).
template <class T>
Gaps<T> lineGaps(const LinePairInput& in, const Vec3<T>* P, const Vec3<T>* V, const Vec3<T>* Q, bool cubicA,
                 bool cubicB, double radiusSum, const T& xi, double etaStart, const T& etaPrev, double side,
                 bool held) {
  using std::sqrt;
  Gaps<T> g;
  Vec3<T> pA, xB;
  projectOnB(P, V, cubicA, cubicB, xi, etaStart, g, pA, xB);
  const Vec3<T> d = xB - pA;
  const Vec3<T> tA = P[1] - P[0], tB = P[3] - P[2];
  const T distance = sqrt(dot(d, d));
  g.gN = side * distance - radiusSum;
  g.gT1 = T(0.0);
  const T m = slipMetric(P, V, cubicB, g.eta, pA);
  g.gT2 = (g.eta - etaPrev) * (held ? frozen(m) : m);
  if (Q) {  // (the turn vectors: LinePairInput::turnSlip)
    Vec3<T> b = cross((-side / distance) * d, unitTangent(P[2], V[2], P[3], V[3], cubicB, g.eta));
    if (held)
      for (int c = 0; c < 3; ++c) b[c] = frozen(b[c]);
    const std::array<Vec3<T>, 2> q = sectionVectors(Q, xi, etaPrev);
    g.gT2 += turnSlipOf(in, P, V, q, cubicA, cubicB, xi, etaPrev, b);
    if (in.acrossSlip) g.gT1 = acrossSlipOf(in, q, -1.0 * d, b, held ? frozen(g.gN) : g.gN);
  }
  g.cosine = dot(tA, tB) / (sqrt(dot(tA, tA)) * sqrt(dot(tB, tB)));
  g.length = T(1.0);
  return g;
}

// Face contact (rectangular sections): A's edge point against the centre line of B's face, the gap
// along the face normal. N = (N_B1, N_B2) the nodal face normals (rotated reference normal).
template <class T>
Gaps<T> faceGaps(const Vec3<T>* P, const Vec3<T>* V, const Vec3<T>* N, bool cubicA, bool cubicB, const T& xi,
                 double etaStart, const T& etaPrev, bool held) {
  using std::sqrt;
  Gaps<T> g;
  Vec3<T> pA, xB;
  projectOnB(P, V, cubicA, cubicB, xi, etaStart, g, pA, xB);
  // held: the normal gap's variation at B's material point eta, the normal's own: on B's translations
  // it sums to -m / |m| exactly. (With eta's variation, -(x_B' . m) d eta / |m| adds a part along
  // B's axis where the nodes' interpolated normal is not normal to the cubic axis: 1e-5 of the normal
  // force on bent beams, which left the applied friction force 1 + 6e-5 times mu N.)
  const T etaN = held ? frozen(g.eta) : g.eta;
  Vec3<T> xN = xB;
  if (held) axisPoint(P[2], V[2], P[3], V[3], cubicB, etaN, &xN, nullptr, nullptr);
  const Vec3<T> m = (1.0 - etaN) * N[0] + etaN * N[1];
  const T nm = sqrt(dot(m, m));
  const Vec3<T> tA = P[1] - P[0], tB = P[3] - P[2];
  g.gN = dot(pA - xN, m) / nm;
  g.gT1 = T(0.0);
  const T metric = slipMetric(P, V, cubicB, g.eta, pA);
  g.gT2 = (g.eta - etaPrev) * (held ? frozen(metric) : metric);
  g.cosine = dot(tA, tB) / (sqrt(dot(tA, tA)) * sqrt(dot(tB, tB)));
  g.length = T(1.0);
  return g;
}

// The double value of a (nested) AD number.
template <class T> double plain(const T& x) {
  if constexpr (std::is_same_v<T, double>) return x;
  else return plain(x.val());
}

// |x| smoothed over kEndSmoothing and scaled to 1 at |x| = 1, as a function of x2 = x^2: A(x2) =
// k (sqrt(x2 + d^2) - d), k = 1 / (sqrt(1 + d^2) - d) (endKinematics).
const double kEndScale = 1.0 / (std::sqrt(1.0 + kEndSmoothing * kEndSmoothing) - kEndSmoothing);
template <class T> T smoothAbs(const T& x2) {
  using std::sqrt;
  return T(kEndScale * (sqrt(x2 + kEndSmoothing * kEndSmoothing) - kEndSmoothing));
}

// A(x2) with its first two derivatives in x2 (endAngle's Newton steps).
template <class T> struct EndReach {
  T value, d1, d2;
  explicit EndReach(const T& x2) : value(smoothAbs<T>(x2)) {
    using std::sqrt;
    const T D = sqrt(x2 + kEndSmoothing * kEndSmoothing);
    d1 = (0.5 * kEndScale) / D;
    d2 = (-0.25 * kEndScale) / (D * D * D);
  }
};

// The angle phi in (-pi/2, pi/2) that maximizes f = R cos(phi) - rE A(1 - c^2), c = c1 cos(phi) + c2
// sin(phi) (endGaps): the best of 73 samples, then safeguarded Newton steps.
double endAngle(double R, double c1, double c2, double rE) {
  const auto f = [&](double phi) {
    const double c = c1 * std::cos(phi) + c2 * std::sin(phi);
    return R * std::cos(phi) - rE * EndReach<double>(1.0 - c * c).value;
  };
  const int n = 72;
  double best = 0.0, fb = f(0.0);
  for (int i = 0; i <= n; ++i) {
    const double phi = -0.5 * M_PI + M_PI * i / n;
    if (f(phi) > fb) fb = f(phi), best = phi;
  }
  const double h = M_PI / n;
  double phi = best;
  for (int it = 0; it < 60; ++it) {
    const double cs = std::cos(phi), sn = std::sin(phi);
    const double c = c1 * cs + c2 * sn, dc = c2 * cs - c1 * sn;
    const EndReach<double> a(1.0 - c * c);
    const double ds = -2.0 * c * dc, dds = -2.0 * (dc * dc - c * c);
    const double f1 = -R * sn - rE * a.d1 * ds, f2 = -R * cs - rE * (a.d2 * ds * ds + a.d1 * dds);
    if (!(f2 < 0.0)) break;
    const double step = std::max(-h, std::min(h, -f1 / f2));
    phi += step;
    if (std::abs(step) < 1e-15) break;
  }
  return phi;
}

// How far A's end face (triad X[0..2], X[0] outward) reaches along the unit direction u: its
// support function, each |x| smoothed (smoothAbs), and its support point s (the face's point
// farthest along u, relative to the end's centre).
template <class T> T endReach(const LinePairInput& in, const Vec3<T>& u, const Vec3<T>* X, Vec3<T>& support) {
  using std::sqrt;
  if (in.endCorner >= 0) {  // one corner of a rectangular end: its offset, unsmoothed
    support = ((in.endCorner & 1 ? -1.0 : 1.0) * in.endHalf[0]) * X[1] +
              ((in.endCorner & 2 ? -1.0 : 1.0) * in.endHalf[1]) * X[2];
    return dot(u, support);
  }
  if (in.endRectangle) {
    const T a2 = dot(u, X[1]), a3 = dot(u, X[2]);
    const EndReach<T> r2(a2 * a2), r3(a3 * a3);
    support = (2.0 * in.endHalf[0] * r2.d1 * a2) * X[1] + (2.0 * in.endHalf[1] * r3.d1 * a3) * X[2];
    return in.endHalf[0] * r2.value + in.endHalf[1] * r3.value;
  }
  const T c = dot(u, X[0]);
  const Vec3<T> inPlane = u - c * X[0];
  support = (in.endRadius / sqrt(dot(inPlane, inPlane) + kEndSmoothing * kEndSmoothing)) * inPlane;
  return in.endRadius * smoothAbs<T>(1.0 - c * c);
}

// The held variations of end contact's three gaps (their values kept): the relative motion of the
// two bodies' material points at one place, `relative` (zero in value), along the held orthonormal
// directions dN, d1, d2. A unit multiplier then applies a unit force on each body at that place.
template <class T>
void holdAtOnePlace(Gaps<T>& g, const Vec3<T>& relative, const Vec3<T>& dN, const Vec3<T>& d1, const Vec3<T>& d2) {
  const auto freeze = [](const Vec3<T>& v) { return Vec3<T>{{frozen(v[0]), frozen(v[1]), frozen(v[2])}}; };
  const Vec3<T> motion = relative - freeze(relative);
  g.gN = frozen(g.gN) + dot(motion, freeze(dN));
  g.gT1 = frozen(g.gT1) + dot(motion, freeze(d1));
  g.gT2 = frozen(g.gT2) + dot(motion, freeze(d2));
}

// The material point at c + r of a body whose frame at c is the orthonormal triad F[0..2] (an end's
// triad, or a beam's section): r's coordinates in the triad held, the triad turning with the body.
template <class T> Vec3<T> materialPointAt(const Vec3<T>& c, const Vec3<T>& r, const Vec3<T>* F) {
  Vec3<T> on = c;
  for (int a = 0; a < 3; ++a) on = on + frozen(dot(r, F[a])) * F[a];
  return on;
}

// End-to-end contact (see endToEndKinematics in the header): P the four nodes' points, X = (e1, e2,
// e3 of A's end, e1, e2, e3 of B's end), each e1 outward.
template <class T>
Gaps<T> endToEndGaps(const LinePairInput& in, const Vec3<T>* P, const Vec3<T>* X, double offset1Prev,
                     double offset2Prev, bool held, double* offsets = nullptr, Vec3d* supportPoint = nullptr) {
  using std::sqrt;
  Gaps<T> g;
  const Vec3<T>& cA = P[in.endNode];
  const Vec3<T>& cB = P[2 + in.otherEnd];
  const Vec3<T>* Y = X + 3;
  const Vec3<T> w = cA - cB;
  const Vec3<T> u = -1.0 * Y[0];  // from A's end towards B's face
  Vec3<T> support;
  const T reach = endReach(in, u, X, support);
  const T o1 = dot(w, Y[1]), o2 = dot(w, Y[2]);
  g.gN = dot(w, Y[0]) - reach;
  g.gT1 = o1 - offset1Prev;
  g.gT2 = o2 - offset2Prev;
  if (held) {
    // (as end contact's: both ends' material points at A's support point q)
    holdAtOnePlace(g, materialPointAt(cA, support, X) - materialPointAt(cB, cA + support - cB, Y), Y[0], Y[1], Y[2]);
  }
  g.xi = T(static_cast<double>(in.endNode));
  g.eta = T(static_cast<double>(in.otherEnd));
  const Vec3<T> tA = P[1] - P[0], tB = P[3] - P[2];
  g.cosine = dot(tA, tB) / (sqrt(dot(tA, tA)) * sqrt(dot(tB, tB)));
  g.length = T(1.0);
  if (offsets) offsets[0] = plain(o1), offsets[1] = plain(o2);
  if (supportPoint)
    for (int a = 0; a < 3; ++a) (*supportPoint)[a] = plain(cA[a] + support[a]);
  return g;
}

// End contact (see endKinematics in the header): P the four line points (A's: the end face's centre
// at endNode), V their tangents, X = (e1, e2, e3 of the end, B's reference vector at B's nodes 1, 2).
// across: the across coordinate (phi, or the offset across the face) of the value.
template <class T>
Gaps<T> endGaps(const LinePairInput& in, const Vec3<T>* P, const Vec3<T>* V, const Vec3<T>* X, bool cubicB, double side,
                double etaStart, double etaPrev, double acrossPrev, double* across, Vec3d* direction, bool held = false,
                Vec3d* supportPoint = nullptr) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  Gaps<T> g;
  const Vec3<T>& pE = P[in.endNode];
  // (A's chord at xi = endNode is the end's centre)
  Vec3<T> onA, xB, dB;
  projectOnB(P, V, false, cubicB, T(static_cast<double>(in.endNode)), etaStart, g, onA, xB);
  axisPoint(P[2], V[2], P[3], V[3], cubicB, g.eta, &xB, &dB, nullptr);
  const T lb = sqrt(dot(dB, dB));
  const Vec3<T> tB = (1.0 / lb) * dB;
  const Vec3<T> w = pE - xB;  // from B's line to the end's centre
  // B's reference vector at eta (the face normal, or the origin of the angle around the axis), made
  // normal to the centre line there (so that the distance along it does not change as the projection
  // moves along the line)
  Vec3<T> m = (1.0 - g.eta) * X[3] + g.eta * X[4];
  m = m - dot(m, tB) * tB;
  m = (1.0 / sqrt(dot(m, m))) * m;
  Vec3<T> u;  // from the end towards B
  Vec3<T> across1;  // the direction of the slip across B (g_T1)
  T distance, offset, arc = T(0.0);  // (arc: circles, the end's distance from B's axis)
  if (in.face) {
    u = -1.0 * m;
    distance = dot(w, m);
    across1 = cross(tB, m);
    across1 = (1.0 / sqrt(dot(across1, across1))) * across1;
    offset = dot(w, across1);
  } else {
    // The separating direction u = cos(phi) a1 + sin(phi) a2 across B's axis (a1 from the end's
    // centre towards the axis) that maximizes the separation side r cos(phi) - r_E A(1 - (u . t)^2):
    // the distance of the disc from B's axis (a face pressed flat on B has its maximum at u = t, not
    // along a1). The maximum in double precision, then Newton steps (exact AD derivatives).
    const T r = sqrt(dot(w, w));
    arc = r;
    const Vec3<T> a1 = (-side / r) * w, a2 = cross(tB, a1);
    const T c1 = dot(a1, X[0]), c2 = dot(a2, X[0]);
    const T R = side * r;
    T phi = T(endAngle(plain(R), plain(c1), plain(c2), in.endRadius));
    for (int it = 0; it < 3; ++it) {
      const T cs = cos(phi), sn = sin(phi);
      const T c = c1 * cs + c2 * sn, dc = c2 * cs - c1 * sn;
      const EndReach<T> a(1.0 - c * c);
      const T ds = -2.0 * c * dc, dds = -2.0 * (dc * dc - c * c);
      const T f1 = -R * sn - in.endRadius * a.d1 * ds;
      const T f2 = -R * cs - in.endRadius * (a.d2 * ds * ds + a.d1 * dds);
      phi -= f1 / f2;
    }
    u = cos(phi) * a1 + sin(phi) * a2;
    distance = R * cos(phi);
    const Vec3<T> f = cross(tB, m);
    offset = atan2(dot(w, f), dot(w, m));
    across1 = cross(tB, (-side) * u);
    across1 = (1.0 / sqrt(dot(across1, across1))) * across1;
  }
  Vec3<T> support;
  const T reach = endReach(in, u, X, support);
  g.gN = distance - in.radiusB - reach;
  const T metric = slipMetric(P, V, cubicB, g.eta, pE);
  g.gT2 = (g.eta - etaPrev) * metric;
  if (in.face) {
    g.gT1 = offset - acrossPrev;
  } else {
    // |p_E - x_B| (phi - acrossPrev), phi - acrossPrev on the branch nearest zero
    const double turns = std::round((plain(offset) - acrossPrev) / (2.0 * M_PI));
    g.gT1 = arc * (offset - (acrossPrev + 2.0 * M_PI * turns));
  }
  if (held) {
    // The variation: the relative motion of the two bodies' material points at one place q, the
    // end's support point, along the three directions held (-u, across B, along B), which are
    // orthonormal. So a unit multiplier applies a unit force on B and its opposite on the end, both
    // at q: their moments balance (forces at the end's centre and B's axis would not), and the
    // Coulomb cone of the multipliers is the cone of the applied force. The end's point at q: its
    // centre and the support point's coordinates in the end's triad (held); B's: its section at the
    // projection (eta held) and q's coordinates in B's frame there (held).
    const Vec3<T> q = pE + support;
    Vec3<T> xh, dh;
    axisPoint(P[2], V[2], P[3], V[3], cubicB, frozen(g.eta), &xh, &dh, nullptr);
    const Vec3<T> th = (1.0 / sqrt(dot(dh, dh))) * dh;
    Vec3<T> mh = (1.0 - frozen(g.eta)) * X[3] + frozen(g.eta) * X[4];
    mh = mh - dot(mh, th) * th;
    mh = (1.0 / sqrt(dot(mh, mh))) * mh;
    const Vec3<T> section[3] = {th, mh, cross(th, mh)};
    holdAtOnePlace(g, materialPointAt(pE, support, X) - materialPointAt(xh, q - xh, section), -1.0 * u, across1, tB);
  }
  const Vec3<T> tA = P[1] - P[0], tBc = P[3] - P[2];
  g.cosine = dot(tA, tBc) / (sqrt(dot(tA, tA)) * sqrt(dot(tBc, tBc)));
  g.length = T(1.0);
  if (across) *across = plain(offset);
  if (direction)
    for (int a = 0; a < 3; ++a) (*direction)[a] = plain(u[a]);
  if (supportPoint)
    for (int a = 0; a < 3; ++a) (*supportPoint)[a] = plain(pE[a] + support[a]);
  return g;
}

// Point contact on the elements' Hermite axes (or chords, see axisPoint): the closest points of the
// curves x_A(xi) (through P[0], P[1], tangents V[0], V[1]) and x_B(eta) (P[2], P[3], V[2], V[3]) from
// the orthogonality conditions F = (x_A' . w, x_B' . w) = 0, w = x_B - x_A, by Newton steps from the
// double solution (xiStart, etaStart): its value is exact, and each step doubles the order of the AD
// derivatives made exact (the error in the Taylor coefficients is O(delta^2) after one step, O(delta^4)
// after two), so two steps give exact first and second variations, the implicit derivatives of xi and
// eta included. Jacobian: dF/d(xi, eta) = [x_A'' . w - |x_A'|^2, x_A' . x_B'; -x_A' . x_B', x_B'' . w +
// |x_B'|^2]. Normal n = sigma (t_B x t_A) / |t_B x t_A| with the curves' tangents at the closest points;
// g_N = w . n - (r_A + r_B); g_T1 = (xi - xiPrev) |x_A'(xi)|, g_T2 = (eta - etaPrev) |x_B'(eta)| (the
// length along the curve per unit parameter at the point: the chord's length on a straight element);
// cosine of the tangents.
template <class T> void curveNewtonStep(const Vec3<T>* P, const Vec3<T>* V, bool cubicA, bool cubicB, T& xi, T& eta) {
  Vec3<T> xA, dA, ddA, xB, dB, ddB;
  axisPoint(P[0], V[0], P[1], V[1], cubicA, xi, &xA, &dA, &ddA);
  axisPoint(P[2], V[2], P[3], V[3], cubicB, eta, &xB, &dB, &ddB);
  const Vec3<T> w = xB - xA;
  const T f1 = dot(dA, w), f2 = dot(dB, w);
  const T ab = dot(dA, dB);
  const T j11 = dot(ddA, w) - dot(dA, dA), j22 = dot(ddB, w) + dot(dB, dB);
  const T det = j11 * j22 + ab * ab;  // j12 = ab, j21 = -ab
  xi -= (j22 * f1 - ab * f2) / det;
  eta -= (ab * f1 + j11 * f2) / det;
}

// The slips' matrix D = M^-1 [m_A, -c |x_B'|; -c |x_A'|, m_B] (curveGaps) as (d11, d12, d21, d22), from
// the slip metrics, the tangents' lengths and their cosine c.
template <class T> std::array<T, 4> slipMatrix(const T& mA, const T& mB, const T& la, const T& lb, const T& c) {
  const T q = 1.0 - c * c;
  return {(mA - c * c * la) / q, c * (mB - lb) / q, c * (mA - la) / q, (mB - c * c * lb) / q};
}

template <class T>
Gaps<T> curveGaps(const Vec3<T>* P, const Vec3<T>* V, bool cubicA, bool cubicB, double radiusSum, double sigma,
                  double xiPrev, double etaPrev, double xiStart, double etaStart, bool held = false) {
  using std::sqrt;
  Gaps<T> g;
  g.xi = T(xiStart);
  g.eta = T(etaStart);
  for (int it = 0; it < 2; ++it) curveNewtonStep(P, V, cubicA, cubicB, g.xi, g.eta);
  Vec3<T> xA, tA, ddA, xB, tB, ddB;
  axisPoint(P[0], V[0], P[1], V[1], cubicA, g.xi, &xA, &tA, &ddA);
  axisPoint(P[2], V[2], P[3], V[3], cubicB, g.eta, &xB, &tB, &ddB);
  const Vec3<T> c = cross(tB, tA);
  const Vec3<T> n = (sigma / sqrt(dot(c, c))) * c;
  const T la = sqrt(dot(tA, tA)), lb = sqrt(dot(tB, tB));
  // The slip metrics: m_A = -j11 / |x_A'| = (|x_A'|^2 - x_A'' . w) / |x_A'|, m_B = j22 / |x_B'| (w = x_B -
  // x_A, j as in curveNewtonStep). For curves crossing at right angles (x_A' . x_B' = 0) a relative
  // motion v of B's point moves xi by x_A' . v / -j11, so m_A dxi = t_A . v: the slip's variation has
  // unit length along the tangent and a friction multiplier applies a force of its own size (on the
  // cone). |x_A'| alone (the chord's length on a straight element, where x'' = 0 and both agree) left
  // out the curvature's share: an applied force 1 / (1 - kappa (r_A + r_B)) times mu N where a curve
  // of curvature kappa turns its convex side to the other (a weave's crossings: 1.28).
  // At other angles the two parameters move together: a relative translation v of B moves them by
  // (dxi, deta) = -J^-1 P (t_A . v, t_B . v), P = diag(|x_A'|, |x_B'|), and the slips g_T = D (xi - xi_p,
  // eta - eta_p) apply the force the Coulomb law means, Q M^-1 lambda_T (M = [1 -c; -c 1], Q = [t_A,
  // -t_B]), when D = -M^-1 S P^-1 J (S = diag(1, -1)) = M^-1 [m_A, -c |x_B'|; -c |x_A'|, m_B]: on the
  // chords (m = |x'|) diag(|x_A'|, |x_B'|), at right angles diag(m_A, m_B).
  // The variations hold D (`held`: its first variations frozen), so the force of a multiplier is the
  // law's at every slip, not only before any: d g_T = D (dxi, deta).
  const T mA = (dot(tA, tA) - dot(ddA, xB - xA)) / la, mB = (dot(tB, tB) + dot(ddB, xB - xA)) / lb;
  const T cosine = dot(tA, tB) / (la * lb);
  const T dxi = g.xi - xiPrev, deta = g.eta - etaPrev;
  std::array<T, 4> D = slipMatrix(mA, mB, la, lb, cosine);
  if (held)
    for (T& d : D) d = frozen(d);
  const auto& [d11, d12, d21, d22] = D;
  g.gN = dot(xB - xA, n) - radiusSum;
  g.gT1 = d11 * dxi + d12 * deta;
  g.gT2 = d21 * dxi + d22 * deta;
  g.cosine = cosine;
  g.length = T(1.0);
  return g;
}

// R and K of every gap from their gradients and Hessians in the coordinates of the four line end
// points (Vectors = 4), of the four end points and the four Hermite tangents (Vectors = 8), or also
// of B's two nodal face normals (Vectors = 10).
template <int Vectors, class Fn>
ContactKinematics kinematicsOf(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Fn gapsOf,
                               Variations order, bool heldVariation = false);
// Line contact's gaps (values, nothing held) with the held variations of g_N, g_T1, g_T2 written out
// per vector (heldLineGaps), and R and K from them by one level of forward AD (heldKinematicsOf).
template <class T, int Vectors> struct HeldLineGaps {
  Gaps<T> g;
  Vec3<T> G[3][Vectors];
};
template <int Vectors, class T>
HeldLineGaps<T, Vectors> heldLineGaps(const LinePairInput& in, const Vec3<T>* P, int turnAt, bool cubicA, bool cubicB,
                                      double side, const T& xi, double etaStart, const T& etaPrev);
template <int Vectors, class Fn>
ContactKinematics heldKinematicsOf(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Fn gapsOf,
                                   Variations order);
template <bool Second>
ContactKinematics pointKinematicsOfOrder(const LinePairInput& in, double sigma, double xiPrev, double etaPrev);
template <bool Second>
ContactKinematics curveKinematicsOfOrder(const LinePairInput& in, double sigma, double xiPrev, double etaPrev);

// Point contact on the Hermite axes (curveGaps): the closest points in double precision, then nested
// forward AD of the gaps in the 24 coordinates of the four line points and four nodal tangents (the
// tests' reference for curveKinematicsOfOrder's written-out gradients).
ContactKinematics curveKinematicsFromGaps(const LinePairInput& in, double sigma, double xiPrev, double etaPrev,
                                          Variations order) {
  const ClosestPoints cp = closestPoints(in);
  const bool cubicA = cubic(in.dA), cubicB = cubic(in.dB);
  return kinematicsOf<8>(
      in, nullptr, nullptr,
      [&](const auto* P, bool held) {
        return curveGaps(P, P + 4, cubicA, cubicB, in.radiusSum, sigma, xiPrev, etaPrev, cp.xi, cp.eta, held);
      },
      order, true);
}

// Where A's axis (the Hermite curve P[0], V[0], P[1], V[1]) meets the plane through `node` normal
// to `tau`: the root of h(xi) = tau . (node - x_A(xi)) by Newton steps from `start` (a double
// solution: as in projectOnB, three steps make the AD derivatives exact).
template <class T>
T planeRoot(const Vec3<T>* P, const Vec3<T>* V, bool cubicA, const Vec3<T>& node, const Vec3<T>& tau, double start,
            int steps) {
  T xi = T(start);
  for (int it = 0; it < steps; ++it) {
    Vec3<T> x, dx;
    axisPoint(P[0], V[0], P[1], V[1], cubicA, xi, &x, &dx, nullptr);
    xi += dot(tau, node - x) / dot(tau, dx);
  }
  return xi;
}

// The segment's bounds as functions of the dofs (the choice of bound from the double solution),
// and the Gauss point xi = lo + s (hi - lo) on it; S the planes' normals at B's two nodes.
template <class T>
void segmentPoint(const Vec3<T>* P, const Vec3<T>* V, const Vec3<T>* S, bool cubicA, const LineSegment& seg, double s,
                  T& xi, T& length) {
  const auto bound = [&](int kind, double value) {
    if (kind < 0) return T(value);
    return planeRoot(P, V, cubicA, P[2 + kind], S[kind], value, 3);
  };
  const T lo = bound(seg.loKind, seg.lo), hi = bound(seg.hiKind, seg.hi);
  length = hi - lo;
  xi = lo + s * length;
}

}  // namespace

Vec3d hermitePoint(const Vec3d& P1, const Vec3d& V1, const Vec3d& P2, const Vec3d& V2, double u) {
  Vec3d x;
  hermite(P1, V1, P2, V2, u, &x, nullptr, nullptr);
  return x;
}

ClosestPoints closestPoints(const LinePairInput& in) {
  ClosestPoints cp;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d pB1 = in.xB1 + in.RB1 * in.oB, pB2 = in.xB2 + in.RB2 * in.oB;
  Vec3d tA = pA2 - pA1, tB = pB2 - pB1;
  Vec3d c = cross(tB, tA);
  cp.sinAngle = norm(c) / (norm(tA) * norm(tB));
  if (!(cp.sinAngle > 1e-12)) return cp;
  solveClosest(pA1, pA2, pB1, pB2, cp.xi, cp.eta);
  cp.pA = pA1 + cp.xi * tA;
  cp.pB = pB1 + cp.eta * tB;
  cp.cA = in.xA1 + cp.xi * (in.xA2 - in.xA1);
  cp.cB = in.xB1 + cp.eta * (in.xB2 - in.xB1);
  if (smoothPoint(in)) {
    // The curves' closest points by Newton's method from the chords' (converged to round-off in a
    // few steps while the elements bend moderately). A solution that does not converge, or runs far
    // beyond the elements (where the cubic's extrapolation means nothing), has no closest points.
    const bool cubicA = cubic(in.dA), cubicB = cubic(in.dB);
    const Vec3d P[4] = {pA1, pA2, pB1, pB2};
    const Vec3d V[4] = {in.RA1 * in.dA, in.RA2 * tangentA2(in), in.RB1 * in.dB, in.RB2 * tangentB2(in)};
    bool converged = false;
    for (int it = 0; it < 50 && !converged; ++it) {
      const double xi0 = cp.xi, eta0 = cp.eta;
      curveNewtonStep(P, V, cubicA, cubicB, cp.xi, cp.eta);
      if (!std::isfinite(cp.xi) || !std::isfinite(cp.eta) || std::abs(cp.xi - 0.5) > 2.5 ||
          std::abs(cp.eta - 0.5) > 2.5)
        break;
      converged = std::abs(cp.xi - xi0) < 1e-15 * (1.0 + std::abs(cp.xi)) &&
                  std::abs(cp.eta - eta0) < 1e-15 * (1.0 + std::abs(cp.eta));
      // (round-off may stall a step above that bound: a step below 1e-13 is a solution too)
      if (!converged && it >= 6)
        converged = std::abs(cp.xi - xi0) < 1e-13 * (1.0 + std::abs(cp.xi)) &&
                    std::abs(cp.eta - eta0) < 1e-13 * (1.0 + std::abs(cp.eta));
    }
    if (!converged) return ClosestPoints{};
    axisPoint(P[0], V[0], P[1], V[1], cubicA, cp.xi, &cp.pA, &tA, nullptr);
    axisPoint(P[2], V[2], P[3], V[3], cubicB, cp.eta, &cp.pB, &tB, nullptr);
    axisPoint(in.xA1, V[0], in.xA2, V[1], cubicA, cp.xi, &cp.cA, nullptr, nullptr);
    axisPoint(in.xB1, V[2], in.xB2, V[3], cubicB, cp.eta, &cp.cB, nullptr, nullptr);
    c = cross(tB, tA);
    cp.sinAngle = norm(c) / (norm(tA) * norm(tB));
    if (!(cp.sinAngle > 1e-12)) return ClosestPoints{};
  }
  const Vec3d n = (1.0 / norm(c)) * c;
  cp.sigma = dot(n, cp.cB - cp.cA) >= 0.0 ? 1.0 : -1.0;
  cp.normal = cp.sigma * n;
  cp.distance = norm(cp.pB - cp.pA);
  cp.gap = dot(cp.pB - cp.pA, cp.normal) - in.radiusSum;
  return cp;
}

ContactKinematics contactKinematics(const LinePairInput& in, double sigma, double xiPrev, double etaPrev,
                                    Variations order) {
  if (smoothPoint(in))
    return order == Variations::Second ? curveKinematicsOfOrder<true>(in, sigma, xiPrev, etaPrev)
                                       : curveKinematicsOfOrder<false>(in, sigma, xiPrev, etaPrev);
  return order == Variations::Second ? pointKinematicsOfOrder<true>(in, sigma, xiPrev, etaPrev)
                                     : pointKinematicsOfOrder<false>(in, sigma, xiPrev, etaPrev);
}

ContactKinematics contactKinematicsFromGaps(const LinePairInput& in, double sigma, double xiPrev, double etaPrev,
                                            Variations order) {
  if (smoothPoint(in)) return curveKinematicsFromGaps(in, sigma, xiPrev, etaPrev, order);
  return kinematicsOf<4>(
      in, nullptr, nullptr,
      [&](const auto* P, bool) { return gaps(P[0], P[1], P[2], P[3], in.radiusSum, sigma, xiPrev, etaPrev); }, order);
}

ClosestPoints lineProjection(const LinePairInput& in, double xi) {
  ClosestPoints cp;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d pB1 = in.xB1 + in.RB1 * in.oB, pB2 = in.xB2 + in.RB2 * in.oB;
  const Vec3d tA = pA2 - pA1, tB = pB2 - pB1;
  cp.sinAngle = norm(cross(tB, tA)) / (norm(tA) * norm(tB));
  cp.xi = xi;
  const Vec3d vA1 = in.RA1 * in.dA, vA2 = in.RA2 * tangentA2(in), vB1 = in.RB1 * in.dB, vB2 = in.RB2 * tangentB2(in);
  const bool cubicA = norm(in.dA) > 0.0, cubicB = norm(in.dB) > 0.0;
  axisPoint(pA1, vA1, pA2, vA2, cubicA, xi, &cp.pA, nullptr, nullptr);
  cp.eta = projectionParameter(pB1, vB1, pB2, vB2, cubicB, cp.pA);
  Vec3d dxB, ddxB, dxA;
  axisPoint(pB1, vB1, pB2, vB2, cubicB, cp.eta, &cp.pB, &dxB, &ddxB);
  axisPoint(pA1, vA1, pA2, vA2, cubicA, xi, nullptr, &dxA, nullptr);
  cp.distance = norm(cp.pB - cp.pA);
  // d/dxi of x_B'(eta) . (x_B(eta) - p_A(xi)) = 0
  cp.etaRate = dot(dxB, dxA) / (dot(ddxB, cp.pB - cp.pA) + dot(dxB, dxB));
  cp.slipMetric = (dot(dxB, dxB) + dot(ddxB, cp.pB - cp.pA)) / norm(dxB);
  if (in.face) {
    // B's face: the normal interpolated between its nodes; the gap along it, outside positive.
    Vec3d m = (1.0 - cp.eta) * (in.RB1 * in.nB) + cp.eta * (in.RB2 * in.nB);
    m = (1.0 / norm(m)) * m;
    cp.normal = -1.0 * m;  // from A towards B
    cp.gap = dot(cp.pA - cp.pB, m);
    const Vec3d across = cross(dxB, m);
    cp.lateral = dot(cp.pA - cp.pB, (1.0 / norm(across)) * across);
    cp.cA = cp.pA;
    cp.cB = cp.pB;
    return cp;
  }
  cp.cA = cp.pA;  // (circular sections: the lines are the axes)
  cp.cB = cp.pB;
  cp.normal = cp.distance > 0.0 ? (1.0 / cp.distance) * (cp.pB - cp.pA) : Vec3d{};
  cp.gap = cp.distance - in.radiusSum;
  return cp;
}

double lineSide(const LinePairInput& in, const ClosestPoints& projection, const Vec3d& keptNormal) {
  if (in.face || dot(keptNormal, keptNormal) == 0.0) return 1.0;
  return dot(projection.pB - projection.pA, keptNormal) < 0.0 ? -1.0 : 1.0;
}

namespace {
// Line contact's kinematics: the Gauss point xi(P) (a fixed parameter, or a point of a segment whose
// bounds move with the dofs) and etaPrev(xi) from the history, through gapsOf(P, V, N, xi, etaPrev).
template <class PointOf>
ContactKinematics lineKinematicsOf(const LinePairInput& in, bool segmented, double side, double etaStart,
                                   Variations order, bool nested, PointOf pointOf) {
  const bool cubicA = norm(in.dA) > 0.0, cubicB = norm(in.dB) > 0.0;
  const Vec3d faceRefs[4] = {in.nB, in.nB, in.sB1, in.sB2};
  const int faceNodes[4] = {2, 3, 2, 3};
  // Circles: the segment planes (segmented) and the turn vectors (LinePairInput::turnSlip) after the
  // eight points and tangents.
  const bool turn = in.turnSlip && !in.face;
  const Vec3d* t = in.turnRef;
  const Vec3d circleRefs[6] = {in.sB1, in.sB2, t[0], t[1], t[2], t[3]}, turnRefs[4] = {t[0], t[1], t[2], t[3]};
  const int circleNodes[6] = {2, 3, 0, 1, 2, 3}, turnNodes[4] = {0, 1, 2, 3};
  const int turnAt = turn ? (segmented ? 10 : 8) : -1;
  ContactKinematics k;
  // held: the variation at the Gauss point's place xi (and etaPrev(xi)) on A, with the slip metric held.
  const auto face = [&](const auto* P, const auto* S, bool held) {
    auto [x, etaPrev, length] = pointOf(P, P + 4, S);
    if (held) x = frozen(x), etaPrev = frozen(etaPrev);
    auto g = faceGaps(P, P + 4, P + 8, cubicA, cubicB, x, etaStart, etaPrev, held);
    g.length = length;
    return g;
  };
  const auto circle = [&](const auto* P, const auto* S, bool held) {
    auto [x, etaPrev, length] = pointOf(P, P + 4, S);
    if (held) x = frozen(x), etaPrev = frozen(etaPrev);
    auto g = lineGaps(in, P, P + 4, turn ? P + turnAt : nullptr, cubicA, cubicB, in.radiusSum, x, etaStart, etaPrev,
                      side, held);
    g.length = length;
    return g;
  };
  // The held variations written out (heldLineGaps), one AD level: the default.
  const auto written = [&](const auto* P, const auto* S, auto vectors) {
    auto [x, etaPrev, length] = pointOf(P, P + 4, S);
    auto h = heldLineGaps<decltype(vectors)::value>(in, P, turnAt, cubicA, cubicB, side, x, etaStart, etaPrev);
    h.g.length = length;
    return h;
  };
  using V8 = std::integral_constant<int, 8>;
  using V10 = std::integral_constant<int, 10>;
  using V12 = std::integral_constant<int, 12>;
  using V14 = std::integral_constant<int, 14>;
  if (!nested) {
    if (in.face && segmented)
      k = heldKinematicsOf<12>(
          in, faceRefs, faceNodes, [&](const auto* P) { return written(P, P + 10, V12{}); }, order);
    else if (in.face)
      k = heldKinematicsOf<10>(
          in, faceRefs, faceNodes, [&](const auto* P) { return written(P, P, V10{}); }, order);
    else if (segmented && turn)
      k = heldKinematicsOf<14>(
          in, circleRefs, circleNodes, [&](const auto* P) { return written(P, P + 8, V14{}); }, order);
    else if (segmented)
      k = heldKinematicsOf<10>(
          in, circleRefs, circleNodes, [&](const auto* P) { return written(P, P + 8, V10{}); }, order);
    else if (turn)
      k = heldKinematicsOf<12>(
          in, turnRefs, turnNodes, [&](const auto* P) { return written(P, P, V12{}); }, order);
    else
      k = heldKinematicsOf<8>(
          in, nullptr, nullptr, [&](const auto* P) { return written(P, P, V8{}); }, order);
  } else if (in.face && segmented)
    k = kinematicsOf<12>(
        in, faceRefs, faceNodes, [&](const auto* P, bool held) { return face(P, P + 10, held); }, order, true);
  else if (in.face)
    k = kinematicsOf<10>(
        in, faceRefs, faceNodes, [&](const auto* P, bool held) { return face(P, P, held); }, order, true);
  else if (segmented && turn)
    k = kinematicsOf<14>(
        in, circleRefs, circleNodes, [&](const auto* P, bool held) { return circle(P, P + 8, held); }, order, true);
  else if (segmented)
    k = kinematicsOf<10>(
        in, circleRefs, circleNodes, [&](const auto* P, bool held) { return circle(P, P + 8, held); }, order, true);
  else if (turn)
    k = kinematicsOf<12>(
        in, turnRefs, turnNodes, [&](const auto* P, bool held) { return circle(P, P, held); }, order, true);
  else
    k = kinematicsOf<8>(
        in, nullptr, nullptr, [&](const auto* P, bool held) { return circle(P, P, held); }, order, true);
  k.cosine = 0.0;
  k.cosineR.fill(0.0);
  return k;
}
}  // namespace

namespace {
ContactKinematics lineKinematicsBy(const LinePairInput& in, double xi, double etaPrev, const Vec3d& keptNormal,
                                   Variations order, bool nested) {
  const ClosestPoints projection = lineProjection(in, xi);
  return lineKinematicsOf(in, false, lineSide(in, projection, keptNormal), projection.eta, order, nested,
                          [&](const auto* P, const auto*, const auto*) {
                            using T = std::decay_t<decltype(P[0][0])>;
                            return std::make_tuple(T(xi), T(etaPrev), T(1.0));
                          });
}
}  // namespace

ContactKinematics lineKinematics(const LinePairInput& in, double xi, double etaPrev, const Vec3d& keptNormal,
                                 Variations order) {
  return lineKinematicsBy(in, xi, etaPrev, keptNormal, order, false);
}

ContactKinematics lineKinematicsFromGaps(const LinePairInput& in, double xi, double etaPrev, const Vec3d& keptNormal,
                                         Variations order) {
  return lineKinematicsBy(in, xi, etaPrev, keptNormal, order, true);
}

LineSegment lineSegment(const LinePairInput& in) {
  LineSegment seg;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d P[2] = {pA1, pA2}, V[2] = {in.RA1 * in.dA, in.RA2 * tangentA2(in)};
  const bool cubicA = norm(in.dA) > 0.0;
  const Vec3d node[2] = {in.xB1 + in.RB1 * in.oB, in.xB2 + in.RB2 * in.oB};
  const Vec3d tau[2] = {in.RB1 * in.sB1, in.RB2 * in.sB2};
  // inside_j(xi) >= 0 where A's point lies on B's element's side of plane j: past node 1's plane
  // along tau_1, before node 2's along tau_2; with its Newton step towards the plane in `step`.
  const auto inside = [&](int j, double xi, double* step = nullptr) {
    Vec3d x, dx;
    axisPoint(P[0], V[0], P[1], V[1], cubicA, xi, &x, &dx, static_cast<Vec3d*>(nullptr));
    const double f = dot(tau[j], x - node[j]);
    if (step) *step = dot(tau[j], node[j] - x) / dot(tau[j], dx);  // (planeRoot's step)
    return j == 0 ? f : -f;
  };
  seg.lo = 0.0;
  seg.hi = 1.0;
  for (int j = 0; j < 2; ++j) {
    // The plane must cross A's axis at a clear angle.
    const double along = dot(tau[j], pA2 - pA1);
    if (!(std::abs(along) > 1e-3 * norm(tau[j]) * norm(pA2 - pA1))) return LineSegment{};
    const double at0 = inside(j, 0.0), at1 = inside(j, 1.0);
    if (!std::isfinite(at0) || !std::isfinite(at1)) return LineSegment{};
    if (at0 >= 0.0 && at1 >= 0.0) continue;  // the whole element on B's side of this plane
    if (at0 < 0.0 && at1 < 0.0) return LineSegment{};  // none of it
    // The plane cuts A's element: its root inside [0, 1], by Newton's method kept in the bracket
    // (bisection where a step would leave it). Only the root inside the element bounds the segment:
    // a root on the cubic's extension beyond the element's ends (where Newton may wander between
    // the cubic's other roots or diverge) would make the segment jump with the dofs.
    double a = 0.0, b = 1.0, fa = at0;
    double xi = at0 / (at0 - at1);  // the chord's root
    for (int it = 0; it < 100; ++it) {
      double newton = 0.0;
      const double fx = inside(j, xi, &newton), next = xi + newton;
      if (fx == 0.0) break;
      if ((fx < 0.0) == (fa < 0.0)) a = xi, fa = fx;
      else b = xi;
      const double step = (next > a && next < b) ? next - xi : 0.5 * (a + b) - xi;
      xi += step;
      if (std::abs(step) < 1e-15 * (1.0 + std::abs(xi)) || b - a < 1e-15) break;
    }
    if (at0 < 0.0) {  // [xi, 1] lies on B's side
      if (xi > seg.lo) seg.lo = xi, seg.loKind = j;
    } else if (xi < seg.hi) {  // [0, xi]
      seg.hi = xi, seg.hiKind = j;
    }
  }
  if (!(seg.hi > seg.lo)) return LineSegment{};
  return seg;
}

namespace {
ContactKinematics segmentKinematicsBy(const LinePairInput& in, const LineSegment& seg, double s, const LineHistory& h,
                                      const Vec3d& keptNormal, Variations order, bool nested) {
  const bool cubicA = norm(in.dA) > 0.0;
  const double xi = seg.lo + s * (seg.hi - seg.lo);
  const ClosestPoints projection = lineProjection(in, xi);
  return lineKinematicsOf(in, true, lineSide(in, projection, keptNormal), projection.eta, order, nested,
                          [&](const auto* P, const auto* V, const auto* S) {
                            using T = std::decay_t<decltype(P[0][0])>;
                            T x, length;
                            segmentPoint(P, V, S, cubicA, seg, s, x, length);
                            return std::make_tuple(x, h.etaPrevAt(x), length);
                          });
}
}  // namespace

ContactKinematics segmentKinematics(const LinePairInput& in, const LineSegment& seg, double s, const LineHistory& h,
                                    const Vec3d& keptNormal, Variations order) {
  return segmentKinematicsBy(in, seg, s, h, keptNormal, order, false);
}

ContactKinematics segmentKinematicsFromGaps(const LinePairInput& in, const LineSegment& seg, double s,
                                            const LineHistory& h, const Vec3d& keptNormal, Variations order) {
  return segmentKinematicsBy(in, seg, s, h, keptNormal, order, true);
}

namespace {
// The gaps' values, gradients G and (with second variations) Hessians H in the coordinates of the
// vectors (3 per vector), as the kernels below hand them to the chain rule.
enum Quantity { kGapN, kGapT1, kGapT2, kXi, kEta, kCosine, kLength, kQuantities };
template <int kCoords> struct CoordinateGaps {
  double value[kQuantities];
  double G[kQuantities][kCoords];  // (the gaps: their variations)
  double gradient[3][kCoords];  // g_N, g_T1, g_T2: the gradients of their values
  double H[3][kCoords][kCoords];  // g_N, g_T1, g_T2: the variations' derivatives
};

// The rotated part r_k of each vector and its node.
template <int Vectors> struct VectorFrame {
  Vec3d r[Vectors];
  int node[Vectors];
};

// The gaps depend on the 24 dofs only through vectors attached to the four nodes m: the line end
// points P_m = x_m + R_m o and (Vectors = 8) the Hermite tangents V_m = R_m d. With the spin
// variation w and the Newton increment delta, a rotated vector r_m = R_m c becomes
// exp(w) exp(delta) r_m, so
//   dP_m = du_m + w x r_m,   dV_m = w x V_m,   d2(r) / dw_i d delta_j = e_i x (e_j x r),
//   R = J^T G,   K_ij = (J^T H J)_ij + sum_k G_k . (e_i x (e_j x r_k)) on vector k's node's spins.
template <int Vectors, bool Second>
ContactKinematics chainRule(const CoordinateGaps<3 * Vectors>& c, const VectorFrame<Vectors>& v) {
  // J by vector: vector k's three rows are nonzero in its node's six columns only, [I (points only),
  // C_k] with C_k e_b = e_b x r_k.
  double Jk[Vectors][3][6];
  for (int k = 0; k < Vectors; ++k)
    for (int b = 0; b < 3; ++b) {
      Vec3d e{};
      e[b] = 1.0;
      const Vec3d col = cross(e, v.r[k]);
      for (int a = 0; a < 3; ++a) {
        Jk[k][a][b] = k < 4 && a == b ? 1.0 : 0.0;
        Jk[k][a][3 + b] = col[a];
      }
    }
  // R = J^T G.
  const auto map = [&](const double* coordinates, Vector24& R) {
    R.fill(0.0);
    for (int k = 0; k < Vectors; ++k) {
      const double* G = &coordinates[3 * k];
      double* Rm = &R[6 * v.node[k]];
      for (int j = 0; j < 6; ++j) Rm[j] += Jk[k][0][j] * G[0] + Jk[k][1][j] * G[1] + Jk[k][2][j] * G[2];
    }
  };
  const auto firstVariation = [&](int q, Vector24& R) { map(c.G[q], R); };
  ContactKinematics out;
  out.xi = c.value[kXi];
  out.eta = c.value[kEta];
  out.cosine = c.value[kCosine];
  firstVariation(kCosine, out.cosineR);
  out.axesCosine = out.cosine;
  out.axesCosineR = out.cosineR;
  out.segment = c.value[kLength];
  firstVariation(kXi, out.xiR);
  firstVariation(kLength, out.segmentR);
  GapDerivatives* dst[3] = {&out.normal, &out.tangent1, &out.tangent2};
  for (int q = 0; q < 3; ++q) {
    GapDerivatives& d = *dst[q];
    d.value = c.value[q];
    firstVariation(q, d.R);
    map(c.gradient[q], d.gradient);
    if constexpr (Second) {
      // J^T H J by 3 x 3 blocks of H.
      const auto& H = c.H[q];
      d.K.fill(0.0);
      for (int k = 0; k < Vectors; ++k) {
        const int mk = v.node[k];
        for (int l = 0; l < Vectors; ++l) {
          const int ml = v.node[l];
          double HJ[3][6];
          for (int a = 0; a < 3; ++a)
            for (int j = 0; j < 6; ++j)
              HJ[a][j] = H[3 * k + a][3 * l] * Jk[l][0][j] + H[3 * k + a][3 * l + 1] * Jk[l][1][j] +
                         H[3 * k + a][3 * l + 2] * Jk[l][2][j];
          for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j)
              d.K[kPairDofs * (6 * mk + i) + 6 * ml + j] +=
                  Jk[k][0][i] * HJ[0][j] + Jk[k][1][i] * HJ[1][j] + Jk[k][2][i] * HJ[2][j];
        }
      }
      // Second derivatives of the rotated vectors, on the spins of the same node:
      // G_k . (e_i x (e_j x r_k)) = r_k,i G_k,j - delta_ij (G_k . r_k).
      for (int k = 0; k < Vectors; ++k) {
        const int m = v.node[k];
        const double* G = &c.G[q][3 * k];
        const Vec3d& r = v.r[k];
        const double Gr = G[0] * r[0] + G[1] * r[1] + G[2] * r[2];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            d.K[kPairDofs * (6 * m + 3 + i) + 6 * m + 3 + j] += r[i] * G[j] - (i == j ? Gr : 0.0);
      }
    }
  }
  return out;
}

// Vector k: 0-3 the points of nodes 0-3, 4-7 their tangents, from 8 on the extra vectors R_m c (face
// normals, segment planes) of the nodes extraNode with references extraRef. p[k]: the vector's value.
template <int Vectors>
VectorFrame<Vectors> vectorFrame(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Vec3d* p) {
  const Vec3d* x[4] = {&in.xA1, &in.xA2, &in.xB1, &in.xB2};
  const Mat3d* Rm[4] = {&in.RA1, &in.RA2, &in.RB1, &in.RB2};
  const Vec3d* o[4] = {&in.oA, &in.oA, &in.oB, &in.oB};
  const Vec3d* dv[4] = {&in.dA, &tangentA2(in), &in.dB, &tangentB2(in)};
  VectorFrame<Vectors> v;
  for (int k = 0; k < Vectors; ++k) {
    const int m = k < 8 ? k % 4 : extraNode[k - 8];
    v.node[k] = m;
    v.r[k] = (*Rm[m]) * (k < 4 ? *o[m] : (k < 8 ? *dv[m] : extraRef[k - 8]));
    p[k] = k < 4 ? *x[m] + v.r[k] : v.r[k];
  }
  return v;
}

// The gaps' values, their gradients as the variations G, and the gradients of g_N, g_T1, g_T2, from
// one AD level over the kCoords coordinates.
template <int kCoords, class In> void valuesAndGradients(const Gaps<In>& g, CoordinateGaps<kCoords>& c) {
  const In* src[kQuantities] = {&g.gN, &g.gT1, &g.gT2, &g.xi, &g.eta, &g.cosine, &g.length};
  for (int q = 0; q < kQuantities; ++q) {
    c.value[q] = src[q]->val();
    for (int k = 0; k < kCoords; ++k) c.G[q][k] = src[q]->dx(k);
    if (q < 3)
      for (int k = 0; k < kCoords; ++k) c.gradient[q][k] = c.G[q][k];
  }
}

// G and H of the gaps by nested forward AD of gapsOf (inner level: the variation, outer: the
// increment; one level with first variations only).
template <int Vectors, bool Second, class Fn>
ContactKinematics kinematicsOfOrder(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Fn gapsOf,
                                    bool heldVariation) {
  constexpr int kCoords = 3 * Vectors;
  using In = Sacado::Fad::SFad<double, kCoords>;
  using Out = std::conditional_t<Second, Sacado::Fad::SFad<In, kCoords>, In>;
  Vec3d p[Vectors];
  const VectorFrame<Vectors> frame = vectorFrame<Vectors>(in, extraRef, extraNode, p);
  CoordinateGaps<kCoords> c;
  // The values and their gradients, all quantities (one AD level).
  const auto full = [&]() {
    Vec3<In> Q[Vectors];
    for (int k = 0; k < Vectors; ++k)
      for (int a = 0; a < 3; ++a) Q[k][a] = In(kCoords, 3 * k + a, p[k][a]);
    valuesAndGradients(gapsOf(static_cast<const Vec3<In>*>(Q), false), c);
  };
  if (heldVariation || !Second) full();
  // The gaps' variations (with the held quantities frozen where heldVariation) and their derivatives.
  if (Second || heldVariation) {
    Vec3<Out> P[Vectors];
    for (int k = 0; k < Vectors; ++k)
      for (int a = 0; a < 3; ++a) {
        if constexpr (Second) P[k][a] = Out(kCoords, 3 * k + a, In(kCoords, 3 * k + a, p[k][a]));
        else P[k][a] = Out(kCoords, 3 * k + a, p[k][a]);
      }
    const Gaps<Out> g = gapsOf(static_cast<const Vec3<Out>*>(P), heldVariation);
    const Out* src[kQuantities] = {&g.gN, &g.gT1, &g.gT2, &g.xi, &g.eta, &g.cosine, &g.length};
    // Without held quantities this pass gives the values and gradients too.
    const int quantities = heldVariation ? 3 : kQuantities;
    for (int q = 0; q < quantities; ++q) {
      const Out& v = *src[q];
      if constexpr (Second) {
        if (!heldVariation) c.value[q] = v.val().val();
        for (int k = 0; k < kCoords; ++k) c.G[q][k] = v.val().dx(k);
        if (q < 3)
          for (int k = 0; k < kCoords; ++k)
            for (int l = 0; l < kCoords; ++l) c.H[q][k][l] = v.dx(l).dx(k);
      } else {
        for (int k = 0; k < kCoords; ++k) c.G[q][k] = v.dx(k);
      }
      if (!heldVariation && q < 3)
        for (int k = 0; k < kCoords; ++k) c.gradient[q][k] = c.G[q][k];
    }
  }
  return chainRule<Vectors, Second>(c, frame);
}

// The point gaps of two straight lines (gaps above) and their gradients in the 12 coordinates of the
// end points P, written out. With a = P1 - P0, b = P3 - P2 and w = p_B - p_A = (g_N + r) n, which is
// orthogonal to a and b:
//  - g_N: dg_N = n . (dp_B - dp_A) at fixed (xi, eta) (their variations and dn are orthogonal to w);
//  - xi, eta from the orthogonality a . w = b . w = 0: aa dxi - ab deta = u1, ab dxi - bb deta = u2,
//    u1 = da . w + a . (dd + eta db - xi da), u2 = db . w + b . (dd + eta db - xi da), d = P2 - P0;
//  - g_T1 = (xi - xiPrev) |a|, g_T2 = (eta - etaPrev) |b|, cosine = a . b / (|a| |b|).
// T = double gives the first variations; T = SFad<double, 12> seeded on the coordinates also the
// Hessians (the gradients' derivatives).
template <class T>
void pointGapGradients(const Vec3<T>* P, double radiusSum, double sigma, double xiPrev, double etaPrev,
                       T value[kQuantities], Vec3<T> G[kQuantities][4]) {
  using std::sqrt;
  const Vec3<T> a = P[1] - P[0], b = P[3] - P[2];
  T xi, eta;
  solveClosest(P[0], P[1], P[2], P[3], xi, eta);
  const Vec3<T> w = (P[2] + eta * b) - (P[0] + xi * a);
  const Vec3<T> c = cross(b, a);
  const Vec3<T> n = (sigma / sqrt(dot(c, c))) * c;
  const T aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
  const T la = sqrt(aa), lb = sqrt(bb);
  const T det = aa * bb - ab * ab;
  value[kGapN] = dot(w, n) - radiusSum;
  value[kGapT1] = (xi - xiPrev) * la;
  value[kGapT2] = (eta - etaPrev) * lb;
  value[kXi] = xi;
  value[kEta] = eta;
  value[kCosine] = ab / (la * lb);
  value[kLength] = T(1.0);
  const T oneXi = 1.0 - xi, oneEta = 1.0 - eta;
  const Vec3<T> U1[4] = {T(-1.0) * w - oneXi * a, w - xi * a, oneEta * a, eta * a};
  const Vec3<T> U2[4] = {T(-1.0) * (oneXi * b), T(-1.0) * (xi * b), oneEta * b - w, w + eta * b};
  const Vec3<T> gN[4] = {T(-1.0) * (oneXi * n), T(-1.0) * (xi * n), oneEta * n, eta * n};
  const Vec3<T> slipA = ((xi - xiPrev) / la) * a, slipB = ((eta - etaPrev) / lb) * b;
  const Vec3<T> cosA = (1.0 / (la * lb)) * b - (value[kCosine] / aa) * a;
  const Vec3<T> cosB = (1.0 / (la * lb)) * a - (value[kCosine] / bb) * b;
  const T zero(0.0);
  const Vec3<T> none{{zero, zero, zero}};
  for (int k = 0; k < 4; ++k) {
    const Vec3<T> dXi = (1.0 / det) * (bb * U1[k] - ab * U2[k]);
    const Vec3<T> dEta = (1.0 / det) * (ab * U1[k] - aa * U2[k]);
    const double signA = k == 0 ? -1.0 : k == 1 ? 1.0 : 0.0, signB = k == 2 ? -1.0 : k == 3 ? 1.0 : 0.0;
    G[kGapN][k] = gN[k];
    G[kGapT1][k] = la * dXi + signA * slipA;
    G[kGapT2][k] = lb * dEta + signB * slipB;
    G[kXi][k] = dXi;
    G[kEta][k] = dEta;
    G[kCosine][k] = signA * cosA + signB * cosB;
    G[kLength][k] = none;
  }
}

// The vectors' coordinates as the independent variables of one AD level (Second), or as they are.
template <int Points, bool Second, class T> void seedVectors(const Vec3d* p, Vec3<T>* P) {
  for (int k = 0; k < Points; ++k)
    for (int a = 0; a < 3; ++a) {
      if constexpr (Second) P[k][a] = T(3 * Points, 3 * k + a, p[k][a]);
      else P[k][a] = p[k][a];
    }
}

// The gaps' values, gradients and (Second) Hessians in the coordinates of `Points` vectors, from their
// values and gradients per vector (of AD type with the coordinates' derivatives when Second).
template <int Points, bool Second, class T>
CoordinateGaps<3 * Points> coordinateGaps(const T* value, const Vec3<T> (*G)[Points],
                                          const Vec3<T> (*gradient)[Points] = nullptr) {
  constexpr int n = 3 * Points;
  CoordinateGaps<n> c;
  for (int q = 0; q < kQuantities; ++q) {
    if constexpr (Second) {
      c.value[q] = value[q].val();
      for (int k = 0; k < n; ++k) c.G[q][k] = G[q][k / 3][k % 3].val();
      if (q < 3)
        for (int k = 0; k < n; ++k)
          for (int l = 0; l < n; ++l) c.H[q][k][l] = G[q][k / 3][k % 3].dx(l);
    } else {
      c.value[q] = value[q];
      for (int k = 0; k < n; ++k) c.G[q][k] = G[q][k / 3][k % 3];
    }
  }
  // (The values' gradients where the variations hold something: `gradient`.)
  for (int q = 0; q < 3; ++q)
    for (int k = 0; k < n; ++k) {
      if (!gradient) c.gradient[q][k] = c.G[q][k];
      else if constexpr (Second) c.gradient[q][k] = gradient[q][k / 3][k % 3].val();
      else c.gradient[q][k] = gradient[q][k / 3][k % 3];
    }
  return c;
}

template <bool Second>
ContactKinematics pointKinematicsOfOrder(const LinePairInput& in, double sigma, double xiPrev, double etaPrev) {
  using T = std::conditional_t<Second, Sacado::Fad::SFad<double, 12>, double>;
  Vec3d p[4];
  const VectorFrame<4> frame = vectorFrame<4>(in, nullptr, nullptr, p);
  Vec3<T> P[4];
  seedVectors<4, Second>(p, P);
  T value[kQuantities];
  Vec3<T> G[kQuantities][4];
  pointGapGradients(P, in.radiusSum, sigma, xiPrev, etaPrev, value, G);
  return chainRule<4, Second>(coordinateGaps<4, Second>(value, G), frame);
}

// The shape values of the vectors (P_1, P_2, V_1, V_2) of one curve at u and their first and second
// derivatives: the cubic Hermite basis, or the chord's (1 - u, u, 0, 0).
template <class T> struct CurveShape { T s[4], d[4], dd[4], ddd[4]; };
template <class T> CurveShape<T> curveShape(bool cubicCurve, const T& u) {
  CurveShape<T> c;
  const T zero(0.0);
  if (!cubicCurve) {
    c.s[0] = 1.0 - u, c.s[1] = u, c.s[2] = zero, c.s[3] = zero;
    c.d[0] = T(-1.0), c.d[1] = T(1.0), c.d[2] = zero, c.d[3] = zero;
    for (T& v : c.dd) v = zero;
    for (T& v : c.ddd) v = zero;
    return c;
  }
  const T u2 = u * u, u3 = u2 * u;
  c.s[0] = 1.0 - 3.0 * u2 + 2.0 * u3, c.s[1] = 3.0 * u2 - 2.0 * u3, c.s[2] = u - 2.0 * u2 + u3, c.s[3] = u3 - u2;
  c.d[0] = 6.0 * u2 - 6.0 * u, c.d[1] = 6.0 * u - 6.0 * u2, c.d[2] = 1.0 - 4.0 * u + 3.0 * u2,
  c.d[3] = 3.0 * u2 - 2.0 * u;
  c.dd[0] = 12.0 * u - 6.0, c.dd[1] = 6.0 - 12.0 * u, c.dd[2] = 6.0 * u - 4.0, c.dd[3] = 6.0 * u - 2.0;
  c.ddd[0] = T(12.0), c.ddd[1] = T(-12.0), c.ddd[2] = T(6.0), c.ddd[3] = T(6.0);
  return c;
}

// The point gaps on the Hermite axes (curveGaps) and their gradients in the 24 coordinates of the
// vectors Q = (P_A1, P_A2, P_B1, P_B2, V_A1, V_A2, V_B1, V_B2), written out. With s_k, d_k the shape
// values of vector k on A at xi and on B at eta (zero on the other curve), w = x_B - x_A = (g_N + r) n,
// which is orthogonal to x_A' and x_B':
//  - g_N: dg_N = n . (dx_B - dx_A) at fixed (xi, eta): G_k = (sB_k - sA_k) n;
//  - xi, eta from F = (x_A' . w, x_B' . w) = 0: J (dxi, deta) = -(dF1, dF2), dF1_k = dA_k w + (sB_k -
//    sA_k) x_A', dF2_k = dB_k w + (sB_k - sA_k) x_B', J as in curveNewtonStep;
//  - the tangents' variations dt_A = sum_k dA_k dQ_k + x_A'' dxi (and B's), and from them the cosine,
//    the slip metrics m_A, m_B (with x''' for the change of x'' . w) and the slips D (xi - xiPrev,
//    eta - etaPrev) (curveGaps) by the product and quotient rules.
// T = double gives the first variations at the double solution; T = SFad<double, 24> seeded on the
// coordinates, with xi and eta through one Newton step from it (exact first derivatives), the Hessians.
template <class T>
void curveGapGradients(const Vec3<T>* Q, bool cubicA, bool cubicB, double radiusSum, double sigma, double xiPrev,
                       double etaPrev, double xiStart, double etaStart, T value[kQuantities], Vec3<T> G[kQuantities][8],
                       Vec3<T> Gv[3][8]) {
  using std::sqrt;
  T xi = T(xiStart), eta = T(etaStart);
  if constexpr (!std::is_same_v<T, double>) curveNewtonStep(Q, Q + 4, cubicA, cubicB, xi, eta);
  const CurveShape<T> a = curveShape(cubicA, xi), b = curveShape(cubicB, eta);
  // Vector k's shape values on A and B (A's vectors: 0, 1, 4, 5; B's: 2, 3, 6, 7).
  const T zero(0.0);
  T sA[8], dA[8], ddAk[8], sB[8], dB[8], ddBk[8];
  const int slot[8] = {0, 1, 0, 1, 2, 3, 2, 3};
  Vec3<T> xA{{zero, zero, zero}}, tA = xA, ddA = xA, dddA = xA, xB = xA, tB = xA, ddB = xA, dddB = xA;
  for (int k = 0; k < 8; ++k) {
    const bool onA = k == 0 || k == 1 || k == 4 || k == 5;
    const int j = slot[k];
    sA[k] = onA ? a.s[j] : zero, dA[k] = onA ? a.d[j] : zero, ddAk[k] = onA ? a.dd[j] : zero;
    sB[k] = onA ? zero : b.s[j], dB[k] = onA ? zero : b.d[j], ddBk[k] = onA ? zero : b.dd[j];
    if (onA)
      xA = xA + a.s[j] * Q[k], tA = tA + a.d[j] * Q[k], ddA = ddA + a.dd[j] * Q[k], dddA = dddA + a.ddd[j] * Q[k];
    else xB = xB + b.s[j] * Q[k], tB = tB + b.d[j] * Q[k], ddB = ddB + b.dd[j] * Q[k], dddB = dddB + b.ddd[j] * Q[k];
  }
  const Vec3<T> w = xB - xA;
  const Vec3<T> c = cross(tB, tA);
  const Vec3<T> n = (sigma / sqrt(dot(c, c))) * c;
  const T aa = dot(tA, tA), bb = dot(tB, tB), ab = dot(tA, tB);
  const T la = sqrt(aa), lb = sqrt(bb);
  const T j11 = dot(ddA, w) - aa, j22 = dot(ddB, w) + bb, det = j11 * j22 + ab * ab;
  // The slip metrics (curveGaps): m_A = -j11 / |x_A'|, m_B = j22 / |x_B'|, and the slips D (xi - xi_p,
  // eta - eta_p), D = M^-1 [m_A, -c |x_B'|; -c |x_A'|, m_B] = [d11, d12; d21, d22].
  const T mA = (aa - dot(ddA, w)) / la, mB = (bb + dot(ddB, w)) / lb;
  const T cosine = ab / (la * lb), q = 1.0 - cosine * cosine;
  const auto [d11, d12, d21, d22] = slipMatrix(mA, mB, la, lb, cosine);
  value[kGapN] = dot(w, n) - radiusSum;
  value[kGapT1] = d11 * (xi - xiPrev) + d12 * (eta - etaPrev);
  value[kGapT2] = d21 * (xi - xiPrev) + d22 * (eta - etaPrev);
  value[kXi] = xi;
  value[kEta] = eta;
  value[kCosine] = cosine;
  value[kLength] = T(1.0);
  const Vec3<T> cosA = (1.0 / (la * lb)) * tB - (cosine / aa) * tA;  // d cosine / d t_A
  const Vec3<T> cosB = (1.0 / (la * lb)) * tA - (cosine / bb) * tB;
  const T slipA = xi - xiPrev, slipB = eta - etaPrev;
  const T tAddA = dot(tA, ddA), tBddB = dot(tB, ddB), cAddA = dot(cosA, ddA), cBddB = dot(cosB, ddB);
  const T wdddA = dot(w, dddA), wdddB = dot(w, dddB), tAddB = dot(tA, ddB), tBddA = dot(tB, ddA);
  const Vec3<T> none{{zero, zero, zero}};
  for (int k = 0; k < 8; ++k) {
    const T s = sB[k] - sA[k];
    const Vec3<T> dF1 = dA[k] * w + s * tA, dF2 = dB[k] * w + s * tB;
    const Vec3<T> dXi = (-1.0 / det) * (j22 * dF1 - ab * dF2);
    const Vec3<T> dEta = (-1.0 / det) * (ab * dF1 + j11 * dF2);
    G[kGapN][k] = s * n;
    // m_A = (|x_A'|^2 - x_A'' . w) / |x_A'| by the product rule; dw = s dQ_k + x_B' deta - x_A' dxi.
    const Vec3<T> dLa = (1.0 / la) * (dA[k] * tA + tAddA * dXi), dLb = (1.0 / lb) * (dB[k] * tB + tBddB * dEta);
    const Vec3<T> dDdAw = ddAk[k] * w + wdddA * dXi + s * ddA + tBddA * dEta - tAddA * dXi;
    const Vec3<T> dDdBw = ddBk[k] * w + wdddB * dEta + s * ddB + tBddB * dEta - tAddB * dXi;
    const Vec3<T> dMA = (1.0 / la) * (2.0 * la * dLa - dDdAw) - (mA / la) * dLa;
    const Vec3<T> dMB = (1.0 / lb) * (2.0 * lb * dLb + dDdBw) - (mB / lb) * dLb;
    const Vec3<T> dC = dA[k] * cosA + cAddA * dXi + dB[k] * cosB + cBddB * dEta;
    // D's entries by the quotient rule (dq = -2 c dc).
    const Vec3<T> dQ = (-2.0 * cosine) * dC;
    const Vec3<T> dD11 = (1.0 / q) * (dMA - (2.0 * cosine * la) * dC - (cosine * cosine) * dLa) - (d11 / q) * dQ;
    const Vec3<T> dD12 = (1.0 / q) * ((mB - lb) * dC + cosine * (dMB - dLb)) - (d12 / q) * dQ;
    const Vec3<T> dD21 = (1.0 / q) * ((mA - la) * dC + cosine * (dMA - dLa)) - (d21 / q) * dQ;
    const Vec3<T> dD22 = (1.0 / q) * (dMB - (2.0 * cosine * lb) * dC - (cosine * cosine) * dLb) - (d22 / q) * dQ;
    // The variations hold D (curveGaps); the values' gradients have its change too.
    G[kGapT1][k] = d11 * dXi + d12 * dEta;
    G[kGapT2][k] = d21 * dXi + d22 * dEta;
    Gv[kGapN][k] = G[kGapN][k];
    Gv[kGapT1][k] = G[kGapT1][k] + slipA * dD11 + slipB * dD12;
    Gv[kGapT2][k] = G[kGapT2][k] + slipA * dD21 + slipB * dD22;
    G[kXi][k] = dXi;
    G[kEta][k] = dEta;
    G[kCosine][k] = dC;
    G[kLength][k] = none;
  }
}

template <bool Second>
ContactKinematics curveKinematicsOfOrder(const LinePairInput& in, double sigma, double xiPrev, double etaPrev) {
  using T = std::conditional_t<Second, Sacado::Fad::SFad<double, 24>, double>;
  const ClosestPoints cp = closestPoints(in);
  Vec3d p[8];
  const VectorFrame<8> frame = vectorFrame<8>(in, nullptr, nullptr, p);
  Vec3<T> Q[8];
  seedVectors<8, Second>(p, Q);
  T value[kQuantities];
  Vec3<T> G[kQuantities][8], Gv[3][8];
  curveGapGradients(Q, cubic(in.dA), cubic(in.dB), in.radiusSum, sigma, xiPrev, etaPrev, cp.xi, cp.eta, value, G, Gv);
  return chainRule<8, Second>(coordinateGaps<8, Second>(value, G, Gv), frame);
}

// lineGaps and faceGaps (held = false: the values) and their held variations written out. P: the
// vectors (P_A1, P_A2, P_B1, P_B2, V_A1, V_A2, V_B1, V_B2, then B's nodal face normals N_1, N_2 of a
// face); vector k's shape values s_k, d_k on A at xi and on B at eta (curveShape, zero on the other
// curve). The variations hold A's material point xi, etaPrev and the slip metric m (the nested form's
// `frozen`); with T = SFad seeded on the coordinates their derivatives are the variations'
// linearization (H), every quantity there varying (xi through the segment's bounds, eta through the
// projection):
//  - eta with xi held, from f = x_B' . (x_B - p_A) = 0: D deta = -df, D = x_B'' . d + |x_B'|^2 (d = x_B
//    - p_A), df_k = -s_k x_B' (A's vectors), d_k d + s_k x_B' (B's);
//  - g_T2 = (eta - etaPrev) m, m = D / |x_B'| (slipMetric): G_k = m deta_k = -df_k / |x_B'|;
//  - circles, g_N = side |d| - r: G_k = side (c_k d^ + (d^ . x_B') deta_k), c_k = -s_k on A, s_k on B
//    (d^ . x_B' is zero at the projection; it is kept so that H is the nested form's to round-off);
//  - a face, g_N = (p_A - x_B(eta_N)) . n(eta_N), n = m / |m|, m = (1 - eta_N) N_1 + eta_N N_2, eta_N
//    held (the normal gap varied at B's material point): G_k = s_k n on A, -s_k n on B, and on N_1, N_2
//    (1 - eta) and eta times (r - (r . n) n) / |m|, r = p_A - x_B.
//  - circles' turn part of g_T2 (turnSlipOf; turnAt the first of the four turn vectors, or -1), b held:
//    on A's points and tangents -r_A d_k (I - t_A t_A^T)(b x t_A,p) / |x_A'(xi)|, on B's r_A d'_k (I -
//    t_B t_B^T)(b x t_B,p) / |x_B'(etaPrev)| (d'_k B's shape derivatives at etaPrev); on the turn vectors
//    of A1, A2 -r_A (t_A,p . b) (1 - xi, xi) (t_A,p x e_A), of B1, B2 r_A (t_B,p . b) (1 - etaPrev,
//    etaPrev) (t_B,p x e_B).
// g_T1 = 0. The segment planes' normals (vectors 10, 11 of a face, 8, 9 of a circle) vary xi only.
template <int Vectors, class T>
HeldLineGaps<T, Vectors> heldLineGaps(const LinePairInput& in, const Vec3<T>* P, int turnAt, bool cubicA, bool cubicB,
                                      double side, const T& xi, double etaStart, const T& etaPrev) {
  using std::sqrt;
  const bool face = in.face;
  HeldLineGaps<T, Vectors> out;
  out.g = face ? faceGaps(P, P + 4, P + 8, cubicA, cubicB, xi, etaStart, etaPrev, false)
               : lineGaps(in, P, P + 4, turnAt >= 0 ? P + turnAt : nullptr, cubicA, cubicB, in.radiusSum, xi, etaStart,
                          etaPrev, side, false);
  const T eta = out.g.eta;
  const CurveShape<T> a = curveShape(cubicA, xi), b = curveShape(cubicB, eta);
  const int slot[8] = {0, 1, 0, 1, 2, 3, 2, 3};
  const auto onA = [](int k) { return k == 0 || k == 1 || k == 4 || k == 5; };
  const T zero(0.0);
  const Vec3<T> none{{zero, zero, zero}};
  Vec3<T> pA = none, xB = none, tB = none, ddB = none;
  for (int k = 0; k < 8; ++k) {
    const int j = slot[k];
    if (onA(k)) pA = pA + a.s[j] * P[k];
    else xB = xB + b.s[j] * P[k], tB = tB + b.d[j] * P[k], ddB = ddB + b.dd[j] * P[k];
  }
  const Vec3<T> d = xB - pA;
  const T speed = sqrt(dot(tB, tB));
  const T D = dot(ddB, d) + speed * speed;
  for (auto& row : out.G)
    for (auto& v : row) v = none;
  Vec3<T> dEta[8];
  for (int k = 0; k < 8; ++k) {
    const int j = slot[k];
    const Vec3<T> df = onA(k) ? (-1.0 * a.s[j]) * tB : b.d[j] * d + b.s[j] * tB;
    dEta[k] = (-1.0 / D) * df;
    out.G[kGapT2][k] = (-1.0 / speed) * df;
  }
  if (face) {
    const Vec3<T> m = (1.0 - eta) * P[8] + eta * P[9];
    const T nm = sqrt(dot(m, m));
    const Vec3<T> n = (1.0 / nm) * m;
    const Vec3<T> r = pA - xB;
    for (int k = 0; k < 8; ++k) out.G[kGapN][k] = (onA(k) ? a.s[slot[k]] : -1.0 * b.s[slot[k]]) * n;
    const Vec3<T> across = (1.0 / nm) * (r - dot(r, n) * n);
    out.G[kGapN][8] = (1.0 - eta) * across;
    out.G[kGapN][9] = eta * across;
  } else {
    const Vec3<T> unit = (1.0 / sqrt(dot(d, d))) * d;
    const T along = dot(unit, tB);
    for (int k = 0; k < 8; ++k)
      out.G[kGapN][k] = side * ((onA(k) ? -1.0 * a.s[slot[k]] : b.s[slot[k]]) * unit + along * dEta[k]);
    if (turnAt >= 0) {  // (-r_A (theta_A - theta_B) . b, b held)
      const CurveShape<T>& onB = b;
      const Vec3<T> b = cross(-side * unit, (1.0 / speed) * tB);
      // The slip across (acrossSlipOf), b held: the axes' points along b (B's at eta: its motion with
      // eta is along t_B, normal to b), the sections' vectors q.
      if (in.acrossSlip) {
        for (int k = 0; k < 8; ++k) out.G[kGapT1][k] = (onA(k) ? a.s[slot[k]] : -1.0 * onB.s[slot[k]]) * b;
        const std::array<T, 2> rho = contactArms(in, T(side * sqrt(dot(d, d)) - in.radiusSum));
        out.G[kGapT1][turnAt] = (-1.0 * rho[0] * (1.0 - xi)) * b;
        out.G[kGapT1][turnAt + 1] = (-1.0 * rho[0] * xi) * b;
        out.G[kGapT1][turnAt + 2] = (-1.0 * rho[1] * (1.0 - etaPrev)) * b;
        out.G[kGapT1][turnAt + 3] = (-1.0 * rho[1] * etaPrev) * b;
      }
      const CurveShape<T> bp = curveShape(cubicB, etaPrev);
      Vec3<T> dA = none, dB = none, tAp, tBp;
      for (int k = 0; k < 8; ++k)
        if (onA(k)) dA = dA + a.d[slot[k]] * P[k];
        else dB = dB + bp.d[slot[k]] * P[k];
      previousTangents(in, cubicA, cubicB, xi, etaPrev, tAp, tBp);
      const T lA = sqrt(dot(dA, dA)), lB = sqrt(dot(dB, dB));
      const Vec3<T> tA = (1.0 / lA) * dA, tBe = (1.0 / lB) * dB;
      const Vec3<T> eA = lifted<T>(in.across[0]), eB = lifted<T>(in.across[1]);
      // d(t_p x t . b) = dt . (b x t_p), dt = (I - t t^T) dx' / |x'|; d((q - n_p) . (t_p x n_p)) (t_p . b).
      const Vec3<T> cA = cross(b, tAp), cB = cross(b, tBp);
      const Vec3<T> gA = (-in.radiusA / lA) * (cA - dot(cA, tA) * tA);
      const Vec3<T> gB = (in.radiusA / lB) * (cB - dot(cB, tBe) * tBe);
      for (int k = 0; k < 8; ++k)
        out.G[kGapT2][k] = out.G[kGapT2][k] + (onA(k) ? a.d[slot[k]] * gA : bp.d[slot[k]] * gB);
      const Vec3<T> twistA = (-in.radiusA * dot(tAp, b)) * cross(tAp, eA);
      const Vec3<T> twistB = (in.radiusA * dot(tBp, b)) * cross(tBp, eB);
      out.G[kGapT2][turnAt] = (1.0 - xi) * twistA;
      out.G[kGapT2][turnAt + 1] = xi * twistA;
      out.G[kGapT2][turnAt + 2] = (1.0 - etaPrev) * twistB;
      out.G[kGapT2][turnAt + 3] = etaPrev * twistB;
    }
  }
  return out;
}

// R and K of line contact from heldLineGaps (gapsOf(Q) with Q seeded on the coordinates): the values
// and their gradients, the held variations G and (Second) their derivatives H, one AD level.
template <int Vectors, bool Second, class Fn>
ContactKinematics heldKinematicsOfOrder(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode,
                                        Fn gapsOf) {
  constexpr int kCoords = 3 * Vectors;
  using In = Sacado::Fad::SFad<double, kCoords>;
  Vec3d p[Vectors];
  const VectorFrame<Vectors> frame = vectorFrame<Vectors>(in, extraRef, extraNode, p);
  Vec3<In> Q[Vectors];
  seedVectors<Vectors, true>(p, Q);
  const HeldLineGaps<In, Vectors> h = gapsOf(static_cast<const Vec3<In>*>(Q));
  CoordinateGaps<kCoords> c;
  valuesAndGradients(h.g, c);
  // The held variations replace the values' gradients as G of g_N, g_T1, g_T2.
  for (int q = 0; q < 3; ++q)
    for (int k = 0; k < kCoords; ++k) {
      const In& v = h.G[q][k / 3][k % 3];
      c.G[q][k] = v.val();
      if constexpr (Second)
        for (int l = 0; l < kCoords; ++l) c.H[q][k][l] = v.dx(l);
    }
  return chainRule<Vectors, Second>(c, frame);
}

template <int Vectors, class Fn>
ContactKinematics heldKinematicsOf(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Fn gapsOf,
                                   Variations order) {
  return order == Variations::Second ? heldKinematicsOfOrder<Vectors, true>(in, extraRef, extraNode, gapsOf)
                                     : heldKinematicsOfOrder<Vectors, false>(in, extraRef, extraNode, gapsOf);
}

template <int Vectors, class Fn>
ContactKinematics kinematicsOf(const LinePairInput& in, const Vec3d* extraRef, const int* extraNode, Fn gapsOf,
                               Variations order, bool heldVariation) {
  return order == Variations::Second
             ? kinematicsOfOrder<Vectors, true>(in, extraRef, extraNode, gapsOf, heldVariation)
             : kinematicsOfOrder<Vectors, false>(in, extraRef, extraNode, gapsOf, heldVariation);
}

}  // namespace

void setTurnSlip(LinePairInput& in, const LinePairInput& converged, const Vec3d& normal, double xi, double eta) {
  vectorFrame<8>(converged, nullptr, nullptr, in.prev);
  in.turnSlip = in.acrossSlip = true;
  // e: the normal made normal to each axis there (unit), so that (q - e) . (t_p x e) is the twist.
  Vec3d t[2];
  previousTangents(in, norm(converged.dA) > 0.0, norm(converged.dB) > 0.0, xi, eta, t[0], t[1]);
  for (int j = 0; j < 2; ++j) {
    const Vec3d e = normal - dot(normal, t[j]) * t[j];
    in.across[j] = norm(e) > 0.0 ? (1.0 / norm(e)) * e : Vec3d{};
  }
  const Mat3d* R[4] = {&converged.RA1, &converged.RA2, &converged.RB1, &converged.RB2};
  for (int m = 0; m < 4; ++m) in.turnRef[m] = transpose(*R[m]) * in.across[m / 2];
  // (the gap there: the contact point midway between the surfaces, acrossSlipOf)
  Vec3d pA, xB;
  axisPoint(in.prev[0], in.prev[4], in.prev[1], in.prev[5], norm(converged.dA) > 0.0, xi, &pA, nullptr, nullptr);
  axisPoint(in.prev[2], in.prev[6], in.prev[3], in.prev[7], norm(converged.dB) > 0.0, eta, &xB, nullptr, nullptr);
  const std::array<double, 2> rho = contactArms(in, dot(pA - xB, normal) - in.radiusSum);
  in.acrossStart = dot(rho[0] * in.across[0] + rho[1] * in.across[1], cross(normal, t[1]));
}

std::array<double, 2> surfaceSlips(const LinePairInput& in, double xi, double etaPrev, double eta, const Vec3d& n) {
  if (!in.turnSlip || in.face) return {0.0, 0.0};
  // (the points, tangents and turn vectors as the kinematics has them)
  const int nodes[4] = {0, 1, 2, 3};
  Vec3d p[12];
  vectorFrame<12>(in, in.turnRef, nodes, p);
  const bool cubicA = norm(in.dA) > 0.0, cubicB = norm(in.dB) > 0.0;
  Vec3d pA, xB;
  axisPoint(p[0], p[4], p[1], p[5], cubicA, xi, &pA, nullptr, nullptr);
  axisPoint(p[2], p[6], p[3], p[7], cubicB, eta, &xB, nullptr, nullptr);
  const Vec3d b = cross(n, unitTangent(p[2], p[6], p[3], p[7], cubicB, eta));
  const std::array<Vec3d, 2> q = sectionVectors(p + 8, xi, etaPrev);
  return {in.acrossSlip ? acrossSlipOf(in, q, pA - xB, b, dot(pA - xB, n) - in.radiusSum) : 0.0,
          turnSlipOf(in, p, p + 4, q, cubicA, cubicB, xi, etaPrev, b)};
}

namespace {
// The vectors of end contact beyond the points and tangents: the end's triad at its node, B's
// reference vector (circles: across its axis; rectangles: the face normal) at B's two nodes.
struct EndVectors {
  Vec3d ref[5];
  int node[5];
  explicit EndVectors(const LinePairInput& in) {
    for (int a = 0; a < 3; ++a) {
      ref[a] = (a == 0 ? in.outward : 1.0) * in.endAxes[a];
      node[a] = in.endNode;
    }
    ref[3] = ref[4] = in.face ? in.nB : in.acrossB;
    node[3] = 2;
    node[4] = 3;
  }
};
}  // namespace

ClosestPoints endProjection(const LinePairInput& in, double side) {
  const EndVectors ev(in);
  Vec3d p[13];
  vectorFrame<13>(in, ev.ref, ev.node, p);
  const bool cubicB = norm(in.dB) > 0.0;
  const Vec3d& pE = p[in.endNode];
  const Vec3d tBc = p[3] - p[2];
  const double eta = projectionParameter(p[2], p[6], p[3], p[7], cubicB, pE);
  ClosestPoints cp;
  double across = 0.0;
  Vec3d support;
  const Gaps<double> g =
      endGaps(in, p, p + 4, p + 8, cubicB, side, eta, eta, 0.0, &across, &cp.normal, false, &support);
  cp.xi = in.endNode;
  cp.eta = g.eta;
  cp.pA = cp.cA = pE;
  if (in.endCorner >= 0) cp.pA = support;  // (a corner: the corner itself)
  axisPoint(p[2], p[6], p[3], p[7], cubicB, g.eta, &cp.pB, nullptr, nullptr);
  cp.cB = cp.pB;
  cp.distance = norm(cp.pB - cp.pA);
  cp.gap = g.gN;
  cp.sigma = side;
  cp.etaRate = across;
  const Vec3d tA = p[1] - p[0];
  cp.sinAngle = norm(cross(tBc, tA)) / (norm(tA) * norm(tBc));
  return cp;
}

ContactKinematics endKinematics(const LinePairInput& in, double side, double etaPrev, double acrossPrev,
                                Variations order) {
  const ClosestPoints cp = endProjection(in, side);
  const EndVectors ev(in);
  const bool cubicB = norm(in.dB) > 0.0;
  ContactKinematics k = kinematicsOf<13>(
      in, ev.ref, ev.node,
      [&](const auto* P, bool held) {
        return endGaps(in, P, P + 4, P + 8, cubicB, side, cp.eta, etaPrev, acrossPrev, nullptr, nullptr, held);
      },
      order, true);
  k.cosine = 0.0;
  k.cosineR.fill(0.0);
  return k;
}

namespace {
// The vectors of end-to-end contact beyond the points and tangents: A's end triad at its node, B's at
// its end node (each e1 outward).
struct EndToEndVectors {
  Vec3d ref[6];
  int node[6];
  explicit EndToEndVectors(const LinePairInput& in) {
    for (int a = 0; a < 3; ++a) {
      ref[a] = (a == 0 ? in.outward : 1.0) * in.endAxes[a];
      node[a] = in.endNode;
      ref[3 + a] = in.otherAxes[a];
      node[3 + a] = 2 + in.otherEnd;
    }
  }
};
}  // namespace

ClosestPoints endToEndProjection(const LinePairInput& in) {
  const EndToEndVectors ev(in);
  Vec3d p[14];
  vectorFrame<14>(in, ev.ref, ev.node, p);
  double offsets[2];
  ClosestPoints cp;
  const Gaps<double> g = endToEndGaps(in, p, p + 8, 0.0, 0.0, false, offsets, &cp.pA);
  cp.xi = in.endNode;
  cp.eta = in.otherEnd;
  cp.normal = -1.0 * p[11];
  cp.gap = g.gN;
  cp.pB = cp.pA + g.gN * cp.normal;
  cp.cA = p[in.endNode];
  cp.cB = p[2 + in.otherEnd];
  cp.distance = norm(cp.pB - cp.pA);
  cp.sigma = 1.0;
  cp.etaRate = offsets[0];
  cp.across2 = offsets[1];
  const Vec3d tA = p[1] - p[0], tB = p[3] - p[2];
  cp.sinAngle = norm(cross(tB, tA)) / (norm(tA) * norm(tB));
  return cp;
}

ContactKinematics endToEndKinematics(const LinePairInput& in, double offset1Prev, double offset2Prev,
                                     Variations order) {
  const EndToEndVectors ev(in);
  ContactKinematics k = kinematicsOf<14>(
      in, ev.ref, ev.node,
      [&](const auto* P, bool held) { return endToEndGaps(in, P, P + 8, offset1Prev, offset2Prev, held); }, order,
      true);
  k.cosine = 0.0;
  k.cosineR.fill(0.0);
  return k;
}

}  // namespace bc::constraints
