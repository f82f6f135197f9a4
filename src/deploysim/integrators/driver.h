#pragma once

/// The one integration driver, for the integrators' own use (not installed): the
/// segments between breakpoints, the step-size rule, the events of each accepted step
/// (located on the dense output, finished on partial steps), terminal events and the
/// zeros a run starts on, and the output samples. It is written once, for any state
/// type; a state adapter supplies the method: Integrate (integrate.cc) adapts a
/// Stepper on the rigid state (t, H_B, q_NB), IntegrateShape (shape_integrate.cc) the
/// Lie-group method on the shape state (t, H_B, q_NB, x). A rigid state is the shape
/// state without shape coordinates; the two adapters differ only in how a step, a
/// partial step and the continuous extension are computed.
///
/// The adapter A provides:
///   using StateType;                           the state (with members t)
///   bool adaptive() const; int order() const;  order: of the error estimate
///   void SetSegment(double a, double b);       the breakpoint interval of the next steps
///   std::vector<double> Breakpoints(double t0, double t1) const;
///   double RotationRate(const StateType& y);   [rad/s] for the automatic first step
///   double MaxStep(const StateType& y);        the method's own bound (inf: none)
///   StateType Step(const StateType& y, double h, double* error_norm);
///   StateType Partial(const StateType& y0, double h);   a step inside the accepted one
///   void Project(StateType& y);               restore an invariant of a step's end (or not)
///   void Accept(const StateType& y0, const StateType& y1);
///   StateType Dense(double t);                 continuous extension of the accepted step
///   StateType DenseSample(double t, std::size_t samples_in_step);
///   bool DenseIsExact();                       Dense is the solution itself
///   static bool Finite(const StateType& y);
///   long evaluations() const; long dense_steps() const;

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/integrators/driver_support.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/integrators/shape_integrate.h"

namespace deploysim::integrators::driver {

/// A scalar function of the state whose sign changes are events.
template <class S>
struct EventSpec {
  std::string name;
  std::function<double(const S&)> g;
  int direction = 0;      ///< +1: rising sign changes only, -1: falling only, 0: both
  bool terminal = false;  ///< stop at the first located terminal event
  bool refine = true;     ///< finish the location on partial steps
  /// dg/dt at a state (optional). With it a step is also searched for a crossing and
  /// return inside it (both zeros between the step's ends, see GrazingCandidate).
  std::function<double(const S&)> rate = {};
};

template <class S>
struct FoundEvent {
  double t = 0.0;
  int index = 0;
  int direction = 0;  ///< +1 rising, -1 falling
  S state;
};

template <class S>
struct Outcome {
  std::vector<FoundEvent<S>> events;  ///< ascending; a terminal event is the last
  bool stopped_at_event = false;
  bool stuck = false;  ///< could not leave a terminal zero it started on
  S final_state;
  Statistics stats;
  Termination termination = Termination::kReachedEnd;
  std::string message;
  double next_step = 0.0;  ///< [s] the step the controller would take next
};

template <class A>
class Driver {
 public:
  using S = typename A::StateType;

  /// Output samples: output_times.at(i) from `next_output` on (advanced past them),
  /// passed to `samples` in order. `emit_rest_at_end`: output times left at the end
  /// (equal to t_end up to rounding) are samples of the end state. `events` and
  /// `output_times` must outlive the driver.
  Driver(A& adapter,
         const IntegratorSettings& settings,
         const S& initial,
         const OutputTimes& output_times,
         std::size_t& next_output,
         const std::vector<EventSpec<S>>& events,
         const std::function<void(const S&)>& samples,
         const std::function<void(const S&)>& observer,
         bool emit_rest_at_end)
      : a_(adapter),
        settings_(settings),
        y_(initial),
        output_times_(output_times),
        next_out_(next_output),
        events_(events),
        samples_(samples),
        observer_(observer),
        emit_rest_at_end_(emit_rest_at_end),
        q_(adapter.order()),
        h_adapt_(settings.step) {}

