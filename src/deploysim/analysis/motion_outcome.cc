#include "deploysim/analysis/motion_outcome.h"

#include <algorithm>
#include <cmath>

#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::analysis {

namespace {

std::string Deg(double rad) {
  return math::FormatSignificant(rad * math::kDegreesPerRadian, 3) + " deg";
}
std::string Sec(double s) { return math::FormatSignificant(s, 4) + " s"; }

/// The first 45-degree crossing beside its linear prediction: measured (with how far off
/// the prediction was), or predicted beyond the run (a lower bound: the linear growth runs
/// ahead of the motion once the sink saturates); empty if neither.
std::string FirstCrossingText(const MotionOutcome& o) {
  const bool predicted = std::isfinite(o.predicted_45_time);
  const std::string model = o.linear.motion == "periodic" ? "Floquet" : "linear";
  if (std::isfinite(o.first_45_time)) {
    const bool only = o.first_45_time == o.last_45_time;
    std::string t =
        (only ? "; 45 deg from h_N at " : "; first 45-degree crossing at ") + Sec(o.first_45_time);
    if (predicted) {
      const double span = o.first_45_time - o.phase_begin;
      const double off = (o.predicted_45_time - o.first_45_time) / span;
      t += " (the " + model + " growth predicts " + Sec(o.predicted_45_time) + ", " +
           math::FormatSignificant(100.0 * std::abs(off), 2) + " % " +
           (off < 0.0 ? "early" : "late") + ")";
    }
    return t;
  }
  if (!predicted) return "";
  return "; 45 deg predicted by the " + model + " growth at " + Sec(o.predicted_45_time) +
         (o.predicted_45_time > o.t_end
              ? ", beyond the run (a lower bound: the linear growth runs ahead of the motion "
                "once the sink saturates)"
              : ", not reached by the run's end at " + Sec(o.t_end) +
                    " (the linear growth runs ahead of the motion once the sink saturates)");
}

/// "+z (minor axis)".
std::string AxisText(const std::string& axis, AxisRole role) {
  return axis + " (" + ToString(role) + " axis)";
}

}  // namespace

void EnvelopeTracker::Reset(double window) {
  mean_square_ = false;
  window_ = window;
  open_ = need_right_ = have_prev_ = false;
  peaks_.clear();
}

void EnvelopeTracker::ResetMeanSquare(double window) {
  Reset(window);
  mean_square_ = true;
  window_samples_.clear();
}

void EnvelopeTracker::AddMeanSquare(double t, double nu) {
  if (window_samples_.empty()) window_start_ = t;
  window_samples_.push_back({t, nu});
  while (t >= window_start_ + window_) {
    // The window [a, a + L] is complete: trapezoids of w nu^2 and of w, w the Hann weight.
    const double a = window_start_;
    double num = 0.0, den = 0.0;
    for (std::size_t i = 1; i < window_samples_.size(); ++i) {
      const EnvelopePeak& p = window_samples_[i - 1];
      const EnvelopePeak& q = window_samples_[i];
      if (p.t < a || q.t > a + window_) continue;
      auto w = [a, this](double x) { return 1.0 - std::cos(math::kTwoPi * (x - a) / window_); };
      const double h = 0.5 * (q.t - p.t);
      num += h * (w(p.t) * p.nu * p.nu + w(q.t) * q.nu * q.nu);
      den += h * (w(p.t) + w(q.t));
    }
    if (den > 0.0) peaks_.push_back({a + 0.5 * window_, std::sqrt(num / den), false});
    window_start_ += 0.5 * window_;
    std::size_t keep = 0;
    while (keep + 1 < window_samples_.size() && window_samples_[keep + 1].t <= window_start_)
      ++keep;
    window_samples_.erase(window_samples_.begin(),
                          window_samples_.begin() + static_cast<std::ptrdiff_t>(keep));
  }
}

void EnvelopeTracker::Add(double t, double nu) {
  if (mean_square_) return AddMeanSquare(t, nu);
  const EnvelopePeak p{t, nu};
  if (need_right_) {
    right_ = p;
    have_right_ = true;
    need_right_ = false;
  }
  const bool starts = !open_ || t >= window_end_;
  if (open_ && starts) Emit();
  if (starts || nu > best_.nu) {
    if (!open_) window_end_ = t;
    while (window_end_ <= t) window_end_ += window_;
    open_ = true;
    best_ = p;
    left_ = prev_;
    have_left_ = have_prev_;
    have_right_ = false;
    need_right_ = true;
  }
  prev_ = p;
  have_prev_ = true;
}

void EnvelopeTracker::AddPeak(double t, double nu) {
  Add(t, nu);
  have_left_ = have_right_ = need_right_ = false;
}

