#include "CorotationalBeam.hpp"

#include <stdexcept>

namespace bc::elements {

namespace {

template <class T> Mat3<T> corotatedFrameT(const Mat3<T>& T1, const Mat3<T>& T2, const Vec3<T>& x1, const Vec3<T>& x2) {
  using std::sqrt;
  Vec3<T> dx = x2 - x1;
  T invL = 1.0 / norm(dx);
  Vec3<T> e1 = invL * dx;
  Vec3<T> q = T(0.5) * (column(T1, 1) + column(T2, 1));
  Vec3<T> r3 = cross(e1, q);
  T invR3 = 1.0 / norm(r3);
  Vec3<T> e3 = invR3 * r3;
  Vec3<T> e2 = cross(e3, e1);
  return fromColumns(e1, e2, e3);
}

// Strain energy of the element for nodal positions x1, x2 and nodal frames T1 = R1 T0, T2 = R2 T0.
template <class T>
T energyOfFrames(const BeamElementData& d, const Vec3<T>& x1, const Vec3<T>& x2, const Mat3<T>& T1, const Mat3<T>& T2) {
  const Mat3<T> Rr = corotatedFrameT(T1, T2, x1, x2);
  const Mat3<T> RrT = transpose(Rr);
  const Vec3<T> th1 = logSO3(RrT * T1);
  const Vec3<T> th2 = logSO3(RrT * T2);
  const T ua = norm(x2 - x1) - d.L0;
  const T tor = th2[0] - th1[0];
  const double k = 2.0 / d.L0;
  return (0.5 * d.EA / d.L0) * ua * ua + (0.5 * d.GJ / d.L0) * tor * tor +
         (k * d.EIz) * (th1[2] * th1[2] + th1[2] * th2[2] + th2[2] * th2[2]) +
         (k * d.EIy) * (th1[1] * th1[1] + th1[1] * th2[1] + th2[1] * th2[1]);
}

}  // namespace

BeamElementData makeBeamElement(const Vec3d& X1, const Vec3d& X2, const Vec3d& sectionY, double EA, double GJ,
                                double EIy, double EIz) {
  BeamElementData d;
  d.X1 = X1;
  d.X2 = X2;
  const Vec3d axis = X2 - X1;
  d.L0 = norm(axis);
  if (!(d.L0 > 0.0)) throw std::invalid_argument("beam element of zero length");
  const Vec3d e1 = (1.0 / d.L0) * axis;
  Vec3d y = sectionY - dot(sectionY, e1) * e1;
  const double ny = norm(y);
  if (ny < 1e-8 * norm(sectionY) || !(ny > 0.0))
    throw std::invalid_argument("section orientation is parallel to the beam axis");
  const Vec3d e2 = (1.0 / ny) * y;
  const Vec3d e3 = cross(e1, e2);
  d.T0 = fromColumns(e1, e2, e3);
  d.EA = EA;
  d.GJ = GJ;
  d.EIy = EIy;
  d.EIz = EIz;
  return d;
}

double strainEnergy(const BeamElementData& d, const BeamElementState& s) {
  return energyOfFrames<double>(d, s.x1, s.x2, s.R1 * d.T0, s.R2 * d.T0);
}

Mat3d corotatedFrame(const BeamElementData& d, const BeamElementState& s) {
  return corotatedFrameT<double>(s.R1 * d.T0, s.R2 * d.T0, s.x1, s.x2);
}

// The energy depends on the positions only through the chord x2 - x1, so AD runs over 9 variables
// v = (x2 - x1, w1, w2) instead of the 12 nodal ones: dof g of the element is variable kVar[g] with
// sign kSign[g] (d/dx1 = -d/d(x2 - x1)).
namespace {
constexpr int kVars = 9;
constexpr int kVar[12] = {0, 1, 2, 3, 4, 5, 0, 1, 2, 6, 7, 8};
constexpr double kSign[12] = {-1, -1, -1, 1, 1, 1, 1, 1, 1, 1, 1, 1};

// The frame exp(w) exp(delta) C of a node, C = R T0 of the current state, for the nested AD below:
// only its value, first derivatives and the mixed second derivatives d2 / dw d delta are ever read
// (w lives on the inner AD level, delta on the outer), so exp(w) exp(delta) can be replaced by
// I + W + D + W D, with W D = delta w^T - (w . delta) I; the dropped W^2 / 2 and D^2 / 2 only
// carry pure second derivatives.
template <class T> Mat3<T> incrementedFrame(const Vec3<T>& w, const Vec3<T>& delta, const Mat3d& C) {
  Mat3<T> M;
  const T wd = dot(w, delta);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) M(a, b) = delta[a] * w[b];
  for (int a = 0; a < 3; ++a) M(a, a) += 1.0 - wd;
  const Vec3<T> s = w + delta;
  M(0, 1) -= s[2];
  M(0, 2) += s[1];
  M(1, 0) += s[2];
  M(1, 2) -= s[0];
  M(2, 0) -= s[1];
  M(2, 1) += s[0];
  Mat3<T> F;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) F(a, b) = M(a, 0) * C(0, b) + M(a, 1) * C(1, b) + M(a, 2) * C(2, b);
  return F;
}
}  // namespace

