#include "deploysim/integrators/shape_integrate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/driver_support.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/lie_anchor.h"
#include "deploysim/integrators/rk_engine.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"

namespace deploysim::integrators {

namespace {

using Vec = Eigen::VectorXd;
using lie::Anchor;

constexpr int kHermiteNodes = 5;

bool SameBits(const ShapeState& a, const ShapeState& b) {
  auto same = [](const double* p, const double* q, std::size_t n) {
    return std::memcmp(p, q, n * sizeof(double)) == 0;
  };
  return a.x.size() == b.x.size() && same(&a.t, &b.t, 1) && same(a.H_B.data(), b.H_B.data(), 3) &&
         same(a.q_NB.coeffs().data(), b.q_NB.coeffs().data(), 4) &&
         same(a.x.data(), b.x.data(), static_cast<std::size_t>(a.x.size()));
}

/// The Lie-group RKMK method on SO(3) x R^(2m) for one run (one shape system, one thread).
class ShapeStepper {
 public:
  ShapeStepper(const ButcherTableau& tableau, const dynamics::ShapeSystem& system)
      : tab_(tableau), sys_(system) {
    dense_ = ChooseDenseKind(tableau);
  }
  bool adaptive() const { return !tab_.b_hat.empty(); }
  int order() const {
    return tab_.b_hat.empty() ? tab_.order : std::min(tab_.order, tab_.embedded_order);
  }
  long evaluations() const { return evaluations_; }
  long dense_steps() const { return dense_steps_; }
  void SetSegmentEnd(double t) { segment_end_ = t; }

  /// One step of size h from y; error_norm (adaptive methods) by the weighted max norm.
  ShapeState Step(const ShapeState& y, double h, const Tolerances& tol, double* error_norm) {
    Anchor a0;
    if (have_committed_ && SameBits(y, committed_key_)) {
      a0 = committed_anchor_;
    } else if (have_proposal_ && SameBits(y, proposal_key_)) {
      a0 = proposal_anchor_;
    } else {
      a0.q_ref = y.q_NB;
      a0.H_ref = y.H_B;
    }
    const int s = tab_.stages();
    const int nx = static_cast<int>(y.x.size());
    const int dim = 3 + nx;
    const double t_end = y.t + h;
    const math::Vec3 H0 = lie::MomentumOf(a0);
    math::Vec3 w0;
    Rate(y.t, H0, y.x, &w0, xdot_);
    const double H0_2 = H0.squaredNorm();
    const double sigma = H0_2 > 0.0 ? w0.dot(H0) / H0_2 : 0.0;
    auto& k = last_.stages;
    for (int i = 0; i < s; ++i) k[static_cast<std::size_t>(i)].resize(dim);
    k[0].head<3>() = w0 - sigma * H0;
    k[0].tail(nx) = xdot_;
    zero_.setZero(dim);
    RkStages<Vec>(
        tab_,
        [&](double ti, const Vec& Yi, Vec& ki) { AlgebraRate(ti, Yi, H0, sigma, y.x, ki); },
        y.t, h, zero_, scratch_, k);
    Vec& Y1 = last_.Y1;
    Y1.resize(dim);
    RkWeightedSum<Vec>(tab_.b, nullptr, h, k, Y1);
    const Anchor a1 = lie::Compose(a0, (sigma * h) * a0.H_ref, Y1.head<3>());
    ShapeState out;
    out.t = t_end;
    out.q_NB = (a1.q_ref * a1.dq).normalized();
    out.H_B = lie::MomentumOf(a1);
    out.x = y.x + Y1.tail(nx);
    if (error_norm != nullptr) {
      *error_norm = 0.0;
      if (adaptive()) {
        Vec& err = scratch_;
        err.resize(dim);
        RkWeightedSum<Vec>(tab_.b, &tab_.b_hat, h, k, err);
        const math::Vec3 H1 = a1.dq.conjugate() * a1.H_ref;
        const math::Vec3 dH = H1.cross(err.head<3>());
        const double scale = std::sqrt(H0_2);
        double norm = 0.0;
        for (int i = 0; i < 3; ++i) {
          const double ref = std::max(std::abs(H0[i]), std::abs(H1[i]));
          norm = std::max(norm, std::abs(dH[i]) / (tol.atol * scale + tol.rtol * ref));
        }
        const int m = nx / 2;
        for (int i = 0; i < nx; ++i) {
          const double ref = std::max(std::abs(y.x[i]), std::abs(out.x[i]));
          const double abs_tol = i < m ? tol.atol : tol.atol * scale;
          norm = std::max(norm, std::abs(err[3 + i]) / (abs_tol + tol.rtol * ref));
        }
        *error_norm = norm;
      }
    }
    last_.a0 = a0;
    last_.sigma = sigma;
    last_.H0 = H0;
    last_.x0 = y.x;
    proposal_key_ = out;
    proposal_anchor_ = a1;
    have_proposal_ = true;
    return out;
  }

