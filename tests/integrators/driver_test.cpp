// integrators::driver::Driver, the one integration driver, on its own: a scalar ODE
// y' = cos t (y = sin t) with a second-order Heun step and its embedded Euler error, so
// that every answer is known in closed form. Segments and breakpoints, the step-size
// rule, output samples, events (directions, terminal, zeros a run starts on) and the
// ways a run stops. Bounds: a few times the measured error (samples 1.3e-10, event times
// 1.4e-11 s at rtol = atol = 1e-10).

#include "deploysim/integrators/driver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <vector>

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

struct Scalar {
  double t = 0.0;
  double y = 0.0;
};

/// Heun's method (order 2) with the Euler step as its error estimate (order 1), cubic
/// Hermite dense output.
class ScalarAdapter {
 public:
  using StateType = Scalar;

  ScalarAdapter(std::function<double(double, double)> f,
                std::vector<double> breakpoints,
                const Tolerances& tol,
                bool adaptive)
      : f_(std::move(f)), breakpoints_(std::move(breakpoints)), tol_(tol), adaptive_(adaptive) {}

  bool adaptive() const { return adaptive_; }
  int order() const { return adaptive_ ? 1 : 2; }
  void SetSegment(double a, double b) { segments.push_back({a, b}); }
  std::vector<double> Breakpoints(double t0, double t1) const {
    std::vector<double> inside;
    for (double b : breakpoints_) {
      if (b > t0 && b < t1) inside.push_back(b);
    }
    return inside;
  }
  double RotationRate(const Scalar& /*y*/) { return 1.0; }
  double MaxStep(const Scalar& /*y*/) { return std::numeric_limits<double>::infinity(); }
  Scalar Step(const Scalar& y, double h, double* error_norm) {
    const double k1 = F(y.t, y.y);
    const double k2 = F(y.t + h, y.y + h * k1);
    const Scalar out{y.t + h, y.y + 0.5 * h * (k1 + k2)};
    if (error_norm != nullptr) {
      *error_norm = std::abs(0.5 * h * (k2 - k1)) / (tol_.atol + tol_.rtol * std::abs(out.y));
    }
    return out;
  }
  Scalar Partial(const Scalar& y0, double h) {
    ++partial_steps;
    return Step(y0, h, nullptr);
  }
  void Project(Scalar& /*y*/) {}
  void Accept(const Scalar& y0, const Scalar& y1) {
    y0_ = y0;
    y1_ = y1;
    f0_ = F(y0.t, y0.y);
    f1_ = F(y1.t, y1.y);
    step_ends.push_back(y1.t);
  }
  Scalar Dense(double t) {
    if (t <= y0_.t) return y0_;
    if (t >= y1_.t) return y1_;
    const double h = y1_.t - y0_.t;
    const double s = (t - y0_.t) / h;
    const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
    const double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
    return {t, h00 * y0_.y + h10 * h * f0_ + h01 * y1_.y + h11 * h * f1_};
  }
  Scalar DenseSample(double t, std::size_t /*samples*/) { return Dense(t); }
  bool DenseIsExact() { return false; }
  static bool Finite(const Scalar& s) { return std::isfinite(s.t) && std::isfinite(s.y); }
  long evaluations() const { return evaluations_; }
  long dense_steps() const { return partial_steps; }

  std::vector<std::pair<double, double>> segments;
  std::vector<double> step_ends;
  long partial_steps = 0;

 private:
  double F(double t, double y) {
    ++evaluations_;
    return f_(t, y);
  }
  std::function<double(double, double)> f_;
  std::vector<double> breakpoints_;
  Tolerances tol_;
  bool adaptive_;
  Scalar y0_, y1_;
  double f0_ = 0.0, f1_ = 0.0;
  long evaluations_ = 0;
};

using Spec = driver::EventSpec<Scalar>;

/// One run of y' = cos t from y(0) = 0 to t_end with the given events.
struct ScalarRun {
  explicit ScalarRun(
      std::vector<Spec> specs = {},
      std::vector<double> breakpoints = {},
      std::function<double(double, double)> f = [](double t, double) { return std::cos(t); },
      Tolerances tolerances = {1e-10, 1e-10})
      : tol(tolerances),
        events(std::move(specs)),
        adapter(std::move(f), std::move(breakpoints), tol, true) {
    settings.tolerances = tol;
  }
  driver::Outcome<Scalar> Go(double t_end, const std::vector<double>& grid = {}) {
    times = grid;
    const VectorTimesForTest output(times);
    driver::Driver<ScalarAdapter> d(
        adapter, settings, Scalar{0.0, 0.0}, output, next, events,
        [this](const Scalar& s) { samples.push_back(s); }, {}, true);
    return d.Run(t_end);
  }
  struct VectorTimesForTest final : OutputTimes {
    explicit VectorTimesForTest(const std::vector<double>& v) : v_(v) {}
    std::size_t size() const override { return v_.size(); }
    double at(std::size_t i) const override { return v_[i]; }
    const std::vector<double>& v_;
  };
  Tolerances tol;
  IntegratorSettings settings;
  std::vector<Spec> events;
  ScalarAdapter adapter;
  std::vector<double> times;
  std::size_t next = 0;
  std::vector<Scalar> samples;
};

