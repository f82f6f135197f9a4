#include "deploysim/schedule/free_hinge_system.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/model/mass_properties.h"

namespace deploysim::schedule {

using math::Mat3;
using math::Vec3;

namespace {

/// Largest system (3 + free hinges) solved by SmallCholeskySolve.
constexpr int kSmallSystem = 12;

/// Solves A x = b for the leading u x u block of the SPD matrix A (u <= kSmallSystem) by
/// Cholesky (A = L L^T) on the stack. Written out instead of Eigen's LLT: this runs at every
/// Runge-Kutta stage, and for the usual 4 to 8 unknowns Eigen's LLT (dynamic or fixed size)
/// took about 1,000 instructions per solve here against about 250 for these loops
/// (callgrind, the smallsat's two-wing deployment). False if A is not positive definite.
bool SmallCholeskySolve(const Eigen::MatrixXd& A,
                        int u,
                        const Eigen::VectorXd& b,
                        Eigen::VectorXd& x) {
  double L[kSmallSystem][kSmallSystem];
  for (int j = 0; j < u; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    L[j][j] = ljj;
    const double inv = 1.0 / ljj;
    for (int i = j + 1; i < u; ++i) {
      double v = A(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v * inv;
    }
  }
  double y[kSmallSystem];
  for (int i = 0; i < u; ++i) {
    double v = b[i];
    for (int k = 0; k < i; ++k) v -= L[i][k] * y[k];
    y[i] = v / L[i][i];
  }
  for (int i = u - 1; i >= 0; --i) {
    double v = y[i];
    for (int k = i + 1; k < u; ++k) v -= L[k][i] * x[k];
    x[i] = v / L[i][i];
  }
  return true;
}

}  // namespace

namespace {

/// Adds the rigid element (m, CoM x, inertia I about x) to `into` whose CoM is `at`.
void AddRigid(model::MassElement& into, Vec3& at, double m, const Vec3& x, const Mat3& I) {
  const double total = into.mass + m;
  const Vec3 c = (into.mass * at + m * x) / total;
  auto shift = [](double mass, const Vec3& d) {
    return Mat3(mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
  };
  into.inertia_cm = into.inertia_cm + shift(into.mass, at - c) + I + shift(m, x - c);
  into.mass = total;
  at = c;
}

}  // namespace

/// The body with every subtree of `locked` panels under which nothing moves merged into
/// its parent: the composite of the parent and the subtree at its locked angles, in the
/// parent's frame (mass, CoM, inertia about the CoM by the parallel-axis theorem).
struct FreeHingeSystem::Merged {
  model::HingedBody body;
  std::vector<HingePlan> plans;
  Eigen::VectorXd angles;
  std::vector<int> red_of, orig_of;
};

FreeHingeSystem::Merged FreeHingeSystem::MergeLockedLeaves(const model::HingedBody& body,
                                                           const std::vector<HingePlan>& plans,
                                                           const Eigen::VectorXd& angles) {
  const int n = static_cast<int>(body.panels.size());
  if (static_cast<int>(plans.size()) != n || angles.size() != n) {
    throw std::invalid_argument("FreeHingeSystem: " + std::to_string(plans.size()) +
                                " hinge plans and " + std::to_string(angles.size()) +
                                " angles for " + std::to_string(n) +
                                " panels (rule: one of each per panel)");
  }
  // Depth of each panel: children are merged before their parents.
  std::vector<int> depth(static_cast<std::size_t>(n), -1);
  std::function<int(int)> depth_of = [&](int k) {
    int& d = depth[static_cast<std::size_t>(k)];
    if (d < 0) {
      const int p = body.panels[static_cast<std::size_t>(k)].parent;
      d = p < 0 ? 0 : depth_of(p) + 1;
    }
    return d;
  };
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    order[static_cast<std::size_t>(k)] = k;
    depth_of(k);
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return depth[static_cast<std::size_t>(a)] > depth[static_cast<std::size_t>(b)];
  });
  std::vector<char> keep(static_cast<std::size_t>(n), 0);
  for (int k : order) {
    if (plans[static_cast<std::size_t>(k)].kind != HingePlan::Kind::kLocked) {
      keep[static_cast<std::size_t>(k)] = 1;
    }
    const int p = body.panels[static_cast<std::size_t>(k)].parent;
    if (keep[static_cast<std::size_t>(k)] && p >= 0) keep[static_cast<std::size_t>(p)] = 1;
  }
  model::HingedBody merged = body;
  for (int k : order) {
    if (keep[static_cast<std::size_t>(k)]) continue;
    const model::Panel& c = merged.panels[static_cast<std::size_t>(k)];
    const Mat3 R = Eigen::AngleAxisd(angles[k], c.hinge_axis_B).toRotationMatrix();
    const Vec3 x = c.hinge_point_B + R * c.com_offset_B;  // in the parent's frame
    const Mat3 I = R * c.body.inertia_cm * R.transpose();
    if (c.parent < 0) {
      AddRigid(merged.hub.body, merged.hub.com_B, c.body.mass, x, I);
    } else {
      model::Panel& p = merged.panels[static_cast<std::size_t>(c.parent)];
      AddRigid(p.body, p.com_offset_B, c.body.mass, x, I);
    }
  }
  Merged out;
  out.body.hub = merged.hub;
  out.red_of.assign(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < n; ++k) {
    if (!keep[static_cast<std::size_t>(k)]) continue;
    out.red_of[static_cast<std::size_t>(k)] = static_cast<int>(out.orig_of.size());
    out.orig_of.push_back(k);
  }
  out.angles.resize(static_cast<Eigen::Index>(out.orig_of.size()));
  for (std::size_t r = 0; r < out.orig_of.size(); ++r) {
    const int k = out.orig_of[r];
    model::Panel pn = merged.panels[static_cast<std::size_t>(k)];
    if (pn.parent >= 0) pn.parent = out.red_of[static_cast<std::size_t>(pn.parent)];
    out.body.panels.push_back(pn);
    out.plans.push_back(plans[static_cast<std::size_t>(k)]);
    out.angles[static_cast<Eigen::Index>(r)] = angles[k];
  }
  return out;
}

std::vector<ModalGroup> ModalGroupsOf(const model::Model& m) {
  std::vector<ModalGroup> out;
  for (const model::Appendage& a : m.appendages) {
    if (a.modes.size() == 0) continue;
    out.push_back(ModalGroup{a.name, a.hinges, a.modes});
  }
  return out;
}

FreeHingeSystem::FreeHingeSystem(const model::HingedBody& body,
                                 const std::vector<HingePlan>& plans,
                                 const Eigen::VectorXd& initial_angles,
                                 const std::vector<ModalGroup>& modal)
    : FreeHingeSystem(MergeLockedLeaves(body, plans, initial_angles), initial_angles, modal) {}

FreeHingeSystem::FreeHingeSystem(Merged merged,
                                 const Eigen::VectorXd& full_angles,
                                 const std::vector<ModalGroup>& modal)
    : body_(std::move(merged.body)),
      tree_(body_),
      plans_(std::move(merged.plans)),
      red_of_(std::move(merged.red_of)),
      orig_of_(std::move(merged.orig_of)),
      full_angles_(full_angles),
      angles_(std::move(merged.angles)) {
  const int n = tree_.size();
  const Eigen::VectorXd initial_angles = angles_;
  prescribed_.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind == HingePlan::Kind::kPrescribed) {
      prescribed_[static_cast<std::size_t>(k)] = PrescribedHinge(p.moves, initial_angles[k]);
    }
  }
  servo_ref_.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind == HingePlan::Kind::kFree && p.drive.motor.kind == Motor::Kind::kServo) {
      servo_ref_[static_cast<std::size_t>(k)] =
          PrescribedHinge(p.drive.motor.follow, initial_angles[k]);
    }
  }
  is_free_.assign(static_cast<std::size_t>(n), 0);
  slip_.assign(static_cast<std::size_t>(n), 0);
  theta_.resize(n);
  theta_dot_.resize(n);
  // Modal groups: their hinges (free plans, never merged) and the block-diagonal basis.
  groups_ = modal;
  is_modal_.assign(static_cast<std::size_t>(n), 0);
  Eigen::Index rows = 0, cols = 0;
  for (const ModalGroup& g : groups_) {
    if (g.basis.rows() != static_cast<Eigen::Index>(g.hinges.size()) || g.basis.cols() < 1) {
      throw std::invalid_argument("FreeHingeSystem: modal group " + g.name +
                                  ": its basis must have one row per hinge and a column");
    }
    rows += g.basis.rows();
    cols += g.basis.cols();
  }
  phi_ = Eigen::MatrixXd::Zero(rows, cols);
  modal_theta0_.resize(rows);
  rows = cols = 0;
  for (const ModalGroup& g : groups_) {
    for (int k : g.hinges) {
      const int r = Computed(k);
      if (plans_[static_cast<std::size_t>(r)].kind != HingePlan::Kind::kFree ||
          is_modal_[static_cast<std::size_t>(r)]) {
        throw std::invalid_argument("FreeHingeSystem: modal group " + g.name + ": hinge " +
                                    std::to_string(k) + " is not free or in two groups");
      }
      is_modal_[static_cast<std::size_t>(r)] = 1;
      modal_theta0_[static_cast<Eigen::Index>(modal_.size())] = angles_[r];
      modal_.push_back(r);
      modal_orig_.push_back(k);
    }
    phi_.block(rows, cols, g.basis.rows(), g.basis.cols()) = g.basis;
    rows += g.basis.rows();
    cols += g.basis.cols();
  }
}