void EnvelopeTracker::Emit() {
  EnvelopePeak p = best_;
  if (have_left_ && have_right_ && best_.nu > left_.nu && best_.nu >= right_.nu) {
    // The vertex of the parabola through the three samples (uneven spacing allowed).
    const double h0 = best_.t - left_.t, h1 = right_.t - best_.t;
    const double d0 = (best_.nu - left_.nu) / h0, d1 = (right_.nu - best_.nu) / h1;
    const double c = (d1 - d0) / (h0 + h1);            // half the second derivative
    const double s = (d0 * h1 + d1 * h0) / (h0 + h1);  // slope at best_.t
    if (c < 0.0) {
      const double dt = -s / (2.0 * c);
      if (std::abs(dt) <= std::max(h0, h1)) {
        p = {best_.t + dt, best_.nu + s * dt + c * dt * dt, true};
      }
    }
  }
  peaks_.push_back(p);
}

bool ExponentialFit::significant() const {
  return valid && std::abs(rate) > 3.0 * rate_sigma &&
         std::abs(rate) * (t_end - t_begin) > std::log(1.05);
}

double TimeConstant(double rate) {
  if (std::isnan(rate)) return rate;
  return rate != 0.0 ? 1.0 / std::abs(rate) : std::numeric_limits<double>::infinity();
}

double ExponentialFit::time_constant() const { return TimeConstant(rate); }

namespace {

/// Least squares of ln nu = a + rate t over `used`.
ExponentialFit FitLine(const std::vector<EnvelopePeak>& used) {
  ExponentialFit f;
  const std::size_t n = used.size();
  if (n < 3) return f;
  double st = 0.0, sy = 0.0;
  for (const EnvelopePeak& p : used) {
    st += p.t;
    sy += std::log(p.nu);
  }
  const double count = static_cast<double>(n);
  const double tm = st / count, ym = sy / count;
  double stt = 0.0, sty = 0.0;
  for (const EnvelopePeak& p : used) {
    stt += (p.t - tm) * (p.t - tm);
    sty += (p.t - tm) * (std::log(p.nu) - ym);
  }
  if (!(stt > 0.0)) return f;
  f.rate = sty / stt;
  double ss = 0.0;
  for (const EnvelopePeak& p : used) {
    const double r = std::log(p.nu) - ym - f.rate * (p.t - tm);
    ss += r * r;
  }
  f.rate_sigma = std::sqrt(ss / (count - 2.0) / stt);
  f.t_begin = used.front().t;
  f.t_end = used.back().t;
  f.nu_begin = std::exp(ym + f.rate * (f.t_begin - tm));
  f.nu_end = std::exp(ym + f.rate * (f.t_end - tm));
  f.points = static_cast<int>(n);
  f.valid = true;
  return f;
}

}  // namespace

double FitStart(const SteadySpin& s, double phase_begin) {
  if (!s.found) return -std::numeric_limits<double>::infinity();
  double wait = 0.0;
  for (const SpinMode& md : s.modes) {
    const double gap = s.growth_rate - md.lambda.real();
    if (gap > 0.0) wait = std::max(wait, std::log(1e4) / gap);
  }
  return phase_begin + wait;
}

ExponentialFit FitEnvelope(const std::vector<EnvelopePeak>& peaks,
                           double floor,
                           double ceiling,
                           double t_start) {
  // The longest stretch of consecutive peaks inside the band, from `from` on.
  auto stretch = [&](double from, std::size_t& begin, std::size_t& end) {
    begin = end = 0;
    for (std::size_t i = 0; i < peaks.size();) {
      if (!(peaks[i].t >= from && peaks[i].nu >= floor && peaks[i].nu <= ceiling)) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < peaks.size() && peaks[j].nu >= floor && peaks[j].nu <= ceiling) ++j;
      if (j - i > end - begin) begin = i, end = j;
      i = j;
    }
  };
  std::size_t best_begin = 0, best_end = 0;
  stretch(t_start, best_begin, best_end);
  if (best_end - best_begin < 4) {
    // No decay time known (or too few peaks after it): the first quarter is the sink's
    // own transient.
    stretch(-std::numeric_limits<double>::infinity(), best_begin, best_end);
    best_begin += (best_end - best_begin) / 4;
  }
  ExponentialFit f;
  if (best_end - best_begin < 4) return f;
  std::size_t maxima = 0;
  for (std::size_t i = best_begin; i < best_end; ++i) maxima += peaks[i].local_max ? 1 : 0;
  const bool only_maxima = maxima >= 4 && 2 * maxima >= best_end - best_begin;
  std::vector<EnvelopePeak> used;
  for (std::size_t i = best_begin; i < best_end; ++i) {
    if (!only_maxima || peaks[i].local_max) used.push_back(peaks[i]);
  }
  f = FitLine(used);
  if (!f.valid) return f;
  f.ceiling = ceiling;
  // The halves' difference: a bias the standard error does not show.
  const auto half = static_cast<std::ptrdiff_t>(used.size() / 2);
  const ExponentialFit a = FitLine({used.begin(), used.begin() + half});
  const ExponentialFit b = FitLine({used.begin() + half, used.end()});
  f.rate_uncertainty =
      f.rate_sigma + (a.valid && b.valid ? std::abs(a.rate - b.rate) : std::abs(f.rate));
  return f;
}

