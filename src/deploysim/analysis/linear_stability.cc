#include "deploysim/analysis/linear_stability.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "deploysim/analysis/floquet.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/so3.h"
#include "deploysim/math/units.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::analysis {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using math::Mat3;
using math::Vec3;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using math::kPi;

/// The scale of each coordinate of y (its finite-difference step is 1e-4 of it): |H| for
/// the momenta (H_B and p_f alike: a hinge's momentum is a part of the system's), 1 rad
/// for the angles.
VectorXd Scales(int m, double M) {
  VectorXd s = VectorXd::Constant(3 + 2 * m, M);
  s.segment(3, m).setOnes();
  return s;
}

/// dF/dy (floquet.h, RichardsonJacobian).
MatrixXd Jacobian(const ReducedFlow& flow, const VectorXd& y, const VectorXd& scale) {
  return RichardsonJacobian(flow.rhs, y, scale);
}

/// Rows/columns kept: every coordinate but the cyclic angles.
std::vector<Eigen::Index> Kept(int m, const std::vector<int>& cyclic) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < 3 + 2 * m; ++i) {
    const bool drop =
        i >= 3 && i < 3 + m &&
        std::find(cyclic.begin(), cyclic.end(), static_cast<int>(i - 3)) != cyclic.end();
    if (!drop) keep.push_back(i);
  }
  return keep;
}

MatrixXd Sub(const MatrixXd& A,
             const std::vector<Eigen::Index>& rows,
             const std::vector<Eigen::Index>& cols) {
  MatrixXd B(rows.size(), cols.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < cols.size(); ++j) B(i, j) = A(rows[i], cols[j]);
  }
  return B;
}

VectorXd Pick(const VectorXd& v, const std::vector<Eigen::Index>& rows) {
  VectorXd out(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[rows[i]];
  return out;
}

/// The starting point: H_B turned onto the principal axis of the held body nearest it.
VectorXd StartingPoint(const ReducedFlow& flow, const VectorXd& y_guess) {
  Mat3 J;
  Vec3 h_r;
  flow.rigid(y_guess, J, h_r);
  const Vec3 H = y_guess.head<3>();
  const math::PrincipalAxes pa = math::PrincipalDecomposition(J);
  int best = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(pa.axes.col(i).dot(H)) > std::abs(pa.axes.col(best).dot(H))) best = i;
  }
  const Vec3 a = pa.axes.col(best);
  VectorXd y = y_guess;
  y.head<3>() = (a.dot(H) >= 0.0 ? 1.0 : -1.0) * H.norm() * a;
  return y;
}

