#pragma once

/// Exact torque-free motion of a rigid body with constant inertia (docs/design.md 2.3; thesis
/// eqs. 2.22-2.64 and 3.16-3.23; Wittenburg, Dynamics of Multibody Systems, 2008, 3.3;
/// Celledoni, Fasso, Safstrom, Zanna, SIAM J. Sci. Comput. 30(4) 2008, for the attitude).
///
/// Conventions (docs/design.md 1): SI units; H_B [kg m^2/s] is the angular momentum in body
/// components, w_NB_B [rad/s] the angular velocity, q_NB the Hamilton quaternion of R_NB
/// (v_N = R_NB v_B). Equations: dH_B/dt = H_B x w_NB_B, w_NB_B = J_B^-1 H_B,
/// dR_NB/dt = R_NB [w_NB_B]x. Invariants: h_N = R_NB H_B, M = |H_B|, T = 1/2 H_B . w_NB_B.
///
/// Internally everything happens in the principal frame P of J_B (moments I1 < I2 < I3
/// ascending, as math::InertiaTensor::Principal returns them; h = (h1, h2, h3) the momentum
/// components along those axes). With 2T I_i - M^2 formed without cancellation,
///   P1 = M^2 - 2T I1 = h2^2 (I2-I1)/I2 + h3^2 (I3-I1)/I3 >= 0,
///   P3 = 2T I3 - M^2 = h1^2 (I3-I1)/I1 + h2^2 (I3-I2)/I2 >= 0,
///   P2 = 2T I2 - M^2 = h1^2 (I2-I1)/I1 - h3^2 (I3-I2)/I3   (sign decides the regime),
/// the solution is, with u = lambda (t - t0) + u0 and sn, cn, dn of parameter m = k^2:
///   D < I2 (minor): h1 = s A1 dn u, h2 = s A2 sn u, h3 = A3 cn u, s = sign h1,
///       lambda^2 = (I2-I1) P3 / (I1 I2 I3), 1 - k^2 = (I3-I1) P2 / ((I2-I1) P3);
///   D > I2 (major): h1 = A1 cn u, h2 = s A2 sn u, h3 = s A3 dn u, s = sign h3,
///       lambda^2 = (I3-I2) P1 / (I1 I2 I3), 1 - k^2 = (I3-I1)(-P2) / ((I3-I2) P1);
///   D = I2 (separatrix): h1 = s1 A1 sech u, h2 = s1 s3 A2 tanh u, h3 = s3 A3 sech u with
///       two independent signs s1 = sign h1, s3 = sign h3 (lambda as for minor);
/// A1^2 = I1 P3/(I3-I1), A3^2 = I3 P1/(I3-I1), A2^2 = I2 P1/(I2-I1) (minor) or
/// I2 P3/(I3-I2) (major); M^2 = A1^2 + A3^2. 1 - k^2 is never formed as 1 - k^2: P1, P2
/// and P3 are formed in double-double (math::DoubleDouble, ~106 bits), so 1 - k^2 is
/// accurate to ~1e-31 of P2's terms however deep the cancellation in P2 (|P2| below 1e-30
/// of its terms counts as the separatrix). A full J_B is diagonalised to double-double
/// first (math::AccuratePrincipalDecomposition: the double eigen-decomposition's O(eps)
/// error would otherwise be amplified like 1/(1 - k^2)), and H_B0 is projected on the
/// axes in double-double. The phase u0 comes from the Carlson form
/// of F (math::InverseJacobi), quadrant by the signs.
/// Two equal moments (within kEqualMomentsRelTol) are the axisymmetric limit of the same
/// formulas with k = 0 (sn = sin, cn = cos, dn = 1): continuous with the general case.
/// H_B constant (at rest, spherical body, pure spin about the intermediate axis, an
/// axisymmetric body with H_B in the plane of equal moments): uniform rotation about w.
///
/// Accuracy (tests/analysis/free_body_solution_test.cpp): against 38-digit integrations,
/// near and on the separatrix (1 - k^2 = 4e-15 ... 0) and generic, |dH|/M <= 5e-15 and
/// attitude <= 6e-14 rad (3.2e-14 on x86-64, 5.9e-14 on aarch64); invariants |H_B|, T,
/// h_N to ~1e-15. A full J_B near the separatrix (1 - k^2 = 1e-9) agrees with the same
/// body in its principal frame to within the effect of a 1-ulp change of the principal
/// input. Cost on x86-64 at -O3: H_B(t) ~0.55 us, q_NB(t) ~0.85 us, construction ~5 us
/// (~6 us for a full J_B).
///
/// Attitude: R_NB(t) = R_NF Rz(psi(t)) A(h(t)) R_BP^T, where A maps P so that h/M becomes the
/// third axis and the x axis points along the part of the reference axis e_r orthogonal
/// to h; e_r is the principal axis 3 if A1 >= A3, else axis 1, so that |h_r| <= M/sqrt 2
/// and the alignment is never near-singular. The rotation about h_N obeys
///   psi' = M (2T - h_r^2/I_r) / (M^2 - h_r^2) = M/I_o + C_r n sn^2 / (1 - n sn^2),
/// (o the other end axis, C_r = +-M (I3-I1)/(I1 I3), n = -q A_r^2/A_o^2 <= 0, q = 1 if h_r is
/// the cn component, m if it is the dn component), integrated in closed form with the
/// incomplete integral of the third kind in Carlson form, split into the exact mean rate
/// over a period (complete Pi) and a bounded periodic part, so accuracy does not decay
/// with |t - t0| beyond the rounding of (t - t0) itself. The quaternion is continuous in t.