std::string ToString(OutcomeClass c) {
  switch (c) {
    case OutcomeClass::kIncomplete:
      return "incomplete";
    case OutcomeClass::kFlipping:
      return "flipping";
    case OutcomeClass::kTransition:
      return "transition";
    case OutcomeClass::kGrowing:
      return "growing";
    case OutcomeClass::kDecaying:
      return "decaying";
    case OutcomeClass::kTumbling:
      return "tumbling";
    case OutcomeClass::kBounded:
      return "bounded";
  }
  return "?";
}

std::string OutcomeName(OutcomeClass c, AxisRole phase, AxisRole end) {
  return c == OutcomeClass::kTransition && phase == AxisRole::kMinor && end == AxisRole::kMajor
             ? "flat spin"
             : ToString(c);
}

std::string ToString(DeploymentFault::Kind k) {
  switch (k) {
    case DeploymentFault::Kind::kJam:
      return "jam";
    case DeploymentFault::Kind::kNeverLatched:
      return "never latched";
    case DeploymentFault::Kind::kRestsShort:
      return "rests short of latch";
    case DeploymentFault::Kind::kNeverReleased:
      return "never released";
  }
  return "?";
}

std::string BodyAxisName(const math::Vec3& a) {
  Eigen::Index i = 0;
  a.cwiseAbs().maxCoeff(&i);
  return std::string(a[i] >= 0.0 ? "+" : "-") + "xyz"[i];
}

std::string Headline(const MotionOutcome& o) {
  std::string h;
  for (const DeploymentFault& f : o.faults) {
    h += "panel " + f.panel_name + " ";
    switch (f.kind) {
      case DeploymentFault::Kind::kJam:
        h += "JAMMED at " + Sec(f.t) + " at " + Deg(f.angle) + " (latch at " + Deg(f.latch_angle) +
             ")";
        break;
      case DeploymentFault::Kind::kNeverLatched:
        h += "NEVER LATCHED";
        break;
      case DeploymentFault::Kind::kRestsShort:
        h += "NEVER LATCHED: it rests on a stop at " + Deg(f.angle) + " from " + Sec(f.t) +
             " (latch at " + Deg(f.latch_angle) + ")";
        break;
      case DeploymentFault::Kind::kNeverReleased:
        h += "NEVER RELEASED";
        break;
    }
    h += "; ";
  }
  const std::string start = AxisText(o.axis_start, o.role_phase);
  const ExponentialFit& f = o.trend;
  switch (o.outcome) {
    case OutcomeClass::kIncomplete:
      h += "the run stopped before its end";
      break;
    case OutcomeClass::kFlipping:
      h += "flips every " + Sec(o.flip_interval) + " about " + start + ", " +
           std::to_string(o.flips) + " flips from " + Sec(o.phase_begin);
      break;
    case OutcomeClass::kTransition:
      h += o.outcome_name + ": the spin moves from " + start + " to " +
           AxisText(o.axis_end, o.role_end);
      if (std::isfinite(o.separatrix_time)) {
        h += ", across the separatrix at " + Sec(o.separatrix_time);
      } else if (std::isfinite(o.last_45_time) && o.last_45_time != o.first_45_time) {
        h += ", last 45-degree crossing at " + Sec(o.last_45_time);
      }
      h += FirstCrossingText(o);
      break;
    case OutcomeClass::kGrowing:
      h += "unstable: the nutation about " + start + " grows from " + Deg(o.nutation_begin) +
           " to " + Deg(o.nutation_end) + ", time constant " + Sec(f.time_constant()) +
           FirstCrossingText(o);
      break;
    case OutcomeClass::kDecaying:
      h += "stable: the nutation about " + start + " decays from " + Deg(o.nutation_begin) +
           " to " + Deg(o.nutation_end) + ", time constant " + Sec(f.time_constant());
      break;
    case OutcomeClass::kTumbling:
      h += "no steady spin about " + start + ": it swings up to " + Deg(o.nutation_max) +
           " from the angular momentum";
      break;
    case OutcomeClass::kBounded:
      if (o.linear.found && o.linear.verdict == "unstable") {
        h += "no growth seen yet about " + start + ": the nutation stays within " +
             Deg(o.nutation_max) + " in the run, but the linearization says unstable (time " +
             "constant " + Sec(TimeConstant(o.linear.growth_rate)) + ")" + FirstCrossingText(o);
      } else {
        h += "steady spin about " + start + ", nutation bounded by " + Deg(o.nutation_max);
      }
      break;
  }
  if (!o.disagreement.empty()) h += " (" + o.disagreement + ")";
  h += ".";
  h[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(h[0])));
  return h;
}

