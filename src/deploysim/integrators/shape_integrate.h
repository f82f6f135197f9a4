#pragma once

/// Integration of a body with free shape coordinates (dynamics::ShapeSystem,
/// docs/design.md 2.7): Runge-Kutta-Munthe-Kaas on SO(3) x R^(2m). The attitude is advanced on
/// SO(3) exactly as by the rigid-body RKMK steppers (rkmk.h: relative to an anchor state, the spin
/// about h_N integrated exactly, the rounding carried in double-double), and H_B = R_NB^T h_N is
/// derived from it, so h_N is conserved to rounding by construction whatever the hinges do; the
/// shape state x = (theta_f, p_f) is advanced by the same tableau as a vector. The Lie-algebra
/// stage equation is
///   u' = J_r^-1(u) (w - sigma H),  H = Exp(-u) H_B(t0),  sigma = w(t0).H(t0) / |H|^2,
/// with R(t0 + tau) = Exp(sigma tau h_N) R(t0) Exp(u(tau)).
///
/// Error control: the weighted max norm of the embedded error over the momentum change
/// the attitude error causes (H_B x du, weights 1 / (atol |H| + rtol |H_i|)), the hinge
/// angles (1 / (atol + rtol |theta|), atol in rad) and momenta (1 / (atol |H| + rtol |p|)).
///
/// Dense output on y = (u, x - x0) over the step: Dormand-Prince's own continuous extension
/// (rkmk-dopri5), cubic Hermite (rkmk4), Hermite of degree 9 on five nodes (rkmk-rkf78,
/// the interior nodes from partial steps), as for the rigid-body steppers.
///
/// Events: sign changes of scalar functions of the state, located on the dense output and
/// finished on partial steps (as integrate.h). A terminal event stops the integration at
/// its time (the events the hybrid driver applies as impulses: latches, stops). A terminal
/// function that is exactly 0 at the start (a panel just rebounded off its stop) must
/// first leave 0 to the side opposite its direction: a step that does not end strictly on
/// that side is rejected and shortened, down to kMinLeaveStep, below which the integration stops as
/// `stuck`.

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/dynamics/shape_system.h"
#include "deploysim/integrators/integrate.h"

namespace deploysim::integrators {

/// The state of a shape system at time t.
struct ShapeState {
  double t = 0.0;
  math::Vec3 H_B = math::Vec3::Zero();       ///< [kg m^2/s] = R_NB^T h_N
  math::Quat q_NB = math::Quat::Identity();  ///< unit
  Eigen::VectorXd x;                         ///< (theta_f [rad], p_f [N m s])
};

/// A scalar function of the state whose sign changes are events.
struct ShapeEventFunction {
  std::string name;
  std::function<double(const ShapeState&)> g;
  /// +1: only rising sign changes (g from < 0 to >= 0), -1: only falling, 0: both.
  int direction = 0;
  /// Stop the integration at the first located terminal event.
  bool terminal = false;
  /// Finish the location on partial steps of the stepper (the event time to the steps'
  /// accuracy); false: on the dense output only (its own error, far below the steps'
  /// tolerance for the degree-9 Hermite and Dormand-Prince extensions; no extra steps).
  bool refine = true;
  /// dg/dt at a state (optional; analytic). With it, a crossing and return of zero
  /// inside one step (a panel that just reaches its latch) is found too: see the
  /// guarantee in docs/design.md, "Events".
  std::function<double(const ShapeState&)> rate = {};
};

struct ShapeEvent {
  double t = 0.0;     ///< [s]
  int index = 0;      ///< Which function.
  int direction = 0;  ///< +1 rising, -1 falling.
  ShapeState state;   ///< At t (a partial step of the stepper).
};

struct ShapeIntegrationResult {
  std::vector<ShapeEvent> events;  ///< Ascending; a terminal event, if any, is the last.
  bool stopped_at_event = false;   ///< Stopped at a terminal event (the last of `events`).
  /// Stopped at the start: a terminal event function was 0 there and no step of at least
  /// kMinLeaveStep could leave its zero towards the side it started from (a panel resting
  /// on its stop). The last of `events` is that event, at the start time.
  bool stuck = false;
  ShapeState final_state;  ///< At t_end, or at the terminal event.
  Statistics stats;
  Termination termination = Termination::kReachedEnd;
  std::string message;
  double next_step = 0.0;  ///< [s] the step size the controller would take next.
};

/// [s, relative to max(1, |t|)] shortest step that may leave a terminal event's zero.
inline constexpr double kMinLeaveStep = 1e-12;

/// The methods for shape systems: "rkmk4" (fixed step), "rkmk-dopri5", "rkmk-rkf78".
std::vector<std::string> ShapeMethodNames();
/// True for a name ShapeMethodNames() lists.
bool IsShapeMethod(const std::string& name);

/// Integrates `system` from `initial` to t_end (> initial.t) or to the first terminal
/// event. Output samples: the times output_times.at(i) for i from *next_output while they
/// are < the stop time (<= t_end when the end is reached), passed to `samples` in
/// order; *next_output is advanced past them. (A sample at exactly a terminal event's time
/// is left to the caller: it shows the state after the event.) settings.step: the initial
/// step (0: automatic). `project`: applied to every step's end once the error control has
/// accepted it, before its events and samples (a projection onto an invariant). Throws
/// std::invalid_argument for an unknown method or settings.
ShapeIntegrationResult IntegrateShape(const std::string& method,
                                      const IntegratorSettings& settings,
                                      const dynamics::ShapeSystem& system,
                                      const ShapeState& initial,
                                      double t_end,
                                      const OutputTimes& output_times,
                                      std::size_t* next_output,
                                      const std::vector<ShapeEventFunction>& events,
                                      const std::function<void(const ShapeState&)>& samples,
                                      const std::function<void(const ShapeState&)>& observer = {},
                                      const std::function<void(ShapeState&)>& project = {});

}  // namespace deploysim::integrators
