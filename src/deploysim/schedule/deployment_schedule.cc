#include "deploysim/schedule/deployment_schedule.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/math/inertia.h"

namespace deploysim::schedule {

namespace {

const model::Configuration& Find(const model::Model& m, const std::string& name) {
  for (const model::Configuration& c : m.configurations) {
    if (c.name == name) return c;
  }
  // ValidateProfile guarantees every stage names an existing configuration.
  assert(false && "configuration not found after validation");
  std::abort();
}

/// Inverse of a symmetric positive definite J, symmetrized (the cofactor formula is
/// symmetric only up to rounding).
math::Mat3 SymmetricInverse(const math::Mat3& J) {
  const math::Mat3 inv = J.inverse();
  return 0.5 * (inv + inv.transpose());
}

dynamics::InertiaSample RigidSampleOf(const math::Mat3& J_B) {
  dynamics::InertiaSample s;
  s.J_B = J_B;
  s.Jdot_B = math::Mat3::Zero();
  s.h_rel_B = math::Vec3::Zero();
  s.J_inv_B = SymmetricInverse(J_B);
  return s;
}

}  // namespace

DeploymentSchedule::DeploymentSchedule(const Profile& profile)
    : DeploymentSchedule((ValidateProfile(profile), profile), kValidated) {}

DeploymentSchedule::DeploymentSchedule(const Profile& profile, Validated)
    : stages_(profile.stages),
      mode_(profile.mode),
      coupling_(profile.coupling),
      model_(profile.model) {
  if (profile.is_hinge_profile()) {
    // Its panels follow their own plans (hinge_plan.h), not a stage table.
    throw std::invalid_argument(
        (profile.source.empty() ? "profile '" + profile.name + "'" : profile.source) +
        ": hinges: a DeploymentSchedule follows the stages of a stage profile; a hinge "
        "profile has none (rule: hinge profiles are run by the free-hinge engine)");
  }
  const bool hinged = model_.kind == model::ModelKind::kHinged;
  if (hinged) {
    // Already checked by ValidateProfile; this normalizes the hinge axes.
    model_.hinged = model::ValidatedHingedBody(model_.hinged, "model '" + model_.name + "'");
  }
  const std::size_t n = stages_.size();
  for (std::size_t i = 1; i < n; ++i) {
    if (stages_[i].from.empty()) stages_[i].from = stages_[i - 1].to;
  }

  // The zero-rate mass properties of a configuration: geometry of a hinged model, or the
  // validated tensor of a tensor model.
  auto rigid = [&](const std::string& name) {
    const model::Configuration& c = Find(model_, name);
    model::MassProperties mp;
    if (hinged) {
      mp = model::ComputeMassProperties(model_.hinged, c.hinge_angles,
                                        Eigen::VectorXd::Zero(c.hinge_angles.size()));
    } else {
      mp.J_B = math::InertiaTensor::FromMatrix(c.J_B, name).matrix();
    }
    return std::make_pair(c.hinge_angles, mp);
  };
  for (const Stage& st : stages_) {
    auto [theta_from, mp_from] = rigid(st.from);
    auto [theta_to, mp_to] = rigid(st.to);
    J_from_.push_back(mp_from.J_B);
    J_to_.push_back(mp_to.J_B);
    sample_from_.push_back(RigidSampleOf(mp_from.J_B));
    sample_to_.push_back(RigidSampleOf(mp_to.J_B));
    if (mode_ == Mode::kGeometry) {
      theta_from_.push_back(theta_from);
      theta_to_.push_back(theta_to);
      mp_from_.push_back(mp_from);
      mp_to_.push_back(mp_to);
    }
  }

  bounds_.push_back(stages_.front().t_begin);
  for (const Stage& st : stages_) bounds_.push_back(st.t_end);
  time_tolerance_ =
      kBoundaryRelTolerance * std::max(std::abs(bounds_.front()), std::abs(bounds_.back()));
}

DeploymentSchedule::Where DeploymentSchedule::Locate(double t, dynamics::Side side) const {
  assert(!std::isnan(t));
  const int n = static_cast<int>(stages_.size());
  const auto it = std::lower_bound(bounds_.begin(), bounds_.end(), t);  // first b >= t
  const int hi = static_cast<int>(it - bounds_.begin());
  // The nearest boundary within the tolerance, if any.
  int k = -1;
  double gap = time_tolerance_;
  if (hi <= n && bounds_[hi] - t <= gap) {
    k = hi;
    gap = bounds_[hi] - t;
  }
  if (hi > 0 && t - bounds_[hi - 1] <= gap) k = hi - 1;

  Where w;
  if (k >= 0) {
    if (side == dynamics::Side::kRight) {
      if (k == n) {
        w.region = Region::kAfter;
        w.stage = n - 1;
        w.tau = 1.0;
      } else {
        w.stage = k;
        w.tau = 0.0;
      }
    } else {
      if (k == 0) {
        w.region = Region::kBefore;
        w.stage = 0;
        w.tau = 0.0;
      } else {
        w.stage = k - 1;
        w.tau = 1.0;
      }
    }
    return w;
  }
  if (hi == 0) {
    w.region = Region::kBefore;
    w.stage = 0;
    w.tau = 0.0;
  } else if (hi > n) {
    w.region = Region::kAfter;
    w.stage = n - 1;
    w.tau = 1.0;
  } else {
    // bounds_[hi - 1] < t < bounds_[hi]: inside stage hi - 1.
    w.stage = hi - 1;
    const double a = bounds_[hi - 1];
    const double b = bounds_[hi];
    w.tau = std::clamp((t - a) / (b - a), 0.0, 1.0);
  }
  return w;
}

int DeploymentSchedule::Ordinal(const Where& w) const {
  switch (w.region) {
    case Region::kBefore:
      return -1;
    case Region::kAfter:
      return static_cast<int>(stages_.size());
    case Region::kInside:
      break;
  }
  return w.stage;
}

bool DeploymentSchedule::StageIsRigid(int i) const {
  const Stage& st = stages_[i];
  return st.is_hold() || st.law == Law::kStep;
}

LawValue DeploymentSchedule::LawAt(const Where& w) const {
  LawValue v;
  if (w.region == Region::kBefore) return v;  // s = 0, no motion
  if (w.region == Region::kAfter || stages_[w.stage].law == Law::kStep) {
    // After the end, and inside a step-law stage (it switched at its start): s = 1.
    v.s = 1.0;
    return v;
  }
  if (stages_[w.stage].is_hold()) return v;
  return EvaluateLaw(stages_[w.stage].law, w.tau);
}

const dynamics::InertiaSample& DeploymentSchedule::RigidSample(const Where& w) const {
  return LawAt(w).s == 0.0 ? sample_from_[w.stage] : sample_to_[w.stage];
}

dynamics::InertiaSample DeploymentSchedule::Evaluate(double t, dynamics::Side side) const {
  const Where w = Locate(t, side);
  if (w.region != Region::kInside || StageIsRigid(w.stage)) return RigidSample(w);
  const int i = w.stage;
  const Stage& st = stages_[i];
  const double duration = st.t_end - st.t_begin;
  const LawValue v = EvaluateLaw(st.law, w.tau);
  dynamics::InertiaSample out;
  if (mode_ == Mode::kTensor) {
    // J = (1 - s) J_from + s J_to (convex, so valid); Jdot = s'(tau)/D (J_to - J_from).
    out.J_B = (1.0 - v.s) * J_from_[i] + v.s * J_to_[i];
    out.Jdot_B = (v.ds / duration) * (J_to_[i] - J_from_[i]);
    out.h_rel_B = math::Vec3::Zero();
  } else {
    const model::MassProperties mp = GeometryAt(w, v);
    out.J_B = mp.J_B;
    out.Jdot_B = mp.Jdot_B;
    out.h_rel_B = mp.h_rel_B;  // both zero under quasi-rigid coupling
    out.relative_kinetic_energy = mp.relative_kinetic_energy;
  }
  out.J_inv_B = SymmetricInverse(out.J_B);
  return out;
}

std::vector<double> DeploymentSchedule::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  for (double b : bounds_) {
    if (b > t0 + time_tolerance_ && b < t1 - time_tolerance_) out.push_back(b);
  }
  return out;
}

