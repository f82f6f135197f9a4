#include "deploysim/run/coupling_comparison.h"

#include <algorithm>
#include <stdexcept>

#include "deploysim/math/quaternion.h"

namespace deploysim::run {

CouplingComparison CompareCouplings(const schedule::Profile& profile) {
  if (profile.mode != schedule::Mode::kGeometry) {
    throw std::invalid_argument(profile.source +
                                ": mode = tensor: the coupling comparison needs mode: geometry "
                                "(h_rel comes from the hinge rates)");
  }
  schedule::Profile p_exact = profile;
  p_exact.coupling = schedule::Coupling::kExact;
  schedule::Profile p_qr = profile;
  p_qr.coupling = schedule::Coupling::kQuasiRigid;
  // A step law is only valid quasi-rigidly; ValidateProfile rejects it for exact coupling.
  CouplingComparison c;
  c.exact = RunMission(p_exact);
  c.quasi_rigid = RunMission(p_qr);
  for (const schedule::Stage& st : profile.stages) {
    if (!st.is_hold()) c.deployment_end = std::max(c.deployment_end, st.t_end);
  }
  const Trajectory& a = c.exact.trajectory;
  const Trajectory& b = c.quasi_rigid.trajectory;
  const double M = a.H_B.front().norm();
  double best_gap = 1e300;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double t = a.time[i];
    c.w_scale = std::max(c.w_scale, a.w_NB_B[i].norm());
    bool moving = false;
    for (const schedule::Stage& st : profile.stages) {
      if (!st.is_hold() && t >= st.t_begin && t <= st.t_end) moving = true;
    }
    if (moving) {
      c.max_w_difference_deploying =
          std::max(c.max_w_difference_deploying, (a.w_NB_B[i] - b.w_NB_B[i]).norm());
    }
    const double gap = std::abs(t - c.deployment_end);
    if (gap < best_gap) {
      best_gap = gap;
      c.attitude_offset_at_deployment_end = math::AngleBetween(a.q_NB[i], b.q_NB[i]);
    }
    if (t > c.deployment_end) {
      c.max_attitude_difference_after =
          std::max(c.max_attitude_difference_after, math::AngleBetween(a.q_NB[i], b.q_NB[i]));
      c.max_H_B_difference_after =
          std::max(c.max_H_B_difference_after, (a.H_B[i] - b.H_B[i]).norm() / M);
    }
  }
  return c;
}

}  // namespace deploysim::run