  Outcome<S> Run(double t_end) {
    EmitUntil(y_.t, true, y_, y_, false);  // samples at the start: the initial state
    for (const EventSpec<S>& e : events_) {
      g_prev_.push_back(e.g(y_));
      r_prev_.push_back(e.rate ? e.rate(y_) : 0.0);
    }
    if (AlreadyPast()) return std::move(out_);
    for (std::size_t e = 0; e < events_.size(); ++e) {
      leaving_.push_back(events_[e].terminal && events_[e].direction != 0 && g_prev_[e] == 0.0);
    }
    std::vector<double> bounds{y_.t};
    for (double b : a_.Breakpoints(y_.t, t_end)) bounds.push_back(b);
    bounds.push_back(t_end);
    for (std::size_t seg = 0; seg + 1 < bounds.size(); ++seg) {
      if (!Segment(bounds[seg], bounds[seg + 1])) return std::move(out_);
    }
    while (emit_rest_at_end_ && next_out_ < output_times_.size()) {
      S s = y_;
      s.t = output_times_.at(next_out_++);
      samples_(s);
    }
    Finish(Termination::kReachedEnd, ToString(Termination::kReachedEnd));
    return std::move(out_);
  }

 private:
  enum class Leave { kLeft, kRetry, kStuck };

  void Finish(Termination why, const std::string& message) {
    out_.termination = why;
    out_.message = message;
    out_.final_state = y_;
    out_.stats.evaluations = a_.evaluations();
    out_.stats.dense_steps = a_.dense_steps();
    out_.next_step = h_adapt_;
  }

  /// The output times up to t_stop (inclusive or not) on the dense output of the
  /// accepted step [y0, y1] (dense false: all equal to y0).
  void EmitUntil(double t_stop, bool inclusive, const S& y0, const S& y1, bool dense) {
    std::size_t end = next_out_;
    while (end < output_times_.size()) {
      const double t = output_times_.at(end);
      if (t > t_stop || (!inclusive && t == t_stop)) break;
      ++end;
    }
    const std::size_t in_step = end - next_out_;
    for (; next_out_ < end; ++next_out_) {
      const double t = output_times_.at(next_out_);
      S s = !dense || t <= y0.t ? y0 : t >= y1.t ? y1 : a_.DenseSample(t, in_step);
      s.t = t;
      samples_(s);
    }
  }

  /// A terminal function already past its zero at the start (crossed within the
  /// location tolerance of the event the previous run stopped at): it happens now.
  bool AlreadyPast() {
    for (std::size_t e = 0; e < events_.size(); ++e) {
      if (events_[e].terminal && events_[e].direction * g_prev_[e] > 0.0) {
        out_.events.push_back({y_.t, static_cast<int>(e), events_[e].direction, y_});
        out_.stopped_at_event = true;
        out_.final_state = y_;
        out_.next_step = settings_.step;
        out_.message = "stopped at event '" + events_[e].name + "' (already past at the start)";
        return true;
      }
    }
    return false;
  }

  /// A step that crosses a terminal zero the run started on, without leaving it first:
  /// retried shorter, down to kMinLeaveStep; a run that cannot leave it is stuck there.
  Leave CheckLeaving(const S& y1, double h) {
    int stuck = -1;
    for (std::size_t e = 0; e < events_.size(); ++e) {
      // Not strictly on the side it left to counts as not having left.
      if (leaving_[e] && events_[e].direction * events_[e].g(y1) >= 0.0) {
        stuck = static_cast<int>(e);
      }
    }
    if (stuck < 0) return Leave::kLeft;
    const double h_min = kMinLeaveStep * std::max(1.0, std::abs(y_.t));
    if (a_.adaptive() && h > h_min) {
      ++out_.stats.rejected;
      h_adapt_ = std::max(h_min, h * 0.1);
      return Leave::kRetry;
    }
    const EventSpec<S>& fn = events_[static_cast<std::size_t>(stuck)];
    out_.events.push_back({y_.t, stuck, fn.direction, y_});
    out_.stopped_at_event = true;
    out_.stuck = true;
    Finish(Termination::kReachedEnd, "stuck at event '" + fn.name + "'");
    return Leave::kStuck;
  }