int FreeHingeSystem::Computed(int k) const {
  const int r = red_of_.at(static_cast<std::size_t>(k));
  if (r < 0) {
    throw std::logic_error("FreeHingeSystem: panel " + std::to_string(k) +
                           " is locked for the whole run (merged into its parent)");
  }
  return r;
}

Eigen::VectorXd FreeHingeSystem::Expand(const Eigen::VectorXd& computed, bool rates) const {
  Eigen::VectorXd full =
      rates ? Eigen::VectorXd::Zero(full_angles_.size()) : Eigen::VectorXd(full_angles_);
  for (std::size_t r = 0; r < orig_of_.size(); ++r) {
    full[orig_of_[r]] = computed[static_cast<Eigen::Index>(r)];
  }
  return full;
}

bool FreeHingeSystem::IsFree(int k) const {
  const int r = red_of_[static_cast<std::size_t>(k)];
  return r >= 0 && (is_free_[static_cast<std::size_t>(r)] != 0 ||
                    is_modal_[static_cast<std::size_t>(r)] != 0);
}

void FreeHingeSystem::Lock(int k, double angle) { LockComputed(Computed(k), angle); }

void FreeHingeSystem::LockComputed(int r, double angle) {
  const int k = orig_of_[static_cast<std::size_t>(r)];
  if (plans_[static_cast<std::size_t>(r)].kind == HingePlan::Kind::kPrescribed ||
      is_modal_[static_cast<std::size_t>(r)]) {
    throw std::logic_error("FreeHingeSystem::Lock: hinge " + std::to_string(k) +
                           " is prescribed or moves with modal coordinates");
  }
  angles_[r] = angle;
  if (is_free_[static_cast<std::size_t>(r)]) {
    is_free_[static_cast<std::size_t>(r)] = 0;
    for (std::size_t a = 0; a < free_.size(); ++a) {
      if (free_[a] == r) {
        free_.erase(free_.begin() + static_cast<std::ptrdiff_t>(a));
        free_orig_.erase(free_orig_.begin() + static_cast<std::ptrdiff_t>(a));
        break;
      }
    }
  }
}