Spec Sine(int direction = 0, bool terminal = false) {
  return {"y", [](const Scalar& s) { return s.y; }, direction, terminal, true};
}

TEST(Driver, ReachesTheEndWithSamplesOnTheGridAndStepsOnTheBreakpoints) {
  ScalarRun run({}, {1.0, 2.5});
  const std::vector<double> grid = UniformGrid(0.0, 4.0, 0.25);
  const driver::Outcome<Scalar> out = run.Go(4.0, grid);
  EXPECT_EQ(out.termination, Termination::kReachedEnd);
  EXPECT_EQ(out.final_state.t, 4.0);
  EXPECT_NEAR(out.final_state.y, std::sin(4.0), 5e-10);
  ASSERT_EQ(run.samples.size(), grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    EXPECT_EQ(run.samples[i].t, grid[i]);
    EXPECT_NEAR(run.samples[i].y, std::sin(grid[i]), 5e-10) << grid[i];
  }
  ASSERT_EQ(run.adapter.segments.size(), 3u);
  EXPECT_EQ(run.adapter.segments[1], std::make_pair(1.0, 2.5));
  // Steps land on the breakpoints exactly.
  const auto& ends = run.adapter.step_ends;
  EXPECT_NE(std::find(ends.begin(), ends.end(), 1.0), ends.end());
  EXPECT_NE(std::find(ends.begin(), ends.end(), 2.5), ends.end());
  EXPECT_EQ(out.stats.steps, static_cast<long>(ends.size()));
  EXPECT_GT(out.next_step, 0.0);
}

TEST(Driver, LocatesEverySignChangeWithItsDirection) {
  ScalarRun run({Sine()});
  const driver::Outcome<Scalar> out = run.Go(7.0);
  // y = sin t: 0 at the start (no event: no sign change from 0), pi falling, 2 pi rising.
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_NEAR(out.events[0].t, M_PI, 5e-11);
  EXPECT_EQ(out.events[0].direction, -1);
  EXPECT_NEAR(out.events[1].t, 2 * M_PI, 5e-11);
  EXPECT_EQ(out.events[1].direction, 1);
  EXPECT_EQ(out.events[1].state.t, out.events[1].t);
  EXPECT_GT(run.adapter.partial_steps, 0);  // finished on partial steps
  EXPECT_EQ(out.stats.dense_steps, run.adapter.partial_steps);
}

TEST(Driver, ADirectionalEventSeesOnlyItsDirection) {
  ScalarRun run({Sine(+1)});
  const driver::Outcome<Scalar> out = run.Go(7.0);
  ASSERT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].direction, 1);
  EXPECT_NEAR(out.events[0].t, 2 * M_PI, 5e-11);
}

TEST(Driver, ATerminalEventStopsTheRunAtItsTime) {
  ScalarRun run({Sine(), Sine(-1, true)});
  const std::vector<double> grid = UniformGrid(0.0, 7.0, 0.5);
  const driver::Outcome<Scalar> out = run.Go(7.0, grid);
  EXPECT_TRUE(out.stopped_at_event);
  ASSERT_FALSE(out.events.empty());
  const driver::FoundEvent<Scalar>& last = out.events.back();
  EXPECT_EQ(last.index, 1);
  EXPECT_NEAR(last.t, M_PI, 5e-11);
  EXPECT_EQ(out.final_state.t, last.t);
  // Samples strictly before the stop; the one at or after it is the caller's.
  ASSERT_FALSE(run.samples.empty());
  EXPECT_LT(run.samples.back().t, last.t);
  EXPECT_EQ(run.next, run.samples.size());
  EXPECT_NE(out.message.find("stopped at event 'y'"), std::string::npos);
}

TEST(Driver, ATerminalZeroAtTheStartMustBeLeftFirst) {
  // g = -y: 0 at the start, falling-terminal: it must first be left towards g > 0, but
  // y = sin t > 0 makes g < 0 at once: the run is stuck at the start.
  Spec stuck{"minus y", [](const Scalar& s) { return -s.y; }, -1, true, true};
  ScalarRun run({stuck});
  const driver::Outcome<Scalar> out = run.Go(1.0);
  EXPECT_TRUE(out.stuck);
  EXPECT_TRUE(out.stopped_at_event);
  EXPECT_EQ(out.final_state.t, 0.0);
  EXPECT_GT(out.stats.rejected, 0);  // retried shorter, down to kMinLeaveStep
  // Rising-terminal g = -y leaves 0 towards g < 0 (the side opposite its direction) at
  // once: it counts again from then on, and its next rising zero (pi) stops the run.
  Spec leaving{"minus y", [](const Scalar& s) { return -s.y; }, +1, true, true};
  ScalarRun leaves({leaving});
  const driver::Outcome<Scalar> left = leaves.Go(7.0);
  EXPECT_FALSE(left.stuck);
  EXPECT_TRUE(left.stopped_at_event);
  EXPECT_NEAR(left.final_state.t, M_PI, 5e-11);
}