  /// The sign change of function e over [ta, tb] inside the accepted step [y_, y1]: g
  /// is ga, gb there (exact), gda, gdb on the continuous extension.
  FoundEvent<S> Locate(std::size_t e,
                       const S& y1,
                       double ta,
                       double tb,
                       double ga,
                       double gb,
                       double gda,
                       double gdb) {
    const EventSpec<S>& fn = events_[e];
    const S y0 = y_;
    const bool refine = fn.refine && !a_.DenseIsExact();
    auto exact_at = [&](double t) {
      return t <= y0.t ? y0 : t >= y1.t ? y1 : a_.Partial(y0, t - y0.t);
    };
    const double t_ev = LocateEvent(
        ta, tb, ga, gb, gda, gdb, [&](double t) { return fn.g(a_.Dense(t)); },
        [&](double t) { return fn.g(exact_at(t)); }, !refine, y1.t - y0.t);
    FoundEvent<S> ev{t_ev, static_cast<int>(e), ga < 0.0 ? 1 : -1,
                     refine ? exact_at(t_ev) : a_.Dense(t_ev)};
    ev.state.t = t_ev;
    return ev;
  }

  /// A grazing candidate of function e over the accepted step [y_, y1] (GrazingCandidate):
  /// the extremum of g on the continuous extension, where its rate is 0; if g has crossed
  /// zero there (on a partial step, when the location is refined), the crossing and the
  /// return are events (those of the function's direction).
  void Grazing(
      std::size_t e, const S& y1, double g1, double r1, std::vector<FoundEvent<S>>& found) {
    const EventSpec<S>& fn = events_[e];
    const double t0 = y_.t, t1 = y1.t;
    const double g0 = g_prev_[e], r0 = r_prev_[e];
    const double tol_t = kEventRelTolerance * (t1 - t0);
    std::uintmax_t iters = kMaxEventIterations;
    const auto bracket = boost::math::tools::toms748_solve(
        [&](double t) { return fn.rate(a_.Dense(t)); }, t0, t1, r0, r1,
        [tol_t](double lo, double hi) { return hi - lo <= tol_t; }, iters);
    const double tm = 0.5 * (bracket.first + bracket.second);
    const double gdm = fn.g(a_.Dense(tm));
    const bool refine = fn.refine && !a_.DenseIsExact();
    const double gm = refine ? fn.g(a_.Partial(y_, tm - t0)) : gdm;
    if ((gm < 0.0) == (g0 < 0.0) && gm != 0.0) return;
    const int dir_in = g0 < 0.0 ? 1 : -1;  // the crossing; the return is the opposite
    if (fn.direction == 0 || fn.direction == dir_in) {
      found.push_back(Locate(e, y1, t0, tm, g0, gm, g0, gdm));
    }
    if (gm != 0.0 && (fn.direction == 0 || fn.direction == -dir_in)) {
      found.push_back(Locate(e, y1, tm, t1, gm, g1, gdm, g1));
    }
  }

  /// Keeps the events before the earliest terminal one (ties: the first) and stops there.
  void StopAtTerminal(const std::vector<FoundEvent<S>>& found, double t_stop, const S& y1) {
    const FoundEvent<S>* term = nullptr;
    for (const FoundEvent<S>& ev : found) {
      if (term == nullptr && events_[static_cast<std::size_t>(ev.index)].terminal &&
          ev.t == t_stop) {
        term = &ev;
      } else if (ev.t < t_stop) {
        out_.events.push_back(ev);
      }
    }
    out_.events.push_back(*term);
    EmitUntil(t_stop, false, y_, y1, true);
    y_ = term->state;
    out_.stopped_at_event = true;
    if (observer_) observer_(y_);
    Finish(Termination::kReachedEnd,
           "stopped at event '" + events_[static_cast<std::size_t>(term->index)].name + "'");
  }

  /// The events over the accepted step [y_, y1]; true when a terminal one stopped the run.
  bool StepEvents(const S& y1) {
    if (events_.empty()) return false;
    std::vector<FoundEvent<S>> found;
    g_next_.resize(events_.size());
    r_next_.resize(events_.size());
    for (std::size_t e = 0; e < events_.size(); ++e) {
      const EventSpec<S>& fn = events_[e];
      const double g1 = fn.g(y1);
      const double r1 = fn.rate ? fn.rate(y1) : 0.0;
      const double g0 = g_prev_[e];
      const bool rising = g0 < 0.0 && g1 >= 0.0;
      const bool falling = g0 > 0.0 && g1 <= 0.0;
      if ((rising && fn.direction >= 0) || (falling && fn.direction <= 0)) {
        found.push_back(Locate(e, y1, y_.t, y1.t, g0, g1, g0, g1));
      } else if (fn.rate && GrazingCandidate(g0, r_prev_[e], g1, r1, y1.t - y_.t)) {
        Grazing(e, y1, g1, r1, found);
      }
      g_next_[e] = g1;
      r_next_[e] = r1;
    }
    std::sort(found.begin(), found.end(),
              [](const FoundEvent<S>& l, const FoundEvent<S>& r) { return l.t < r.t; });
    double t_stop = std::numeric_limits<double>::infinity();
    for (const FoundEvent<S>& ev : found) {
      if (events_[static_cast<std::size_t>(ev.index)].terminal) t_stop = std::min(t_stop, ev.t);
    }
    if (t_stop < std::numeric_limits<double>::infinity()) {
      StopAtTerminal(found, t_stop, y1);
      return true;
    }
    out_.events.insert(out_.events.end(), found.begin(), found.end());
    std::fill(leaving_.begin(), leaving_.end(), 0);  // the accepted step left the zeros
    g_prev_.swap(g_next_);
    r_prev_.swap(r_next_);
    return false;
  }

