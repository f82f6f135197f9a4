#include "deploysim/analysis/free_body_solution.h"

#include <algorithm>
#include <array>
#include <boost/math/special_functions/ellint_rj.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deploysim/math/quaternion.h"
#include "deploysim/math/units.h"

namespace deploysim::analysis {

namespace {

using math::Quat;
using math::SnCnDn;
using math::Vec3;
using DD = math::DoubleDouble;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Boost.Math evaluates double special functions in extended precision by default (10x slower
/// here); R_J in double is accurate to a few ulp, all the periodic part of psi needs.
using FastPolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
using math::kPi;
/// Accepted deviation of |q_NB0| from 1.
constexpr double kUnitQuatTol = math::kUnitQuaternionTolerance;  // math::ValidateUnitQuaternion

double Sign(double x) { return std::signbit(x) ? -1.0 : 1.0; }

/// h_i = coef_i * f_i with f = dn on dn_axis, sn on axis 1, cn on cn_axis.
Vec3 Pattern(const Vec3& coef, int dn_axis, int cn_axis, const SnCnDn& f) {
  Vec3 h;
  h[dn_axis] = coef[dn_axis] * f.dn;
  h[1] = coef[1] * f.sn;
  h[cn_axis] = coef[cn_axis] * f.cn;
  return h;
}

/// Below this fraction of its terms P2 is not resolved by the double-double evaluation
/// (error <= ~20 u^2 = 2.5e-31 of its terms) and is taken as 0 (the separatrix);
/// 1 - k^2 < ~1e-30 would give K > 35 anyway. Exact separatrix data (e.g. I2 the harmonic
/// mean of I1, I3 and |h1| = |h3|) then land on it.
constexpr double kSeparatrixRelTol = 1e-30;

/// P2 = h1^2 (I2-I1)/I1 - h3^2 (I3-I2)/I3 in double-double: near the separatrix P2 can be
/// a tiny difference of its two terms, and 1 - k^2 is proportional to it. Exact inputs (a
/// diagonal J_B) then give 1 - k^2 to ~1e-31 of the terms however deep the cancellation.
DD SeparatrixDistance(const DD& I1, const DD& I2, const DD& I3, const DD& h1, const DD& h3) {
  const DD a = Square(h1) * (I2 - I1) / I1;
  const DD b = Square(h3) * (I3 - I2) / I3;
  const DD d = a - b;
  return Abs(d) <= (a + b) * kSeparatrixRelTol ? DD(0.0) : d;
}

/// Rotation R_{P'P} taking the reference principal axis to the third axis of P':
/// identity for axis 2, the cyclic permutation (x, y, z) -> (y, z, x) for axis 0.
Quat PermutationQuat(int ref_axis) {
  if (ref_axis == 2) return Quat::Identity();
  math::Mat3 Q;
  Q << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return Quat(Q);
}

}  // namespace

const char* ToString(Regime regime) {
  switch (regime) {
    case Regime::kMinorAxis:
      return "minor-axis";
    case Regime::kMajorAxis:
      return "major-axis";
    case Regime::kSeparatrix:
      return "separatrix";
    case Regime::kIntermediateAxisSpin:
      return "intermediate-axis-spin";
    case Regime::kAxisymmetric:
      return "axisymmetric";
    case Regime::kSpherical:
      return "spherical";
    case Regime::kAtRest:
      return "at-rest";
  }
  return "unknown";
}

/// Principal moments and momentum components and the quadratic invariants, in
/// double-double (see the class comment for P1, P2, P3).
struct FreeBodySolution::Invariants {
  DD I1, I2, I3;     ///< Principal moments, ascending, equal ones merged.
  DD h1, h2, h3;     ///< Principal components of H_B0.
  DD g21, g32, g31;  ///< I2 - I1, I3 - I2, I3 - I1.
  DD M2, T2;         ///< |H|^2, 2T.
  DD P1, P2, P3;     ///< M^2 - 2T I1, 2T I2 - M^2, 2T I3 - M^2.
};

FreeBodySolution::FreeBodySolution(const math::InertiaTensor& J_B,
                                   const Vec3& H_B0,
                                   const Quat& q_NB0,
                                   double t0)
    : q_NB0_(q_NB0), t0_(t0) {
  if (!H_B0.allFinite() || !std::isfinite(t0) || !q_NB0.coeffs().allFinite() ||
      std::abs(q_NB0.norm() - 1.0) > kUnitQuatTol) {
    std::ostringstream os;
    os.precision(17);
    os << "FreeBodySolution: H_B0 = (" << H_B0.transpose() << "), t0 = " << t0
       << ", |q_NB0| = " << q_NB0.norm()
       << " (rule: H_B0 and t0 finite, q_NB0 a unit quaternion within " << kUnitQuatTol << ")";
    throw std::invalid_argument(os.str());
  }
  q_NB0_.normalize();
  const math::PrincipalAxesDD pd = math::AccuratePrincipalDecomposition(J_B.matrix());
  std::array<DD, 3> I = pd.moments;
  const DD tol = I[2] * kEqualMomentsRelTol;
  const bool eq01 = I[1] - I[0] <= tol;
  const bool eq12 = I[2] - I[1] <= tol;
  if (eq01 && eq12) {
    I[0] = I[1] = I[2] = (I[0] + I[1] + I[2]) / 3.0;
  } else if (eq01) {
    I[0] = I[1] = (I[0] + I[1]) * 0.5;
  } else if (eq12) {
    I[1] = I[2] = (I[1] + I[2]) * 0.5;
  }
  std::array<DD, 3> h;  // V^T H_B0
  for (int j = 0; j < 3; ++j) {
    h[j] = pd.V[0][j] * H_B0[0] + pd.V[1][j] * H_B0[1] + pd.V[2][j] * H_B0[2];
  }
  principal_ = pd.Rounded();
  for (int i = 0; i < 3; ++i) {
    principal_.moments[i] = static_cast<double>(I[i]);
    h0_[i] = static_cast<double>(h[i]);
  }
  w0_B_ = principal_.axes * h0_.cwiseQuotient(principal_.moments);

  Invariants v;
  v.I1 = I[0], v.I2 = I[1], v.I3 = I[2];
  v.h1 = h[0], v.h2 = h[1], v.h3 = h[2];
  v.g21 = v.I2 - v.I1, v.g32 = v.I3 - v.I2, v.g31 = v.I3 - v.I1;
  const DD h1s = Square(v.h1), h2s = Square(v.h2), h3s = Square(v.h3);
  v.M2 = h1s + h2s + h3s;
  v.T2 = h1s / v.I1 + h2s / v.I2 + h3s / v.I3;
  v.P1 = h2s * v.g21 / v.I2 + h3s * v.g31 / v.I3;
  v.P3 = h1s * v.g31 / v.I1 + h2s * v.g32 / v.I2;
  v.P2 = SeparatrixDistance(v.I1, v.I2, v.I3, v.h1, v.h3);
  M_ = static_cast<double>(Sqrt(v.M2));
  energy_ = static_cast<double>(v.T2 * 0.5);
  D_ = v.M2 > 0.0 ? static_cast<double>(v.M2 / v.T2) : 0.0;

  const bool triaxial = v.g21 != 0.0 && v.g32 != 0.0;
  if (v.M2 == 0) {
    regime_ = Regime::kAtRest;
  } else if (v.g31 == 0) {
    regime_ = Regime::kSpherical;
  } else if (triaxial && v.P2 == 0.0 && (v.h1 == 0.0 || v.h3 == 0.0)) {
    regime_ = Regime::kIntermediateAxisSpin;
  } else if (triaxial && v.P2 == 0) {
    SetUpSeparatrix(v);
  } else {
    SetUpPeriodic(v);
  }
  if (constant_) {
    mc_ = regime_ == Regime::kIntermediateAxisSpin ? 0.0 : 1.0;
    lambda_ = 0.0;
  } else {
    SetUpAttitude(q_NB0_);
  }
}

void FreeBodySolution::SetUpSeparatrix(const Invariants& v) {
  // h1 = s1 A1 sech u, h2 = s1 s3 A2 tanh u, h3 = s3 A3 sech u: two independent signs.
  regime_ = Regime::kSeparatrix;
  constant_ = false;
  mc_ = 0.0;
  jacobi_ = math::JacobiElliptic(0.0);
  const double A1 = static_cast<double>(Sqrt(v.I1 * v.P3 / v.g31));
  const double A3 = static_cast<double>(Sqrt(v.I3 * v.P1 / v.g31));
  const double A2 = static_cast<double>(Sqrt(v.I2 * v.P1 / v.g21));
  const double s1 = Sign(h0_[0]), s3 = Sign(h0_[2]);
  coef_ = Vec3(s1 * A1, s1 * s3 * A2, s3 * A3);
  dn_axis_ = 0;
  cn_axis_ = 2;
  lambda_ = static_cast<double>(Sqrt(v.g21 * v.P3 / (v.I1 * v.I2 * v.I3)));
  period_ = kInf;
  // sinh u0 = tanh u0 / sech u0, with sech u0 from both decaying components.
  const double sech0 = (std::abs(h0_[0]) + std::abs(h0_[2])) / (A1 + A3);
  u0_ = std::asinh(h0_[1] / coef_[1] / sech0);
}

void FreeBodySolution::SetUpPeriodic(const Invariants& v) {
  // Circulation about axis 0 (minor) or 2 (major); an axisymmetric body is the k = 0 limit
  // of the branch whose circulation axis is its symmetry axis.
  const bool minor = v.g32 == 0.0 || (v.g21 != 0.0 && v.P2 > 0.0);
  const bool axisymmetric = v.g21 == 0.0 || v.g32 == 0.0;
  regime_ =
      axisymmetric ? Regime::kAxisymmetric : (minor ? Regime::kMinorAxis : Regime::kMajorAxis);
  dn_axis_ = minor ? 0 : 2;
  cn_axis_ = minor ? 2 : 0;
  const DD lambda2 = (minor ? v.g21 * v.P3 : v.g32 * v.P1) / (v.I1 * v.I2 * v.I3);
  if (!(lambda2 > 0)) return;  // axisymmetric with H in the plane of equal moments: constant
  constant_ = false;
  DD mc = 1.0;  // 1 - k^2 = (I3-I1) P2 / ((I2-I1) P3) or (I3-I1)(-P2) / ((I3-I2) P1)
  if (!axisymmetric) mc = minor ? v.g31 * v.P2 / (v.g21 * v.P3) : v.g31 * -v.P2 / (v.g32 * v.P1);
  mc_ = std::clamp(static_cast<double>(mc), 0.0, 1.0);
  jacobi_ = math::JacobiElliptic(mc_);
  const double A1 = static_cast<double>(Sqrt(v.I1 * v.P3 / v.g31));
  const double A3 = static_cast<double>(Sqrt(v.I3 * v.P1 / v.g31));
  const double A2 =
      static_cast<double>(minor ? Sqrt(v.I2 * v.P1 / v.g21) : Sqrt(v.I2 * v.P3 / v.g32));
  const double s = Sign(h0_[dn_axis_]);
  coef_[0] = minor ? s * A1 : A1;
  coef_[1] = s * A2;
  coef_[2] = minor ? A3 : s * A3;
  lambda_ = static_cast<double>(Sqrt(lambda2));
  period_ = 4.0 * jacobi_.K() / lambda_;
  if (A2 > 0.0) {  // else a pure spin about the dn axis, u0 = 0
    u0_ = math::InverseJacobi(h0_[1] / coef_[1], h0_[cn_axis_] / std::abs(coef_[cn_axis_]),
                              std::abs(h0_[dn_axis_]) / std::abs(coef_[dn_axis_]), mc_);
  }
}

void FreeBodySolution::SetUpAttitude(const Quat& q_NB0) {
  const Vec3& I = principal_.moments;
  const double A1 = std::abs(coef_[0]);
  const double A3 = std::abs(coef_[2]);
  // Reference axis: the end axis whose amplitude is smaller keeps |h_r| <= M / sqrt(2).
  ref_axis_ = A1 >= A3 ? 2 : 0;
  const int other = 2 - ref_axis_;
  const double A_r = ref_axis_ == 2 ? A3 : A1;
  const double A_o = ref_axis_ == 2 ? A1 : A3;
  const bool separatrix = regime_ == Regime::kSeparatrix;
  const double q = (separatrix || ref_axis_ == cn_axis_) ? 1.0 : jacobi_.m();
  n_char_ = -q * (A_r / A_o) * (A_r / A_o);
  const double C_r = (ref_axis_ == 2 ? 1.0 : -1.0) * M_ * (I[2] - I[0]) / (I[0] * I[2]);
  const double rate_o = M_ / I[other];

  // Direction of the orthogonal part of h at u = 0 (sn = 0, cn = dn = 1).
  const Vec3 h_at_zero(coef_[0], 0.0, coef_[2]);
  const double px = ref_axis_ == 2 ? h_at_zero[0] : h_at_zero[1];
  const double py = ref_axis_ == 2 ? h_at_zero[1] : h_at_zero[2];
  const double pn = std::hypot(px, py);
  perp_dir_[0] = px / pn;
  perp_dir_[1] = py / pn;

  if (separatrix) {
    const double nu = -n_char_;
    sqrt_nu_ = std::sqrt(nu);
    sep_coef_ = C_r / lambda_ * sqrt_nu_ / (1.0 + nu);
    omega_gamma_ = rate_o - C_r * nu / (1.0 + nu);
    winding_ = false;
  } else {
    const double K = jacobi_.K();
    const double rj_c = n_char_ == 0.0 ? 0.0 : boost::math::ellint_rj(0.0, mc_, 1.0, 1.0 - n_char_);
    rj_over_k_ = rj_c / K;
    pi_coef_ = C_r * n_char_ / (3.0 * lambda_);
    const double omega_avg = rate_o + C_r * n_char_ / 3.0 * rj_over_k_;
    // The orthogonal part winds around the reference axis when that axis carries dn.
    winding_ = dn_axis_ == ref_axis_;
    delta_ = 0.0;
    if (winding_) {
      // At r = +-K (sn = +-1, cn = 0) the orthogonal part is +-coef_1 along axis 1.
      const double wx = ref_axis_ == 2 ? 0.0 : coef_[1];
      const double wy = ref_axis_ == 2 ? coef_[1] : 0.0;
      const double cross = perp_dir_[0] * wy - perp_dir_[1] * wx;
      delta_ = cross >= 0.0 ? kPi : -kPi;
    }
    omega_gamma_ = omega_avg - delta_ * lambda_ / (2.0 * K);
  }
  periodic0_ = 0.0;
  periodic0_ = Evaluate(t0_, true).gamma;

  // q_NB(t) = q_left (x) qz(gamma) (x) conj(q_align(t)) (x) q_right, gamma(t0) = 0.
  const Quat q_PB(principal_.axes.transpose());
  q_right_ = PermutationQuat(ref_axis_) * q_PB;
  q_left_ = q_NB0 * q_right_.conjugate() * AlignQuat(h0_);
  q_left_.normalize();
}

double FreeBodySolution::PerpAngle(const Vec3& h) const {
  const double px = ref_axis_ == 2 ? h[0] : h[1];
  const double py = ref_axis_ == 2 ? h[1] : h[2];
  return std::atan2(perp_dir_[0] * py - perp_dir_[1] * px, perp_dir_[0] * px + perp_dir_[1] * py);
}

double FreeBodySolution::PeriodicPi(double r, const SnCnDn& f) const {
  if (n_char_ == 0.0) return 0.0;
  const double s = f.sn;
  const double s3_rj = s == 0.0 ? 0.0
                                : s * s * s *
                                      boost::math::ellint_rj(f.cn * f.cn, f.dn * f.dn, 1.0,
                                                             1.0 - n_char_ * s * s, FastPolicy());
  return s3_rj - rj_over_k_ * r;
}

Quat FreeBodySolution::AlignQuat(const Vec3& h) const {
  // h' = Q h / M; minimal rotation taking z to h': (1 + h'_z, z x h') normalised.
  const Vec3 hp = ref_axis_ == 2 ? h / M_ : Vec3(h[1], h[2], h[0]) / M_;
  Quat q(1.0 + hp[2], -hp[1], hp[0], 0.0);
  q.normalize();
  return q;
}

FreeBodySolution::State FreeBodySolution::Evaluate(double t, bool with_gamma) const {
  State out{h0_, 0.0};
  if (constant_) return out;
  const double tau = t - t0_;
  const double u = lambda_ * tau + u0_;
  if (regime_ == Regime::kSeparatrix) {
    const double th = std::tanh(u);
    const double sech = 1.0 / std::cosh(u);
    out.h = Pattern(coef_, dn_axis_, cn_axis_, SnCnDn{th, sech, sech});
    if (with_gamma) {
      const double periodic = sep_coef_ * std::atan(sqrt_nu_ * th) - PerpAngle(out.h);
      out.gamma = omega_gamma_ * tau + (periodic - periodic0_);
    }
    return out;
  }
  const math::JacobiElliptic::Reduced f = jacobi_.Evaluate(u);
  out.h = Pattern(coef_, dn_axis_, cn_axis_, f.at_u);
  if (with_gamma) {
    double periodic = pi_coef_ * PeriodicPi(f.r, f.at_r);
    if (winding_) {
      const Vec3 h_r = Pattern(coef_, dn_axis_, cn_axis_, f.at_r);
      periodic -= PerpAngle(h_r) - delta_ * f.r / (2.0 * jacobi_.K());
    } else {
      periodic -= PerpAngle(out.h);
    }
    out.gamma = omega_gamma_ * tau + (periodic - periodic0_);
  }
  return out;
}

Vec3 FreeBodySolution::H_B(double t) const { return principal_.axes * Evaluate(t, false).h; }

Vec3 FreeBodySolution::w_NB_B(double t) const {
  return principal_.axes * Evaluate(t, false).h.cwiseQuotient(principal_.moments);
}

Quat FreeBodySolution::AttitudeOf(const State& p) const {
  const Quat qz(std::cos(0.5 * p.gamma), 0.0, 0.0, std::sin(0.5 * p.gamma));
  Quat q = q_left_ * qz * AlignQuat(p.h).conjugate() * q_right_;
  q.normalize();
  return q;
}

Quat FreeBodySolution::q_NB(double t) const {
  if (constant_) return q_NB0_ * math::ExpQuat((t - t0_) * w0_B_);
  return AttitudeOf(Evaluate(t, true));
}

void FreeBodySolution::StateAt(double t, Vec3* H_B, Quat* q_NB) const {
  if (constant_) {
    *H_B = principal_.axes * h0_;
    *q_NB = q_NB0_ * math::ExpQuat((t - t0_) * w0_B_);
    return;
  }
  // Evaluate(t, true).h is Evaluate(t, false).h: h is computed before gamma.
  const State p = Evaluate(t, true);
  *H_B = principal_.axes * p.h;
  *q_NB = AttitudeOf(p);
}

int FreeBodySolution::intermediate_axis() const {
  const Vec3& I = principal_.moments;
  if (I[0] == I[1] || I[1] == I[2]) return -1;
  int i = 0;
  principal_.axes.col(1).cwiseAbs().maxCoeff(&i);
  return i;
}

Vec3 FreeBodySolution::intermediate_axis_B() const {
  if (intermediate_axis() < 0) return Vec3::Zero();
  return principal_.axes.col(1);
}

double FreeBodySolution::flip_half_period() const {
  const bool periodic = regime_ == Regime::kMinorAxis || regime_ == Regime::kMajorAxis;
  if (!periodic || constant_ || coef_[1] == 0.0) return kInf;
  return 0.5 * period_;
}

std::vector<double> FreeBodySolution::FlipTimes(double t_begin, double t_end) const {
  std::vector<double> times;
  if (!(t_begin <= t_end)) return times;
  if (regime_ == Regime::kSeparatrix) {
    const double t = t0_ - u0_ / lambda_;  // tanh(u) = 0
    if (t >= t_begin && t <= t_end) times.push_back(t);
    return times;
  }
  if (flip_half_period() == kInf) return times;
  // Zeros of sn(u) at u = 2 K j.
  const double two_k = 2.0 * jacobi_.K();
  const double j_first = std::ceil((lambda_ * (t_begin - t0_) + u0_) / two_k);
  const double j_last = std::floor((lambda_ * (t_end - t0_) + u0_) / two_k);
  if (j_last - j_first + 1.0 > kMaxFlips) {
    std::ostringstream os;
    os << "FreeBodySolution::FlipTimes: [" << t_begin << ", " << t_end << "] s holds "
       << j_last - j_first + 1.0 << " flips (rule: at most " << kMaxFlips << ")";
    throw std::invalid_argument(os.str());
  }
  for (double j = j_first - 1.0; j <= j_last + 1.0; j += 1.0) {
    const double t = t0_ + (two_k * j - u0_) / lambda_;
    if (t >= t_begin && t <= t_end) times.push_back(t);
  }
  return times;
}

double SeparatrixDistance(const FreeBodySolution& sol, const math::Vec3& H_B) {
  const math::Vec3& I = sol.principal_axes().moments;
  const math::Vec3 h = sol.principal_axes().axes.transpose() * H_B;
  const double two_T = 2.0 * sol.energy();
  const double mc = sol.complementary_parameter();
  switch (sol.regime()) {
    case Regime::kMinorAxis: {
      // P3 = 2T I3 - M^2 (a sum of non-negative terms); P2 = 2T I2 - M^2 > 0.
      const double P3 = h[0] * h[0] * (I[2] - I[0]) / I[0] + h[1] * h[1] * (I[2] - I[1]) / I[1];
      const double P2 = mc * (I[1] - I[0]) * P3 / (I[2] - I[0]);
      return -P2 / two_T / (I[2] - I[0]);
    }
    case Regime::kMajorAxis: {
      // P1 = M^2 - 2T I1 (non-negative terms); -P2 = M^2 - 2T I2 > 0.
      const double P1 = h[1] * h[1] * (I[1] - I[0]) / I[1] + h[2] * h[2] * (I[2] - I[0]) / I[2];
      const double minus_P2 = mc * (I[2] - I[1]) * P1 / (I[2] - I[0]);
      return minus_P2 / two_T / (I[2] - I[0]);
    }
    case Regime::kSeparatrix:
    case Regime::kIntermediateAxisSpin:
      return 0.0;
    case Regime::kAxisymmetric:
      return (sol.D() - I[1]) / (I[2] - I[0]);
    case Regime::kSpherical:
    case Regime::kAtRest:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace deploysim::analysis