namespace {
// a = J^-T m with J the left Jacobian of SO(3) at theta: a rotation exp(theta) perturbed on the left
// by exp(eps) has the rotation vector theta + J^-1 eps, so m . dtheta = (J^-T m) . eps. With
// Theta = skew(theta): J^-1 = I - Theta / 2 + c Theta^2, c = 1 / t^2 - (1 + cos t) / (2 t sin t),
// t = |theta| (series below t = 1e-2, where c = 1/12 + t^2/720 + t^4/30240 + O(t^6)).
template <class T> Vec3<T> inverseLeftJacobianTransposed(const Vec3<T>& theta, const Vec3<T>& m) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T t2 = dot(theta, theta);
  T c;
  if (val(t2) < 1e-4) {
    c = 1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0));
  } else {
    const T t = sqrt(t2);
    c = 1.0 / t2 - (1.0 + cos(t)) / (2.0 * t * sin(t));
  }
  const Vec3<T> tm = cross(theta, m);
  return m + 0.5 * tm + c * cross(theta, tm);
}

// The strain energy's derivatives along the chord c = x2 - x1 and the spins w1, w2 of the nodal
// frames T1, T2 (T = exp(w) T): g[0..2], g[3..5], g[6..8]. With N = dE/dl and m_i = dE/dtheta_i
// (local components), a perturbation moves the local rotations by dtheta_i = J^-1(theta_i) Rr^T
// (w_i - omega), omega the spin of the co-rotated frame Rr = [e1 e2 e3], whose components are
//   omega . e3 = e2 . dc / l,   omega . e2 = -e3 . dc / l,
//   omega . e1 = -e2 . de3 = -((q x e2) . de1 - e3 . dq) / |e1 x q|,
// de1 = (I - e1 e1^T) dc / l, dq = (w1 x t1 + w2 x t2) / 2 (t_i the frames' second columns). So
//   g_c = N e1 - B3 e2 / l + B2 e3 / l + B1 (I - e1 e1^T)(q x e2) / (l |e1 x q|),
//   g_wi = b_i - B1 (t_i x e3) / (2 |e1 x q|),   b_i = Rr J^-T(theta_i) m_i,  B_k = (b_1 + b_2) . e_k.
template <class T>
std::array<T, 9> energyGradient(const BeamElementData& d, const Vec3<T>& c, const Mat3<T>& T1, const Mat3<T>& T2) {
  const T l = norm(c);
  const Vec3<T> e1 = (1.0 / l) * c;
  const Vec3<T> t1 = column(T1, 1), t2 = column(T2, 1);
  const Vec3<T> q = T(0.5) * (t1 + t2);
  const Vec3<T> r = cross(e1, q);
  const T rn = norm(r);
  const Vec3<T> e3 = (1.0 / rn) * r;
  const Vec3<T> e2 = cross(e3, e1);
  const Mat3<T> Rr = fromColumns(e1, e2, e3);
  const Mat3<T> RrT = transpose(Rr);
  const Vec3<T> th1 = logSO3(RrT * T1);
  const Vec3<T> th2 = logSO3(RrT * T2);
  const double k = 2.0 / d.L0;
  const T N = (d.EA / d.L0) * (l - d.L0);
  const T tor = (d.GJ / d.L0) * (th2[0] - th1[0]);
  const Vec3<T> m1{{-tor, k * d.EIy * (2.0 * th1[1] + th2[1]), k * d.EIz * (2.0 * th1[2] + th2[2])}};
  const Vec3<T> m2{{tor, k * d.EIy * (th1[1] + 2.0 * th2[1]), k * d.EIz * (th1[2] + 2.0 * th2[2])}};
  const Vec3<T> b1 = Rr * inverseLeftJacobianTransposed(th1, m1);
  const Vec3<T> b2 = Rr * inverseLeftJacobianTransposed(th2, m2);
  const Vec3<T> B = b1 + b2;
  const T B1 = dot(B, e1), B2 = dot(B, e2), B3 = dot(B, e3);
  const Vec3<T> p = cross(q, e2);
  const Vec3<T> pPerp = p - dot(p, e1) * e1;
  const Vec3<T> gc = N * e1 + (B2 / l) * e3 - (B3 / l) * e2 + (B1 / (l * rn)) * pPerp;
  const T h = B1 / (2.0 * rn);
  const Vec3<T> g1 = b1 - h * cross(t1, e3);
  const Vec3<T> g2 = b2 - h * cross(t2, e3);
  return {gc[0], gc[1], gc[2], g1[0], g1[1], g1[2], g2[0], g2[1], g2[2]};
}
}  // namespace