#include <limits>
#include <vector>

#include "deploysim/math/elliptic.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/types.h"

namespace deploysim::analysis {

/// The kind of torque-free motion, from D = M^2 / (2T) and the principal moments
/// I1 <= I2 <= I3 (minor, intermediate, major axis).
enum class Regime {
  kMinorAxis,             ///< I1 <= D < I2: H_B circulates about the minor axis (least moment).
  kMajorAxis,             ///< I2 < D <= I3: H_B circulates about the major axis (largest moment).
  kSeparatrix,            ///< D = I2, H_B off the intermediate axis: tanh/sech, aperiodic.
  kIntermediateAxisSpin,  ///< H_B along the intermediate axis: unstable equilibrium, H_B const.
  kAxisymmetric,          ///< Two equal moments: H_B precesses about the symmetry axis (or const).
  kSpherical,             ///< Three equal moments: H_B constant, w parallel to H.
  kAtRest,                ///< H_B = 0.
};

/// "minor-axis", "major-axis", "separatrix", "intermediate-axis-spin", "axisymmetric",
/// "spherical", "at-rest".
const char* ToString(Regime regime);

/// Closed-form torque-free motion for constant inertia, valid for all t (also t < t0).
/// Class invariant: immutable after construction; every query is a pure function of t.
class FreeBodySolution {
 public:
  /// Moments whose difference is below this fraction of the largest are treated as equal
  /// (their mean is used): the axisymmetric or spherical regime.
  static constexpr double kEqualMomentsRelTol = 1e-13;
  /// FlipTimes refuses to list more flips than this (throws std::invalid_argument).
  static constexpr double kMaxFlips = 1e7;

  /// J_B [kg m^2] (any axis order, full symmetric tensors allowed), H_B0 = H_B(t0)
  /// [kg m^2/s], q_NB0 = q_NB(t0), t0 [s]. Throws std::invalid_argument for non-finite
  /// H_B0 or t0, or a non-unit q_NB0 (| |q| - 1 | > 1e-12).
  FreeBodySolution(const math::InertiaTensor& J_B,
                   const math::Vec3& H_B0,
                   const math::Quat& q_NB0 = math::Quat::Identity(),
                   double t0 = 0.0);

  /// Body-frame angular momentum H_B(t) [kg m^2/s]; |H_B(t)| = M and
  /// 1/2 H_B . J^-1 H_B = T for all t.
  math::Vec3 H_B(double t) const;
  /// Angular velocity w_NB_B(t) = J_B^-1 H_B(t) [rad/s] (principal moments as used, see
  /// kEqualMomentsRelTol).
  math::Vec3 w_NB_B(double t) const;
  /// Attitude q_NB(t) (unit, continuous in t); R_NB(t) H_B(t) = h_N for all t.
  math::Quat q_NB(double t) const;
  /// H_B(t) and q_NB(t) from one evaluation of the elliptic functions (bit for bit the
  /// values of H_B(t) and q_NB(t), at about 60% of their cost).
  void StateAt(double t, math::Vec3* H_B, math::Quat* q_NB) const;

  Regime regime() const { return regime_; }
  /// Complementary parameter mc = 1 - k^2 of the elliptic functions, formed from the exact
  /// identity (no cancellation): 0 on the separatrix, 1 for axisymmetric bodies and pure
  /// spins about the minor or major axis; 1 also for the regimes with constant H_B.
  double complementary_parameter() const { return mc_; }
  /// Rate lambda [rad/s] of the elliptic argument u = lambda (t - t0) + u0 (0 if H_B is
  /// constant; for axisymmetric bodies the precession rate |(I3-I1) h_s / (I1 I3)|).
  double lambda() const { return lambda_; }
  /// Full period [s] of H_B(t), 4 K / lambda; +inf on the separatrix and when H_B is constant.
  double period() const { return period_; }
  /// Kinetic energy T = 1/2 H_B . J^-1 H_B [J].
  double energy() const { return energy_; }
  /// M = |H_B| [kg m^2/s].
  double momentum_magnitude() const { return M_; }
  /// D = M^2 / (2T) [kg m^2], I1 <= D <= I3 (thesis 2.29); 0 at rest.
  double D() const { return D_; }
  /// Principal decomposition used (ascending moments, right-handed axes in B).
  const math::PrincipalAxes& principal_axes() const { return principal_; }

