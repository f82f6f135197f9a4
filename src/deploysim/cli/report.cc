#include "deploysim/cli/report.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace deploysim::cli {

namespace {

std::string Num(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (std::isnan(v)) return "nan";
  return fmt::format("{:.6g}", v);
}

std::string JsonNum(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{:.17g}", v);
}

std::string JsonStr(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      o += fmt::format("\\u{:04x}", static_cast<int>(c));
    } else {
      o += c;
    }
  }
  return o + "\"";
}

std::string JsonList(const std::vector<double>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + JsonNum(v[i]);
  return o + "]";
}

}  // namespace

std::string FormatSummary(const analysis::MissionResult& r) {
  std::string o;
  const auto& p = r.profile;
  o += fmt::format("deploysim analysis of '{}' ({}; model '{}', mode {}, coupling {})\n", p.name,
                   p.source, p.model.name, schedule::ToString(p.mode),
                   schedule::ToString(p.coupling));
  o +=
      fmt::format("integrator {}: {} steps, {} rejected, {} rhs evaluations, {:.3g} s wall; {}\n\n",
                  p.integrator.method, r.stats.steps, r.stats.rejected, r.stats.evaluations,
                  r.wall_seconds, r.message);
  o += fmt::format("{:>2}  {:<18} {:<13} {:>9} {:>9}  {:<13} {:<14} {:>10} {:>12} {:>14} {:>9}\n",
                   "#", "stage", "law", "t0 [s]", "t1 [s]", "spin axis", "regime", "1-k^2",
                   "sep. dist.", "flip every [s]", "flips");
  for (const auto& s : r.stages) {
    const std::string flips =
        s.rigid ? fmt::format("{}/{}", s.observed_flips.size(), s.predicted_flips.size())
                : fmt::format("{}", s.observed_flips.size());
    o += fmt::format("{:>2}  {:<18} {:<13} {:>9} {:>9}  {:<13} {:<14} {:>10} {:>12} {:>14} {:>9}\n",
                     s.index, s.name.substr(0, 18), s.law, Num(s.t_begin), Num(s.t_end),
                     analysis::ToString(s.spin_axis_end), s.rigid ? s.regime : "(deploying)",
                     s.rigid ? Num(s.one_minus_k2) : "-", Num(s.separatrix_distance),
                     s.rigid ? Num(s.predicted_flip_half_period) : "-", flips);
  }
  o += "\n(spin axis: role of the body spin axis among the principal axes at the stage end; "
       "flips: observed/predicted for constant stages;\n sep. dist.: (D - I2)/(I3 - I1), 0 on the "
       "separatrix, < 0 circulating about the minor axis)\n\n";
  double worst = 0.0;
  for (const auto& s : r.stages) worst = std::max(worst, s.max_flip_time_difference);
  o += fmt::format("flips located: {}", r.flip_times.size());
  if (!r.flip_times.empty()) {
    o += fmt::format(" (first at {} s); max |located - analytic| on constant stages: {} s",
                     Num(r.flip_times.front()), Num(worst));
  }
  o += "\n";
  if (r.danger_windows.empty()) {
    o += "danger windows (spin axis = intermediate axis): none\n";
  } else {
    o += "danger windows (spin axis = intermediate axis):";
    for (const auto& w : r.danger_windows)
      o += fmt::format(" [{}, {}] s", Num(w.t_begin), Num(w.t_end));
    o += "\n";
  }
  o += fmt::format("invariants: max |h_N(t) - h_N(0)|/|h_N| = {}\n", Num(r.max_h_N_drift));
  return o;
}

std::string FormatCouplingComparison(const analysis::CouplingComparison& c) {
  std::string o = "exact vs quasi-rigid coupling (h_rel from the hinge rates vs h_rel = 0):\n";
  o += fmt::format("  max |w_exact - w_quasi| while deploying: {} rad/s ({} of max |w|)\n",
                   Num(c.max_w_difference_deploying),
                   Num(c.w_scale > 0 ? c.max_w_difference_deploying / c.w_scale : 0.0));
  o += fmt::format("  attitude offset at the end of deployment (t = {} s): {} rad ({} deg)\n",
                   Num(c.deployment_end), Num(c.attitude_offset_at_deployment_end),
                   Num(c.attitude_offset_at_deployment_end * 180.0 / M_PI));
  o += fmt::format("  after deployment: max attitude difference {} rad, max |dH_B|/|H| {}\n",
                   Num(c.max_attitude_difference_after), Num(c.max_H_B_difference_after));
  o += fmt::format("  flips: exact {}, quasi-rigid {}\n", c.exact.flip_times.size(),
                   c.quasi_rigid.flip_times.size());
  return o;
}

