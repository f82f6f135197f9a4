#include "deploysim/integrators/integrate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "deploysim/integrators/driver.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::integrators {

namespace {

using driver::kTimeEps;

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

void ValidateSettings(const StepperInfo& info, const IntegratorSettings& s) {
  std::ostringstream os;
  os.precision(17);
  if (!info.adaptive) {
    os << "integrator " << info.name << ": step = " << s.step
       << " (rule: a fixed-step method needs a finite step > 0)";
    Require(std::isfinite(s.step) && s.step > 0.0, os.str());
  } else {
    os << "integrator " << info.name << ": step = " << s.step
       << " (rule: the initial step is 0 (automatic) or finite > 0)";
    Require(std::isfinite(s.step) && s.step >= 0.0, os.str());
    std::ostringstream r;
    r.precision(17);
    r << "integrator " << info.name << ": rtol = " << s.tolerances.rtol
      << " (rule: 1e-16 <= rtol < 1)";
    Require(
        std::isfinite(s.tolerances.rtol) && s.tolerances.rtol >= 1e-16 && s.tolerances.rtol < 1.0,
        r.str());
    std::ostringstream a;
    a.precision(17);
    a << "integrator " << info.name << ": atol = " << s.tolerances.atol
      << " (rule: atol > 0 and finite; relative to |H_B(0)| for momenta, in rad for angles)";
    Require(std::isfinite(s.tolerances.atol) && s.tolerances.atol > 0.0, a.str());
  }
  std::ostringstream m;
  m.precision(17);
  m << "integrator " << info.name << ": max_step = " << s.max_step << " (rule: max_step > 0)";
  Require(s.max_step > 0.0 && !std::isnan(s.max_step), m.str());
  Require(s.max_steps > 0, "integrator " + info.name + ": max_steps must be > 0");
}

bool Finite(const State& s) {
  return std::isfinite(s.t) && s.H_B.allFinite() && s.q_NB.coeffs().allFinite();
}

}  // namespace

std::string ToString(Termination t) {
  switch (t) {
    case Termination::kReachedEnd:
      return "reached the end time";
    case Termination::kMaxSteps:
      return "stopped: max_steps reached";
    case Termination::kStepSizeUnderflow:
      return "stopped: step size underflow";
    case Termination::kNonFinite:
      return "stopped: the state became non-finite";
  }
  return "unknown";
}

UniformGridTimes::UniformGridTimes(double t0, double t_end, double dt)
    : t0_(t0), t_end_(t_end), dt_(dt) {
  Require(dt > 0.0 && std::isfinite(dt), "output step must be finite and > 0");
  Require(t_end >= t0, "output grid: t_end must be >= t0");
  const double span = t_end - t0;
  const auto n = static_cast<std::int64_t>(std::floor(span / dt * (1.0 + 1e-12)));
  // t0 + i dt for i <= n; then t_end appended, or in place of the last one if that is
  // t_end up to rounding.
  const double last = t0 + static_cast<double>(n) * dt;
  size_ = static_cast<std::size_t>(n) +
          (t_end - last > kTimeEps * std::max(1.0, std::abs(t_end)) ? 2 : 1);
}

std::vector<double> UniformGrid(double t0, double t_end, double dt) {
  const UniformGridTimes times(t0, t_end, dt);
  std::vector<double> grid;
  grid.reserve(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) grid.push_back(times.at(i));
  return grid;
}

namespace {

class VectorTimes final : public OutputTimes {
 public:
  explicit VectorTimes(const std::vector<double>& v) : v_(v) {}
  std::size_t size() const override { return v_.size(); }
  double at(std::size_t i) const override { return v_[i]; }

 private:
  const std::vector<double>& v_;
};

}  // namespace

IntegrationResult Integrate(const Stepper& stepper,
                            const IntegratorSettings& settings,
                            const dynamics::InertiaSource& source,
                            const State& initial,
                            double t_end,
                            const std::vector<double>& output_times,
                            const std::vector<EventFunction>& events,
                            const StepObserver& observer,
                            const SampleObserver& samples) {
  return Integrate(stepper, settings, source, initial, t_end, VectorTimes(output_times), events,
                   observer, samples);
}

namespace {

void ValidateOutputTimes(const OutputTimes& output_times, double t0, double t_end) {
  const std::size_t n = output_times.size();
  bool finite = true, sorted = true;
  double previous = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = output_times.at(i);
    finite = finite && std::isfinite(t);
    sorted = sorted && !(t < previous);
    previous = t;
  }
  Require(finite, "output times must be finite");
  Require(std::isfinite(t_end) && t_end > t0, "end time must be finite and > start time");
  Require(sorted, "output times must be ascending");
  Require(n == 0 || (output_times.at(0) >= t0 && output_times.at(n - 1) <= t_end),
          "output times must lie within [t0, t_end]");
}