namespace {

/// A JSON object, member by member.
class JsonObject {
 public:
  JsonObject& Raw(const std::string& key, const std::string& value) {
    text_ += (text_.size() > 1 ? ", " : "") + math::JsonString(key) + ": " + value;
    return *this;
  }
  JsonObject& Num(const std::string& key, double v) { return Raw(key, math::JsonNumber(v)); }
  JsonObject& Str(const std::string& key, const std::string& v) {
    return Raw(key, math::JsonString(v));
  }
  JsonObject& Bool(const std::string& key, bool v) { return Raw(key, v ? "true" : "false"); }
  std::string Text() const { return text_ + "}"; }

 private:
  std::string text_ = "{";
};

std::string FitJson(const ExponentialFit& f) {
  return JsonObject()
      .Bool("valid", f.valid)
      .Num("rate", f.rate)
      .Num("rate_sigma", f.rate_sigma)
      .Num("rate_uncertainty", f.rate_uncertainty)
      .Num("time_constant", f.time_constant())
      .Num("t_begin", f.t_begin)
      .Num("t_end", f.t_end)
      .Num("nu_begin", f.nu_begin)
      .Num("nu_end", f.nu_end)
      .Num("points", f.points)
      .Num("ceiling", f.ceiling)
      .Text();
}

std::string LinearJson(const SteadySpin& s) {
  std::string modes = "[";
  for (std::size_t i = 0; i < s.modes.size(); ++i) {
    modes += (i ? ", [" : "[") + math::JsonNumber(s.modes[i].lambda.real()) + ", " +
             math::JsonNumber(s.modes[i].lambda.imag()) + ", " +
             math::JsonNumber(s.modes[i].momentum_share) + "]";
  }
  return JsonObject()
      .Bool("found", s.found)
      .Str("reason", s.reason)
      .Str("motion", s.motion)
      .Num("period", s.motion == "periodic" ? s.period : std::numeric_limits<double>::quiet_NaN())
      .Num("residual", s.residual)
      .Str("verdict", s.verdict)
      .Num("growth_rate", s.growth_rate)
      .Num("time_constant", TimeConstant(s.growth_rate))
      .Num("frequency", s.frequency)
      .Num("max_real", s.max_real)
      .Num("quasi_rigid_rate", s.quasi_rigid_rate)
      .Num("rigid_frequency", s.rigid_frequency)
      .Raw("modes", modes + "]")
      .Text();
}

}  // namespace

std::string OutcomeJson(const MotionOutcome& o) {
  std::string faults = "[";
  for (std::size_t i = 0; i < o.faults.size(); ++i) {
    const DeploymentFault& d = o.faults[i];
    faults += (i ? ", " : "") + JsonObject()
                                    .Str("kind", ToString(d.kind))
                                    .Num("panel", d.panel)
                                    .Str("panel_name", d.panel_name)
                                    .Num("t", d.t)
                                    .Num("angle", d.angle)
                                    .Num("latch_angle", d.latch_angle)
                                    .Text();
  }
  return JsonObject()
      .Str("class", ToString(o.outcome))
      .Str("name", o.outcome_name)
      .Str("headline", o.headline)
      .Str("axis_start", o.axis_start)
      .Str("role_start", ToString(o.role_start))
      .Str("axis_end", o.axis_end)
      .Str("role_end", ToString(o.role_end))
      .Str("role_phase", ToString(o.role_phase))
      .Num("phase_begin", o.phase_begin)
      .Num("t_end", o.t_end)
      .Num("nutation_begin", o.nutation_begin)
      .Num("nutation_end", o.nutation_end)
      .Num("nutation_max", o.nutation_max)
      .Raw("trend", FitJson(o.trend))
      .Num("flips", o.flips)
      .Num("flip_interval", o.flip_interval)
      .Num("transition_time", o.transition_time)
      .Num("separatrix_time", o.separatrix_time)
      .Num("first_45_time", o.first_45_time)
      .Num("last_45_time", o.last_45_time)
      .Num("predicted_45_time", o.predicted_45_time)
      .Num("time_to_tumble", o.time_to_tumble)
      .Raw("time_to_tumble_measured", o.time_to_tumble_measured ? "true" : "false")
      .Num("max_excursion", o.max_excursion)
      .Raw("faults", faults + "]")
      .Raw("linear", LinearJson(o.linear))
      .Str("rigid_rule", o.rigid_rule)
      .Str("disagreement", o.disagreement)
      .Text();
}

}  // namespace deploysim::analysis
