#pragma once

/// The integration driver shared by every stepper: splits [t0, t_end] at the source's
/// breakpoints (steps land on them exactly and restart, docs/design.md 2.5), controls the
/// step size of adaptive methods, samples the solution on a requested output grid
/// independent of the steps, and locates events (sign changes of scalar functions of
/// the state, e.g. the Dzhanibekov flip).
///
/// Dense output: the solution at t in (t_n, t_n + h) is the stepper's continuous
/// extension of the accepted step (Stepper::Dense: Dormand-Prince's own, Hermite
/// interpolants, the closed form of `exact`), which agrees with the step at both ends
/// and costs at most one partial step per accepted step. Events are bracketed on it and
/// finished on the stepper's exact partial steps (unless the dense output is exact).
///
/// The stepper is only read: its per-run caches and carries live in a workspace that
/// Integrate creates (Stepper::NewWorkspace) and owns for the run, so one stepper
/// object may serve several runs in several threads at once.
///
/// Initial state: H_B is used bit for bit; q_NB must be a unit quaternion
/// (math::ValidateUnitQuaternion) and is normalized.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

/// Settings of one run. Validated by Integrate (std::invalid_argument naming the rule).
struct IntegratorSettings {
  /// Fixed step [s] for fixed-step methods (required, > 0); optional initial step for
  /// adaptive ones (0: chosen automatically).
  double step = 0.0;
  Tolerances tolerances;
  /// Upper bound on the step of adaptive methods [s] (> 0).
  double max_step = 1e300;
  /// Give up after this many steps (accepted + rejected).
  long max_steps = 50'000'000;
};

/// A scalar function of the state whose sign changes are events.
struct EventFunction {
  std::string name;
  std::function<double(const State&)> g;
  /// dg/dt at a state (optional; analytic). With it, a crossing and return of zero
  /// inside one step is found too (docs/design.md, "Events").
  std::function<double(const State&)> rate = {};
};

struct Event {
  double t = 0.0;     ///< [s] located time of the sign change.
  int index = 0;      ///< Which event function.
  int direction = 0;  ///< +1: g rose through 0; -1: g fell through 0.
  State state;        ///< State at the event (dense output).
};

struct Statistics {
  long steps = 0;        ///< Accepted steps.
  long rejected = 0;     ///< Rejected step attempts.
  long evaluations = 0;  ///< Right-hand-side (inertia source) evaluations, dense output included.
  long dense_steps = 0;  ///< Partial steps taken for the continuous extensions and events.
};

enum class Termination { kReachedEnd, kMaxSteps, kStepSizeUnderflow, kNonFinite };
std::string ToString(Termination t);

struct IntegrationResult {
  std::vector<State> samples;  ///< At the requested output times.
  std::vector<Event> events;   ///< Ascending in time.
  State final_state;
  Statistics stats;
  Termination termination = Termination::kReachedEnd;
  std::string message;  ///< Why it stopped, for the user.
};

/// Output times by index, ascending, computed on demand: a grid of 1e7 times need not
/// be stored (a std::vector is adapted by the vector overload of Integrate).
class OutputTimes {
 public:
  virtual ~OutputTimes() = default;
  virtual std::size_t size() const = 0;
  /// Time number i < size().
  virtual double at(std::size_t i) const = 0;
};

/// UniformGrid(t0, t_end, dt) as OutputTimes: the same times, bit for bit, unstored.
class UniformGridTimes final : public OutputTimes {
 public:
  /// Throws std::invalid_argument as UniformGrid does.
  UniformGridTimes(double t0, double t_end, double dt);
  std::size_t size() const override { return size_; }
  double at(std::size_t i) const override {
    return i + 1 == size_ ? t_end_ : t0_ + static_cast<double>(i) * dt_;
  }

 private:
  double t0_, t_end_, dt_;
  std::size_t size_ = 0;
};

/// Called after every accepted step with the new state.
using StepObserver = std::function<void(const State&)>;

/// Receives the samples at the output times, in order, instead of
/// IntegrationResult::samples (which then stays empty): long runs need not hold them.
using SampleObserver = std::function<void(const State&)>;

/// Integrates from `initial` to `t_end` (> initial.t). `output_times` must be
/// ascending and within [initial.t, t_end]. Events are located to ~1e-13 of the step
/// (toms748 on the continuous extension, then within +-1e-6 of the step around that
/// root on the stepper's partial steps, so the event time and state have the steps'
/// accuracy; `exact` on rigid segments: on the closed form); at most one sign change
/// per step and function is
/// seen, so steps must be short against the event spacing (the adaptive and exact
/// methods ensure that on their own).
IntegrationResult Integrate(const Stepper& stepper,
                            const IntegratorSettings& settings,
                            const dynamics::InertiaSource& source,
                            const State& initial,
                            double t_end,
                            const std::vector<double>& output_times = {},
                            const std::vector<EventFunction>& events = {},
                            const StepObserver& observer = {},
                            const SampleObserver& samples = {});

/// The same with output times computed on demand (samples usually to `samples`: then
/// nothing grows with the number of output times).
IntegrationResult Integrate(const Stepper& stepper,
                            const IntegratorSettings& settings,
                            const dynamics::InertiaSource& source,
                            const State& initial,
                            double t_end,
                            const OutputTimes& output_times,
                            const std::vector<EventFunction>& events,
                            const StepObserver& observer,
                            const SampleObserver& samples);

/// A uniform output grid t0, t0 + dt, ..., t_end (t_end included).
std::vector<double> UniformGrid(double t0, double t_end, double dt);

}  // namespace deploysim::integrators
