#include "deploysim/run/run_loop.h"

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/inertia.h"
#include "deploysim/run/hinge_body.h"
#include "deploysim/run/stage_body.h"

namespace deploysim::run {

void RunState::AddStats(const integrators::Statistics& more) {
  stats.steps += more.steps;
  stats.rejected += more.rejected;
  stats.evaluations += more.evaluations;
  stats.dense_steps += more.dense_steps;
}

bool RunState::Stopped(integrators::Termination how, const std::string& why) {
  if (how == integrators::Termination::kReachedEnd) return false;
  termination = how;
  message = why;
  return true;
}

RunSample RunBody::GridSample(double t, const math::Vec3& H_B, const math::Quat& q_NB, double t1) {
  // At a prescribed rate jump (a window's end on an output time) the sample holds the
  // state after it, as every output does; the run's end holds its final state.
  return SampleOf(t, H_B, q_NB, Eigen::VectorXd(),
                  t >= t1 ? dynamics::Side::kLeft : dynamics::Side::kRight);
}

void RunBody::OpenPhase(RunState& st, const RunSample& start) {
  const PhaseInfo info = Describe(start.t);
  st.rec().OpenPhase(info, start);
  st.rec().SetSteadySpin(Steady(start, info));
}

namespace {

// Rates of s . H_B / |H_B| below this fraction of |w| are rounding noise (a pure spin
// has a rate of exactly zero in exact arithmetic): they count as zero, so that noise
// does not look like an extremum.
constexpr double kRateNoise = 1e-12;
// Locating a minimum of s . H_B on a rigid interval: toms748 to this fraction of the step.
constexpr double kRootRelTolerance = 1e-12;
constexpr std::uintmax_t kMaxRootIterations = 100;

/// The output grid merged with `extra` times not on it (ascending, few): the merged,
/// sorted list of the times, unstored.
class GridWithExtras final : public integrators::OutputTimes {
 public:
  GridWithExtras(const integrators::OutputTimes& grid, std::vector<double> extra)
      : grid_(grid), extra_(std::move(extra)) {
    for (std::size_t e = 0; e < extra_.size(); ++e) {
      position_.push_back(CountTimes(grid_, extra_[e], false) + e);
    }
  }
  std::size_t size() const override { return grid_.size() + extra_.size(); }
  double at(std::size_t k) const override {
    const auto it = std::lower_bound(position_.begin(), position_.end(), k);
    const std::size_t e = static_cast<std::size_t>(it - position_.begin());  // extras before k
    if (it != position_.end() && *it == k) return extra_[e];
    return grid_.at(k - e);
  }

 private:
  const integrators::OutputTimes& grid_;
  std::vector<double> extra_;
  std::vector<std::size_t> position_;  // index of extra_[e] in the merged list
};

/// J_B(t) as the events and the step observer see it, cached for the last time asked
/// (the flip function and the spin-axis rate are evaluated at the same states).
class CachedSource {
 public:
  explicit CachedSource(const dynamics::InertiaSource& source) : source_(source) {}
  const dynamics::InertiaSample& At(double t) {
    if (!valid_ || t != t_) {
      sample_ = source_.Evaluate(t);
      t_ = t;
      valid_ = true;
    }
    return sample_;
  }

 private:
  const dynamics::InertiaSource& source_;
  dynamics::InertiaSample sample_{};
  double t_ = 0.0;
  bool valid_ = false;
};

/// One segment of the rigid-body path, [st.t, t_next]: the body's J_B(t) and h_rel_B(t)
/// drive the rigid-body equations. Samples come on the output grid merged with the phase
/// boundaries inside the segment (kept apart: they close one phase and open the next).
/// The spin-axis extrema inside a step are located exactly (closed form, toms748 on the
/// rate) on rigid intervals and on the cubic Hermite interpolant of f elsewhere: the error
/// control keeps the steps short against the nutation.
class RigidSegment {
 public:
  RigidSegment(RunState& st,
               RunBody& body,
               const integrators::Stepper& stepper,
               const std::vector<double>& breakpoints,
               double t1)
      : st_(st),
        body_(body),
        stepper_(stepper),
        source_(body.source()),
        breakpoints_(breakpoints),
        t1_(t1),
        cache_(source_) {}
  SegmentEnd Run(double t_next, const std::vector<double>& boundaries);

