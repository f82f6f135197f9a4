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
#include "deploysim/integrators/driver.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/lie_anchor.h"
#include "deploysim/integrators/rk_engine.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"

namespace deploysim::integrators {

namespace {

using Vec = Eigen::VectorXd;
using lie::Anchor;

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

  /// |w| [rad/s] at y: the hub's rotation rate.
  double RotationRate(const ShapeState& y) {
    math::Vec3 w;
    Rate(y.t, y.H_B, y.x, &w, xdot_);
    return w.norm();
  }

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
        tab_, [&](double ti, const Vec& Yi, Vec& ki) { AlgebraRate(ti, Yi, H0, sigma, y.x, ki); },
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
        // (theta_f, p_f); accumulators after them (ShapeSystem) do not act back and are
        // left out of the error control.
        const int m = sys_.free_count();
        for (int i = 0; i < 2 * m; ++i) {
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
    dense_out_.Reset();
  }

  /// The continuous extension of the accepted step at t.
  ShapeState Dense(double t, const Tolerances& tol) {
    if (t <= acc_.t0) return acc_.y0;
    if (t >= acc_.t1) return acc_.y1;
    const double h = acc_.t1 - acc_.t0;
    const double tau = t - acc_.t0;
    const double th = tau / h;
    const int dim = static_cast<int>(acc_.Y1.size());
    const ShapeState begin = acc_.y0;
    const Vec Y = dense_out_.At(
        dense_, th, h, Vec::Zero(dim), acc_.Y1, acc_.stages,
        [&] {
          Vec f1;
          AlgebraRate(acc_.t1, acc_.Y1, acc_.H0, acc_.sigma, acc_.x0, f1);
          return f1;
        },
        [&](double x, Vec& Y_x, Vec& f_x) {
          Step(begin, x * h, tol, nullptr);
          ++dense_steps_;
          Y_x = last_.Y1;
          AlgebraRate(begin.t + x * h, last_.Y1, acc_.H0, acc_.sigma, acc_.x0, f_x);
        });
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
  StepInterpolant<Vec> dense_out_;
  Vec scratch_, zero_, xdot_, xs_;
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

/// The Lie-group method on the shape state for the driver (driver.h).
class ShapeAdapter {
 public:
  using StateType = ShapeState;

  ShapeAdapter(const ButcherTableau& tableau,
               const dynamics::ShapeSystem& system,
               const Tolerances& tolerances,
               const std::function<void(ShapeState&)>& project)
      : stepper_(tableau, system), system_(system), tol_(tolerances), project_(project) {}

  bool adaptive() const { return stepper_.adaptive(); }
  int order() const { return stepper_.order(); }
  void SetSegment(double /*a*/, double b) { stepper_.SetSegmentEnd(b); }
  std::vector<double> Breakpoints(double t0, double t1) const {
    return system_.Breakpoints(t0, t1);
  }
  double RotationRate(const ShapeState& y) { return stepper_.RotationRate(y); }
  double MaxStep(const ShapeState& /*y*/) { return std::numeric_limits<double>::infinity(); }
  ShapeState Step(const ShapeState& y, double h, double* error_norm) {
    return stepper_.Step(y, h, tol_, error_norm);
  }
  ShapeState Partial(const ShapeState& y0, double h) {
    ++partial_steps_;
    return stepper_.Step(y0, h, tol_, nullptr);
  }
  void Accept(const ShapeState& y0, const ShapeState& y1) { stepper_.Accept(y0, y1); }
  void Project(ShapeState& y) {
    if (project_) project_(y);
  }
  ShapeState Dense(double t) { return stepper_.Dense(t, tol_); }
  ShapeState DenseSample(double t, std::size_t /*samples_in_step*/) { return Dense(t); }
  bool DenseIsExact() { return false; }
  static bool Finite(const ShapeState& s) { return integrators::Finite(s); }
  long evaluations() const { return stepper_.evaluations(); }
  long dense_steps() const { return stepper_.dense_steps() + partial_steps_; }

 private:
  ShapeStepper stepper_;
  long partial_steps_ = 0;
  const dynamics::ShapeSystem& system_;
  const Tolerances& tol_;
  const std::function<void(ShapeState&)>& project_;
};

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
                                      const std::function<void(const ShapeState&)>& observer,
                                      const std::function<void(ShapeState&)>& project) {
  const ButcherTableau& tableau = TableauOf(method);  // an unknown method fails first
  if (!(t_end > initial.t) || !std::isfinite(t_end)) {
    throw std::invalid_argument("IntegrateShape: end time must be finite and > start time");
  }
  if (initial.x.size() < 2 * system.free_count()) {
    throw std::invalid_argument("IntegrateShape: the shape state has " +
                                std::to_string(initial.x.size()) + " entries for " +
                                std::to_string(system.free_count()) + " free hinges");
  }
  if (tableau.b_hat.empty() && !(settings.step > 0.0)) {
    throw std::invalid_argument("integrator " + method +
                                ": step = 0 (rule: a fixed-step method needs a finite step > 0)");
  }
  std::vector<driver::EventSpec<ShapeState>> specs;
  for (const ShapeEventFunction& e : events) {
    specs.push_back({e.name, e.g, e.direction, e.terminal, e.refine, e.rate});
  }
  ShapeAdapter adapter(tableau, system, settings.tolerances, project);
  const std::function<void(const ShapeState&)> emit = [&samples](const ShapeState& s) {
    if (samples) samples(s);
  };
  driver::Driver<ShapeAdapter> run(adapter, settings, initial, output_times, *next_output, specs,
                                   emit, observer, false);
  driver::Outcome<ShapeState> out = run.Run(t_end);
  ShapeIntegrationResult result;
  for (driver::FoundEvent<ShapeState>& e : out.events) {
    result.events.push_back({e.t, e.index, e.direction, std::move(e.state)});
  }
  result.stopped_at_event = out.stopped_at_event;
  result.stuck = out.stuck;
  result.final_state = std::move(out.final_state);
  result.stats = out.stats;
  result.termination = out.termination;
  result.message = std::move(out.message);
  result.next_step = out.next_step;
  return result;
}

}  // namespace deploysim::integrators