void FreeHingeSystem::Free(int k) { FreeComputed(Computed(k)); }

void FreeHingeSystem::FreeComputed(int r) {
  const int k = orig_of_[static_cast<std::size_t>(r)];
  if (plans_[static_cast<std::size_t>(r)].kind != HingePlan::Kind::kFree ||
      is_free_[static_cast<std::size_t>(r)] || is_modal_[static_cast<std::size_t>(r)]) {
    throw std::logic_error("FreeHingeSystem::Free: hinge " + std::to_string(k) +
                           " is not a locked free hinge");
  }
  is_free_[static_cast<std::size_t>(r)] = 1;
  free_.push_back(r);
  free_orig_.push_back(k);
}

Eigen::VectorXd FreeHingeSystem::Lock(int k, double angle, const Eigen::VectorXd& x) {
  const int m = free_count();
  const auto it = std::find(free_orig_.begin(), free_orig_.end(), k);
  if (it == free_orig_.end()) {
    throw std::logic_error("FreeHingeSystem::Lock: hinge " + std::to_string(k) + " is not free");
  }
  const int gone = static_cast<int>(it - free_orig_.begin());
  Eigen::VectorXd nx(2 * (m - 1));
  for (int a = 0, j = 0; a < m; ++a) {
    if (a == gone) continue;
    nx[j] = x[a];
    nx[m - 1 + j] = x[m + a];
    ++j;
  }
  Lock(k, angle);
  return nx;
}

Eigen::VectorXd FreeHingeSystem::Free(
    int k, double t, const math::Vec3& H_B, const Eigen::VectorXd& x, double rate) {
  Snapshot before = Snap(t, H_B, x);
  const int m = free_count();
  const int mh = static_cast<int>(free_.size());  // the new hinge's place: after the hinges
  const int mq = modal_count();
  Free(k);
  before.theta_dot[k] = rate;
  const Eigen::VectorXd full = ShapeState(t, H_B, before.theta, before.theta_dot);
  Eigen::VectorXd nx(2 * (m + 1));
  nx.head(mh) = x.head(mh);
  nx[mh] = full[mh];
  nx.segment(mh + 1, mq) = x.segment(mh, mq);
  nx.segment(m + 1, mh) = x.segment(m, mh);
  nx[m + 1 + mh] = full[m + 1 + mh];
  nx.segment(m + 2 + mh, mq) = x.segment(m + mh, mq);
  return nx;
}

void FreeHingeSystem::Setup(double t, const Eigen::VectorXd& x, dynamics::Side side) const {
  const int n = tree_.size();
  const int m = free_count();
  moving_.clear();
  for (int k = 0; k < n; ++k) {
    theta_dot_[k] = 0.0;
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind == HingePlan::Kind::kPrescribed) {
      const HingeKinematics hk = prescribed_[static_cast<std::size_t>(k)].At(t, side);
      theta_[k] = hk.angle;
      theta_dot_[k] = hk.rate;
      if (hk.rate != 0.0) moving_.push_back(k);
    } else if (!IsFree(k)) {
      theta_[k] = angles_[k];
    }
  }
  const int mh = static_cast<int>(free_.size());
  for (int a = 0; a < mh; ++a) theta_[free_[static_cast<std::size_t>(a)]] = x[a];
  if (!modal_.empty()) {
    // The modal hinges at theta_0 + basis q (q: entries mh .. m - 1).
    const Eigen::VectorXd th = modal_theta0_ + phi_ * x.segment(mh, m - mh);
    for (std::size_t i = 0; i < modal_.size(); ++i) {
      theta_[modal_[i]] = th[static_cast<Eigen::Index>(i)];
    }
  }
  cols_.assign(free_.begin(), free_.end());
  cols_.insert(cols_.end(), modal_.begin(), modal_.end());
  cols_.insert(cols_.end(), moving_.begin(), moving_.end());
  if (!pose_valid_ || theta_ != pose_theta_) {
    model::ComputePose(body_, tree_, theta_, pose_);
    pose_theta_ = theta_;
    pose_valid_ = true;
    mass_valid_ = false;
  }
}