 private:
  RunSample WithWork(RunSample o) const {
    o.work = st_.work;
    o.work.drive += o.kinetic - kinetic0_;
    return o;
  }
  void OnSample(const integrators::State& s);
  void OnStep(const integrators::State& y);
  AxisPoint PointOf(const integrators::State& y);
  double Rate(const math::Vec3& H_B, const dynamics::InertiaSample& js) const;
  double RigidMinimum(const integrators::State& a, const integrators::State& b) const;

  RunState& st_;
  RunBody& body_;
  const integrators::Stepper& stepper_;
  const dynamics::InertiaSource& source_;
  const std::vector<double>& breakpoints_;
  const double t1_;
  CachedSource cache_;
  double kinetic0_ = 0.0;  // [J] at the segment's start (right limit)
  std::vector<double> boundaries_, extra_;
  std::size_t next_boundary_ = 0, next_extra_ = 0, delivered_ = 0;
  const integrators::OutputTimes* times_ = nullptr;
  integrators::State last_sample_, prev_step_;
  AxisPoint prev_point_;
};

// A time of the merged list (the integrator delivers them in order): a phase boundary
// closes the open phase (J_B from the left) and opens the next (from the right); a grid
// time is sampled.
void RigidSegment::OnSample(const integrators::State& s) {
  const double t = times_->at(delivered_++);
  last_sample_ = s;
  if (next_boundary_ < boundaries_.size() && boundaries_[next_boundary_] == t) {
    ++next_boundary_;
    const Eigen::VectorXd none;
    st_.rec().ClosePhase(WithWork(body_.SampleOf(t, s.H_B, s.q_NB, none, dynamics::Side::kLeft)));
    body_.OpenPhase(st_, WithWork(body_.SampleOf(t, s.H_B, s.q_NB, none, dynamics::Side::kRight)));
  }
  if (next_extra_ < extra_.size() && extra_[next_extra_] == t) {
    ++next_extra_;
    return;
  }
  st_.rec().Sample(WithWork(body_.GridSample(t, s.H_B, s.q_NB, t1_)));
}

double RigidSegment::Rate(const math::Vec3& H_B, const dynamics::InertiaSample& js) const {
  const math::Vec3 w = js.J_inv_B * (H_B - js.h_rel_B);
  const double rate = st_.s.dot(H_B.cross(w)) / st_.M;
  return std::abs(rate) <= kRateNoise * w.norm() ? 0.0 : rate;
}

AxisPoint RigidSegment::PointOf(const integrators::State& y) {
  AxisPoint p;
  p.t = y.t;
  p.f = st_.s.dot(y.H_B) / st_.M;
  p.H_B = y.H_B;
  const dynamics::InertiaSample& right = cache_.At(y.t);
  p.rate_start = Rate(y.H_B, right);
  p.Hdot_start = y.H_B.cross(right.J_inv_B * (y.H_B - right.h_rel_B));
  p.rate_end = p.rate_start;
  p.Hdot_end = p.Hdot_start;
  if (std::binary_search(breakpoints_.begin(), breakpoints_.end(), y.t)) {
    const dynamics::InertiaSample left = source_.Evaluate(y.t, dynamics::Side::kLeft);
    p.rate_end = Rate(y.H_B, left);
    p.Hdot_end = y.H_B.cross(left.J_inv_B * (y.H_B - left.h_rel_B));
  }
  return p;
}

double RigidSegment::RigidMinimum(const integrators::State& a, const integrators::State& b) const {
  const dynamics::InertiaSample js = source_.Evaluate(a.t, dynamics::Side::kRight);
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(js.J_B), a.H_B,
                                       a.q_NB.normalized(), a.t);
  const math::Vec3 s = st_.s;
  const double M = st_.M;
  auto g = [&](double t) {
    const math::Vec3 H = sol.H_B(t);
    const math::Vec3 w = sol.w_NB_B(t);
    const double rate = s.dot(H.cross(w)) / M;
    return std::abs(rate) <= kRateNoise * w.norm() ? 0.0 : rate;
  };
  const double ga = g(a.t);
  const double gb = g(b.t);
  if (!(ga < 0.0 && gb > 0.0)) return std::min(s.dot(a.H_B), s.dot(b.H_B)) / M;
  std::uintmax_t iterations = kMaxRootIterations;
  const double tol = kRootRelTolerance * (b.t - a.t);
  const auto bracket = boost::math::tools::toms748_solve(
      g, a.t, b.t, ga, gb, [tol](double lo, double hi) { return hi - lo <= tol; }, iterations);
  return s.dot(sol.H_B(0.5 * (bracket.first + bracket.second))) / M;
}

void RigidSegment::OnStep(const integrators::State& y) {
  st_.rec().Progress(y.t);
  const AxisPoint next = PointOf(y);
  const integrators::State& a = prev_step_;
  st_.rec().SpinAxisStep(prev_point_, next, [&]() -> double {
    return source_.IsRigidOn(a.t, y.t)
               ? RigidMinimum(a, y)
               : math::CubicHermiteMinimum(prev_point_.t, prev_point_.f, prev_point_.rate_start,
                                           next.t, next.f, next.rate_end);
  });
  prev_step_ = y;
  prev_point_ = next;
}

SegmentEnd RigidSegment::Run(double t_next, const std::vector<double>& boundaries) {
  kinetic0_ =
      body_.SampleOf(st_.t, st_.y.H_B, st_.y.q_NB, Eigen::VectorXd(), dynamics::Side::kRight)
          .kinetic;
  // The grid times of the segment plus the phase boundaries in it not on the grid.
  const std::size_t out_end = CountTimes(*st_.grid, t_next, true);
  const WindowTimes grid(*st_.grid, st_.next_out, out_end);
  // The boundaries in (t, t_next], found by bisection (a rotor may have 10^4 windows and
  // a run many segments).
  const auto first = std::upper_bound(boundaries.begin(), boundaries.end(), st_.t);
  const auto last = std::upper_bound(first, boundaries.end(), t_next);
  for (auto it = first; it != last; ++it) {
    const double b = *it;
    boundaries_.push_back(b);
    const std::size_t i = CountTimes(grid, b, false);
    if (!(i < grid.size() && grid.at(i) == b)) extra_.push_back(b);
  }
  const GridWithExtras times(grid, extra_);
  times_ = &times;
  prev_step_ = st_.y;
  prev_point_ = PointOf(st_.y);
  last_sample_ = st_.y;
  CachedSource& cache = cache_;
  const std::vector<integrators::EventFunction> events =
      RigidSpinAxisEvents(st_.s, [&cache](double t) { return cache.At(t); });
  const integrators::IntegrationResult r = integrators::Integrate(
      stepper_, st_.settings, source_, st_.y, t_next, times, events,
      [this](const integrators::State& y) { OnStep(y); },
      [this](const integrators::State& y) { OnSample(y); });
  st_.AddStats(r.stats);
  // A segment that stopped early: its remaining times get its last sample (every
  // boundary in it closes its phase).
  while (delivered_ < times.size()) OnSample(integrators::State(last_sample_));
  st_.next_out = out_end;
  for (const integrators::Event& e : r.events) {
    if (e.index == 1) {
      st_.rec().Crossing45(e.t);
    } else {
      st_.rec().CandidateFlip(e.t, source_.Evaluate(e.t).J_B, e.state.H_B);
    }
  }
  const bool stopped = st_.Stopped(r.termination, r.message);
  st_.y = r.final_state;
  st_.t = stopped ? r.final_state.t : t_next;
  st_.y.t = st_.t;
  // The drives' work over the segment: the change of the kinetic energy (with nothing
  // free, the locked springs keep theirs); at a boundary inside the run, after its jump.
  const dynamics::Side side = st_.t < t1_ ? dynamics::Side::kRight : dynamics::Side::kLeft;
  st_.work.drive +=
      body_.SampleOf(st_.t, st_.y.H_B, st_.y.q_NB, Eigen::VectorXd(), side).kinetic - kinetic0_;
  return stopped ? SegmentEnd::kStopped : SegmentEnd::kReached;
}

/// The loop: segments from t0 to t1, rigid or free, with the body's changes between them.
class Loop {
 public:
  Loop(const CompiledRun& run,
       RunBody& body,
       SampleSink* sink,
       const std::function<void(double)>& progress,
       const RunOptions& options);
  MissionResult Run();