  /// The driver accepts the last step (from y0) as y1.
  void Accept(const ShapeState& y0, const ShapeState& y1) {
    committed_key_ = y1;
    committed_anchor_ = proposal_anchor_;
    have_committed_ = true;
    acc_ = last_;
    acc_.t0 = y0.t;
    acc_.t1 = y1.t;
    acc_.y0 = y0;
    acc_.y1 = y1;
    have_f1_ = false;
    have_nodes_ = false;
  }

  /// The continuous extension of the accepted step at t.
  ShapeState Dense(double t, const Tolerances& tol) {
    if (t <= acc_.t0) return acc_.y0;
    if (t >= acc_.t1) return acc_.y1;
    const double h = acc_.t1 - acc_.t0;
    const double tau = t - acc_.t0;
    const double th = tau / h;
    const int dim = static_cast<int>(acc_.Y1.size());
    const Vec zero = Vec::Zero(dim);
    Vec Y;
    if (dense_ == DenseKind::kDopri) {
      Y = DopriDenseV<Vec>(th, h, zero, acc_.Y1, acc_.stages);
    } else {
      if (!have_f1_) {
        const double t_save = segment_end_;
        AlgebraRate(acc_.t1, acc_.Y1, acc_.H0, acc_.sigma, acc_.x0, f1_);
        segment_end_ = t_save;
        have_f1_ = true;
      }
      if (dense_ == DenseKind::kHermiteCubic) {
        Y = HermiteCubicV<Vec>(th, h, zero, acc_.stages[0], acc_.Y1, f1_);
      } else {
        if (!have_nodes_) {
          const ShapeState begin = acc_.y0;
          for (int j = 0; j < kHermiteNodes; ++j) {
            nodes_x_[static_cast<std::size_t>(j)] = static_cast<double>(j) / (kHermiteNodes - 1);
            if (j == 0) {
              nodes_y_[0] = zero;
              nodes_f_[0] = acc_.stages[0];
            } else if (j == kHermiteNodes - 1) {
              nodes_y_[static_cast<std::size_t>(j)] = acc_.Y1;
              nodes_f_[static_cast<std::size_t>(j)] = f1_;
            } else {
              const double xj = nodes_x_[static_cast<std::size_t>(j)];
              Step(begin, xj * h, tol, nullptr);
              ++dense_steps_;
              nodes_y_[static_cast<std::size_t>(j)] = last_.Y1;
              AlgebraRate(begin.t + xj * h, last_.Y1, acc_.H0, acc_.sigma, acc_.x0,
                          nodes_f_[static_cast<std::size_t>(j)]);
            }
          }
          have_nodes_ = true;
        }
        Y = HermiteNodesV<Vec>(th, h, kHermiteNodes, nodes_x_.data(), nodes_y_.data(),
                               nodes_f_.data());
      }
    }
    const Anchor a =
        lie::ComposeForOutput(acc_.a0, (acc_.sigma * tau) * acc_.a0.H_ref, Y.head<3>());
    ShapeState out;
    out.t = t;
    out.q_NB = (a.q_ref * a.dq).normalized();
    out.H_B = lie::MomentumOf(a);
    out.x = acc_.x0 + Y.tail(dim - 3);
    return out;
  }

 private:
  struct StepData {
    Anchor a0;
    double sigma = 0.0;
    math::Vec3 H0 = math::Vec3::Zero();
    Vec x0, Y1;
    std::array<Vec, kMaxRkStages> stages;
    double t0 = 0.0, t1 = 0.0;
    ShapeState y0, y1;
  };