bool DeploymentSchedule::IsRigidOn(double t0, double t1) const {
  if (t1 < t0) std::swap(t0, t1);
  const int a = Ordinal(Locate(t0, dynamics::Side::kRight));
  const int b = Ordinal(Locate(t1, dynamics::Side::kLeft));
  if (a != b) return false;
  return a < 0 || a >= static_cast<int>(stages_.size()) || StageIsRigid(a);
}

int DeploymentSchedule::StageAt(double t, dynamics::Side side) const {
  return Locate(t, side).stage;
}

Eigen::VectorXd DeploymentSchedule::HingeAngles(double t, dynamics::Side side) const {
  if (mode_ != Mode::kGeometry) return {};
  const Where w = Locate(t, side);
  const double s = LawAt(w).s;
  // (1 - s) from + s to: exactly the configuration's angles at s = 0 and s = 1.
  return (1.0 - s) * theta_from_[w.stage] + s * theta_to_[w.stage];
}

Eigen::VectorXd DeploymentSchedule::HingeRates(double t, dynamics::Side side) const {
  if (mode_ != Mode::kGeometry) return {};
  const Where w = Locate(t, side);
  const Stage& st = stages_[w.stage];
  const double scale = LawAt(w).ds / (st.t_end - st.t_begin);
  return scale * (theta_to_[w.stage] - theta_from_[w.stage]);
}

