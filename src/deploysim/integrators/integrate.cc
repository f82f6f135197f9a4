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

IntegrationResult Integrate(const Stepper& stepper,
                            const IntegratorSettings& settings,
                            const dynamics::InertiaSource& source,
                            const State& initial,
                            double t_end,
                            const OutputTimes& output_times,
                            const std::vector<EventFunction>& events,
                            const StepObserver& observer,
                            const SampleObserver& samples) {
  const StepperInfo& info = stepper.info();
  ValidateSettings(info, settings);
  Require(Finite(initial), "initial state must be finite");
  const math::Quat q_NB0 = math::ValidateUnitQuaternion(initial.q_NB, "initial attitude q_NB");
  {
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
    Require(std::isfinite(t_end) && t_end > initial.t, "end time must be finite and > start time");
    Require(sorted, "output times must be ascending");
    Require(n == 0 || (output_times.at(0) >= initial.t && output_times.at(n - 1) <= t_end),
            "output times must lie within [t0, t_end]");
  }

  // The initial condition is the given state: H_B bit for bit, q_NB normalized (the
  // steppers carry their attitude relative to it, rkmk.h). h_N only for reporting and
  // the error weights.
  State y = initial;
  y.q_NB = q_NB0;
  Problem problem(source, math::Vec3(y.q_NB * y.H_B));
  const std::unique_ptr<StepperWorkspace> workspace = stepper.NewWorkspace();
  StepperWorkspace& ws = *workspace;
  long event_partial_steps = 0;
  // The exact solution at t in the last accepted step [y0, y1]: a partial step.
  auto exact_at = [&](const State& y0, const State& y1, double t) {
    if (t <= y0.t) return y0;
    if (t >= y1.t) return y1;
    ++event_partial_steps;
    return stepper.Step(problem, y0, t - y0.t, settings.tolerances, ws).result;
  };
  auto dense_at = [&](const State& y0, const State& y1, double t) {
    if (t <= y0.t) return y0;
    if (t >= y1.t) return y1;
    return stepper.Dense(problem, t, settings.tolerances, ws);
  };

  IntegrationResult result;
  if (!samples) result.samples.reserve(output_times.size());
  auto emit = [&](const State& s) {
    if (samples) {
      samples(s);
    } else {
      result.samples.push_back(s);
    }
  };
  std::size_t next_out = 0;
  while (next_out < output_times.size() && output_times.at(next_out) <= y.t) {
    emit(y);
    ++next_out;
  }
  std::vector<double> g_prev(events.size());
  for (std::size_t e = 0; e < events.size(); ++e) g_prev[e] = events[e].g(y);

  std::vector<double> bounds{y.t};
  for (double b : source.Breakpoints(y.t, t_end)) bounds.push_back(b);
  bounds.push_back(t_end);

  const Tolerances& tol = settings.tolerances;
  const int q = info.error_order > 0 ? std::min(info.order, info.error_order) : info.order;
  double h_adapt = settings.step;
  long attempts = 0;

  for (std::size_t seg = 0; seg + 1 < bounds.size(); ++seg) {
    const double a = bounds[seg];
    const double b = bounds[seg + 1];
    problem.SetSegment(a, b);
    driver::SegmentSteps steps(a, b, info.adaptive, settings.step);
    const double eps = steps.eps();
    if (info.adaptive && h_adapt <= 0.0) {
      // Automatic first step: a small fraction of the rotation time scale.
      const math::Vec3 w = problem.Sample(a).J_inv_B * (y.H_B - problem.Sample(a).h_rel_B);
      const double rate = std::max(w.norm(), 1.0 / (b - a));
      h_adapt = 0.01 * std::pow(tol.rtol, 1.0 / (q + 1)) / rate;
    }
    while (y.t < b - eps) {
      if (++attempts > settings.max_steps) {
        result.termination = Termination::kMaxSteps;
        result.message = "max_steps reached at t = " + std::to_string(y.t);
        result.final_state = y;
        result.stats.evaluations = problem.evaluations();
        result.stats.dense_steps = ws.dense_steps + event_partial_steps;
        return result;
      }
      bool last = false;
      const double h = steps.Next(
          y.t,
          info.adaptive ? std::min({h_adapt, settings.max_step, stepper.MaxStep(problem, y, ws)})
                        : 0.0,
          &last);
      StepAttempt att = stepper.Step(problem, y, h, tol, ws);
      if (info.adaptive) {
        const double err = att.error_norm;
        if (!std::isfinite(err) || err > 1.0) {
          ++result.stats.rejected;
          h_adapt = h * driver::RejectedStepFactor(err, q);
          if (h_adapt < 1e-14 * std::max(1.0, std::abs(y.t))) {
            result.termination = Termination::kStepSizeUnderflow;
            result.message = "step size underflow at t = " + std::to_string(y.t);
            result.final_state = y;
            result.stats.evaluations = problem.evaluations();
            result.stats.dense_steps = ws.dense_steps + event_partial_steps;
            return result;
          }
          continue;
        }
        const double grow = driver::AcceptedStepFactor(err, q);
        // Do not let the short last step of a segment shrink the next segment's steps.
        if (!last || grow * h > h_adapt) h_adapt = h * grow;
      }
      State y1 = att.result;
      if (last) y1.t = b;
      if (!Finite(y1)) {
        result.termination = Termination::kNonFinite;
        result.message = "state became non-finite at t = " + std::to_string(y.t);
        result.final_state = y;
        result.stats.evaluations = problem.evaluations();
        result.stats.dense_steps = ws.dense_steps + event_partial_steps;
        return result;
      }
      ++result.stats.steps;
      stepper.Accept(problem, y, y1, ws);

      // Events: sign changes of g over the step, located on the dense output.
      if (!events.empty()) {
        std::vector<Event> found;
        for (std::size_t e = 0; e < events.size(); ++e) {
          const double g1 = events[e].g(y1);
          const double g0 = g_prev[e];
          if ((g0 < 0.0 && g1 >= 0.0) || (g0 > 0.0 && g1 <= 0.0)) {
            const EventFunction& fn = events[e];
            double t_ev = y1.t;
            if (g1 != 0.0) {
              const State& y0 = y;
              t_ev = driver::LocateEvent(
                  y0.t, y1.t, g0, g1, [&](double t) { return fn.g(dense_at(y0, y1, t)); },
                  [&](double t) { return fn.g(exact_at(y0, y1, t)); }, stepper.DenseIsExact(ws));
            }
            Event ev;
            ev.t = t_ev;
            ev.index = static_cast<int>(e);
            ev.direction = g1 > g0 ? 1 : -1;
            ev.state = stepper.DenseIsExact(ws) ? dense_at(y, y1, t_ev) : exact_at(y, y1, t_ev);
            found.push_back(ev);
          }
          g_prev[e] = g1;
        }
        std::sort(found.begin(), found.end(),
                  [](const Event& l, const Event& r) { return l.t < r.t; });
        result.events.insert(result.events.end(), found.begin(), found.end());
      }

      std::size_t step_out = next_out;
      while (step_out < output_times.size() && output_times.at(step_out) <= y1.t) ++step_out;
      const std::size_t samples_in_step = step_out - next_out;
      while (next_out < step_out) {
        const double t_out = output_times.at(next_out);
        State s = t_out <= y.t    ? y
                  : t_out >= y1.t ? y1
                                  : stepper.DenseSample(problem, t_out, samples_in_step, tol, ws);
        s.t = t_out;
        emit(s);
        ++next_out;
      }
      y = y1;
      if (observer) observer(y);
    }
  }
  // Output times that equal t_end up to rounding.
  while (next_out < output_times.size()) {
    State s = y;
    s.t = output_times.at(next_out);
    emit(s);
    ++next_out;
  }
  result.final_state = y;
  result.stats.evaluations = problem.evaluations();
  result.stats.dense_steps = ws.dense_steps + event_partial_steps;
  result.termination = Termination::kReachedEnd;
  result.message = ToString(result.termination);
  return result;
}

}  // namespace deploysim::integrators
