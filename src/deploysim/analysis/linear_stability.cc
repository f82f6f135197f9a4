#include "deploysim/analysis/linear_stability.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "deploysim/math/inertia.h"
#include "deploysim/math/so3.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::analysis {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using math::Mat3;
using math::Vec3;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

/// The scale of each coordinate of y (its finite-difference step is 1e-4 of it): |H| for
/// the momenta (H_B and p_f alike: a hinge's momentum is a part of the system's), 1 rad
/// for the angles.
VectorXd Scales(int m, double M) {
  VectorXd s = VectorXd::Constant(3 + 2 * m, M);
  s.segment(3, m).setOnes();
  return s;
}

/// dF/dy by central differences with one Richardson extrapolation:
/// D = (4 D(h/2) - D(h)) / 3, error O(h^4) plus rounding ~ eps |F| / h.
MatrixXd Jacobian(const ReducedFlow& flow, const VectorXd& y, const VectorXd& scale) {
  const Eigen::Index n = y.size();
  MatrixXd A(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    auto diff = [&](double h) {
      VectorXd yp = y, ym = y;
      yp[j] += h;
      ym[j] -= h;
      return VectorXd((flow.rhs(yp) - flow.rhs(ym)) / (2.0 * h));
    };
    const double h = 1e-4 * scale[j];
    A.col(j) = (4.0 * diff(0.5 * h) - diff(h)) / 3.0;
  }
  return A;
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

/// Gauss-Newton on F(y) = 0 (cyclic angles' rows left out) and |H_B| = M.
bool SolveEquilibrium(const ReducedFlow& flow,
                      const std::vector<int>& cyclic,
                      double M,
                      VectorXd& y,
                      double& residual) {
  const int m = flow.free;
  const VectorXd scale = Scales(m, M);
  const std::vector<Eigen::Index> keep = Kept(m, cyclic);
  auto residuals = [&](const VectorXd& yy) {
    const VectorXd f = flow.rhs(yy);
    VectorXd r(keep.size() + 1);
    for (std::size_t i = 0; i < keep.size(); ++i) r[i] = f[keep[i]];
    r[keep.size()] = (yy.head<3>().squaredNorm() - M * M) / M;
    return r;
  };
  const VectorXd kept_scale = Pick(scale, keep);
  for (int it = 0; it < 40; ++it) {
    const VectorXd r = residuals(y);
    MatrixXd Jr(r.size(), keep.size());
    for (std::size_t j = 0; j < keep.size(); ++j) {
      const Eigen::Index c = keep[j];
      const double h = 1e-6 * scale[c];
      VectorXd yp = y, ym = y;
      yp[c] += h;
      ym[c] -= h;
      Jr.col(static_cast<Eigen::Index>(j)) = (residuals(yp) - residuals(ym)) / (2.0 * h);
    }
    const VectorXd du = Jr.colPivHouseholderQr().solve(-r);
    for (std::size_t j = 0; j < keep.size(); ++j) y[keep[j]] += du[static_cast<Eigen::Index>(j)];
    if ((du.array() / kept_scale.array()).abs().maxCoeff() < 1e-14) break;
  }
  residual = residuals(y).norm();
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
  if (flow.rhs_later &&
      (flow.rhs_later(y) - flow.rhs(y)).norm() > 1e-9 * (flow.rhs(y).norm() + M)) {
    out.reason = "the phase is not steady: a prescribed motion or a motor changes it in time";
    return out;
  }
  if (cyclic.empty() && m > 0) {
    const MatrixXd A = Jacobian(flow, y, Scales(m, M));
    for (int a = 0; a < m; ++a) {
      if (A.col(3 + a).norm() <= 1e-12 * A.norm()) cyclic.push_back(a);
    }
  }
  if (!SolveEquilibrium(flow, cyclic, M, y, out.residual)) {
    out.reason = "no steady spin found near the phase's state";
    return out;
  }
  out.y = y;
  out.w_B = Vec3::Zero();
  {
    Mat3 J;
    Vec3 h_r;
    flow.rigid(y, J, h_r);
    out.w_B = J.inverse() * (y.head<3>() - h_r);
  }
  const double rate = out.w_B.norm() + M / 1e300;
  out.residual /= M * rate;
  if (out.residual > 1e-8) {
    out.reason = "no steady spin found near the phase's state (residual " +
                 std::to_string(out.residual) + ")";
    return out;
  }
  if (flow.rhs_later && (flow.rhs_later(y) - flow.rhs(y)).norm() > 1e-9 * M * rate) {
    out.reason = "the phase is not steady: a prescribed motion or a motor changes it in time";
    return out;
  }
  const std::vector<Eigen::Index> keep = Kept(m, cyclic);
  const MatrixXd A = Jacobian(flow, y, Scales(m, M));
  const MatrixXd Ak = Sub(A, keep, keep);
  Eigen::EigenSolver<MatrixXd> es(Ak);
  if (es.info() != Eigen::Success) {
    out.reason = "the eigenvalue solver did not converge";
    return out;
  }
  const Vec3 u = y.head<3>() / M;
  const VectorXd scale = Pick(Scales(m, M), keep);
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
    const std::complex<double> lam = es.eigenvalues()[i];
    if (std::abs(lam) <= kNeutralRate * rate) continue;  // |H|, a rotor's momentum
    const Eigen::VectorXcd v =
        es.eigenvectors().col(i).cwiseQuotient(scale.cast<std::complex<double>>());
    const Eigen::Vector3cd vH = v.head<3>();
    const Eigen::Vector3cd tilt =
        vH - u.cast<std::complex<double>>() * (u.cast<std::complex<double>>().dot(vH));
    out.modes.push_back({lam, tilt.norm() / std::max(v.norm(), 1e-300)});
  }
  std::sort(out.modes.begin(), out.modes.end(),
            [](const SpinMode& a, const SpinMode& b) { return a.lambda.real() > b.lambda.real(); });
  double share = 0.0;
  for (const SpinMode& md : out.modes) share = std::max(share, md.momentum_share);
  out.max_real = out.modes.empty() ? 0.0 : out.modes.front().lambda.real();
  for (const SpinMode& md : out.modes) {  // the first (largest real part) that tilts H_B
    if (md.momentum_share >= 0.25 * share) {
      out.growth_rate = md.lambda.real();
      out.frequency = std::abs(md.lambda.imag());
      break;
    }
  }
  const double neutral = 1e-7 * rate;  // the Jacobian's own error is ~1e-12 relative
  out.verdict = out.max_real > neutral    ? "unstable"
                : out.max_real < -neutral ? "asymptotically stable"
                                          : "neutrally stable";
  QuasiRigid(flow, A, keep, out);
  out.found = true;
  return out;
}

ReducedFlow FlowOf(const schedule::FreeHingeSystem& sys, double t, double t_later) {
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
  if (t_later != t)
    f.rhs_later = [rhs_at, t_later](const VectorXd& y) { return rhs_at(t_later, y); };
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