 private:
  RunSample Current(dynamics::Side side) const {
    RunSample o = body_.SampleOf(st_.t, st_.y.H_B, st_.y.q_NB, st_.x, side);
    o.work = st_.work;
    return o;
  }
  /// After a free segment reached a prescribed window's boundary: a phase boundary.
  void WindowBoundary();
  void Finish();

  RunBody& body_;
  const double t0_, t1_;
  RunState st_;
  std::unique_ptr<integrators::Stepper> rigid_stepper_;
  std::vector<double> breakpoints_;  // the rigid path's (left limits of J_B there)
  std::vector<double> boundaries_;   // phase boundaries of the rigid path
};

Loop::Loop(const CompiledRun& run,
           RunBody& body,
           SampleSink* sink,
           const std::function<void(double)>& progress,
           const RunOptions& options)
    : body_(body),
      t0_(run.profile().t_begin()),
      t1_(run.profile().t_end()),
      rigid_stepper_(analysis::MakeStepper(run.profile().integrator.method)),
      breakpoints_(body.source().Breakpoints(t0_, t1_)),
      boundaries_(body.PhaseBoundaries(t0_, t1_)) {
  st_.t = t0_;
  st_.settings = run.settings();
  body_.Start(st_);
  const dynamics::InertiaSample s0 = body_.source().Evaluate(t0_);
  st_.s = options.spin_axis_B ? *options.spin_axis_B : analysis::InitialSpinAxis(s0.J_B, st_.y.H_B);
  st_.M = st_.y.H_B.norm();
  st_.recorder.emplace(st_.s, st_.y.q_NB * st_.y.H_B, sink, progress, t0_, t1_);
  st_.full_grid.emplace(t0_, t1_, run.profile().output.dt);
  st_.grid.emplace(*st_.full_grid, 0, sink != nullptr ? st_.full_grid->size() : 0);
  st_.message = integrators::ToString(st_.termination);
  st_.out.run = run.handle();
  st_.out.spin_axis_B = st_.s;
  st_.rec().SpinAxisCos(st_.s.dot(st_.y.H_B) / st_.M);
}

void Loop::WindowBoundary() {
  if (!(st_.t < t1_ && std::binary_search(boundaries_.begin(), boundaries_.end(), st_.t))) return;
  const RunSample before = Current(dynamics::Side::kLeft);
  st_.rec().ClosePhase(before);
  // A prescribed rate may jump here: the drive's impulsive work.
  st_.work.drive += Current(dynamics::Side::kRight).kinetic - before.kinetic;
  body_.OpenPhase(st_, Current(dynamics::Side::kRight));
}

MissionResult Loop::Run() {
  bool started = false;
  while (true) {
    const bool changed = body_.ChangesDue(st_, started);
    if (!started || changed) {
      const RunSample start = Current(dynamics::Side::kRight);
      if (!started) st_.out.energy_initial = start.kinetic + start.spring;
      body_.OpenPhase(st_, start);
      started = true;
    }
    if (!(st_.t < t1_)) break;
    if (body_.FreeMotion()) {
      const SegmentEnd end = body_.FreeSegment(st_, body_.NextFreeChange(st_.t, t1_));
      if (end == SegmentEnd::kStopped) break;
      if (end == SegmentEnd::kReached) WindowBoundary();
    } else {
      RigidSegment seg(st_, body_, *rigid_stepper_, breakpoints_, t1_);
      if (seg.Run(body_.NextChange(st_.t, t1_), boundaries_) == SegmentEnd::kStopped) break;
    }
  }
  Finish();
  return std::move(st_.out);
}

void Loop::Finish() {
  // A run that stopped early: the remaining times get its last state.
  if (st_.termination != integrators::Termination::kReachedEnd && st_.rec().sampling()) {
    RunSample s = Current(dynamics::Side::kRight);
    while (st_.next_out < st_.grid->size()) {
      s.t = st_.grid->at(st_.next_out++);
      st_.rec().Sample(s);
    }
  }
  const RunSample final_sample = Current(dynamics::Side::kLeft);
  st_.rec().ClosePhase(final_sample);
  MissionResult& out = st_.out;
  out.final_state = st_.y;
  out.final_J_B = final_sample.J_B;
  out.energy_final = final_sample.kinetic + final_sample.spring;
  out.work = st_.work;
  out.stats = st_.stats;
  out.termination = st_.termination;
  out.message = st_.message;
  st_.rec().Finish(out);
}

}  // namespace

MissionResult RunLoop(const CompiledRun& run,
                      RunBody& body,
                      SampleSink* sink,
                      const std::function<void(double)>& progress,
                      const RunOptions& options) {
  Loop loop(run, body, sink, progress, options);
  return loop.Run();
}

MissionResult RunMission(const CompiledRun& run,
                         SampleSink& sink,
                         const std::function<void(double)>& progress,
                         const RunOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  std::unique_ptr<RunBody> body;
  if (run.profile().is_hinge_profile()) {
    body = std::make_unique<HingeBody>(run, options);
  } else {
    body = std::make_unique<StageBody>(run);
  }
  MissionResult out =
      RunLoop(run, *body, options.sample_trajectory ? &sink : nullptr, progress, options);
  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::run
