#include "deploysim/integrators/integrate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "deploysim/integrators/driver_support.h"
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
      << " (rule: atol > 0 and finite; it is relative to |H_B(0)|)";
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

/// One adaptive (or fixed-step) run of the rigid-body equations: the segments between
/// the source's breakpoints, the step-size control, the events located on each accepted
/// step and the output samples on the dense output.
class RigidDriver {
 public:
  RigidDriver(const Stepper& stepper,
              const IntegratorSettings& settings,
              const dynamics::InertiaSource& source,
              const State& initial,
              const OutputTimes& output_times,
              const std::vector<EventFunction>& events,
              const StepObserver& observer,
              const SampleObserver& samples)
      : stepper_(stepper),
        info_(stepper.info()),
        settings_(settings),
        source_(source),
        y_(initial),
        problem_(source, math::Vec3(initial.q_NB * initial.H_B)),
        workspace_(stepper.NewWorkspace()),
        ws_(*workspace_),
        output_times_(output_times),
        events_(events),
        observer_(observer),
        samples_(samples),
        q_(info_.error_order > 0 ? std::min(info_.order, info_.error_order) : info_.order),
        h_adapt_(settings.step) {}

  IntegrationResult Run(double t_end);

 private:
  bool Segment(double a, double b);
  double FirstStep(double a, double b);
  IntegrationResult& Stop(Termination t, const std::string& message);
  void Emit(const State& s);
  void LocateEvents(const State& y1);
  void EmitSamples(const State& y1);
  // The exact solution at t in the last accepted step [y0, y1]: a partial step.
  State ExactAt(const State& y0, const State& y1, double t) {
    if (t <= y0.t) return y0;
    if (t >= y1.t) return y1;
    ++event_partial_steps_;
    return stepper_.Step(problem_, y0, t - y0.t, settings_.tolerances, ws_).result;
  }
  State DenseAt(const State& y0, const State& y1, double t) {
    if (t <= y0.t) return y0;
    if (t >= y1.t) return y1;
    return stepper_.Dense(problem_, t, settings_.tolerances, ws_);
  }

  const Stepper& stepper_;
  const StepperInfo& info_;
  const IntegratorSettings& settings_;
  const dynamics::InertiaSource& source_;
  State y_;
  Problem problem_;
  const std::unique_ptr<StepperWorkspace> workspace_;
  StepperWorkspace& ws_;
  const OutputTimes& output_times_;
  const std::vector<EventFunction>& events_;
  const StepObserver& observer_;
  const SampleObserver& samples_;
  const int q_;
  double h_adapt_;
  long attempts_ = 0;
  long event_partial_steps_ = 0;
  std::size_t next_out_ = 0;
  std::vector<double> g_prev_;
  IntegrationResult result_;
};

IntegrationResult& RigidDriver::Stop(Termination t, const std::string& message) {
  result_.termination = t;
  result_.message = message;
  result_.final_state = y_;
  result_.stats.evaluations = problem_.evaluations();
  result_.stats.dense_steps = ws_.dense_steps + event_partial_steps_;
  return result_;
}

void RigidDriver::Emit(const State& s) {
  if (samples_) {
    samples_(s);
  } else {
    result_.samples.push_back(s);
  }
}

// Automatic first step: a small fraction of the rotation time scale.
double RigidDriver::FirstStep(double a, double b) {
  const math::Vec3 w = problem_.Sample(a).J_inv_B * (y_.H_B - problem_.Sample(a).h_rel_B);
  const double rate = std::max(w.norm(), 1.0 / (b - a));
  return 0.01 * std::pow(settings_.tolerances.rtol, 1.0 / (q_ + 1)) / rate;
}

// Events: sign changes of g over the step [y_, y1], located on the dense output.
void RigidDriver::LocateEvents(const State& y1) {
  if (events_.empty()) return;
  std::vector<Event> found;
  const bool exact_dense = stepper_.DenseIsExact(ws_);
  for (std::size_t e = 0; e < events_.size(); ++e) {
    const double g1 = events_[e].g(y1);
    const double g0 = g_prev_[e];
    if ((g0 < 0.0 && g1 >= 0.0) || (g0 > 0.0 && g1 <= 0.0)) {
      const EventFunction& fn = events_[e];
      const State& y0 = y_;
      double t_ev = y1.t;
      if (g1 != 0.0) {
        t_ev = driver::LocateEvent(
            y0.t, y1.t, g0, g1, [&](double t) { return fn.g(DenseAt(y0, y1, t)); },
            [&](double t) { return fn.g(ExactAt(y0, y1, t)); }, exact_dense);
      }
      Event ev;
      ev.t = t_ev;
      ev.index = static_cast<int>(e);
      ev.direction = g1 > g0 ? 1 : -1;
      ev.state = exact_dense ? DenseAt(y0, y1, t_ev) : ExactAt(y0, y1, t_ev);
      found.push_back(ev);
    }
    g_prev_[e] = g1;
  }
  std::sort(found.begin(), found.end(), [](const Event& l, const Event& r) { return l.t < r.t; });
  result_.events.insert(result_.events.end(), found.begin(), found.end());
}