std::string FormatJson(const analysis::MissionResult& r, const analysis::CouplingComparison* c) {
  const auto& p = r.profile;
  std::string o = "{\n";
  o += fmt::format("  \"profile\": {},\n  \"source\": {},\n  \"model\": {},\n", JsonStr(p.name),
                   JsonStr(p.source), JsonStr(p.model.name));
  o += fmt::format("  \"mode\": {},\n  \"coupling\": {},\n  \"integrator\": {},\n",
                   JsonStr(schedule::ToString(p.mode)), JsonStr(schedule::ToString(p.coupling)),
                   JsonStr(p.integrator.method));
  o += fmt::format("  \"termination\": {},\n  \"steps\": {},\n  \"rhs_evaluations\": {},\n",
                   JsonStr(r.message), r.stats.steps, r.stats.evaluations);
  o += fmt::format("  \"wall_seconds\": {},\n  \"max_h_N_drift\": {},\n", JsonNum(r.wall_seconds),
                   JsonNum(r.max_h_N_drift));
  o += fmt::format("  \"flip_times\": {},\n  \"stages\": [\n", JsonList(r.flip_times));
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    const auto& s = r.stages[i];
    o += fmt::format(
        "    {{\"index\": {}, \"name\": {}, \"law\": {}, \"t_begin\": {}, \"t_end\": {}, "
        "\"rigid\": {}, \"principal_moments_end\": [{}, {}, {}], \"spin_axis_end\": {}, "
        "\"regime\": {}, \"one_minus_k2\": {}, \"separatrix_distance\": {}, "
        "\"flip_half_period\": {}, \"predicted_flips\": {}, \"observed_flips\": {}, "
        "\"max_flip_time_difference\": {}}}{}\n",
        s.index, JsonStr(s.name), JsonStr(s.law), JsonNum(s.t_begin), JsonNum(s.t_end),
        s.rigid ? "true" : "false", JsonNum(s.moments_end[0]), JsonNum(s.moments_end[1]),
        JsonNum(s.moments_end[2]), JsonStr(analysis::ToString(s.spin_axis_end)),
        s.rigid ? JsonStr(s.regime) : "null", s.rigid ? JsonNum(s.one_minus_k2) : "null",
        JsonNum(s.separatrix_distance), JsonNum(s.predicted_flip_half_period),
        JsonList(s.predicted_flips), JsonList(s.observed_flips),
        JsonNum(s.max_flip_time_difference), i + 1 < r.stages.size() ? "," : "");
  }
  o += "  ],\n  \"danger_windows\": [";
  for (std::size_t i = 0; i < r.danger_windows.size(); ++i) {
    o += fmt::format("{}[{}, {}]", i ? ", " : "", JsonNum(r.danger_windows[i].t_begin),
                     JsonNum(r.danger_windows[i].t_end));
  }
  o += "]";
  if (c != nullptr) {
    o += fmt::format(
        ",\n  \"coupling_comparison\": {{\"max_w_difference_deploying\": {}, \"w_scale\": {}, "
        "\"deployment_end\": {}, \"attitude_offset_at_deployment_end\": {}, "
        "\"max_attitude_difference_after\": {}, \"max_H_B_difference_after\": {}}}",
        JsonNum(c->max_w_difference_deploying), JsonNum(c->w_scale), JsonNum(c->deployment_end),
        JsonNum(c->attitude_offset_at_deployment_end), JsonNum(c->max_attitude_difference_after),
        JsonNum(c->max_H_B_difference_after));
  }
  o += "\n}\n";
  return o;
}

}  // namespace deploysim::cli