void FreeHingeSystem::UpdateMassMatrix() const {
  if (mass_valid_ && cols_ == mass_cols_) return;
  if (modal_.empty()) {
    model::ComputeMassMatrix(body_, tree_, pose_, cols_, M_);
  } else {
    // In the coordinates (w, free hinges, q, moving) directly, from each coordinate's
    // velocity field (model::ComputeMassMatrixInSpeeds): the hinge-column matrix would
    // cost O(n m^2) for the m modal hinges.
    const int n = tree_.size();
    const int mh = static_cast<int>(free_.size()), nk = modal_count();
    const int nq = static_cast<int>(moving_.size());
    speeds_.setZero(3 + n, 3 + mh + nk + nq);
    speeds_.topLeftCorner<3, 3>().setIdentity();
    for (int a = 0; a < mh; ++a) speeds_(3 + free_[static_cast<std::size_t>(a)], 3 + a) = 1.0;
    for (std::size_t i = 0; i < modal_.size(); ++i) {
      speeds_.row(3 + modal_[i]).segment(3 + mh, nk) = phi_.row(static_cast<Eigen::Index>(i));
    }
    for (int b = 0; b < nq; ++b) {
      speeds_(3 + moving_[static_cast<std::size_t>(b)], 3 + mh + nk + b) = 1.0;
    }
    model::ComputeMassMatrixInSpeeds(body_, tree_, pose_, speeds_, fields_, M_);
  }
  mass_cols_ = cols_;
  mass_valid_ = true;
}

Eigen::VectorXd FreeHingeSystem::CoordinateRates() const {
  const int mh = static_cast<int>(free_.size());
  Eigen::VectorXd r(mh + modal_count());
  for (int a = 0; a < mh; ++a) r[a] = theta_dot_[free_[static_cast<std::size_t>(a)]];
  if (modal_count() > 0) r.tail(modal_count()) = q_dot_;
  return r;
}

Eigen::VectorXd FreeHingeSystem::CoordinateForces(double t,
                                                  dynamics::Side side,
                                                  const Eigen::VectorXd& x) const {
  const int mh = static_cast<int>(free_.size());
  Eigen::VectorXd f(mh + modal_count());
  for (int a = 0; a < mh; ++a) {
    const int k = free_[static_cast<std::size_t>(a)];
    f[a] = Torque(k, t, side, x[a], theta_dot_[k]);
  }
  if (!modal_.empty()) {
    Eigen::VectorXd qh(static_cast<Eigen::Index>(modal_.size()));
    for (std::size_t i = 0; i < modal_.size(); ++i) {
      const int k = modal_[i];
      qh[static_cast<Eigen::Index>(i)] = Torque(k, t, side, theta_[k], theta_dot_[k]);
    }
    f.tail(modal_count()).noalias() = phi_.transpose() * qh;
  }
  return f;
}

Eigen::VectorXd FreeHingeSystem::ProjectGradient(const Eigen::VectorXd& g_hinges) const {
  if (modal_.empty()) return g_hinges;
  const Eigen::Index mh = static_cast<Eigen::Index>(free_.size());
  const Eigen::Index g = phi_.rows(), k = phi_.cols();
  const Eigen::Index rest = g_hinges.size() - mh - g;
  Eigen::VectorXd out(mh + k + rest);
  out.head(mh) = g_hinges.head(mh);
  out.segment(mh, k).noalias() = phi_.transpose() * g_hinges.segment(mh, g);
  out.tail(rest) = g_hinges.tail(rest);
  return out;
}

void FreeHingeSystem::HingeRatesOf(const Eigen::VectorXd& z, Eigen::VectorXd& rates) const {
  const int mh = static_cast<int>(free_.size());
  for (int a = 0; a < mh; ++a) rates[free_[static_cast<std::size_t>(a)]] = z[3 + a];
  if (!modal_.empty()) {
    const Eigen::VectorXd th = phi_ * z.segment(3 + mh, modal_count());
    for (std::size_t i = 0; i < modal_.size(); ++i) {
      rates[modal_[i]] = th[static_cast<Eigen::Index>(i)];
    }
  }
}