  void Rate(double t, const math::Vec3& H, const Vec& x, math::Vec3* w, Vec& xdot) {
    ++evaluations_;
    const dynamics::Side side = t >= segment_end_ ? dynamics::Side::kLeft : dynamics::Side::kRight;
    sys_.Evaluate(t, H, x, side, *w, xdot);
  }

  /// F(Y) = (J_r^-1(u) (w - sigma H), x') at x = x0 + Y_x, H = Exp(-u) H0.
  void AlgebraRate(
      double t, const Vec& Y, const math::Vec3& H0, double sigma, const Vec& x0, Vec& out) {
    const int nx = static_cast<int>(x0.size());
    const math::Vec3 u = Y.head<3>();
    const math::Vec3 H = math::ExpQuat(-u) * H0;
    xs_ = x0 + Y.tail(nx);
    math::Vec3 w;
    Rate(t, H, xs_, &w, xdot_);
    out.resize(3 + nx);
    out.head<3>() = math::DexpInv(u, w - sigma * H);
    out.tail(nx) = xdot_;
  }

  const ButcherTableau& tab_;
  const dynamics::ShapeSystem& sys_;
  DenseKind dense_;
  double segment_end_ = std::numeric_limits<double>::infinity();
  long evaluations_ = 0;
  long dense_steps_ = 0;
  StepData last_, acc_;
  bool have_proposal_ = false, have_committed_ = false;
  ShapeState proposal_key_, committed_key_;
  Anchor proposal_anchor_, committed_anchor_;
  bool have_f1_ = false, have_nodes_ = false;
  Vec f1_, scratch_, zero_, xdot_, xs_;
  std::array<double, kMaxHermiteNodes> nodes_x_{};
  std::array<Vec, kMaxHermiteNodes> nodes_y_, nodes_f_;
};

const ButcherTableau& TableauOf(const std::string& method) {
  for (const MethodEntry& m : NumericalMethods()) {
    if (m.family == MethodEntry::Family::kRkmk && method == m.name) return m.tableau();
  }
  std::string list;
  for (const std::string& n : ShapeMethodNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("integrator '" + method +
                              "' cannot integrate free hinges (rule: a Lie-group method: " + list +
                              ", or exact)");
}

bool Finite(const ShapeState& s) {
  return std::isfinite(s.t) && s.H_B.allFinite() && s.q_NB.coeffs().allFinite() && s.x.allFinite();
}

}  // namespace

std::vector<std::string> ShapeMethodNames() {
  std::vector<std::string> names;
  for (const MethodEntry& m : NumericalMethods()) {
    if (m.family == MethodEntry::Family::kRkmk) names.emplace_back(m.name);
  }
  return names;
}

bool IsShapeMethod(const std::string& name) {
  for (const std::string& n : ShapeMethodNames()) {
    if (n == name) return true;
  }
  return false;
}

namespace {

/// One run of the shape equations up to t_end or the first terminal event: the segments
/// between the system's breakpoints, the step-size control, terminal zeros the run
/// starts on (it must leave them before they count again), the events of each accepted
/// step and the output samples on the dense output.
class ShapeDriver {
 public:
  ShapeDriver(const std::string& method,
              const IntegratorSettings& settings,
              const dynamics::ShapeSystem& system,
              const ShapeState& initial,
              const OutputTimes& output_times,
              std::size_t* next_output,
              const std::vector<ShapeEventFunction>& events,
              const std::function<void(const ShapeState&)>& samples,
              const std::function<void(const ShapeState&)>& observer)
      : settings_(settings),
        tol_(settings.tolerances),
        system_(system),
        stepper_(TableauOf(method), system),
        adaptive_(stepper_.adaptive()),
        q_(stepper_.order()),
        y_(initial),
        output_times_(output_times),
        next_out_(*next_output),
        events_(events),
        samples_(samples),
        observer_(observer),
        h_adapt_(settings.step) {
    if (!adaptive_ && !(settings.step > 0.0)) {
      throw std::invalid_argument("integrator " + method +
                                  ": step = 0 (rule: a fixed-step method needs a finite step > 0)");
    }
  }