/// A Stepper on the rigid state (t, H_B, q_NB) for the driver (driver.h): the problem
/// (inertia source, segment, evaluation count), the stepper's workspace for the run and
/// the accepted step, whose continuous extension is clamped to its ends.
class RigidAdapter {
 public:
  using StateType = State;

  RigidAdapter(const Stepper& stepper,
               const Tolerances& tolerances,
               const dynamics::InertiaSource& source,
               const State& initial)
      : stepper_(stepper),
        info_(stepper.info()),
        tol_(tolerances),
        source_(source),
        problem_(source, math::Vec3(initial.q_NB * initial.H_B)),
        workspace_(stepper.NewWorkspace()),
        ws_(*workspace_) {}

  bool adaptive() const { return info_.adaptive; }
  int order() const {
    return info_.error_order > 0 ? std::min(info_.order, info_.error_order) : info_.order;
  }
  void SetSegment(double a, double b) { problem_.SetSegment(a, b); }
  std::vector<double> Breakpoints(double t0, double t1) const {
    return source_.Breakpoints(t0, t1);
  }
  double RotationRate(const State& y) {
    const dynamics::InertiaSample s = problem_.Sample(y.t);
    return (s.J_inv_B * (y.H_B - s.h_rel_B)).norm();
  }
  double MaxStep(const State& y) { return stepper_.MaxStep(problem_, y, ws_); }
  State Step(const State& y, double h, double* error_norm) {
    StepAttempt attempt = stepper_.Step(problem_, y, h, tol_, ws_);
    *error_norm = attempt.error_norm;
    return attempt.result;
  }
  State Partial(const State& y0, double h) {
    ++partial_steps_;
    return stepper_.Step(problem_, y0, h, tol_, ws_).result;
  }
  void Project(State& /*y*/) {}  // the rigid state has no invariant to restore
  void Accept(const State& y0, const State& y1) {
    stepper_.Accept(problem_, y0, y1, ws_);
    y0_ = y0;
    y1_ = y1;
  }
  State Dense(double t) {
    if (t <= y0_.t) return y0_;
    if (t >= y1_.t) return y1_;
    return stepper_.Dense(problem_, t, tol_, ws_);
  }
  State DenseSample(double t, std::size_t samples_in_step) {
    return stepper_.DenseSample(problem_, t, samples_in_step, tol_, ws_);
  }
  bool DenseIsExact() { return stepper_.DenseIsExact(ws_); }
  static bool Finite(const State& s) { return integrators::Finite(s); }
  long evaluations() const { return problem_.evaluations(); }
  long dense_steps() const { return ws_.dense_steps + partial_steps_; }

 private:
  const Stepper& stepper_;
  const StepperInfo& info_;
  const Tolerances& tol_;
  const dynamics::InertiaSource& source_;
  Problem problem_;
  const std::unique_ptr<StepperWorkspace> workspace_;
  StepperWorkspace& ws_;
  State y0_, y1_;  // the accepted step
  long partial_steps_ = 0;
};

}  // namespace

IntegrationResult Integrate(const Stepper& stepper,
                            const IntegratorSettings& settings,
                            const dynamics::InertiaSource& source,
                            const State& initial,
                            double t_end,
                            const OutputTimes& output_times,
                            const std::vector<EventFunction>& events,
                            const StepObserver& observer,
                            const SampleObserver& samples) {
  ValidateSettings(stepper.info(), settings);
  Require(Finite(initial), "initial state must be finite");
  const math::Quat q_NB0 = math::ValidateUnitQuaternion(initial.q_NB, "initial attitude q_NB");
  ValidateOutputTimes(output_times, initial.t, t_end);
  // The initial condition is the given state: H_B bit for bit, q_NB normalized (the
  // steppers carry their attitude relative to it, rkmk.h). h_N only for reporting and
  // the error weights.
  State y = initial;
  y.q_NB = q_NB0;
  std::vector<driver::EventSpec<State>> specs;
  for (const EventFunction& e : events) specs.push_back({e.name, e.g, 0, false, true, e.rate});
  IntegrationResult result;
  if (!samples) result.samples.reserve(output_times.size());
  const std::function<void(const State&)> emit =
      samples ? samples : [&result](const State& s) { result.samples.push_back(s); };
  RigidAdapter adapter(stepper, settings.tolerances, source, y);
  std::size_t next_output = 0;
  driver::Driver<RigidAdapter> run(adapter, settings, y, output_times, next_output, specs, emit,
                                   observer, true);
  driver::Outcome<State> out = run.Run(t_end);
  for (driver::FoundEvent<State>& e : out.events) {
    result.events.push_back({e.t, e.index, e.direction, std::move(e.state)});
  }
  result.final_state = out.final_state;
  result.stats = out.stats;
  result.termination = out.termination;
  result.message = std::move(out.message);
  return result;
}

}  // namespace deploysim::integrators