  /// The automatic first step: a small fraction of the rotation time scale.
  double FirstStep(double a, double b) {
    const double rate = std::max(a_.RotationRate(y_), 1.0 / (b - a));
    return 0.01 * std::pow(settings_.tolerances.rtol, 1.0 / (q_ + 1)) / rate;
  }

  /// The steps of one segment [a, b] between breakpoints; false when the run stopped.
  bool Segment(double a, double b) {
    a_.SetSegment(a, b);
    SegmentSteps steps(a, b, a_.adaptive(), settings_.step);
    const double eps = steps.eps();
    if (a_.adaptive() && h_adapt_ <= 0.0) h_adapt_ = FirstStep(a, b);
    while (y_.t < b - eps) {
      if (++attempts_ > settings_.max_steps) {
        Finish(Termination::kMaxSteps, "max_steps reached at t = " + std::to_string(y_.t));
        return false;
      }
      bool last = false;
      const double h = steps.Next(
          y_.t, a_.adaptive() ? std::min({h_adapt_, settings_.max_step, a_.MaxStep(y_)}) : 0.0,
          &last);
      double err = 0.0;
      S y1 = a_.Step(y_, h, &err);
      if (a_.adaptive()) {
        // A non-finite trial state (a step far too long for a stiff hinge) is rejected like
        // a large error, whatever its error norm says.
        if (!A::Finite(y1)) err = std::numeric_limits<double>::infinity();
        if (!std::isfinite(err) || err > 1.0) {
          ++out_.stats.rejected;
          h_adapt_ = h * RejectedStepFactor(err, q_);
          if (h_adapt_ < 1e-14 * std::max(1.0, std::abs(y_.t))) {
            Finish(Termination::kStepSizeUnderflow,
                   "step size underflow at t = " + std::to_string(y_.t));
            return false;
          }
          continue;
        }
        const double grow = AcceptedStepFactor(err, q_);
        // Do not let the short last step of a segment shrink the next segment's steps.
        if (!last || grow * h > h_adapt_) h_adapt_ = h * grow;
      }
      a_.Project(y1);
      const Leave leave = CheckLeaving(y1, h);
      if (leave == Leave::kStuck) return false;
      if (leave == Leave::kRetry) continue;
      if (last) y1.t = b;
      if (!A::Finite(y1)) {
        Finish(Termination::kNonFinite, "state became non-finite at t = " + std::to_string(y_.t));
        return false;
      }
      ++out_.stats.steps;
      a_.Accept(y_, y1);
      if (StepEvents(y1)) return false;
      EmitUntil(y1.t, true, y_, y1, true);
      y_ = y1;
      if (observer_) observer_(y_);
    }
    return true;
  }

  A& a_;
  const IntegratorSettings& settings_;
  S y_;
  const OutputTimes& output_times_;
  std::size_t& next_out_;
  const std::vector<EventSpec<S>>& events_;
  const std::function<void(const S&)> samples_;
  const std::function<void(const S&)> observer_;
  const bool emit_rest_at_end_;
  const int q_;
  double h_adapt_;
  long attempts_ = 0;
  std::vector<double> g_prev_, g_next_;  // g at the ends of the accepted step
  std::vector<double> r_prev_, r_next_;  // their rates (0 without a rate function)
  std::vector<char> leaving_;            // terminal functions at exactly 0, not yet left
  Outcome<S> out_;
};

}  // namespace deploysim::integrators::driver