  ShapeIntegrationResult Run(double t_end);

 private:
  enum class Leave { kLeft, kRetry, kStuck };
  bool AlreadyPast();
  bool Segment(double a, double b);
  Leave CheckLeaving(const ShapeState& y1, double h);
  bool StepEvents(const ShapeState& y1);
  ShapeEvent Locate(std::size_t e, const ShapeState& y1, bool rising);
  bool StopAtTerminal(std::vector<ShapeEvent>& found, double t_stop, const ShapeState& y1);
  void EmitUntil(
      double t_stop, bool inclusive, const ShapeState& y0, const ShapeState& y1, bool dense);
  void Finish(Termination why, const std::string& message) {
    result_.termination = why;
    result_.message = message;
    result_.final_state = y_;
    result_.stats.evaluations = stepper_.evaluations();
    result_.stats.dense_steps = stepper_.dense_steps();
    result_.next_step = h_adapt_;
  }

  const IntegratorSettings& settings_;
  const Tolerances& tol_;
  const dynamics::ShapeSystem& system_;
  ShapeStepper stepper_;
  const bool adaptive_;
  const int q_;
  ShapeState y_;
  const OutputTimes& output_times_;
  std::size_t& next_out_;
  const std::vector<ShapeEventFunction>& events_;
  const std::function<void(const ShapeState&)>& samples_;
  const std::function<void(const ShapeState&)>& observer_;
  double h_adapt_;
  long attempts_ = 0;
  std::vector<double> g_prev_;
  std::vector<char> leaving_;  // terminal functions at exactly 0, not yet left
  ShapeIntegrationResult result_;
};

void ShapeDriver::EmitUntil(
    double t_stop, bool inclusive, const ShapeState& y0, const ShapeState& y1, bool dense) {
  while (next_out_ < output_times_.size()) {
    const double t_out = output_times_.at(next_out_);
    if (t_out > t_stop || (!inclusive && t_out == t_stop)) break;
    ShapeState s = !dense || t_out <= y0.t ? y0 : t_out >= y1.t ? y1 : stepper_.Dense(t_out, tol_);
    s.t = t_out;
    if (samples_) samples_(s);
    ++next_out_;
  }
}

// A terminal function already past its zero at the start (crossed within the location
// tolerance of the event the previous run stopped at, e.g. two symmetric panels
// latching together): the event happens now.
bool ShapeDriver::AlreadyPast() {
  for (std::size_t e = 0; e < events_.size(); ++e) {
    if (events_[e].terminal && events_[e].direction * g_prev_[e] > 0.0) {
      ShapeEvent ev;
      ev.t = y_.t;
      ev.index = static_cast<int>(e);
      ev.direction = events_[e].direction;
      ev.state = y_;
      result_.events.push_back(ev);
      result_.stopped_at_event = true;
      result_.final_state = y_;
      result_.next_step = settings_.step;
      result_.message = "stopped at event '" + events_[e].name + "' (already past at the start)";
      return true;
    }
  }
  return false;
}

// A step that crosses a terminal zero it started on, without leaving it first: retried
// shorter, down to a minimum step; a run that cannot leave it is stuck there.
ShapeDriver::Leave ShapeDriver::CheckLeaving(const ShapeState& y1, double h) {
  int stuck_event = -1;
  for (std::size_t e = 0; e < events_.size(); ++e) {
    if (!leaving_[e]) continue;
    // Not strictly on the side it left to (g1 == 0: the excursion is below the
    // angle's rounding) counts as not having left.
    if (events_[e].direction * events_[e].g(y1) >= 0.0) stuck_event = static_cast<int>(e);
  }
  if (stuck_event < 0) return Leave::kLeft;
  const double h_min = kMinLeaveStep * std::max(1.0, std::abs(y_.t));
  if (adaptive_ && h > h_min) {
    ++result_.stats.rejected;
    h_adapt_ = std::max(h_min, h * 0.1);
    return Leave::kRetry;
  }
  const ShapeEventFunction& fn = events_[static_cast<std::size_t>(stuck_event)];
  ShapeEvent ev;
  ev.t = y_.t;
  ev.index = stuck_event;
  ev.direction = fn.direction;
  ev.state = y_;
  result_.events.push_back(ev);
  result_.stopped_at_event = true;
  result_.stuck = true;
  Finish(Termination::kReachedEnd, "stuck at event '" + fn.name + "'");
  return Leave::kStuck;
}

// The event of function e inside the step [y_, y1], located on the dense output (and
// finished on partial steps when the function asks for it).
ShapeEvent ShapeDriver::Locate(std::size_t e, const ShapeState& y1, bool rising) {
  const ShapeEventFunction& fn = events_[e];
  const ShapeState y0 = y_;
  auto exact_at = [&](double t) {
    if (t <= y0.t) return y0;
    if (t >= y1.t) return y1;
    return stepper_.Step(y0, t - y0.t, tol_, nullptr);
  };
  const double g0 = g_prev_[e];
  const double g1 = fn.g(y1);
  double t_ev = y1.t;
  if (g1 != 0.0) {
    t_ev = driver::LocateEvent(
        y0.t, y1.t, g0, g1, [&](double t) { return fn.g(stepper_.Dense(t, tol_)); },
        [&](double t) { return fn.g(exact_at(t)); }, !fn.refine);
  }
  ShapeEvent ev;
  ev.t = t_ev;
  ev.index = static_cast<int>(e);
  ev.direction = rising ? 1 : -1;
  ev.state = fn.refine ? exact_at(t_ev) : stepper_.Dense(t_ev, tol_);
  ev.state.t = t_ev;
  return ev;
}

// Keeps the events up to the earliest terminal one (ties: the first) and stops there.
bool ShapeDriver::StopAtTerminal(std::vector<ShapeEvent>& found,
                                 double t_stop,
                                 const ShapeState& y1) {
  ShapeEvent term;
  std::vector<ShapeEvent> kept;
  bool have_term = false;
  for (const ShapeEvent& ev : found) {
    if (!have_term && events_[static_cast<std::size_t>(ev.index)].terminal && ev.t == t_stop) {
      term = ev;
      have_term = true;
      continue;
    }
    if (ev.t < t_stop) kept.push_back(ev);
  }
  result_.events.insert(result_.events.end(), kept.begin(), kept.end());
  result_.events.push_back(term);
  EmitUntil(t_stop, false, y_, y1, true);
  y_ = term.state;
  result_.stopped_at_event = true;
  if (observer_) observer_(y_);
  Finish(Termination::kReachedEnd,
         "stopped at event '" + events_[static_cast<std::size_t>(term.index)].name + "'");
  return true;
}

// The events over the accepted step [y_, y1]; true when a terminal one stopped the run.
bool ShapeDriver::StepEvents(const ShapeState& y1) {
  double t_stop = std::numeric_limits<double>::infinity();
  bool terminal = false;
  std::vector<ShapeEvent> found;
  std::vector<double> g_new(events_.size());
  for (std::size_t e = 0; e < events_.size(); ++e) {
    const double g1 = events_[e].g(y1);
    g_new[e] = g1;
    const double g0 = g_prev_[e];
    const bool rising = g0 < 0.0 && g1 >= 0.0;
    const bool falling = g0 > 0.0 && g1 <= 0.0;
    const int dir = events_[e].direction;
    if (!((rising && dir >= 0) || (falling && dir <= 0))) continue;
    found.push_back(Locate(e, y1, rising));
    if (events_[e].terminal && found.back().t < t_stop) {
      t_stop = found.back().t;
      terminal = true;
    }
  }
  std::sort(found.begin(), found.end(),
            [](const ShapeEvent& l, const ShapeEvent& r) { return l.t < r.t; });
  if (terminal) return StopAtTerminal(found, t_stop, y1);
  result_.events.insert(result_.events.end(), found.begin(), found.end());
  std::fill(leaving_.begin(), leaving_.end(), 0);  // the accepted step left the zeros
  g_prev_ = g_new;
  return false;
}

// The steps of one segment [a, b] between breakpoints; false when the run stopped.
bool ShapeDriver::Segment(double a, double b) {
  stepper_.SetSegmentEnd(b);
  driver::SegmentSteps steps(a, b, adaptive_, settings_.step);
  const double eps = steps.eps();
  if (adaptive_ && h_adapt_ <= 0.0) {
    // Automatic first step: a small fraction of the rotation time scale.
    const double rate = std::max(1.0, 1.0 / (b - a));
    h_adapt_ = 0.01 * std::pow(tol_.rtol, 1.0 / (q_ + 1)) / rate;
  }
  while (y_.t < b - eps) {
    if (++attempts_ > settings_.max_steps) {
      Finish(Termination::kMaxSteps, "max_steps reached at t = " + std::to_string(y_.t));
      return false;
    }
    bool last = false;
    const double h =
        steps.Next(y_.t, adaptive_ ? std::min(h_adapt_, settings_.max_step) : 0.0, &last);
    double err = 0.0;
    ShapeState y1 = stepper_.Step(y_, h, tol_, &err);
    if (adaptive_) {
      if (!std::isfinite(err) || err > 1.0) {
        ++result_.stats.rejected;
        h_adapt_ = h * driver::RejectedStepFactor(err, q_);
        if (h_adapt_ < 1e-14 * std::max(1.0, std::abs(y_.t))) {
          Finish(Termination::kStepSizeUnderflow,
                 "step size underflow at t = " + std::to_string(y_.t));
          return false;
        }
        continue;
      }
      const double grow = driver::AcceptedStepFactor(err, q_);
      if (!last || grow * h > h_adapt_) h_adapt_ = h * grow;
    }
    const Leave leave = CheckLeaving(y1, h);
    if (leave == Leave::kStuck) return false;
    if (leave == Leave::kRetry) continue;
    if (last) y1.t = b;
    if (!Finite(y1)) {
      Finish(Termination::kNonFinite, "state became non-finite at t = " + std::to_string(y_.t));
      return false;
    }
    ++result_.stats.steps;
    stepper_.Accept(y_, y1);
    if (StepEvents(y1)) return false;
    EmitUntil(y1.t, true, y_, y1, true);
    y_ = y1;
    if (observer_) observer_(y_);
  }
  return true;
}

ShapeIntegrationResult ShapeDriver::Run(double t_end) {
  // Samples at or before the start: the initial state.
  EmitUntil(y_.t, true, y_, y_, false);
  for (const ShapeEventFunction& e : events_) g_prev_.push_back(e.g(y_));
  if (AlreadyPast()) return std::move(result_);
  for (std::size_t e = 0; e < events_.size(); ++e) {
    leaving_.push_back(events_[e].terminal && events_[e].direction != 0 && g_prev_[e] == 0.0);
  }
  std::vector<double> bounds{y_.t};
  for (double b : system_.Breakpoints(y_.t, t_end)) bounds.push_back(b);
  bounds.push_back(t_end);
  for (std::size_t seg = 0; seg + 1 < bounds.size(); ++seg) {
    if (!Segment(bounds[seg], bounds[seg + 1])) return std::move(result_);
  }
  Finish(Termination::kReachedEnd, ToString(Termination::kReachedEnd));
  return std::move(result_);
}

}  // namespace

ShapeIntegrationResult IntegrateShape(const std::string& method,
                                      const IntegratorSettings& settings,
                                      const dynamics::ShapeSystem& system,
                                      const ShapeState& initial,
                                      double t_end,
                                      const OutputTimes& output_times,
                                      std::size_t* next_output,
                                      const std::vector<ShapeEventFunction>& events,
                                      const std::function<void(const ShapeState&)>& samples,
                                      const std::function<void(const ShapeState&)>& observer) {
  TableauOf(method);  // an unknown method fails first
  if (!(t_end > initial.t) || !std::isfinite(t_end)) {
    throw std::invalid_argument("IntegrateShape: end time must be finite and > start time");
  }
  if (initial.x.size() != 2 * system.free_count()) {
    throw std::invalid_argument("IntegrateShape: the shape state has " +
                                std::to_string(initial.x.size()) + " entries for " +
                                std::to_string(system.free_count()) + " free hinges");
  }
  ShapeDriver driver(method, settings, system, initial, output_times, next_output, events, samples,
                     observer);
  return driver.Run(t_end);
}

}  // namespace deploysim::integrators
