#include "deploysim/analysis/floquet.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/math/units.h"

namespace deploysim::analysis {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The step per period: h times the fastest rate of the motion at most this (the flow
/// map's error ~ (h rate)^8 per radian of the motion). Measured: the Floquet rates of the
/// damper-on-rotor craft equal the steady eigenvalues of the same craft to 1.5e-9 (0.03
/// gave 2e-9 at 3.3 times the cost).
constexpr double kStepAngle = 0.1;

/// The shooting stops at this residual (the flow map's own rounding is ~1e-12).
constexpr double kConverged = 1e-11;

/// A singular value of the scaled M - I below this is a conserved quantity's (the
/// monodromy's own error is ~1e-10; a mode's |mu - 1| this small is neutral for any use).
constexpr double kConservedLevel = 1e-7;

/// The reference state is carried along the flow for this many periods before its
/// conserved quantities are held (floquet.cc, SolvePeriodicOrbit).
constexpr double kSettlePeriods = 3.0;

/// The longest flow map the shooting integrates (a stiff mode beside a long period would
/// cost more than a run).
constexpr int kMaxSteps = 20000;

int StepsFor(double period, double fastest) {
  return std::max(64, static_cast<int>(std::ceil(period * fastest / kStepAngle)));
}

/// The largest |eigenvalue| of dF/dy at (0, y) (forward differences: a step size only).
double SpectralRadius(const OrbitProblem& p, const VectorXd& y) {
  const Eigen::Index n = y.size();
  const VectorXd f0 = p.rhs(0.0, y);
  MatrixXd A(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    VectorXd yp = y;
    const double h = 1e-6 * p.scale[j];
    yp[j] += h;
    A.col(j) = (p.rhs(0.0, yp) - f0) / h;
  }
  return Eigen::EigenSolver<MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace

MatrixXd RichardsonJacobian(const std::function<VectorXd(const VectorXd&)>& g,
                            const VectorXd& y,
                            const VectorXd& scale) {
  const Eigen::Index n = y.size();
  MatrixXd A(g(y).size(), n);
  for (Eigen::Index j = 0; j < n; ++j) {
    auto diff = [&](double h) {
      VectorXd yp = y, ym = y;
      yp[j] += h;
      ym[j] -= h;
      return VectorXd((g(yp) - g(ym)) / (2.0 * h));
    };
    const double h = 1e-4 * scale[j];
    A.col(j) = (4.0 * diff(0.5 * h) - diff(h)) / 3.0;
  }
  return A;
}

VectorXd FlowMap(const TimeRhs& f, double t0, const VectorXd& y0, double T, int steps) {
  const integrators::ButcherTableau& tab = integrators::Fehlberg78();
  const int s = tab.stages();
  const double h = T / steps;
  std::vector<VectorXd> k(static_cast<std::size_t>(s));
  VectorXd y = y0;
  for (int i = 0; i < steps; ++i) {
    const double t = t0 + i * h;
    for (int j = 0; j < s; ++j) {
      VectorXd yj = y;
      for (int l = 0; l < j; ++l) {
        const double a = tab.a[static_cast<std::size_t>(j)][static_cast<std::size_t>(l)];
        if (a != 0.0) yj += (h * a) * k[static_cast<std::size_t>(l)];
      }
      k[static_cast<std::size_t>(j)] = f(t + tab.c[static_cast<std::size_t>(j)] * h, yj);
    }
    for (int j = 0; j < s; ++j) {
      const double b = tab.b[static_cast<std::size_t>(j)];
      if (b != 0.0) y += (h * b) * k[static_cast<std::size_t>(j)];
    }
  }
  return y;
}

namespace {

/// The shooting's state: the orbit's start, its period and the flow map's step count.
struct Shot {
  VectorXd y;
  double T = 0.0;
  double residual = 0.0;
};

/// Levenberg-Marquardt on the return R(y, T) = (Phi_T(y) - y - a) / scale, |H| = M and the
/// rows `held`: l . ((y - reference) / scale) = 0 (conserved quantities kept at the
/// reference's values, to first order).
Shot Shoot(const OrbitProblem& p,
           Shot s,
           double fastest,
           const std::vector<VectorXd>& held,
           const VectorXd& reference) {
  const Eigen::Index n = s.y.size();
  const double M = p.momentum;
  std::vector<Eigen::Index> coords;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i != p.phase) coords.push_back(i);
  }
  const Eigen::Index nu = static_cast<Eigen::Index>(coords.size()) + (p.period_fixed ? 0 : 1);
  const Eigen::Index rows = n + 1 + static_cast<Eigen::Index>(held.size());
  // The step count is held within an iteration: a count that jumps with T would make the
  // map jagged in T.
  int steps = StepsFor(s.T, fastest);
  auto residuals = [&](const VectorXd& yy, double TT) {
    VectorXd r(rows);
    r.head(n) = (FlowMap(p.rhs, 0.0, yy, TT, steps) - yy - p.advance).cwiseQuotient(p.scale);
    r[n] = (yy.head<3>().squaredNorm() - M * M) / (M * M);
    const VectorXd dy = (yy - reference).cwiseQuotient(p.scale);
    for (std::size_t k = 0; k < held.size(); ++k)
      r[n + 1 + static_cast<Eigen::Index>(k)] = held[k].dot(dy);
    return r;
  };
  for (int it = 0; it < 60; ++it) {
    steps = StepsFor(s.T, fastest);
    const VectorXd r = residuals(s.y, s.T);
    s.residual = r.head(n).norm();
    // At the map's rounding level (~1e-12) a further step only slides along a family.
    if (!std::isfinite(r.norm()) || r.norm() < kConverged) break;
    // Central differences in scaled unknowns (each coordinate over its scale, T over
    // itself): error ~1e-10, so a family's direction is singular to that level.
    constexpr double d = 1e-5;
    MatrixXd Jr(rows, nu);
    for (std::size_t j = 0; j < coords.size(); ++j) {
      VectorXd yp = s.y, ym = s.y;
      yp[coords[j]] += d * p.scale[coords[j]];
      ym[coords[j]] -= d * p.scale[coords[j]];
      Jr.col(static_cast<Eigen::Index>(j)) = (residuals(yp, s.T) - residuals(ym, s.T)) / (2.0 * d);
    }
    if (!p.period_fixed) {
      Jr.col(nu - 1) =
          (residuals(s.y, s.T * (1.0 + d)) - residuals(s.y, s.T * (1.0 - d))) / (2.0 * d);
    }
    // Levenberg-Marquardt with the damping |r|^2 (Yamashita and Fukushima 2001): where the
    // orbits form a family (a conserved quantity beside |H|, a free rotor's rate) the
    // Jacobian is singular on it and nearly so beside it, and a Gauss-Newton step would
    // slide far along the family; the damped step goes to a member near the start and
    // still converges quadratically.
    MatrixXd aug(rows + nu, nu);
    aug << Jr, std::sqrt(r.squaredNorm()) * MatrixXd::Identity(nu, nu);
    VectorXd rhs = VectorXd::Zero(rows + nu);
    rhs.head(rows) = -r;
    const VectorXd du = aug.colPivHouseholderQr().solve(rhs);
    for (std::size_t j = 0; j < coords.size(); ++j)
      s.y[coords[j]] += du[static_cast<Eigen::Index>(j)] * p.scale[coords[j]];
    if (!p.period_fixed) s.T *= 1.0 + du[nu - 1];
    if (!(s.T > 0.0) || !std::isfinite(s.T)) break;
    if (du.cwiseAbs().maxCoeff() < 1e-13) break;
  }
  s.residual = residuals(s.y, s.T).head(n).norm();
  return s;
}

/// dPhi_T/dy0.
MatrixXd Monodromy(const OrbitProblem& p, const VectorXd& y, double T, int steps) {
  return RichardsonJacobian([&](const VectorXd& y0) { return FlowMap(p.rhs, 0.0, y0, T, steps); },
                            y, p.scale);
}

/// The gradients of the conserved quantities at an orbit (scaled): the left singular
/// vectors of S^-1 (M - I) S with a singular value at the monodromy's error level.
std::vector<VectorXd> ConservedGradients(const MatrixXd& monodromy,
                                         const VectorXd& y,
                                         const VectorXd& scale) {
  const Eigen::Index n = monodromy.rows();
  const MatrixXd A = scale.cwiseInverse().asDiagonal() * (monodromy - MatrixXd::Identity(n, n)) *
                     scale.asDiagonal();
  const Eigen::JacobiSVD<MatrixXd> svd(A, Eigen::ComputeFullU);
  // |H| is held exactly by its own row: the others are taken orthogonal to its gradient
  // (held twice, to first and to all orders, the rows would disagree at second order).
  VectorXd g = VectorXd::Zero(n);
  g.head<3>() = y.head<3>().cwiseProduct(scale.head<3>()).normalized();
  std::vector<VectorXd> out;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(svd.singularValues()[i] < kConservedLevel)) continue;
    VectorXd l = svd.matrixU().col(i);
    l -= g * g.dot(l);
    for (const VectorXd& o : out) l -= o * o.dot(l);
    if (l.norm() > 0.1) out.push_back(l.normalized());
  }
  return out;
}

}  // namespace