  /// Index (0, 1, 2) of the body axis e_i of B along which the intermediate principal axis
  /// lies (for a diagonal J_B) or to which it is closest (largest |component|, full J_B);
  /// -1 when two moments are equal (no intermediate axis).
  int intermediate_axis() const;
  /// Unit intermediate principal axis in B (zero vector when intermediate_axis() == -1).
  math::Vec3 intermediate_axis_B() const;

  /// Times in [t_begin, t_end] [s], ascending, at which H_B . e_intermediate changes sign
  /// (the Dzhanibekov flip): every T/2 in the periodic regimes (none if that component is
  /// identically zero, i.e. a pure spin), at most one on the separatrix, none otherwise.
  std::vector<double> FlipTimes(double t_begin, double t_end) const;
  /// T/2 [s] between flips in the periodic regimes with flips; +inf otherwise.
  double flip_half_period() const;

 private:
  struct Invariants;
  struct State {
    math::Vec3 h;  ///< Momentum in principal components [kg m^2/s].
    double gamma;  ///< Rotation angle about h_N [rad] (see q_NB), 0 at t0.
  };
  void SetUpSeparatrix(const Invariants& v);
  void SetUpPeriodic(const Invariants& v);
  void SetUpAttitude(const math::Quat& q_NB0);
  /// Momentum in principal components and, if with_gamma, the attitude angle gamma(t).
  State Evaluate(double t, bool with_gamma) const;
  /// q_NB of an evaluated state (with gamma).
  math::Quat AttitudeOf(const State& p) const;
  /// Continuous angle of the h-component orthogonal to the reference axis, measured from
  /// the direction of its value at u = 0 (|result| <= pi/2 within a half period).
  double PerpAngle(const math::Vec3& h) const;
  /// Bounded periodic part of Pi(n; r) - (Pi(n)/K) r, over n/3, at the reduced argument.
  double PeriodicPi(double r, const math::SnCnDn& f) const;
  /// Unit quaternion of the minimal rotation taking the reference axis to h/M.
  math::Quat AlignQuat(const math::Vec3& h) const;

  math::PrincipalAxes principal_;  ///< Moments [kg m^2] as used (equal ones merged).
  math::Vec3 h0_;                  ///< Principal components of H_B0.
  math::Quat q_NB0_;
  double t0_;
  Regime regime_ = Regime::kAtRest;
  bool constant_ = true;  ///< H_B constant: uniform rotation about w.
  double M_ = 0.0;
  double energy_ = 0.0;
  double D_ = 0.0;
  double mc_ = 1.0;
  double lambda_ = 0.0;
  double period_ = std::numeric_limits<double>::infinity();
  double u0_ = 0.0;
  math::JacobiElliptic jacobi_{1.0};
  int dn_axis_ = 0;  ///< Principal index carrying dn (minor: 0, major: 2).
  int cn_axis_ = 2;  ///< Principal index carrying cn.
  math::Vec3 coef_;  ///< Signed amplitudes: h_i = coef_i * f_i(u).
  // Attitude.
  int ref_axis_ = 2;                 ///< Reference principal axis r (0 or 2).
  bool winding_ = false;             ///< The orthogonal part of h turns by Delta every half period.
  double n_char_ = 0.0;              ///< Characteristic n <= 0 of the third-kind integral.
  double rj_over_k_ = 0.0;           ///< R_J(0, mc, 1, 1 - n) / K.
  double pi_coef_ = 0.0;             ///< C_r n / (3 lambda) [rad].
  double sep_coef_ = 0.0;            ///< Separatrix: (C_r/lambda) sqrt(nu)/(1+nu) [rad].
  double sqrt_nu_ = 0.0;             ///< Separatrix: sqrt(-n).
  double omega_gamma_ = 0.0;         ///< Secular rate of gamma [rad/s].
  double delta_ = 0.0;               ///< Winding per half period [rad] (+-pi or 0).
  double perp_dir_[2] = {1.0, 0.0};  ///< Unit direction of the orthogonal part at u = 0.
  double periodic0_ = 0.0;           ///< Periodic part of gamma at t0.
  math::Quat q_left_;                ///< Constant factor C (left).
  math::Quat q_right_;               ///< Constant factor Q R_PB (right).
  math::Vec3 w0_B_;                  ///< Angular velocity in the constant regimes.
};

/// The separatrix distance (D - I2) / (I3 - I1), D = M^2 / (2T), of the torque-free
/// motion `sol` started from momentum H_B, formed without cancellation from its 1 - k^2 (so its
/// sign is the regime's, and it stays accurate where D - I2 is far below rounding of D): 0 on the
/// separatrix and for a pure intermediate-axis spin, < 0 about the minor axis, NaN for
/// three equal moments or at rest.
double SeparatrixDistance(const FreeBodySolution& sol, const math::Vec3& H_B);

}  // namespace deploysim::analysis