Eigen::VectorXd DeploymentSchedule::HingeAccelerations(double t, dynamics::Side side) const {
  if (mode_ != Mode::kGeometry) return {};
  const Where w = Locate(t, side);
  const Stage& st = stages_[w.stage];
  const double duration = st.t_end - st.t_begin;
  const double scale = LawAt(w).dds / (duration * duration);
  return scale * (theta_to_[w.stage] - theta_from_[w.stage]);
}

model::MassProperties DeploymentSchedule::GeometryAt(const Where& w, const LawValue& v) const {
  const int i = w.stage;
  // No hinge motion at an end configuration: the precomputed zero-rate properties.
  if (v.ds == 0.0 && (v.s == 0.0 || v.s == 1.0)) return v.s == 0.0 ? mp_from_[i] : mp_to_[i];
  const double duration = stages_[i].t_end - stages_[i].t_begin;
  // theta = (1 - s) theta_from + s theta_to, theta' = s'(tau) / D (theta_to - theta_from).
  const Eigen::VectorXd theta = (1.0 - v.s) * theta_from_[i] + v.s * theta_to_[i];
  const Eigen::VectorXd theta_dot = (v.ds / duration) * (theta_to_[i] - theta_from_[i]);
  model::MassProperties mp = model::ComputeMassProperties(model_.hinged, theta, theta_dot);
  if (coupling_ == Coupling::kQuasiRigid) {
    // The instantaneously rigid body: no relative momentum and no relative kinetic energy.
    mp.h_rel_B = math::Vec3::Zero();
    mp.relative_kinetic_energy = 0.0;
  }
  return mp;
}

model::MassProperties DeploymentSchedule::MassPropertiesAt(double t, dynamics::Side side) const {
  if (mode_ == Mode::kTensor) {
    const dynamics::InertiaSample s = Evaluate(t, side);
    model::MassProperties mp;
    mp.J_B = s.J_B;
    mp.Jdot_B = s.Jdot_B;
    return mp;
  }
  const Where w = Locate(t, side);
  return GeometryAt(w, LawAt(w));
}

}  // namespace deploysim::schedule
