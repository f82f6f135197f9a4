#include "deploysim/dynamics/rigid_body.h"

namespace deploysim::dynamics {

math::Vec4 QuaternionRate(const math::Quat& q_NB, const math::Vec3& w_NB_B) {
  const math::Quat wq(0.0, w_NB_B.x(), w_NB_B.y(), w_NB_B.z());
  return 0.5 * (q_NB * wq).coeffs();
}

double KineticEnergy(const InertiaSample& s, const math::Vec3& H_B) {
  const math::Vec3 w = AngularVelocity(s, H_B);
  return 0.5 * w.dot(s.J_B * w);
}

}  // namespace deploysim::dynamics
