#include "deploysim/schedule/initial_spin.h"

#include <cmath>
#include <stdexcept>

#include "deploysim/math/inertia.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::schedule {

namespace {

// A transverse momentum smaller than this fraction of |H_B| has no direction of its own:
// the tilt then goes towards the next principal axis.
constexpr double kNoTransverse = 1e-12;

/// The unit direction, normal to s, towards which H tilts when it has no transverse part:
/// the next principal axis (ascending moments, cyclic) of J_B after the one nearest s.
math::Vec3 TiltTowardsNextAxis(const math::Mat3& J_B, const math::Vec3& s) {
  const math::PrincipalAxes pa = math::PrincipalDecomposition(J_B);
  int i = 0;
  for (int j = 0; j < 3; ++j) {
    if (std::abs(pa.axes.col(j).dot(s)) > std::abs(pa.axes.col(i).dot(s))) i = j;
  }
  const math::Vec3 u = pa.axes.col((i + 1) % 3);
  return (u - u.dot(s) * s).normalized();
}

}  // namespace

dynamics::InertiaSample InitialInertia(const Profile& p) {
  if (!p.is_hinge_profile()) return DeploymentSchedule(p).Evaluate(p.t_begin());
  const std::string where = p.source.empty() ? p.name : p.source;
  const model::HingedBody body = model::ValidatedHingedBody(
      p.model.hinged, p.model.source.empty() ? where + ": model" : p.model.source);
  const FreeHingeSystem sys(body, p.hinges,
                            p.model.configuration(p.initial.configuration).hinge_angles);
  return sys.Evaluate(p.t_begin());
}

math::Vec3 TiltMomentum(const math::Vec3& H,
                        const math::Vec3& s,
                        const math::Mat3& J_B,
                        std::optional<double> nutation,
                        std::optional<double> azimuth) {
  const double M = H.norm();
  const math::Vec3 transverse = H - H.dot(s) * s;
  math::Vec3 u = transverse.norm() > kNoTransverse * M ? math::Vec3(transverse.normalized())
                                                       : TiltTowardsNextAxis(J_B, s);
  if (azimuth) u = std::cos(*azimuth) * u + std::sin(*azimuth) * s.cross(u);
  const double theta = nutation ? *nutation : std::atan2(transverse.norm(), H.dot(s));
  return M * (std::cos(theta) * s + std::sin(theta) * u);
}

math::Vec3 ScaleToSpinRate(const math::Vec3& H,
                           const math::Vec3& s,
                           const dynamics::InertiaSample& s0,
                           double rate) {
  const math::Vec3 w = s0.J_inv_B * (H - s0.h_rel_B);
  const double ws = w.dot(s);
  if (!(std::abs(ws) > 0.0)) {
    throw std::invalid_argument(
        "spin_rate: the base angular velocity has no component along the spin axis");
  }
  return s0.J_B * (w * (rate / std::abs(ws))) + s0.h_rel_B;
}

math::Vec3 SpinMomentum(const dynamics::InertiaSample& s0, const InitialSpin& spin) {
  const math::Vec3 s = spin.axis_B.normalized();
  const math::Vec3 H0 = s0.J_B * (spin.rate * s) + s0.h_rel_B;
  const math::Vec3 H = TiltMomentum(H0, s, s0.J_B, spin.nutation, spin.azimuth);
  return ScaleToSpinRate(H, s, s0, spin.rate);
}

}  // namespace deploysim::schedule
