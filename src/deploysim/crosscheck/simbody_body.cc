#include "deploysim/crosscheck/simbody_body.h"

#include <Eigen/Dense>
#include <cstdlib>
#include <stdexcept>

#include "deploysim/crosscheck/simtk_support.h"

namespace deploysim::crosscheck::simtk {

namespace {
constexpr int kHubU = 6;  // Free mobilizer: 3 angular + 3 linear speeds
}  // namespace

std::vector<std::size_t> TreeOrder(const model::HingedBody& body, const std::string& where) {
  const std::size_t n = body.panels.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int p = body.panels[k].parent;
    if (p < -1 || p >= static_cast<int>(n) || p == static_cast<int>(k)) {
      throw std::invalid_argument(where + ": panels[" + std::to_string(k) + "] (" +
                                  body.panels[k].name + ").parent = " + std::to_string(p) +
                                  ": must be -1 (the hub) or another panel's index");
    }
  }
  std::vector<std::size_t> order;
  std::vector<bool> placed(n, false);
  for (bool progress = true; progress && order.size() < n;) {
    progress = false;
    for (std::size_t k = 0; k < n; ++k) {
      const int p = body.panels[k].parent;
      if (!placed[k] && (p < 0 || placed[static_cast<std::size_t>(p)])) {
        placed[k] = true;
        order.push_back(k);
        progress = true;
      }
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!placed[k]) {
      throw std::invalid_argument(where + ": panels[" + std::to_string(k) + "] (" +
                                  body.panels[k].name +
                                  ").parent: the parents form a cycle (must be a tree)");
    }
  }
  return order;
}

void AddHingedBodies(HingedSystem& sys, const model::HingedBody& body, const std::string& where) {
  const std::vector<std::size_t> order = TreeOrder(body, where);
  const model::Hub& h = body.hub;
  sys.hub = SimTK::MobilizedBody::Free(
      sys.matter.Ground(), SimTK::Transform(),
      SimTK::Body::Rigid(AboutOrigin(h.body.mass, h.com_B, h.body.inertia_cm)), SimTK::Transform());
  sys.pins.assign(body.panels.size(), SimTK::MobilizedBody::Pin());
  for (std::size_t k : order) {
    const model::Panel& p = body.panels[k];
    SimTK::MobilizedBody& parent =
        p.parent < 0
            ? static_cast<SimTK::MobilizedBody&>(sys.hub)
            : static_cast<SimTK::MobilizedBody&>(sys.pins[static_cast<std::size_t>(p.parent)]);
    // F (on the parent, at the hinge point, given in the parent's frame: from its origin,
    // in its axes) and M (on the panel, at its origin) have Z = a_k.
    const SimTK::Rotation R_PF(SimTK::UnitVec3(ToSimTK(p.hinge_axis_B)), SimTK::ZAxis);
    const SimTK::Body::Rigid panel(AboutOrigin(p.body.mass, p.com_offset_B, p.body.inertia_cm));
    sys.pins[k] =
        SimTK::MobilizedBody::Pin(parent, SimTK::Transform(R_PF, ToSimTK(p.hinge_point_B)), panel,
                                  SimTK::Transform(R_PF, SimTK::Vec3(0)));
  }
}

double KineticEnergyAboutCom(const HingedSystem& sys, const SimTK::State& s) {
  sys.system.realize(s, SimTK::Stage::Velocity);
  // Zero in exact arithmetic (the linear momentum is zero and nothing pushes the system).
  const SimTK::Vec3 v_cm = sys.matter.calcSystemMassCenterVelocityInGround(s);
  return sys.matter.calcKineticEnergy(s) - 0.5 * sys.matter.calcSystemMass(s) * v_cm.normSqr();
}

math::Mat3 HubRotation(const HingedSystem& sys, const SimTK::State& s) {
  sys.system.realize(s, SimTK::Stage::Position);
  return ToEigen(sys.hub.getBodyRotation(s).asMat33());
}

math::Vec3 HubAngularVelocity_B(const HingedSystem& sys, const SimTK::State& s) {
  sys.system.realize(s, SimTK::Stage::Velocity);
  return HubRotation(sys, s).transpose() * ToEigen(sys.hub.getBodyAngularVelocity(s));
}

math::Mat3 SystemInertia_B(const HingedSystem& sys, const SimTK::State& s) {
  sys.system.realize(s, SimTK::Stage::Position);
  const math::Mat3 R_NB = HubRotation(sys, s);
  const math::Mat3 I_N = ToEigen(sys.matter.calcSystemCentralInertiaInGround(s).toMat33());
  const math::Mat3 J = R_NB.transpose() * I_N * R_NB;
  return 0.5 * (J + J.transpose());
}

math::Vec3 Momentum_N(const HingedSystem& sys, const SimTK::State& s) {
  return CentralMomentum(sys.system, sys.matter, s).head<3>();
}

void FitHubVelocity(const HingedSystem& sys,
                    SimTK::State& s,
                    const math::Vec3* w_N,
                    const math::Vec3& h_N,
                    const math::Vec3& p_N) {
  if (sys.hub.getNumU(s) != kHubU) std::abort();  // Free mobilizer: broken invariant
  Vec6 u = Vec6::Zero();
  if (w_N != nullptr) u.head<3>() = *w_N;
  const int first = w_N != nullptr ? 3 : 0;  // unknown speeds and targeted momenta
  const int m = kHubU - first;
  auto set = [&](const Vec6& x) {
    for (int j = 0; j < kHubU; ++j) sys.hub.setOneU(s, j, x[j]);
  };
  Vec6 target;
  target << h_N, p_N;
  for (int pass = 0; pass < 2; ++pass) {
    set(u);
    const Vec6 b = CentralMomentum(sys.system, sys.matter, s);
    Eigen::MatrixXd A(m, m);
    for (int j = 0; j < m; ++j) {
      Vec6 e = u;
      e[first + j] += 1.0;
      set(e);
      const Vec6 column = CentralMomentum(sys.system, sys.matter, s) - b;
      for (int i = 0; i < m; ++i) A(i, j) = column[first + i];
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (lu.rank() < m) std::abort();  // positive-definite system inertia: full rank
    Eigen::VectorXd rhs(m);
    for (int i = 0; i < m; ++i) rhs[i] = target[first + i] - b[first + i];
    const Eigen::VectorXd du = lu.solve(rhs);
    for (int i = 0; i < m; ++i) u[first + i] += du[i];
  }
  set(u);
}

void AppendSample(const HingedSystem& sys,
                  const SimTK::State& s,
                  double t_label,
                  SimbodyTrajectory& tr) {
  const math::Mat3 R_NB = HubRotation(sys, s);
  const math::Vec3 h_N = Momentum_N(sys, s);
  tr.time.push_back(t_label);
  tr.h_N.push_back(h_N);
  tr.H_B.push_back(R_NB.transpose() * h_N);
  tr.w_NB_B.push_back(HubAngularVelocity_B(sys, s));
  tr.q_NB.push_back(math::Quat(R_NB).normalized());
  tr.kinetic_energy.push_back(KineticEnergyAboutCom(sys, s));
  const auto n = static_cast<Eigen::Index>(sys.pins.size());
  Eigen::VectorXd angle(n), rate(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    angle[k] = sys.pins[static_cast<std::size_t>(k)].getOneQ(s, 0);
    rate[k] = sys.pins[static_cast<std::size_t>(k)].getOneU(s, 0);
  }
  tr.hinge_angles.push_back(angle);
  tr.hinge_rates.push_back(rate);
}

}  // namespace deploysim::crosscheck::simtk
