#include "deploysim/dynamics/inertia_source.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include "deploysim/math/so3.h"

namespace deploysim::dynamics {

double TotalKineticEnergy(const InertiaSample& s, const math::Vec3& H_B) {
  const math::Vec3 w = s.J_inv_B * (H_B - s.h_rel_B);
  return 0.5 * w.dot(H_B + s.h_rel_B) + s.relative_kinetic_energy;
}

std::vector<double> InertiaSource::Breakpoints(double /*t0*/, double /*t1*/) const { return {}; }

bool InertiaSource::IsRigidOn(double /*t0*/, double /*t1*/) const { return false; }

ConstantInertia::ConstantInertia(const math::InertiaTensor& J_B)
    : J_B_(J_B), sample_{J_B.matrix(), math::Mat3::Zero(), math::Vec3::Zero(), J_B.inverse()} {}

InertiaSample ConstantInertia::Evaluate(double /*t*/, Side /*side*/) const { return sample_; }

bool ConstantInertia::IsRigidOn(double /*t0*/, double /*t1*/) const { return true; }

FunctionInertia::FunctionInertia(MatFn J_B,
                                 MatFn Jdot_B,
                                 VecFn h_rel_B,
                                 std::vector<double> breakpoints)
    : J_B_(std::move(J_B)),
      Jdot_B_(std::move(Jdot_B)),
      h_rel_B_(std::move(h_rel_B)),
      breakpoints_(std::move(breakpoints)) {
  std::sort(breakpoints_.begin(), breakpoints_.end());
}

InertiaSample FunctionInertia::Evaluate(double t, Side /*side*/) const {
  InertiaSample s;
  s.J_B = J_B_(t);
  assert(math::InertiaTensor::Check(s.J_B).empty());
  s.Jdot_B = Jdot_B_(t);
  s.h_rel_B = h_rel_B_(t);
  s.J_inv_B = s.J_B.inverse();
  return s;
}

std::vector<double> FunctionInertia::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  for (double b : breakpoints_) {
    if (b > t0 && b < t1) out.push_back(b);
  }
  return out;
}

FunctionInertia MakeSyntheticInertia(const math::Vec3& m0,
                                     const math::Vec3& dm,
                                     double omega,
                                     double axis_rate,
                                     const math::Vec3& h0) {
  auto rot = [axis_rate](double t) { return math::ExpSO3(math::Vec3(0.0, 0.0, axis_rate * t)); };
  auto J = [=](double t) -> math::Mat3 {
    const math::Vec3 m = m0 + dm * std::sin(omega * t);
    const math::Mat3 R = rot(t);
    return R * m.asDiagonal() * R.transpose();
  };
  auto Jdot = [=](double t) -> math::Mat3 {
    const math::Vec3 m = m0 + dm * std::sin(omega * t);
    const math::Vec3 mdot = dm * (omega * std::cos(omega * t));
    const math::Mat3 R = rot(t);
    const math::Mat3 Rdot = R * math::Hat(math::Vec3(0.0, 0.0, axis_rate));
    const math::Mat3 D = m.asDiagonal();
    return Rdot * D * R.transpose() + R * mdot.asDiagonal() * R.transpose() +
           R * D * Rdot.transpose();
  };
  auto h = [=](double t) -> math::Vec3 { return h0 * std::cos(omega * t); };
  return FunctionInertia(J, Jdot, h);
}

}  // namespace deploysim::dynamics