void internalForce(const BeamElementData& d, const BeamElementState& s, Vector12& f) {
  const std::array<double, 9> g = energyGradient<double>(d, s.x2 - s.x1, s.R1 * d.T0, s.R2 * d.T0);
  for (int i = 0; i < 12; ++i) f[i] = kSign[i] * g[kVar[i]];
}

void internalForceAndTangent(const BeamElementData& d, const BeamElementState& s, Vector12& f, Matrix12& K) {
  // The gradient (the force) differentiated by one level of AD along the Newton increment delta:
  // chord c + dc, frames exp(delta_i) T_i, of which (I + skew(delta_i)) T_i carries the value and
  // the first derivatives.
  using F = Sacado::Fad::SFad<double, kVars>;
  Vec3<F> c, d1, d2;
  for (int k = 0; k < 3; ++k) {
    c[k] = F(kVars, k, s.x2[k] - s.x1[k]);
    d1[k] = F(kVars, 3 + k, 0.0);
    d2[k] = F(kVars, 6 + k, 0.0);
  }
  const auto incremented = [](const Vec3<F>& delta, const Mat3d& C) {
    Mat3<F> M = skew(delta);
    for (int a = 0; a < 3; ++a) M(a, a) += 1.0;
    Mat3<F> T;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) T(a, b) = M(a, 0) * C(0, b) + M(a, 1) * C(1, b) + M(a, 2) * C(2, b);
    return T;
  };
  const std::array<F, 9> g = energyGradient(d, c, incremented(d1, s.R1 * d.T0), incremented(d2, s.R2 * d.T0));
  for (int i = 0; i < 12; ++i) {
    f[i] = kSign[i] * g[kVar[i]].val();
    for (int j = 0; j < 12; ++j) K[12 * i + j] = kSign[i] * kSign[j] * g[kVar[i]].dx(kVar[j]);
  }
}

void internalForceAndTangentFromEnergy(const BeamElementData& d, const BeamElementState& s, Vector12& f, Matrix12& K) {
  // Inner AD level: the virtual variation w (gives the force); outer level: the Newton increment
  // delta (gives the tangent). Rotations: R = exp(w) exp(delta) R_current, both at zero.
  using In = Sacado::Fad::SFad<double, kVars>;
  using Out = Sacado::Fad::SFad<In, kVars>;
  Vec3<Out> x1, x2, w1, w2, d1, d2;
  for (int k = 0; k < 3; ++k) {
    x1[k] = Out(In(s.x1[k]));
    x2[k] = x1[k] + Out(kVars, k, In(kVars, k, s.x2[k] - s.x1[k]));
    w1[k] = Out(In(kVars, 3 + k, 0.0));
    w2[k] = Out(In(kVars, 6 + k, 0.0));
    d1[k] = Out(kVars, 3 + k, In(0.0));
    d2[k] = Out(kVars, 6 + k, In(0.0));
  }
  const Mat3<Out> T1 = incrementedFrame(w1, d1, s.R1 * d.T0);
  const Mat3<Out> T2 = incrementedFrame(w2, d2, s.R2 * d.T0);
  const Out E = energyOfFrames(d, x1, x2, T1, T2);
  for (int i = 0; i < 12; ++i) {
    f[i] = kSign[i] * E.val().dx(kVar[i]);
    for (int j = 0; j < 12; ++j) K[12 * i + j] = kSign[i] * kSign[j] * E.dx(kVar[j]).dx(kVar[i]);
  }
}

}  // namespace bc::elements