void FreeHingeSystem::Solve(const Vec3& H_B, const Eigen::VectorXd& x) const {
  const int m = free_count();
  const int q = static_cast<int>(moving_.size());
  UpdateMassMatrix();
  const int u = 3 + m;
  rhs_.resize(u);
  rhs_.head<3>() = H_B;
  if (m > 0) rhs_.tail(m) = x.segment(m, m);
  if (q > 0) {
    rates_.resize(q);
    for (int b = 0; b < q; ++b) rates_[b] = theta_dot_[moving_[static_cast<std::size_t>(b)]];
    rhs_.noalias() -= M_.block(0, u, u, q) * rates_;
  }
  sol_.resize(u);
  // A trial step far too long for a stiff hinge can leave non-finite angles or momenta: the
  // solution is then non-finite too, and the step's error rejects it (the driver shortens
  // it). The mass matrix of finite angles is positive definite: failing there is a bug.
  const bool finite = theta_.allFinite() && rhs_.allFinite();
  bool solved = false;
  if (u <= kSmallSystem) {
    solved = finite && SmallCholeskySolve(M_, u, rhs_, sol_);
  } else if (finite) {
    A_ = M_.topLeftCorner(u, u);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(A_);
    solved = llt.info() == Eigen::Success;
    if (solved) sol_ = llt.solve(rhs_);
  }
  if (!solved && finite) {
    throw std::runtime_error("FreeHingeSystem: the mass matrix is not positive definite");
  }
  if (!solved) sol_.setConstant(std::numeric_limits<double>::quiet_NaN());
  w_ = sol_.head<3>();
  HingeRatesOf(sol_, theta_dot_);
  q_dot_ = sol_.segment(3 + static_cast<Eigen::Index>(free_.size()), modal_count());
}

void FreeHingeSystem::Evaluate(double t,
                               const Vec3& H_B,
                               const Eigen::VectorXd& x,
                               dynamics::Side side,
                               Vec3& w_NB_B,
                               Eigen::VectorXd& x_dot) const {
  const int m = free_count();
  Setup(t, x, side);
  Solve(H_B, x);
  model::ComputeVelocity(body_, tree_, pose_, w_, theta_dot_, vel_);
  const bool ledger = x.size() == 2 * m + kLedgerTerms;
  x_dot.resize(ledger ? 2 * m + kLedgerTerms : 2 * m);
  if (modal_.empty()) {
    model::KineticEnergyGradient(tree_, pose_, vel_, free_, grad_);
    for (int a = 0; a < m; ++a) {
      const int k = free_[static_cast<std::size_t>(a)];
      const double rate = theta_dot_[k];
      x_dot[a] = rate;
      x_dot[m + a] = grad_[a] + Torque(k, t, side, x[a], rate);
    }
  } else {
    std::vector<int> wrt(free_.begin(), free_.end());
    wrt.insert(wrt.end(), modal_.begin(), modal_.end());
    model::KineticEnergyGradient(tree_, pose_, vel_, wrt, grad_);
    x_dot.head(m) = CoordinateRates();
    x_dot.segment(m, m) = ProjectGradient(grad_) + CoordinateForces(t, side, x);
  }
  if (ledger) {
    const Powers p = PowersNow(t, side, H_B, x);
    x_dot.tail<kLedgerTerms>() << p.damper, p.friction, p.motor, p.drive;
  }
  w_NB_B = w_;
}

FreeHingeSystem::Powers FreeHingeSystem::PowersNow(double t,
                                                   dynamics::Side side,
                                                   const Vec3& H_B,
                                                   const Eigen::VectorXd& x) const {
  Powers p;
  for (int a = 0; a < static_cast<int>(free_.size()); ++a) {
    const int k = free_[static_cast<std::size_t>(a)];
    const FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
    const double rate = theta_dot_[k];
    const NonConservativeParts q =
        NonConservativeTorqueParts(d, rate, slip_[static_cast<std::size_t>(k)]);
    p.damper += q.damper * rate;
    p.friction += q.friction * rate;
    double motor = q.motor;
    if (d.motor.kind == Motor::Kind::kServo) {
      motor +=
          ServoTorque(d.motor, servo_ref_[static_cast<std::size_t>(k)].At(t, side), x[a], rate);
    }
    p.motor += motor * rate;
  }
  for (int k : modal_) {  // a spring and a damper each
    const FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
    const double rate = theta_dot_[k];
    const NonConservativeParts q = NonConservativeTorqueParts(d, rate, 0);
    p.damper += q.damper * rate;
    p.friction += q.friction * rate;
    p.motor += q.motor * rate;
  }
  if (!moving_.empty()) p.drive = DrivePower(t, side, H_B, x);
  return p;
}