PeriodicOrbit SolvePeriodicOrbit(const OrbitProblem& p, const VectorXd& y_guess) {
  PeriodicOrbit out;
  const double fastest =
      std::max({p.fastest, SpectralRadius(p, y_guess), math::kTwoPi / p.period_guess});
  if (StepsFor(p.period_guess, fastest) > kMaxSteps) {
    out.reason = "the periodic motion's period is more than " + std::to_string(kMaxSteps) +
                 " steps of its fastest mode: not linearized";
    return out;
  }
  Shot s{y_guess, p.period_guess, 0.0};
  s = Shoot(p, s, fastest, {}, y_guess);
  if (!p.invariants.empty()) {
    // Exactly: each invariant's row, scaled like the momenta.
    std::vector<VectorXd> rows;
    for (const VectorXd& c : p.invariants) rows.push_back(c.cwiseProduct(p.scale) / c.norm());
    s = Shoot(p, s, fastest, rows, p.reference.size() ? p.reference : y_guess);
  } else if (std::isfinite(s.residual) && s.T > 0.0) {
    // The orbits of a family differ in their conserved quantities: the phase's orbit keeps
    // the phase's values (to first order in its distance from the orbit).
    const std::vector<VectorXd> held =
        ConservedGradients(Monodromy(p, s.y, s.T, StepsFor(s.T, fastest)), s.y, p.scale);
    if (!held.empty()) {
      // The reference's values carried along the flow for a few periods: conserved, and
      // nearer the family once the sink's own transient has decayed (the first-order hold
      // then errs by the square of what is left, the nutation).
      const VectorXd start = p.reference.size() ? p.reference : y_guess;
      const double settle = kSettlePeriods * p.period_guess;
      const VectorXd ref = FlowMap(p.rhs, 0.0, start, settle, StepsFor(settle, fastest));
      s = Shoot(p, s, fastest, held, std::isfinite(ref.norm()) ? ref : start);
    }
  }
  out.y0 = s.y;
  out.period = s.T;
  out.steps = StepsFor(s.T, fastest);
  out.residual = s.residual;
  if (!std::isfinite(s.residual) || !(s.T > 0.0)) {
    out.reason = "the shooting for a periodic motion diverged";
    return out;
  }
  out.monodromy = Monodromy(p, s.y, s.T, out.steps);
  out.found = true;
  return out;
}

}  // namespace deploysim::analysis
