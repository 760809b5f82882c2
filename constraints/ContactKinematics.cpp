#include "ContactKinematics.hpp"

#include <cmath>

namespace bc::constraints {

using namespace bc::math;

namespace {

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

template <class T>
struct Gaps {
  T gN, gT1, gT2, xi, eta;
  T cosine;  // t_A . t_B / (|t_A| |t_B|): the metric of the tangential gaps (isotropic friction)
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
  return g;
}

// Line contact at a Gauss point of line A (fixed parameter xi, a material point) against line B: the
// point projected on line B (t_B . (p_B - p_A) = 0, linear in eta for a straight line), the normal
// along p_B - p_A, the gap |p_B - p_A| - (r_A + r_B), and the slip along line B from etaPrev. Line A's
// own tangential gap is zero (the point is material on A).
template <class T>
Gaps<T> lineGaps(const Vec3<T>& pA1, const Vec3<T>& pA2, const Vec3<T>& pB1, const Vec3<T>& pB2, double radiusSum,
                 double xi, double etaPrev) {
  using std::sqrt;
  Gaps<T> g;
  const Vec3<T> tA = pA2 - pA1, tB = pB2 - pB1;
  const Vec3<T> pA = pA1 + xi * tA;
  g.xi = T(xi);
  g.eta = dot(tB, pA - pB1) / dot(tB, tB);
  const Vec3<T> d = pB1 + g.eta * tB - pA;
  g.gN = sqrt(dot(d, d)) - radiusSum;
  g.gT1 = T(0.0);
  g.gT2 = (g.eta - etaPrev) * sqrt(dot(tB, tB));
  g.cosine = dot(tA, tB) / (sqrt(dot(tA, tA)) * sqrt(dot(tB, tB)));
  return g;
}

// R and K of every gap from their gradients and Hessians in the 12 end-point coordinates.
template <class Fn>
ContactKinematics kinematicsOf(const LinePairInput& in, Fn gapsOf);

}  // namespace

ClosestPoints closestPoints(const LinePairInput& in) {
  ClosestPoints cp;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d pB1 = in.xB1 + in.RB1 * in.oB, pB2 = in.xB2 + in.RB2 * in.oB;
  const Vec3d tA = pA2 - pA1, tB = pB2 - pB1;
  const Vec3d c = cross(tB, tA);
  cp.sinAngle = norm(c) / (norm(tA) * norm(tB));
  if (!(cp.sinAngle > 1e-12)) return cp;
  solveClosest(pA1, pA2, pB1, pB2, cp.xi, cp.eta);
  cp.pA = pA1 + cp.xi * tA;
  cp.pB = pB1 + cp.eta * tB;
  cp.cA = in.xA1 + cp.xi * (in.xA2 - in.xA1);
  cp.cB = in.xB1 + cp.eta * (in.xB2 - in.xB1);
  const Vec3d n = (1.0 / norm(c)) * c;
  cp.sigma = dot(n, cp.cB - cp.cA) >= 0.0 ? 1.0 : -1.0;
  cp.normal = cp.sigma * n;
  cp.distance = norm(cp.pB - cp.pA);
  cp.gap = dot(cp.pB - cp.pA, cp.normal) - in.radiusSum;
  return cp;
}

ContactKinematics contactKinematics(const LinePairInput& in, double sigma, double xiPrev, double etaPrev) {
  return kinematicsOf(in, [&](const auto& P) { return gaps(P[0], P[1], P[2], P[3], in.radiusSum, sigma, xiPrev, etaPrev); });
}

ClosestPoints lineProjection(const LinePairInput& in, double xi) {
  ClosestPoints cp;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d pB1 = in.xB1 + in.RB1 * in.oB, pB2 = in.xB2 + in.RB2 * in.oB;
  const Vec3d tA = pA2 - pA1, tB = pB2 - pB1;
  cp.sinAngle = norm(cross(tB, tA)) / (norm(tA) * norm(tB));
  cp.xi = xi;
  cp.pA = pA1 + xi * tA;
  cp.eta = dot(tB, cp.pA - pB1) / dot(tB, tB);
  cp.pB = pB1 + cp.eta * tB;
  cp.cA = in.xA1 + xi * (in.xA2 - in.xA1);
  cp.cB = in.xB1 + cp.eta * (in.xB2 - in.xB1);
  cp.distance = norm(cp.pB - cp.pA);
  cp.normal = cp.distance > 0.0 ? (1.0 / cp.distance) * (cp.pB - cp.pA) : Vec3d{};
  cp.gap = cp.distance - in.radiusSum;
  return cp;
}

ContactKinematics lineKinematics(const LinePairInput& in, double xi, double etaPrev) {
  return kinematicsOf(in, [&](const auto& P) { return lineGaps(P[0], P[1], P[2], P[3], in.radiusSum, xi, etaPrev); });
}

namespace {
template <class Fn>
ContactKinematics kinematicsOf(const LinePairInput& in, Fn gapsOf) {
  // The gaps depend on the 24 dofs only through the four line end points P_m = x_m + R_m o (12
  // coordinates). Nested forward AD gives the gradient G and Hessian H of each gap in those 12;
  // the chain rule then gives R and K in the 24 dofs. With the spin variation w (inner) and the
  // Newton increment delta (outer), P_m = x_m + exp(w) exp(delta) R_m o, so
  //   dP_m = du_m + w x r_m,   d2P_m / dw_i d delta_j = e_i x (e_j x r_m),   r_m = R_m o,
  //   R = J^T G,   K_ij = (J^T H J)_ij + sum_m G_m . (e_i x (e_j x r_m)) on node m's spins.
  constexpr int kPoints = 12;
  using In = Sacado::Fad::SFad<double, kPoints>;
  using Out = Sacado::Fad::SFad<In, kPoints>;
  const Vec3d* x[4] = {&in.xA1, &in.xA2, &in.xB1, &in.xB2};
  const Mat3d* Rm[4] = {&in.RA1, &in.RA2, &in.RB1, &in.RB2};
  const Vec3d* o[4] = {&in.oA, &in.oA, &in.oB, &in.oB};
  Vec3d r[4];
  Vec3<Out> P[4];
  for (int m = 0; m < 4; ++m) {
    r[m] = (*Rm[m]) * (*o[m]);
    const Vec3d p = *x[m] + r[m];
    for (int a = 0; a < 3; ++a) P[m][a] = Out(kPoints, 3 * m + a, In(kPoints, 3 * m + a, p[a]));
  }
  const Gaps<Out> g = gapsOf(P);

  // J: 12 x 24, dP_(m,a) / d dof; nonzero only in node m's 6 columns: [I, -skew(r_m)].
  double J[kPoints][kPairDofs] = {};
  for (int m = 0; m < 4; ++m)
    for (int a = 0; a < 3; ++a) {
      J[3 * m + a][6 * m + a] = 1.0;
      for (int b = 0; b < 3; ++b) {
        Vec3d e{};
        e[b] = 1.0;
        J[3 * m + a][6 * m + 3 + b] = cross(e, r[m])[a];
      }
    }

  ContactKinematics out;
  out.xi = g.xi.val().val();
  out.eta = g.eta.val().val();
  out.cosine = g.cosine.val().val();
  for (int i = 0; i < kPairDofs; ++i) {
    double Ri = 0.0;
    for (int k = 0; k < kPoints; ++k) Ri += J[k][i] * g.cosine.val().dx(k);
    out.cosineR[i] = Ri;
  }
  const Out* src[3] = {&g.gN, &g.gT1, &g.gT2};
  GapDerivatives* dst[3] = {&out.normal, &out.tangent1, &out.tangent2};
  for (int q = 0; q < 3; ++q) {
    const Out& v = *src[q];
    double G[kPoints], H[kPoints][kPoints], HJ[kPoints][kPairDofs];
    for (int k = 0; k < kPoints; ++k) {
      G[k] = v.val().dx(k);
      for (int l = 0; l < kPoints; ++l) H[k][l] = v.dx(l).dx(k);
    }
    for (int k = 0; k < kPoints; ++k)
      for (int j = 0; j < kPairDofs; ++j) {
        double sum = 0.0;
        for (int l = 0; l < kPoints; ++l) sum += H[k][l] * J[l][j];
        HJ[k][j] = sum;
      }
    GapDerivatives& d = *dst[q];
    d.value = v.val().val();
    for (int i = 0; i < kPairDofs; ++i) {
      double Ri = 0.0;
      for (int k = 0; k < kPoints; ++k) Ri += J[k][i] * G[k];
      d.R[i] = Ri;
      for (int j = 0; j < kPairDofs; ++j) {
        double sum = 0.0;
        for (int k = 0; k < kPoints; ++k) sum += J[k][i] * HJ[k][j];
        d.K[kPairDofs * i + j] = sum;
      }
    }
    // Second derivatives of the end points: the spins of the same node.
    for (int m = 0; m < 4; ++m) {
      const Vec3d Gm{{G[3 * m], G[3 * m + 1], G[3 * m + 2]}};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          Vec3d ei{}, ej{};
          ei[i] = 1.0;
          ej[j] = 1.0;
          d.K[kPairDofs * (6 * m + 3 + i) + 6 * m + 3 + j] += dot(Gm, cross(ei, cross(ej, r[m])));
        }
    }
  }
  return out;
}

}  // namespace

}  // namespace bc::constraints