// The drives' power is dE/dt along the flow minus the free hinges' powers (the work-energy
// theorem: the constraint torques that hold the prescribed motion do the rest). With
// u = (w, theta'_f) unknown, v = theta'_p prescribed, M = [A C; C' D] over (u, v) and the
// momenta pi = (H_B, p_f), E = 1/2 pi' A^-1 pi + 1/2 v' S v + V with S = D - C' A^-1 C.
// Write x = A^-1 pi, y = A^-1 C v (u = x - y), X = (x, 0), Y = (y, -v) (so (u, v) = X - Y),
// and g_j(z) = 1/2 z' (dM/dtheta_j) z, which is model::KineticEnergyGradient at velocities z.
// Then dE/dt = P_free + P_drive with
//   P_drive = sum_b [(g_b(Y) - g_b(X)) v_b + (S v)_b v'_b]           (explicit time)
//           + y_w . H_B' + sum_f y_f p_f'                                (dE/dpi = x = u + y)
//           - sum_f theta'_f (g_f(X) - g_f(X - Y) - g_f(Y))              (dE/dtheta_f at fixed pi)
// over moving prescribed hinges b and free hinges f; H_B' = H_B x w, p_f' the flow's.
// Checked against a difference quotient of E along the flow (free_hinge_system_test.cpp).
double FreeHingeSystem::DrivePower(double t,
                                   dynamics::Side side,
                                   const Vec3& H_B,
                                   const Eigen::VectorXd& x) const {
  const int m = free_count();
  const int u = 3 + m;
  const int q = static_cast<int>(moving_.size());
  A_ = M_.topLeftCorner(u, u);
  const Eigen::LLT<Eigen::MatrixXd> llt(A_);
  Eigen::VectorXd pi(u);
  pi.head<3>() = H_B;
  pi.tail(m) = x.segment(m, m);
  Eigen::VectorXd v(q);
  for (int b = 0; b < q; ++b) v[b] = theta_dot_[moving_[static_cast<std::size_t>(b)]];
  const Eigen::VectorXd xa = llt.solve(pi);
  const Eigen::VectorXd ya = llt.solve(M_.block(0, u, u, q) * v);
  const Eigen::VectorXd Sv = M_.block(u, u, q, q) * v - M_.block(0, u, u, q).transpose() * ya;
  // g over (free, moving) at the velocities z (w = z.head<3>(), free rates z.tail(m), the
  // moving prescribed hinges at v_sign v).
  std::vector<int> wrt(free_.begin(), free_.end());
  wrt.insert(wrt.end(), modal_.begin(), modal_.end());
  wrt.insert(wrt.end(), moving_.begin(), moving_.end());
  auto half_form = [&](const Eigen::VectorXd& z, double v_sign, Eigen::VectorXd& g) {
    drive_rates_.setZero(tree_.size());
    HingeRatesOf(z, drive_rates_);
    for (int b = 0; b < q; ++b) drive_rates_[moving_[static_cast<std::size_t>(b)]] = v_sign * v[b];
    model::ComputeVelocity(body_, tree_, pose_, z.head<3>(), drive_rates_, drive_vel_);
    Eigen::VectorXd gh;
    model::KineticEnergyGradient(tree_, pose_, drive_vel_, wrt, gh);
    g = ProjectGradient(gh);
  };
  half_form(xa, 0.0, drive_gx_);
  half_form(ya, -1.0, drive_gy_);
  Eigen::VectorXd g_uv;  // at the actual velocities (u, v) = X - Y
  half_form(xa - ya, 1.0, g_uv);
  double power = 0.0;
  for (int b = 0; b < q; ++b) {
    const int k = moving_[static_cast<std::size_t>(b)];
    const double accel = prescribed_[static_cast<std::size_t>(k)].At(t, side).acceleration;
    power += (drive_gy_[m + b] - drive_gx_[m + b]) * v[b] + Sv[b] * accel;
  }
  power += ya.head<3>().dot(H_B.cross(w_));
  const Eigen::VectorXd rates = CoordinateRates();
  const Eigen::VectorXd forces = CoordinateForces(t, side, x);
  for (int a = 0; a < m; ++a) {
    const double p_dot = g_uv[a] + forces[a];
    power += ya[3 + a] * p_dot - rates[a] * (drive_gx_[a] - g_uv[a] - drive_gy_[a]);
  }
  return power;
}

double FreeHingeSystem::Torque(
    int k, double t, dynamics::Side side, double theta, double theta_dot) const {
  const FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  double q = DriveTorque(d, theta, theta_dot, slip_[static_cast<std::size_t>(k)]);
  if (d.motor.kind == Motor::Kind::kServo) {
    q +=
        ServoTorque(d.motor, servo_ref_[static_cast<std::size_t>(k)].At(t, side), theta, theta_dot);
  }
  return q;
}

double FreeHingeSystem::NextBreakpoint(double t) const {
  double next = std::numeric_limits<double>::infinity();
  for (const PrescribedHinge& p : prescribed_) next = std::min(next, p.NextBreakpoint(t));
  for (const PrescribedHinge& p : servo_ref_) next = std::min(next, p.NextBreakpoint(t));
  return next;
}