// y' = 1 - t (y = t - t^2 / 2, which Heun's steps and the cubic Hermite give exactly)
// and g = y - (1/2 - d), which just reaches zero near the peak at t = 1: both zeros,
// 1 -+ sqrt(2 d), 2.8e-3 s apart, fall inside one step of about 0.04 s. Without a rate
// the step's ends show no sign change and the pair is missed; with it the step is
// searched on the dense output and both zeros are found (and only the rising one when
// the direction asks for it).
TEST(Driver, FindsAZeroPairInsideOneStepFromTheRate) {
  const double d = 1e-6;
  auto g = [d](const Scalar& s) { return s.y - (0.5 - d); };
  auto rate = [](const Scalar& s) { return 1.0 - s.t; };
  const double t_in = 1.0 - std::sqrt(2.0 * d), t_out = 1.0 + std::sqrt(2.0 * d);
  auto run = [&](Spec spec) {
    ScalarRun r({spec}, {}, [](double t, double) { return 1.0 - t; }, {1e-3, 1e-3});
    driver::Outcome<Scalar> out = r.Go(3.0);
    double longest = 0.0;  // the step across the peak
    for (std::size_t i = 1; i < r.adapter.step_ends.size(); ++i) {
      if (r.adapter.step_ends[i - 1] < t_in && r.adapter.step_ends[i] > t_out) {
        longest = r.adapter.step_ends[i] - r.adapter.step_ends[i - 1];
      }
    }
    return std::make_pair(out, longest);
  };
  const auto [blind, step] = run(Spec{"graze", g, 0, false, true});
  EXPECT_GT(step, 2.0 * (t_out - t_in));  // the pair is inside one step
  EXPECT_TRUE(blind.events.empty());
  const auto [seen, step2] = run(Spec{"graze", g, 0, false, true, rate});
  ASSERT_EQ(seen.events.size(), 2u);
  EXPECT_EQ(seen.events[0].direction, 1);
  EXPECT_EQ(seen.events[1].direction, -1);
  EXPECT_NEAR(seen.events[0].t, t_in, 1e-12);  // measured 9e-14
  EXPECT_NEAR(seen.events[1].t, t_out, 1e-12);
  std::printf("zero pair found at %.3g and %.3g s from the closed form\n", seen.events[0].t - t_in,
              seen.events[1].t - t_out);
  const auto [rising, step3] = run(Spec{"graze", g, +1, true, true, rate});
  ASSERT_EQ(rising.events.size(), 1u);
  EXPECT_TRUE(rising.stopped_at_event);
  EXPECT_EQ(rising.events[0].t, seen.events[0].t);
}

TEST(Driver, ATerminalFunctionAlreadyPastItsZeroStopsAtTheStart) {
  Spec past{"past", [](const Scalar&) { return 1.0; }, +1, true, true};
  ScalarRun run({past});
  const driver::Outcome<Scalar> out = run.Go(1.0);
  EXPECT_TRUE(out.stopped_at_event);
  EXPECT_EQ(out.final_state.t, 0.0);
  EXPECT_EQ(out.stats.steps, 0);
}

TEST(Driver, StopsAtMaxStepsAndOnANonFiniteState) {
  ScalarRun few;
  few.settings.max_steps = 3;
  EXPECT_EQ(few.Go(10.0).termination, Termination::kMaxSteps);
  ScalarRun blowup({}, {}, [](double t, double) { return t > 0.5 ? std::nan("") : 1.0; });
  const driver::Outcome<Scalar> out = blowup.Go(1.0);
  // A NaN error norm is a rejection: the step shrinks until it underflows.
  EXPECT_EQ(out.termination, Termination::kStepSizeUnderflow);
  EXPECT_GT(out.final_state.t, 0.49);
  EXPECT_LE(out.final_state.t, 0.5);
}

TEST(Driver, FixedStepsDivideEachSegment) {
  Tolerances tol{1e-6, 1e-6};
  ScalarAdapter adapter([](double t, double) { return std::cos(t); }, {0.3}, tol, false);
  IntegratorSettings settings;
  settings.step = 0.25;
  std::size_t next = 0;
  const UniformGridTimes none(0.0, 1.0, 1.0);
  std::vector<driver::EventSpec<Scalar>> specs;
  driver::Driver<ScalarAdapter> d(
      adapter, settings, Scalar{}, none, next, specs, [](const Scalar&) {}, {}, true);
  const driver::Outcome<Scalar> out = d.Run(1.0);
  EXPECT_EQ(out.termination, Termination::kReachedEnd);
  // [0, 0.3] in 2 steps of 0.15, [0.3, 1] in 3 of 0.7 / 3.
  const std::vector<double> expected = {0.15, 0.3, 0.3 + 0.7 / 3, 0.3 + 1.4 / 3, 1.0};
  ASSERT_EQ(adapter.step_ends.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(adapter.step_ends[i], expected[i], 1e-15);
  }
  EXPECT_EQ(adapter.step_ends[1], 0.3);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
