#pragma once

/// Replays a recorded hinge-angle history (e.g. Simbody's spring-driven deployment) as
/// the reduced model's inertia source, with exact coupling (docs/design.md 2.5).
///
/// Interpolant: on each knot interval [t_i, t_{i+1}] (h = t_{i+1} - t_i, s = (t - t_i)/h)
/// the quintic Hermite polynomial matching theta, theta' and theta'' at both knots,
///   theta(s) = p0 A0 + h v0 A1 + h^2 a0 A2 + h^2 a1 A3 + h v1 A4 + p1 A5,
///   A0 = 1 - 10s^3 + 15s^4 - 6s^5,  A1 = s - 6s^3 + 8s^4 - 3s^5,
///   A2 = (s^2 - 3s^3 + 3s^4 - s^5)/2,  A3 = (s^3 - 2s^4 + s^5)/2,
///   A4 = -4s^3 + 7s^4 - 3s^5,  A5 = 10s^3 - 15s^4 + 6s^5,
/// exact for quintics, C2 across knots, interpolation error O(h^6 theta^(6)). The rate
/// used for h_rel is the interpolant's own derivative, so J_B(t) and h_rel_B(t) are
/// consistent (Jdot is the derivative of J). The knots are breakpoints (the integrator
/// restarts at each), so every step sees one polynomial. J_B, dJ_B/dt and h_rel_B come
/// from model::ComputeMassProperties. Outside [t_first, t_last] the end values hold with
/// zero rates.

#include <Eigen/Core>
#include <vector>

#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/model/model.h"

namespace deploysim::crosscheck {

/// theta(t), theta'(t) of the quintic Hermite interpolant of `h` (see above).
struct HingeState {
  Eigen::VectorXd angle;  ///< [rad]
  Eigen::VectorXd rate;   ///< [rad/s]
};

class HingeHistorySource final : public dynamics::InertiaSource {
 public:
  /// `body` must be valid (model::ValidatedHingedBody); the history needs >= 2 knots,
  /// strictly increasing times and one entry per panel in every vector. Throws
  /// std::invalid_argument otherwise.
  HingeHistorySource(model::HingedBody body, HingeHistory history);

  dynamics::InertiaSample Evaluate(double t,
                                   dynamics::Side side = dynamics::Side::kRight) const override;
  /// The knots strictly inside (t0, t1).
  std::vector<double> Breakpoints(double t0, double t1) const override;

  HingeState Interpolate(double t, dynamics::Side side = dynamics::Side::kRight) const;
  const HingeHistory& history() const { return history_; }

 private:
  model::HingedBody body_;
  HingeHistory history_;
};

}  // namespace deploysim::crosscheck