std::vector<double> FreeHingeSystem::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  for (const PrescribedHinge& p : prescribed_) {
    for (double b : p.Breakpoints(t0, t1)) out.push_back(b);
  }
  for (const PrescribedHinge& p : servo_ref_) {
    for (double b : p.Breakpoints(t0, t1)) out.push_back(b);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

dynamics::InertiaSample FreeHingeSystem::Evaluate(double t, dynamics::Side side) const {
  if (!free_.empty()) {
    throw std::logic_error("FreeHingeSystem: evaluated as an inertia source with free hinges");
  }
  // Modal coordinates at 0 (the appendages at their angles theta_0, at rest).
  Setup(t, Eigen::VectorXd::Zero(2 * free_count()), side);
  if (sample_valid_ && theta_ == sample_theta_ && theta_dot_ == sample_theta_dot_) return sample_;
  const model::MassProperties mp = model::ComputeMassProperties(body_, theta_, theta_dot_);
  dynamics::InertiaSample s;
  s.J_B = mp.J_B;
  s.Jdot_B = mp.Jdot_B;
  s.h_rel_B = mp.h_rel_B;
  s.J_inv_B = mp.J_B.inverse();
  s.relative_kinetic_energy = mp.relative_kinetic_energy;
  sample_ = s;
  sample_theta_ = theta_;
  sample_theta_dot_ = theta_dot_;
  sample_valid_ = true;
  return s;
}

bool FreeHingeSystem::IsRigidOn(double t0, double t1) const {
  if (free_count() > 0) return false;
  for (const PrescribedHinge& p : prescribed_) {
    if (!p.IsAtRestOn(t0, t1)) return false;
  }
  return true;
}

FreeHingeSystem::Snapshot FreeHingeSystem::Snap(double t,
                                                const Vec3& H_B,
                                                const Eigen::VectorXd& x,
                                                dynamics::Side side) const {
  const int m = free_count();
  Setup(t, x, side);
  Solve(H_B, x);
  Snapshot s;
  s.w_NB_B = w_;
  s.theta = Expand(theta_, false);
  s.theta_dot = Expand(theta_dot_, true);
  s.J_B = M_.block<3, 3>(0, 0);
  s.coordinate_rates = CoordinateRates();
  Eigen::VectorXd rates(m + static_cast<Eigen::Index>(moving_.size()));
  rates.head(m) = s.coordinate_rates;
  for (std::size_t b = 0; b < moving_.size(); ++b) {
    rates[m + static_cast<Eigen::Index>(b)] = theta_dot_[moving_[b]];
  }
  s.h_rel_B = M_.block(0, 3, 3, rates.size()) * rates;
  Eigen::VectorXd v(3 + rates.size());
  v << w_, rates;
  s.kinetic_energy = 0.5 * v.dot(M_ * v);
  for (int k = 0; k < tree_.size(); ++k) {
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind == HingePlan::Kind::kFree) s.spring_energy += SpringEnergy(p.drive, theta_[k]);
  }
  std::vector<int> moved(free_.begin(), free_.end());
  moved.insert(moved.end(), modal_.begin(), modal_.end());
  for (int k : moved) {
    const FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
    double q = NonConservativeTorque(d, theta_dot_[k], slip_[static_cast<std::size_t>(k)]);
    if (d.motor.kind == Motor::Kind::kServo) {
      q += ServoTorque(d.motor, servo_ref_[static_cast<std::size_t>(k)].At(t, side), theta_[k],
                       theta_dot_[k]);
    }
    s.power += q * theta_dot_[k];
  }
  s.powers = PowersNow(t, side, H_B, x);
  return s;
}

Mat3 FreeHingeSystem::InertiaRate(double t,
                                  const Vec3& H_B,
                                  const Eigen::VectorXd& x,
                                  dynamics::Side side) const {
  Setup(t, x, side);
  Solve(H_B, x);
  return model::ComputeMassProperties(body_, theta_, theta_dot_).Jdot_B;
}

Eigen::VectorXd FreeHingeSystem::ShapeState(double t,
                                            const Vec3& H_B,
                                            const Eigen::VectorXd& theta,
                                            const Eigen::VectorXd& theta_dot,
                                            dynamics::Side side) const {
  const int m = free_count();
  const int mh = static_cast<int>(free_.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * m);
  for (int a = 0; a < mh; ++a) x[a] = theta[free_orig_[static_cast<std::size_t>(a)]];
  // Modal coordinates: the least-squares fit of the hinges' angles and rates (exact when
  // they lie in the basis's span, as a straight beam at rest does).
  Eigen::VectorXd q_rate;
  if (!modal_.empty()) {
    Eigen::VectorXd th(phi_.rows()), thd(phi_.rows());
    for (std::size_t i = 0; i < modal_orig_.size(); ++i) {
      th[static_cast<Eigen::Index>(i)] = theta[modal_orig_[i]];
      thd[static_cast<Eigen::Index>(i)] = theta_dot[modal_orig_[i]];
    }
    const auto fit = phi_.colPivHouseholderQr();
    x.segment(mh, modal_count()) = fit.solve(th - modal_theta0_);
    q_rate = fit.solve(thd);
  }
  Setup(t, x, side);
  // Full velocity vector over (w, cols_): the free hinges' rates as given, the
  // prescribed ones from their moves; w from H_B = J w + B theta'.
  UpdateMassMatrix();
  const int c = static_cast<int>(cols_.size());
  Eigen::VectorXd rates(c);
  for (int b = 0; b < c; ++b) {
    const int k = cols_[static_cast<std::size_t>(b)];
    rates[b] = is_free_[static_cast<std::size_t>(k)]
                   ? theta_dot[orig_of_[static_cast<std::size_t>(k)]]
                   : theta_dot_[k];
  }
  if (!modal_.empty()) {
    // cols_ is (free, modal hinges, moving); M_ is over (free, q, moving).
    const Eigen::Index g = phi_.rows();
    Eigen::VectorXd r(mh + modal_count() + (c - mh - g));
    r << rates.head(mh), q_rate, rates.tail(c - mh - g);
    rates = r;
  }
  const Eigen::Index cr = rates.size();
  const Mat3 J = M_.block<3, 3>(0, 0);
  const Vec3 w = J.llt().solve(H_B - M_.block(0, 3, 3, cr) * rates);
  for (int a = 0; a < m; ++a) {
    x[m + a] = (M_.block<1, 3>(3 + a, 0) * w)(0) + M_.row(3 + a).tail(cr).dot(rates);
  }
  return x;
}