/// Levenberg-Marquardt (floquet.cc says why) on F(y) = 0 (cyclic angles' rows left out),
/// |H_B| = M and the invariants c . y at their values at `reference` (the phase's state).
/// `residual`: |F| alone.
bool SolveEquilibrium(const ReducedFlow& flow,
                      const std::vector<int>& cyclic,
                      const std::vector<VectorXd>& invariants,
                      const VectorXd& reference,
                      double M,
                      VectorXd& y,
                      double& residual) {
  const int m = flow.free;
  const VectorXd scale = Scales(m, M);
  const std::vector<Eigen::Index> keep = Kept(m, cyclic);
  const Eigen::Index rows = static_cast<Eigen::Index>(keep.size() + 1 + invariants.size());
  auto residuals = [&](const VectorXd& yy) {
    const VectorXd f = flow.rhs(yy);
    VectorXd r(rows);
    for (std::size_t i = 0; i < keep.size(); ++i) r[i] = f[keep[i]];
    r[keep.size()] = (yy.head<3>().squaredNorm() - M * M) / M;
    for (std::size_t k = 0; k < invariants.size(); ++k)
      r[keep.size() + 1 + k] = invariants[k].dot(yy - reference);
    return r;
  };
  // The unknowns: the kept coordinates but the cyclic angles' momenta, which the phase
  // conserves (nothing depends on the angle): the steady spin of this phase has the
  // phase's values of them, not those of another member of the family.
  std::vector<Eigen::Index> vary;
  for (Eigen::Index c : keep) {
    const bool conserved = c >= 3 + m && std::find(cyclic.begin(), cyclic.end(),
                                                   static_cast<int>(c - 3 - m)) != cyclic.end();
    if (!conserved) vary.push_back(c);
  }
  const VectorXd kept_scale = Pick(scale, vary);
  for (int it = 0; it < 40; ++it) {
    const VectorXd r = residuals(y);
    MatrixXd Jr(r.size(), vary.size());
    for (std::size_t j = 0; j < vary.size(); ++j) {
      const Eigen::Index c = vary[j];
      const double h = 1e-6 * scale[c];
      VectorXd yp = y, ym = y;
      yp[c] += h;
      ym[c] -= h;
      Jr.col(static_cast<Eigen::Index>(j)) = (residuals(yp) - residuals(ym)) / (2.0 * h);
    }
    const double lambda = r.squaredNorm() / (M * M);
    MatrixXd aug(Jr.rows() + Jr.cols(), Jr.cols());
    aug << Jr, std::sqrt(lambda) * MatrixXd::Identity(Jr.cols(), Jr.cols());
    VectorXd rhs_aug = VectorXd::Zero(aug.rows());
    rhs_aug.head(r.size()) = -r;
    const VectorXd du = aug.colPivHouseholderQr().solve(rhs_aug);
    for (std::size_t j = 0; j < vary.size(); ++j) y[vary[j]] += du[static_cast<Eigen::Index>(j)];
    if ((du.array() / kept_scale.array()).abs().maxCoeff() < 1e-14) break;
  }
  residual = residuals(y).head(keep.size()).norm();
  return std::isfinite(residual);
}

/// The eigen decomposition of d/dH of H x J^-1 (H - h_r), the held body's momentum
/// equation linearized. A 3x3 problem solved as a dynamic-size one: Eigen's EigenSolver is
/// one of its costliest templates to compile, and this file instantiates it once.
Eigen::EigenSolver<MatrixXd> HeldMomentumEigen(const Mat3& J,
                                               const Vec3& h_r,
                                               const Vec3& H,
                                               bool vectors) {
  const Mat3 Jinv = J.inverse();
  const MatrixXd A = -math::Hat(Vec3(Jinv * (H - h_r))) + math::Hat(H) * Jinv;
  return Eigen::EigenSolver<MatrixXd>(A, vectors);
}

/// The quasi-rigid energy-sink estimate (see the header), from the Jacobian at y*.
void QuasiRigid(const ReducedFlow& flow,
                const MatrixXd& A,
                const std::vector<Eigen::Index>& keep,
                SteadySpin& out) {
  out.quasi_rigid_rate = kNaN;
  out.rigid_frequency = kNaN;
  Mat3 J;
  Vec3 h_r;
  flow.rigid(out.y, J, h_r);
  const Vec3 H = out.y.head<3>();
  const Mat3 Jinv = J.inverse();
  const Vec3 w = Jinv * (H - h_r);
  const Eigen::EigenSolver<MatrixXd> es = HeldMomentumEigen(J, h_r, H, true);
  int k = -1;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(es.eigenvalues()[i].imag()) > kNeutralRate * w.norm() &&
        (k < 0 || es.eigenvalues()[i].imag() > es.eigenvalues()[k].imag())) {
      k = i;
    }
  }
  if (k < 0) return;
  const std::complex<double> lam(0.0, es.eigenvalues()[k].imag());
  out.rigid_frequency = lam.imag();
  if (!flow.sink_power) return;
  const Eigen::Vector3cd v = es.eigenvectors().col(k);
  // The sink driven by it: X = (lam - A_xx)^-1 A_xH v over the kept shape coordinates.
  const Eigen::Index ns = static_cast<Eigen::Index>(keep.size()) - 3;
  Eigen::VectorXcd X = Eigen::VectorXcd::Zero(ns);
  if (ns > 0) {
    MatrixXd Axx(ns, ns), AxH(ns, 3);
    for (Eigen::Index i = 0; i < ns; ++i) {
      for (Eigen::Index j = 0; j < ns; ++j) Axx(i, j) = A(keep[3 + i], keep[3 + j]);
      for (Eigen::Index j = 0; j < 3; ++j) AxH(i, j) = A(keep[3 + i], j);
    }
    const Eigen::MatrixXcd S =
        lam * Eigen::MatrixXcd::Identity(ns, ns) - Axx.cast<std::complex<double>>();
    X = S.partialPivLu().solve(AxH.cast<std::complex<double>>() * v);
  }
  // Mean sink power over a cycle at amplitude eps, and the energy excess of the mode.
  const double eps = 1e-5 * H.norm() / v.norm();
  const double mu = w.norm() / H.norm() * (w.dot(H) >= 0.0 ? 1.0 : -1.0);
  const int n = 16;
  double P = 0.0, dE = 0.0;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> e = std::polar(1.0, 2.0 * kPi * i / n);
    VectorXd y = out.y;
    const Vec3 dH = eps * (v * e).real();
    y.head<3>() += dH;
    for (Eigen::Index j = 0; j < ns; ++j) y[keep[3 + j]] += eps * (X[j] * e).real();
    P += flow.sink_power(y) / n;
    dE += 0.5 * dH.dot((Jinv - mu * Mat3::Identity()) * dH) / n;
  }
  if (dE != 0.0) out.quasi_rigid_rate = P / (2.0 * dE);
}

}  // namespace

