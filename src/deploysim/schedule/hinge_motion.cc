#include "deploysim/schedule/hinge_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace deploysim::schedule {

PrescribedHinge::PrescribedHinge(std::vector<HingeMove> moves, double initial_angle)
    : moves_(std::move(moves)) {
  double angle = initial_angle;
  start_angles_.reserve(moves_.size());
  for (const HingeMove& m : moves_) {
    start_angles_.push_back(angle);
    angle = m.kind == HingeMove::Kind::kTo ? m.angle : angle + m.rate * (m.t_end - m.t_begin);
  }
  end_angle_ = angle;
}

HingeKinematics PrescribedHinge::At(double t, dynamics::Side side) const {
  HingeKinematics k;
  // The first window not over at t (from the right at its end): the windows ascend and
  // do not overlap, so a binary search finds it (a rotor may have 10^4 windows).
  const auto over = [&](const HingeMove& m) {
    return t > m.t_end || (t == m.t_end && side == dynamics::Side::kRight);
  };
  const std::size_t j = static_cast<std::size_t>(
      std::partition_point(moves_.begin(), moves_.end(), over) - moves_.begin());
  if (j == moves_.size()) {
    k.angle = end_angle_;
    return k;
  }
  const HingeMove& m = moves_[j];
  const double theta_b = start_angles_[j];
  k.angle = theta_b;
  // Before this window (from the left at its start): hold the angle reached so far.
  if (t < m.t_begin || (t == m.t_begin && side == dynamics::Side::kLeft)) return k;
  const double D = m.t_end - m.t_begin;
  if (m.kind == HingeMove::Kind::kTo) {
    const LawValue v = EvaluateLaw(m.law, (t - m.t_begin) / D);
    const double swing = m.angle - theta_b;
    k.angle = theta_b + v.s * swing;
    k.rate = v.ds / D * swing;
    k.acceleration = v.dds / (D * D) * swing;
    return k;
  }
  k.angle = theta_b + m.rate * (t - m.t_begin);
  k.rate = m.rate;
  k.acceleration = 0.0;
  return k;
}

std::vector<HingeMove>::const_iterator PrescribedHinge::FirstNotOver(double t) const {
  return std::partition_point(moves_.begin(), moves_.end(),
                              [t](const HingeMove& m) { return m.t_end <= t; });
}

double PrescribedHinge::NextBreakpoint(double t) const {
  const auto m = FirstNotOver(t);
  if (m == moves_.end()) return std::numeric_limits<double>::infinity();
  return m->t_begin > t ? m->t_begin : m->t_end;
}

std::vector<double> PrescribedHinge::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  // The moves that end after t0, up to the first that starts at or after t1.
  for (auto m = FirstNotOver(t0); m != moves_.end() && m->t_begin < t1; ++m) {
    for (double b : {m->t_begin, m->t_end}) {
      if (b > t0 && b < t1 && (out.empty() || out.back() < b)) out.push_back(b);
    }
  }
  return out;
}

bool PrescribedHinge::IsAtRestOn(double t0, double t1) const {
  for (const HingeMove& m : moves_) {
    if (m.t_begin < t1 && m.t_end > t0) return false;
  }
  return true;
}

double DriveTorque(const FreeDrive& d, double theta, double theta_dot, int slip) {
  return -d.spring.stiffness * (theta - d.spring.rest_angle) + d.spring.preload +
         NonConservativeTorque(d, theta_dot, slip);
}

double NonConservativeTorque(const FreeDrive& d, double theta_dot, int slip) {
  const NonConservativeParts q = NonConservativeTorqueParts(d, theta_dot, slip);
  return q.damper + q.motor + q.friction;
}

NonConservativeParts NonConservativeTorqueParts(const FreeDrive& d, double theta_dot, int slip) {
  NonConservativeParts q;
  q.damper = -d.damping * theta_dot;
  switch (d.motor.kind) {
    case Motor::Kind::kNone:
      break;
    case Motor::Kind::kConstant:
      q.motor = d.motor.torque;
      break;
    case Motor::Kind::kTorqueSpeed:
      q.motor = d.motor.stall_torque * (1.0 - theta_dot / d.motor.no_load_speed);
      break;
    case Motor::Kind::kServo:
      break;  // time-dependent: ServoTorque, added by the caller
  }
  if (IsCoulomb(d.friction)) {
    q.friction = -d.friction.torque * slip;
  } else if (d.friction.torque > 0.0) {
    q.friction = -d.friction.torque * std::tanh(theta_dot / d.friction.regularization_speed);
  }
  return q;
}

double ServoTorque(const Motor& m, const HingeKinematics& ref, double theta, double theta_dot) {
  if (m.kind != Motor::Kind::kServo) return 0.0;
  return m.servo_stiffness * (ref.angle - theta) + m.servo_damping * (ref.rate - theta_dot);
}

double SpringEnergy(const FreeDrive& d, double theta) {
  const double x = theta - d.spring.rest_angle;
  return 0.5 * d.spring.stiffness * x * x - d.spring.preload * x;
}

}  // namespace deploysim::schedule