Eigen::VectorXd FreeHingeSystem::ImpulseResponse(double t,
                                                 const Vec3& H_B,
                                                 const Eigen::VectorXd& x,
                                                 int a) const {
  Setup(t, x, dynamics::Side::kRight);
  Solve(H_B, x);
  const int u = 3 + free_count();
  A_ = M_.topLeftCorner(u, u);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(A_);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(u);
  e[3 + a] = 1.0;
  return llt.solve(e);
}

double FreeHingeSystem::InverseMass(double t,
                                    const Vec3& H_B,
                                    const Eigen::VectorXd& x,
                                    int a) const {
  return ImpulseResponse(t, H_B, x, a)[3 + a];
}

double FreeHingeSystem::HoldingTorque(int k,
                                      double t,
                                      const Vec3& H_B,
                                      const Eigen::VectorXd& x) const {
  if (probe_ == nullptr || probe_k_ != k || probe_free_ != free_) {
    probe_ = std::make_shared<FreeHingeSystem>(*this);
    probe_->probe_.reset();
    probe_->Free(k);
    probe_->SetSlip(k, 0);  // at rate 0: no friction in the free acceleration
    probe_k_ = k;
    probe_free_ = free_;
  }
  const FreeHingeSystem& p = *probe_;
  const int m = free_count();
  Snapshot now = Snap(t, H_B, x.head(2 * m));
  now.theta_dot[k] = 0.0;
  const Eigen::VectorXd xp = p.ShapeState(t, H_B, now.theta, now.theta_dot);
  const int a = static_cast<int>(p.free_.size()) - 1;  // k, after the probe's other hinges
  return -p.Acceleration(a, t, H_B, xp) / p.InverseMass(t, H_B, xp, a);
}

double FreeHingeSystem::Acceleration(int a,
                                     double t,
                                     const Vec3& H_B,
                                     const Eigen::VectorXd& x) const {
  const int m = free_count();
  const int k = free_orig_[static_cast<std::size_t>(a)];  // Snap speaks of model panels
  const Eigen::VectorXd xs = x.head(2 * m);
  Vec3 w;
  Eigen::VectorXd xd;
  Evaluate(t, H_B, xs, dynamics::Side::kRight, w, xd);
  const Vec3 Hd = H_B.cross(w);
  const double h = kHoldingStep;
  const double up = Snap(t + h, H_B + h * Hd, xs + h * xd).theta_dot[k];
  const double down = Snap(t - h, H_B - h * Hd, xs - h * xd).theta_dot[k];
  return (up - down) / (2.0 * h);
}

FreeHingeSystem::Impulse FreeHingeSystem::ApplyImpulse(
    double t, const Vec3& H_B, Eigen::VectorXd& x, int a, double rate_after) const {
  const int m = free_count();
  const int u = 3 + m;
  // Column a of the inverse of the unknowns' block: the response of (w, theta'_f) to a
  // unit jump of p_a.
  const Eigen::VectorXd col = ImpulseResponse(t, H_B, x, a);
  Impulse out;
  const int k = free_[static_cast<std::size_t>(a)];
  out.rate_before = theta_dot_[k];
  out.rate_after = rate_after;
  out.lambda = (rate_after - out.rate_before) / col[3 + a];
  out.w_jump_B = out.lambda * col.head<3>();
  // The work of the impulse pair at the hinge, lambda times the mean of the rates before
  // and after (the rate changes linearly with lambda); without moving prescribed hinges it
  // is the change of the kinetic energy, for a plastic latch -theta'^2 / (2 (A^-1)_aa).
  out.energy_dissipated =
      -(out.lambda * out.rate_before + 0.5 * out.lambda * out.lambda * col[3 + a]);
  // The moving prescribed hinges keep their rates: their conjugate momenta jump by the
  // coupling rows times the jump of (w, theta'_f), and their drives do that times the
  // (unchanged) rate.
  const int q = static_cast<int>(moving_.size());
  for (int b = 0; b < q; ++b) {
    const double dp = out.lambda * M_.row(u + b).head(u).dot(col);
    out.drive_work += dp * theta_dot_[moving_[static_cast<std::size_t>(b)]];
  }
  x[m + a] += out.lambda;
  return out;
}

}  // namespace deploysim::schedule