namespace {

/// The nutation mode and the verdict from out.modes (sorted here): the first mode, by
/// largest real part, whose momentum share is at least a quarter of the largest.
void PickNutationMode(SteadySpin& out, double neutral) {
  std::sort(out.modes.begin(), out.modes.end(),
            [](const SpinMode& a, const SpinMode& b) { return a.lambda.real() > b.lambda.real(); });
  double share = 0.0;
  for (const SpinMode& md : out.modes) share = std::max(share, md.momentum_share);
  out.max_real = out.modes.empty() ? 0.0 : out.modes.front().lambda.real();
  for (const SpinMode& md : out.modes) {
    if (md.momentum_share >= 0.25 * share) {
      out.growth_rate = md.lambda.real();
      out.frequency = std::abs(md.lambda.imag());
      break;
    }
  }
  out.verdict = out.max_real > neutral    ? "unstable"
                : out.max_real < -neutral ? "asymptotically stable"
                                          : "neutrally stable";
}

/// The share of an eigenvector (scaled back to the coordinates' units) that tilts H_B
/// away from the unit vector u.
double MomentumShare(const Eigen::VectorXcd& v, const Vec3& u) {
  const Eigen::Vector3cd vH = v.head<3>();
  const Eigen::Vector3cd uc = u.cast<std::complex<double>>();
  const Eigen::Vector3cd tilt = vH - uc * (uc.dot(vH));
  return tilt.norm() / std::max(v.norm(), 1e-300);
}

/// The hub's spin at y.
Vec3 HubRate(const ReducedFlow& flow, const VectorXd& y) {
  Mat3 J;
  Vec3 h_r;
  flow.rigid(y, J, h_r);
  return J.inverse() * (y.head<3>() - h_r);
}

/// [rad/s] the scale of the motion's rates: the hub's spin, or |H| over the mean moment
/// where the hub hardly turns (a despun hub beside a spinning body).
double RateScale(const ReducedFlow& flow, const VectorXd& y) {
  Mat3 J;
  Vec3 h_r;
  flow.rigid(y, J, h_r);
  return std::max(HubRate(flow, y).norm(), 3.0 * y.head<3>().norm() / J.trace());
}

/// A state near y where nothing is symmetric: H_B tilted by 0.1 rad, the angles by 0.1 rad
/// (a time dependence that a symmetric state hides shows there).
VectorXd GenericState(const VectorXd& y, int m) {
  VectorXd g = y;
  const Vec3 H = y.head<3>();
  Vec3 side = H.unitOrthogonal();
  side = (0.8 * side + 0.6 * H.normalized().cross(side)).normalized();
  g.head<3>() = (H + 0.1 * H.norm() * side).normalized() * H.norm();
  for (int a = 0; a < m; ++a) g[3 + a] += 0.1 * (a + 1);
  return g;
}

enum class TimeDependence { kNone, kPeriodic, kOther };

/// Whether F changes over the phase, and whether it repeats with flow.period.
TimeDependence DependenceOnTime(const ReducedFlow& flow, const VectorXd& y, double M) {
  if (!flow.rhs_time) return TimeDependence::kNone;
  const VectorXd g = GenericState(y, flow.free);
  const VectorXd f0 = flow.rhs_time(0.0, g);
  const double tol = 1e-9 * (f0.norm() + M * HubRate(flow, g).norm());
  const double span = std::isfinite(flow.phase_length) ? flow.phase_length : 1e4;
  bool changes = false;
  for (double frac : {0.37, 0.71}) {
    const double tau = frac * (flow.period > 0.0 ? std::min(flow.period, span) : span);
    changes = changes || (flow.rhs_time(tau, g) - f0).norm() > tol;
  }
  if (!changes) return TimeDependence::kNone;
  if (!(flow.period > 0.0) || flow.period > flow.phase_length) return TimeDependence::kOther;
  for (double frac : {0.0, 0.37}) {
    const double tau = frac * flow.period;
    if ((flow.rhs_time(tau + flow.period, g) - flow.rhs_time(tau, g)).norm() > tol)
      return TimeDependence::kOther;
  }
  return TimeDependence::kPeriodic;
}

/// The momenta of the winding hinges that the flow conserves: c . y = u . H_B - p_a (the
/// system's momentum about the rotor's axis u less the rotor side's own: the momentum of
/// the body it turns against, conserved when that body is symmetric about u and nothing
/// else turns on it), kept where F conserves it at a generic state.
std::vector<VectorXd> RotorInvariants(const ReducedFlow& flow, const VectorXd& y) {
  std::vector<VectorXd> out;
  const int m = flow.free;
  const VectorXd g = GenericState(y, m);
  const VectorXd f = flow.rhs(g);
  for (std::size_t k = 0; k < flow.winding.size() && k < flow.winding_axes.size(); ++k) {
    const int a = flow.winding[k];
    VectorXd c = VectorXd::Zero(3 + 2 * m);
    c.head<3>() = flow.winding_axes[k];
    c[3 + m + a] = -1.0;
    if (std::abs(c.dot(f)) <= 1e-10 * f.norm()) out.push_back(c);
  }
  return out;
}

/// The Floquet modes of the periodic orbit through y (an autonomous one if `rotor` >= 0,
/// the free hinge whose angle advances 2 pi per period; else F repeats with flow.period).
SteadySpin PeriodicSpin(
    const ReducedFlow& flow, const VectorXd& y, const VectorXd& phase_state, double M, int rotor) {
  SteadySpin out;
  out.motion = "periodic";
  const int m = flow.free;
  const Eigen::Index n = 3 + 2 * m;
  OrbitProblem p;
  p.scale = Scales(m, M);
  p.advance = VectorXd::Zero(n);
  p.momentum = M;
  p.fastest = HubRate(flow, y).norm();
  p.reference = phase_state;
  p.invariants = RotorInvariants(flow, phase_state);
  if (rotor >= 0) {
    const double turn = flow.rhs(y)[3 + rotor];
    p.rhs = [&flow](double, const VectorXd& yy) { return flow.rhs(yy); };
    p.advance[3 + rotor] = turn > 0.0 ? 2.0 * kPi : -2.0 * kPi;
    p.period_guess = 2.0 * kPi / std::abs(turn);
    p.phase = 3 + rotor;
  } else {
    p.rhs = flow.rhs_time;
    p.period_guess = flow.period;
    p.period_fixed = true;
  }
  p.fastest = std::max(p.fastest, 2.0 * kPi / p.period_guess);
  const PeriodicOrbit orbit = SolvePeriodicOrbit(p, y);
  out.residual = orbit.residual;
  out.period = orbit.period;
  out.y = orbit.y0;
  if (!orbit.found || !(orbit.residual <= kSolutionResidual)) {
    out.reason = orbit.found ? "no periodic motion found near the phase's state (residual " +
                                   math::FormatSignificant(orbit.residual, 3) + ")"
                             : orbit.reason;
    return out;
  }
  out.w_B = HubRate(flow, out.y);
  out.orbit_slack = rotor >= 0 ? 1.0 / 16.0 : 0.0;
  if (rotor >= 0) {
    out.orbit_rotor = rotor;
    out.orbit_rotor_angle = out.y[3 + rotor];
    out.orbit_rotor_advance = p.advance[3 + rotor];
  }
  {
    VectorXd yk = out.y;
    const double dt = orbit.period / kOrbitPoints;
    const int sub = std::max(1, orbit.steps / kOrbitPoints);
    for (int k = 0; k < kOrbitPoints; ++k) {
      out.orbit_axes.push_back(Vec3(yk.head<3>()).normalized());
      yk = FlowMap(p.rhs, k * dt, yk, dt, sub);
    }
  }
  Eigen::EigenSolver<MatrixXd> es(orbit.monodromy);
  if (es.info() != Eigen::Success) {
    out.reason = "the eigenvalue solver did not converge";
    return out;
  }
  const Vec3 u = out.y.head<3>() / M;
  const double T = orbit.period;
  // The multipliers 1 that the orbit's symmetries put there: along the orbit (an
  // autonomous one), |H|, each rotor invariant. They are the ones nearest 1 (a defective
  // pair splits under the monodromy's error by ~1e-5).
  const std::size_t ones = (rotor >= 0 ? 1 : 0) + 1 + p.invariants.size();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(es.eigenvalues().size()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
  std::sort(order.begin(), order.end(), [&es](Eigen::Index a, Eigen::Index b) {
    return std::abs(es.eigenvalues()[a] - 1.0) < std::abs(es.eigenvalues()[b] - 1.0);
  });
  for (std::size_t k = std::min(ones, order.size()); k < order.size(); ++k) {
    const std::complex<double> mu = es.eigenvalues()[order[k]];
    const Eigen::VectorXcd v =
        es.eigenvectors().col(order[k]).cwiseQuotient(p.scale.cast<std::complex<double>>());
    out.modes.push_back({std::log(mu) / T, MomentumShare(v, u)});
  }
  const double rate = RateScale(flow, out.y);
  PickNutationMode(out, 1e-7 * rate);
  out.quasi_rigid_rate = kNaN;  // the textbook estimate needs a steady spin
  out.rigid_frequency = kNaN;
  out.found = true;
  return out;
}

/// The relative equilibrium near y (cyclic angles left out) and its eigenvalues; the
/// `invariants` (RotorInvariants) held at the phase's state's values.
SteadySpin SteadyModes(const ReducedFlow& flow,
                       const std::vector<int>& cyclic,
                       const std::vector<VectorXd>& invariants,
                       const VectorXd& phase_state,
                       double M,
                       VectorXd y) {
  SteadySpin out;
  out.motion = "steady";
  const int m = flow.free;
  // The invariants held where the equations allow it: a rotor at rest on the hub (turning
  // with it) keeps them only by turning slowly (the phase is then periodic with a period
  // far beyond any use), and the steady spin nearest the phase's state is taken instead.
  VectorXd held = y;
  double held_residual = 0.0;
  const bool with =
      !invariants.empty() &&
      SolveEquilibrium(flow, cyclic, invariants, phase_state, M, held, held_residual) &&
      held_residual <= kSolutionResidual * M * RateScale(flow, held);
  if (with) {
    y = held;
    out.residual = held_residual;
  } else if (!SolveEquilibrium(flow, cyclic, {}, phase_state, M, y, out.residual)) {
    out.reason = "no steady spin found near the phase's state";
    return out;
  }
  out.y = y;
  out.w_B = HubRate(flow, y);
  const double rate = RateScale(flow, y);
  out.residual /= M * rate;
  if (!(out.residual <= kSolutionResidual)) {
    out.reason = "no steady spin found near the phase's state (residual " +
                 math::FormatSignificant(out.residual, 3) + ")";
    return out;
  }
  const std::vector<Eigen::Index> keep = Kept(m, cyclic);
  const MatrixXd A = Jacobian(flow, y, Scales(m, M));
  Eigen::EigenSolver<MatrixXd> es(Sub(A, keep, keep));
  if (es.info() != Eigen::Success) {
    out.reason = "the eigenvalue solver did not converge";
    return out;
  }
  const Vec3 u = y.head<3>() / M;
  const VectorXd scale = Pick(Scales(m, M), keep);
  // The zero eigenvalues that symmetries and conserved quantities put there: |H|, each
  // cyclic angle's momentum, and for each other rotor invariant its value and the angle
  // of the rotor (turning the rotor and what rides it is another steady spin). They are
  // the ones nearest 0 (a defective pair splits under the Jacobian's error by ~1e-6).
  // Beyond them, a zero at rounding level is a neutral direction of the model itself (a
  // slosh pendulum on the spin axis swings freely in the plane): no mode either.
  const std::size_t zeros = 1 + cyclic.size() + 2 * invariants.size();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(es.eigenvalues().size()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
  std::sort(order.begin(), order.end(), [&es](Eigen::Index a, Eigen::Index b) {
    return std::abs(es.eigenvalues()[a]) < std::abs(es.eigenvalues()[b]);
  });
  for (std::size_t k = std::min(zeros, order.size()); k < order.size(); ++k) {
    const std::complex<double> lam = es.eigenvalues()[order[k]];
    if (std::abs(lam) <= kNeutralRate * rate) continue;
    const Eigen::VectorXcd v =
        es.eigenvectors().col(order[k]).cwiseQuotient(scale.cast<std::complex<double>>());
    out.modes.push_back({lam, MomentumShare(v, u)});
  }
  PickNutationMode(out, 1e-7 * rate);  // the Jacobian's own error is ~1e-12 relative
  QuasiRigid(flow, A, keep, out);
  out.found = true;
  return out;
}

/// The free hinge that turns as a rotor and that F depends on (a damper rides it): its
/// index in free order, -1 if none; -2 if several do (their angles' motion is not one
/// period).
int TurningRotor(const ReducedFlow& flow, const VectorXd& y, const std::vector<int>& cyclic) {
  const double w = HubRate(flow, y).norm();
  const VectorXd f = flow.rhs(y);
  int found = -1;
  for (int a : flow.winding) {
    if (std::find(cyclic.begin(), cyclic.end(), a) != cyclic.end()) continue;
    if (!(std::abs(f[3 + a]) > 1e-3 * w)) continue;
    if (found >= 0) return -2;
    found = a;
  }
  return found;
}

}  // namespace

SteadySpin LinearizeSteadySpin(const ReducedFlow& flow, const VectorXd& y_guess) {
  SteadySpin out;
  const int m = flow.free;
  const double M = y_guess.head<3>().norm();
  if (!(M > 0.0)) {
    out.reason = "no angular momentum";
    return out;
  }
  std::vector<int> cyclic = flow.cyclic;
  VectorXd y = StartingPoint(flow, y_guess);
  const TimeDependence dep = DependenceOnTime(flow, y_guess, M);
  if (dep == TimeDependence::kOther) {
    out.reason =
        "the phase is neither steady nor periodic: a prescribed motion or a motor changes it "
        "in time";
    return out;
  }
  if (dep == TimeDependence::kPeriodic) return PeriodicSpin(flow, y, y_guess, M, -1);
  if (cyclic.empty() && m > 0) {
    const MatrixXd A = Jacobian(flow, y, Scales(m, M));
    for (int a = 0; a < m; ++a) {
      if (A.col(3 + a).norm() <= 1e-12 * A.norm()) cyclic.push_back(a);
    }
  }
  const int rotor = TurningRotor(flow, y_guess, cyclic);
  if (rotor == -2) {
    out.reason = "two rotors turn and the motion depends on both angles: not periodic";
    return out;
  }
  if (rotor >= 0) return PeriodicSpin(flow, y, y_guess, M, rotor);
  // Rotor invariants of hinges that are not cyclic (cyclic ones hold their momentum).
  std::vector<VectorXd> invariants;
  for (const VectorXd& c : RotorInvariants(flow, y_guess)) {
    int a = 0;
    while (a < m && c[3 + m + a] == 0.0) ++a;
    if (std::find(cyclic.begin(), cyclic.end(), a) == cyclic.end()) invariants.push_back(c);
  }
  return SteadyModes(flow, cyclic, invariants, y_guess, M, y);
}

ReducedFlow FlowOf(const schedule::FreeHingeSystem& sys,
                   double t,
                   double length,
                   double period,
                   std::vector<int> winding,
                   std::vector<Vec3> winding_axes) {
  ReducedFlow f;
  const int m = sys.free_count();
  f.free = m;
  auto rhs_at = [&sys, m](double tt, const VectorXd& y) {
    Vec3 w;
    VectorXd xd;
    const VectorXd x = y.tail(2 * m);
    const Vec3 H = y.head<3>();
    sys.Evaluate(tt, H, x, dynamics::Side::kRight, w, xd);
    VectorXd out(3 + 2 * m);
    out << H.cross(w), xd;
    return out;
  };
  f.rhs = [rhs_at, t](const VectorXd& y) { return rhs_at(t, y); };
  f.rhs_time = [rhs_at, t](double tau, const VectorXd& y) { return rhs_at(t + tau, y); };
  f.phase_length = length;
  f.period = period;
  f.winding = std::move(winding);
  f.winding_axes = std::move(winding_axes);
  f.sink_power = [&sys, t, m](const VectorXd& y) {
    const schedule::FreeHingeSystem::Powers p = sys.Snap(t, y.head<3>(), y.tail(2 * m)).powers;
    return p.damper + p.friction;
  };
  f.rigid = [&sys, t, m](const VectorXd& y, Mat3& J, Vec3& h_r) {
    const schedule::FreeHingeSystem::Snapshot s = sys.Snap(t, y.head<3>(), y.tail(2 * m));
    J = s.J_B;
    h_r = s.h_rel_B;
  };
  return f;
}

double AngleFromOrbit(const SteadySpin& s, double tau, const Vec3& H_B, double slack_share) {
  const std::vector<Vec3>& curve = s.orbit_axes;
  const long n = static_cast<long>(curve.size());
  const Vec3 h = H_B.normalized();
  const double x = tau / s.period * static_cast<double>(n);
  const long k0 = static_cast<long>(std::floor(x));
  auto at = [&curve, n](long k) -> const Vec3& {
    return curve[static_cast<std::size_t>(((k % n) + n) % n)];
  };
  if (slack_share == 0.0) {
    // An exact clock: the orbit's point at this phase, interpolated (a projection onto
    // the curve would drop the part of the nutation along it).
    const Vec3 p = (at(k0) + (x - static_cast<double>(k0)) * (at(k0 + 1) - at(k0))).normalized();
    return std::atan2(p.cross(h).norm(), p.dot(h));
  }
  const long slack = 1 + static_cast<long>(slack_share * static_cast<double>(n));
  double best = std::numeric_limits<double>::infinity();
  for (long k = k0 - slack; k <= k0 + slack; ++k) {
    const Vec3& a = at(k);
    const Vec3& b = at(k + 1);
    // The nearest point of the chord a-b (flat: the segment is short), then its angle.
    const Vec3 d = b - a;
    const double u =
        d.squaredNorm() > 0.0 ? std::clamp((h - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    const Vec3 p = (a + u * d).normalized();
    best = std::min(best, std::atan2(p.cross(h).norm(), p.dot(h)));
  }
  return best;
}

double HeldNutationRate(const Mat3& J_B, const Vec3& h_r, const Vec3& H_B) {
  const Eigen::EigenSolver<MatrixXd> es = HeldMomentumEigen(J_B, h_r, H_B, false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

ReducedFlow FlowOf(const Mat3& J_B, const Vec3& h_r) {
  ReducedFlow f;
  const Mat3 Jinv = J_B.inverse();
  f.rhs = [Jinv, h_r](const VectorXd& y) {
    const Vec3 H = y.head<3>();
    return VectorXd(H.cross(Jinv * (H - h_r)));
  };
  f.rigid = [J_B, h_r](const VectorXd&, Mat3& J, Vec3& h) {
    J = J_B;
    h = h_r;
  };
  return f;
}

}  // namespace deploysim::analysis
