#include "deploysim/schedule/hinge_motion.h"

#include <cmath>
#include <utility>

namespace deploysim::schedule {

PrescribedHinge::PrescribedHinge(std::vector<HingeMove> moves, double initial_angle)
    : moves_(std::move(moves)), initial_angle_(initial_angle) {
  double angle = initial_angle;
  start_angles_.reserve(moves_.size());
  for (const HingeMove& m : moves_) {
    start_angles_.push_back(angle);
    angle = m.kind == HingeMove::Kind::kTo ? m.angle : angle + m.rate * (m.t_end - m.t_begin);
  }
}

HingeKinematics PrescribedHinge::At(double t, dynamics::Side side) const {
  HingeKinematics k;
  k.angle = initial_angle_;
  for (std::size_t j = 0; j < moves_.size(); ++j) {
    const HingeMove& m = moves_[j];
    const double theta_b = start_angles_[j];
    // Before this window (from the left at its start): hold the angle reached so far.
    const bool before = t < m.t_begin || (t == m.t_begin && side == dynamics::Side::kLeft);
    if (before) return k;
    const bool after = t > m.t_end || (t == m.t_end && side == dynamics::Side::kRight);
    const double D = m.t_end - m.t_begin;
    if (m.kind == HingeMove::Kind::kTo) {
      if (after) {
        k.angle = m.angle;
        continue;
      }
      const LawValue v = EvaluateLaw(m.law, (t - m.t_begin) / D);
      const double swing = m.angle - theta_b;
      k.angle = theta_b + v.s * swing;
      k.rate = v.ds / D * swing;
      k.acceleration = v.dds / (D * D) * swing;
      return k;
    }
    if (after) {
      k.angle = theta_b + m.rate * D;
      continue;
    }
    k.angle = theta_b + m.rate * (t - m.t_begin);
    k.rate = m.rate;
    k.acceleration = 0.0;
    return k;
  }
  return k;
}

std::vector<double> PrescribedHinge::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  for (const HingeMove& m : moves_) {
    for (double b : {m.t_begin, m.t_end}) {
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