// The output times in (y_.t, y1.t], on the dense output of the step.
void RigidDriver::EmitSamples(const State& y1) {
  std::size_t step_out = next_out_;
  while (step_out < output_times_.size() && output_times_.at(step_out) <= y1.t) ++step_out;
  const std::size_t samples_in_step = step_out - next_out_;
  while (next_out_ < step_out) {
    const double t_out = output_times_.at(next_out_);
    State s = t_out <= y_.t   ? y_
              : t_out >= y1.t ? y1
                              : stepper_.DenseSample(problem_, t_out, samples_in_step,
                                                     settings_.tolerances, ws_);
    s.t = t_out;
    Emit(s);
    ++next_out_;
  }
}

// The steps of one segment [a, b] between breakpoints; false when the run stopped.
bool RigidDriver::Segment(double a, double b) {
  problem_.SetSegment(a, b);
  driver::SegmentSteps steps(a, b, info_.adaptive, settings_.step);
  const double eps = steps.eps();
  if (info_.adaptive && h_adapt_ <= 0.0) h_adapt_ = FirstStep(a, b);
  while (y_.t < b - eps) {
    if (++attempts_ > settings_.max_steps) {
      Stop(Termination::kMaxSteps, "max_steps reached at t = " + std::to_string(y_.t));
      return false;
    }
    bool last = false;
    const double h = steps.Next(y_.t,
                                info_.adaptive ? std::min({h_adapt_, settings_.max_step,
                                                           stepper_.MaxStep(problem_, y_, ws_)})
                                               : 0.0,
                                &last);
    StepAttempt att = stepper_.Step(problem_, y_, h, settings_.tolerances, ws_);
    if (info_.adaptive) {
      const double err = att.error_norm;
      if (!std::isfinite(err) || err > 1.0) {
        ++result_.stats.rejected;
        h_adapt_ = h * driver::RejectedStepFactor(err, q_);
        if (h_adapt_ < 1e-14 * std::max(1.0, std::abs(y_.t))) {
          Stop(Termination::kStepSizeUnderflow,
               "step size underflow at t = " + std::to_string(y_.t));
          return false;
        }
        continue;
      }
      const double grow = driver::AcceptedStepFactor(err, q_);
      // Do not let the short last step of a segment shrink the next segment's steps.
      if (!last || grow * h > h_adapt_) h_adapt_ = h * grow;
    }
    State y1 = att.result;
    if (last) y1.t = b;
    if (!Finite(y1)) {
      Stop(Termination::kNonFinite, "state became non-finite at t = " + std::to_string(y_.t));
      return false;
    }
    ++result_.stats.steps;
    stepper_.Accept(problem_, y_, y1, ws_);
    LocateEvents(y1);
    EmitSamples(y1);
    y_ = y1;
    if (observer_) observer_(y_);
  }
  return true;
}

IntegrationResult RigidDriver::Run(double t_end) {
  if (!samples_) result_.samples.reserve(output_times_.size());
  while (next_out_ < output_times_.size() && output_times_.at(next_out_) <= y_.t) {
    Emit(y_);
    ++next_out_;
  }
  for (const EventFunction& e : events_) g_prev_.push_back(e.g(y_));
  std::vector<double> bounds{y_.t};
  for (double b : source_.Breakpoints(y_.t, t_end)) bounds.push_back(b);
  bounds.push_back(t_end);
  for (std::size_t seg = 0; seg + 1 < bounds.size(); ++seg) {
    if (!Segment(bounds[seg], bounds[seg + 1])) return std::move(result_);
  }
  // Output times that equal t_end up to rounding.
  while (next_out_ < output_times_.size()) {
    State s = y_;
    s.t = output_times_.at(next_out_);
    Emit(s);
    ++next_out_;
  }
  Stop(Termination::kReachedEnd, ToString(Termination::kReachedEnd));
  return std::move(result_);
}

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
  RigidDriver driver(stepper, settings, source, y, output_times, events, observer, samples);
  return driver.Run(t_end);
}

}  // namespace deploysim::integrators
