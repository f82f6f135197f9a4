#include "deploysim/cli/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "deploysim/analysis/work_estimate.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"
#include "deploysim/schedule/profile_warnings.h"

namespace deploysim::cli {

namespace {

std::string Num(double v) { return math::FormatSignificant(v, 6); }

std::string JsonList(const std::vector<double>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + math::JsonNumber(v[i]);
  return o + "]";
}

constexpr double kDegPerRad = math::kDegreesPerRadian;

/// One sample as a JSON object, a member per column of the schema: a number (scalars),
/// a list (vectors, quaternions w x y z, per-panel values) or a list of rows (matrices).
/// "null" when there is no sample.
std::string SampleJson(const run::Trajectory& t,
                       std::size_t k,
                       const run::TrajectorySchema& schema) {
  if (k >= t.size()) return "null";
  const std::size_t panels = run::PanelCount(t);
  std::string o = "{";
  for (const run::TrajectoryColumn& c : schema.columns()) {
    std::vector<double> v(run::Width(c, panels));
    if (!v.empty()) c.values(t, k, v.data());
    std::string value;
    if (c.shape == run::ColumnShape::kScalar) {
      value = math::JsonNumber(v[0]);
    } else if (c.shape == run::ColumnShape::kMatrix3) {
      value = fmt::format("[{}, {}, {}]", JsonList({v[0], v[1], v[2]}),
                          JsonList({v[3], v[4], v[5]}), JsonList({v[6], v[7], v[8]}));
    } else {
      value = JsonList(v);
    }
    o += fmt::format("{}{}: {}", o.size() > 1 ? ", " : "", math::JsonString(c.name), value);
  }
  return o + "}";
}

std::string PanelName(const run::MissionResult& r, int panel) {
  const auto& panels = r.profile().model.hinged.panels;
  if (panel < 0 || static_cast<std::size_t>(panel) >= panels.size()) {
    return "#" + std::to_string(panel);
  }
  return panels[static_cast<std::size_t>(panel)].name;
}

/// Per panel of the model: the index of the appendage whose bending hinge it is (a
/// generated free hinge, model::Appendage::hinges), or -1 (the model file's own panels and
/// an appendage's root stub, which a profile deploys like any panel).
std::vector<int> BendingHingeOwners(const model::Model& m) {
  std::vector<int> owner(m.hinged.panels.size(), -1);
  for (std::size_t i = 0; i < m.appendages.size(); ++i) {
    for (int h : m.appendages[i].hinges) {
      if (h >= 0 && static_cast<std::size_t>(h) < owner.size()) {
        owner[static_cast<std::size_t>(h)] = static_cast<int>(i);
      }
    }
  }
  return owner;
}

/// One list of panel names ("a, b, c") with each appendage's bending hinges replaced by
/// the appendage's name and their count, where its first hinge was: "wing, boom_px (12)".
std::string GroupedList(const model::Model& m,
                        const std::map<std::string, int>& owner,
                        const std::string& list) {
  std::vector<std::string> shown;
  std::vector<int> count(m.appendages.size(), 0);
  std::vector<std::size_t> slot(m.appendages.size(), std::string::npos);
  for (std::size_t pos = 0; pos <= list.size();) {
    const std::size_t end = std::min(list.find(", ", pos), list.size());
    const std::string item = list.substr(pos, end - pos);
    const auto it = owner.find(item);
    if (it == owner.end()) {
      shown.push_back(item);
    } else {
      const auto a = static_cast<std::size_t>(it->second);
      if (slot[a] == std::string::npos) {
        slot[a] = shown.size();
        shown.emplace_back();
      }
      ++count[a];
    }
    pos = end + 2;
  }
  for (std::size_t a = 0; a < slot.size(); ++a) {
    if (slot[a] != std::string::npos) {
      shown[slot[a]] = fmt::format("{} ({})", m.appendages[a].name, count[a]);
    }
  }
  std::string out;
  for (std::size_t i = 0; i < shown.size(); ++i) out += (i ? ", " : "") + shown[i];
  return out;
}

/// A hinge profile's phase name as the text shows it: each list of panels ("free: a, b;
/// moved: c", run/hinge_body.cc) with an appendage's bending hinges named once,
/// by the appendage and their count ("free: boom_px (12), boom_mx (6)"). The name itself
/// (the HDF5 file's /stages/name, --json) keeps every hinge.
std::string PhaseLabel(const model::Model& m, const std::string& name) {
  std::map<std::string, int> owner;  // a bending hinge's panel name -> its appendage
  const std::vector<int> owners = BendingHingeOwners(m);
  for (std::size_t k = 0; k < owners.size(); ++k) {
    if (owners[k] >= 0) owner[m.hinged.panels[k].name] = owners[k];
  }
  if (owner.empty()) return name;
  std::string out;
  for (std::size_t pos = 0; pos <= name.size();) {
    const std::size_t end = std::min(name.find("; ", pos), name.size());
    const std::string part = name.substr(pos, end - pos);
    const std::size_t colon = part.find(": ");
    out += (pos ? "; " : "");
    out += colon == std::string::npos
               ? part
               : part.substr(0, colon + 2) + GroupedList(m, owner, part.substr(colon + 2));
    pos = end + 2;
  }
  return out;
}

/// "appendages: boom_px (beam: 6 segments, 2 planes, 12 bending hinges), ..." for a model
/// with appendages, else empty.
std::string AppendagesLine(const model::Model& m) {
  std::string o;
  for (const model::Appendage& a : m.appendages) {
    o += o.empty() ? "appendages: " : ", ";
    if (a.kind == model::Appendage::Kind::kBeam) {
      const std::size_t planes = a.chain_frequencies.size();
      // A beam reduced to its first clamped modes (model::Appendage::modes) says in how many.
      const std::string modal =
          a.modes.cols() > 0 ? fmt::format(" in {} modal coordinates", a.modes.cols()) : "";
      o += fmt::format("{} (beam: {} segments, {} plane{}, {} bending hinges{})", a.name,
                       a.segments, planes, planes == 1 ? "" : "s", a.hinges.size(), modal);
    } else {
      o += fmt::format("{} (slosh pendulum: {} hinges)", a.name, a.hinges.size());
    }
  }
  return o.empty() ? o : o + "\n";
}

/// The stage column's width: 18 for stage profiles, wider for the longer names of a
/// hinge profile's phases ("free: wing_plus_x, wing_minus_x"), at most 48.
std::size_t StageNameWidth(const run::MissionResult& r) {
  std::size_t w = 18;
  for (const auto& s : r.stages) {
    w = std::max(w, std::min<std::size_t>(PhaseLabel(r.profile().model, s.name).size(), 48));
  }
  return w;
}

/// One line per run of consecutive stages with the same caveat, "!" marking the ones
/// whose verdict holds only for a perfectly rigid body (docs/design.md 2.7, major-axis rule).
std::string FormatCaveats(const run::MissionResult& r) {
  if (r.stages.empty()) return "";
  std::string o =
      "caveats (what each stage's verdict assumes; ! = holds only for a perfectly rigid "
      "body):\n";
  for (std::size_t i = 0; i < r.stages.size();) {
    std::size_t j = i + 1;
    while (j < r.stages.size() && r.stages[j].caveat == r.stages[i].caveat &&
           r.stages[j].rigid_body_only == r.stages[i].rigid_body_only) {
      ++j;
    }
    const std::string range = j - i == 1
                                  ? fmt::format("{}", r.stages[i].index)
                                  : fmt::format("{}-{}", r.stages[i].index, r.stages[j - 1].index);
    o += fmt::format("{} {:<6} {}\n", r.stages[i].rigid_body_only ? "!" : " ", range,
                     r.stages[i].caveat.empty() ? "-" : r.stages[i].caveat);
    i = j;
  }
  return o;
}

}  // namespace

/// The energy ledger at the end (run::WorkLedger): E0 -> E1 and where it went, the
/// sources that did no work left out.
std::string FormatLedger(const run::MissionResult& r) {
  const run::WorkLedger& w = r.work;
  std::string terms;
  for (const auto& [name, value] : {std::pair<const char*, double>{"dampers", w.damper},
                                    {"friction", w.friction},
                                    {"motors", w.motor},
                                    {"drives", w.drive},
                                    {"impacts", w.impacts}}) {
    if (value != 0.0)
      terms += fmt::format("{}{} {} J", terms.empty() ? "" : ", ", name, Num(value));
  }
  const double gap = r.energy_final - r.energy_initial - w.sum();
  return fmt::format(
      "energy ledger: E = T + V from {} to {} J; work done on the system: {}; unaccounted {} "
      "J\n",
      Num(r.energy_initial), Num(r.energy_final), terms.empty() ? "none" : terms, Num(gap));
}

/// The outcome block: the headline, then what was measured and what was predicted.
std::string FormatOutcome(const run::MissionResult& r) {
  const analysis::MotionOutcome& o = r.outcome;
  if (o.headline.empty()) return "";  // a result not made by a run
  constexpr double kDeg = math::kDegreesPerRadian;
  std::string t = fmt::format("verdict: {}\n", o.headline);
  t += fmt::format(
      "  measured: {} from {} s; spin axis {} ({}) -> {} ({}); nutation {} -> {} deg, largest "
      "{} deg; largest spin-axis excursion {} deg\n",
      o.outcome_name, Num(o.phase_begin), o.axis_start, analysis::ToString(o.role_start),
      o.axis_end, analysis::ToString(o.role_end), Num(o.nutation_begin * kDeg),
      Num(o.nutation_end * kDeg), Num(o.nutation_max * kDeg), Num(o.max_excursion * kDeg));
  if (o.trend.valid) {
    t += fmt::format(
        "  envelope fit{}: rate {} +- {} 1/s (standard error {}; time constant {} s) over {} "
        "peaks, {}..{} s\n",
        o.trend.ceiling > analysis::kFitCeiling ? " (nutation up to 45 deg: the trend, not a "
                                                  "linear rate)"
                                                : "",
        Num(o.trend.rate), Num(o.trend.rate_uncertainty), Num(o.trend.rate_sigma),
        Num(o.trend.time_constant()), o.trend.points, Num(o.trend.t_begin), Num(o.trend.t_end));
  }
  if (o.linear.found) {
    t += fmt::format(
        "  linear stability of the {}: {}; nutation mode rate {} 1/s (time constant "
        "{} s), frequency {} rad/s{}",
        o.linear.motion == "periodic"
            ? fmt::format("periodic motion (period {} s, Floquet, residual {})",
                          Num(o.linear.period), Num(o.linear.residual))
            : std::string("steady spin"),
        o.linear.verdict, Num(o.linear.growth_rate),
        Num(analysis::TimeConstant(o.linear.growth_rate)), Num(o.linear.frequency),
        o.linear.motion == "periodic" ? " (modulo 2 pi / period)" : "");
    if (std::isfinite(o.linear.quasi_rigid_rate)) {
      t += fmt::format("; quasi-rigid estimate {} 1/s", Num(o.linear.quasi_rigid_rate));
    }
    if (std::isfinite(o.predicted_45_time)) {
      t += fmt::format("; 45 deg predicted at {} s", Num(o.predicted_45_time));
    }
    t += "\n";
  } else if (!o.linear.reason.empty()) {
    t += fmt::format("  linear stability: none ({})\n", o.linear.reason);
  }
  if (o.time_to_tumble_measured) {
    t += fmt::format("  time to tumble (45 deg from h_N): {} s after {} s, measured\n",
                     Num(o.time_to_tumble), Num(o.phase_begin));
  } else if (std::isfinite(o.time_to_tumble)) {
    t += fmt::format(
        "  time to tumble (45 deg from h_N): {} s after {} s, predicted from the linear rate (not "
        "reached in the run)\n",
        Num(o.time_to_tumble), Num(o.phase_begin));
  } else if (std::isinf(o.time_to_tumble)) {
    t += "  time to tumble: never (the steady spin does not grow)\n";
  }
  if (!o.rigid_rule.empty()) t += fmt::format("  rigid-body rule: {}\n", o.rigid_rule);
  return t + "\n";
}

std::string FormatSummary(const run::MissionResult& r) {
  std::string o;
  const auto& p = r.profile();
  o += fmt::format("deploysim analysis of '{}' ({}; model '{}', mode {}, coupling {})\n", p.name,
                   p.source, p.model.name, schedule::ToString(p.mode),
                   schedule::ToString(p.coupling));
  o += AppendagesLine(p.model);
  o += fmt::format("integrator {}: {} steps, {} rejected, {} rhs evaluations, {:.3g} s wall; {}\n",
                   p.integrator.method, r.stats.steps, r.stats.rejected, r.stats.evaluations,
                   r.wall_seconds, r.message);
  // The estimate made before the run (analysis/work_estimate.h), beside what it took.
  const analysis::WorkEstimate& e = r.run->work();
  if (e.steps > 0.0) {
    o += fmt::format("work estimate before the run: {} (measured {:.3g} of the steps)\n",
                     analysis::DescribeWork(e), static_cast<double>(r.stats.steps) / e.steps);
  }
  o += "\n";
  o += FormatOutcome(r);
  // One row per stage; in a hinge profile one row per run of consecutive phases of the
  // same hinges and law (a stop impact starts a new phase: a panel bouncing 100 times on
  // its stop would otherwise fill 100 rows), with the values at the run's end.
  struct Row {
    std::string index;
    const run::StageReport* first;
    const run::StageReport* last;
    std::size_t observed = 0, predicted = 0;
  };
  std::vector<Row> rows;
  bool merged = false;
  for (const auto& s : r.stages) {
    if (p.is_hinge_profile() && !rows.empty() && rows.back().last->name == s.name &&
        rows.back().last->law == s.law && rows.back().last->rigid == s.rigid) {
      Row& row = rows.back();
      row.last = &s;
      row.index = fmt::format("{}-{}", row.first->index, s.index);
      row.observed += s.observed_flips.size();
      row.predicted += s.predicted_flips.size();
      merged = true;
      continue;
    }
    rows.push_back(
        {fmt::format("{}", s.index), &s, &s, s.observed_flips.size(), s.predicted_flips.size()});
  }
  std::size_t index_width = 2;
  for (const Row& row : rows) index_width = std::max(index_width, row.index.size());
  const std::size_t name_width = StageNameWidth(r);
  o += fmt::format("{:>{}}  {:<{}} {:<13} {:>9} {:>9}  {:<13} {:<14} {:>10} {:>14} {:>14} {:>9}\n",
                   "#", index_width, "stage", name_width, "law", "t0 [s]", "t1 [s]", "spin axis",
                   "polhode about", "1-k^2 [-]", "sep. dist. [-]", "flip every [s]", "flips");
  for (const Row& row : rows) {
    const run::StageReport& s = *row.last;
    const std::string flips = s.rigid ? fmt::format("{}/{}", row.observed, row.predicted)
                                      : fmt::format("{}", row.observed);
    const std::string regime = s.rigid           ? s.regime
                               : s.law == "free" ? "(free hinges)"
                                                 : "(deploying)";
    o += fmt::format(
        "{:>{}}  {:<{}} {:<13} {:>9} {:>9}  {:<13} {:<14} {:>10} {:>14} {:>14} {:>9}\n", row.index,
        index_width, PhaseLabel(p.model, s.name).substr(0, name_width), name_width, s.law,
        Num(row.first->t_begin), Num(s.t_end), analysis::ToString(s.spin_axis_end), regime,
        s.rigid ? Num(s.one_minus_k2) : "-", Num(s.separatrix_distance),
        s.rigid ? Num(s.predicted_flip_half_period) : "-", flips);
  }
  if (merged) {
    o += "\n(a-b: consecutive phases of the same free hinges, split at stop impacts; spin axis, "
         "polhode and sep. dist. at the end of the last)";
  }
  o += "\n(spin axis: role of the body spin axis among the principal axes at the stage end;\n"
       " polhode about: the principal axis the angular velocity circulates about in the body "
       "(D < I2: minor, D > I2: major);\n"
       " an intermediate spin axis on a minor- or major-axis polhode is a spin that flips;\n"
       " 1-k^2: complementary elliptic parameter, 0 on the separatrix; flips: observed/predicted "
       "for constant stages;\n sep. dist.: (D - I2)/(I3 - I1), 0 on the separatrix, < 0 "
       "circulating about the minor axis)\n\n";
  const std::string caveats = FormatCaveats(r);
  if (!caveats.empty()) o += caveats + "\n";
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
  o += FormatLedger(r);
  return o;
}

/// "panels locked (latch, jam or rest on a stop): wing 61.2 s (latch), boom never": per
/// panel when it locked and how (the locking event at that time); the appendages' bending
/// hinges left out (free springs, they never lock). Empty for stage profiles.
std::string LockedLine(const run::MissionResult& r) {
  const std::vector<int> owner = BendingHingeOwners(r.profile().model);
  std::string locked;
  for (std::size_t k = 0; k < r.latch_times.size(); ++k) {
    if (k < owner.size() && owner[k] >= 0) continue;
    const double t = r.latch_times[k];
    locked += locked.empty() ? "" : ", ";
    locked += PanelName(r, static_cast<int>(k)) + " ";
    if (std::isnan(t)) {
      locked += "never";
      continue;
    }
    std::string how;
    for (const run::HingeEvent& e : r.hinge_events) {
      if (e.panel == static_cast<int>(k) && e.t == t && e.kind != run::HingeEvent::Kind::kRelease &&
          e.kind != run::HingeEvent::Kind::kStop) {
        how = run::ToString(e.kind);
      }
    }
    locked += fmt::format("{} s{}", Num(t), how.empty() ? "" : " (" + how + ")");
  }
  if (r.latch_times.empty() || locked.empty()) return "";
  return "panels locked (latch, jam or rest on a stop): " + locked + "\n";
}

/// The hinge events the timeline lists: all but the releases of the appendages' bending
/// hinges at the run's start (free from the start by construction; AppendagesLine names
/// them once). The file and --json keep them. `hidden`: how many were left out.
std::vector<run::HingeEvent> ListedEvents(const run::MissionResult& r, std::size_t& hidden) {
  const std::vector<int> owner = BendingHingeOwners(r.profile().model);
  const double t0 = r.profile().t_begin();
  std::vector<run::HingeEvent> out;
  hidden = 0;
  for (const run::HingeEvent& e : r.hinge_events) {
    const bool bending = e.panel >= 0 && static_cast<std::size_t>(e.panel) < owner.size() &&
                         owner[static_cast<std::size_t>(e.panel)] >= 0;
    if (bending && e.kind == run::HingeEvent::Kind::kRelease && e.t <= t0) {
      ++hidden;
      continue;
    }
    out.push_back(e);
  }
  return out;
}

std::string FormatTimeline(const run::MissionResult& r) {
  if (!r.profile().is_hinge_profile() && r.hinge_events.empty()) return "";
  std::size_t name_width = 5;  // "panel"
  for (const auto& p : r.profile().model.hinged.panels) {
    name_width = std::max(name_width, p.name.size());
  }
  std::string o = "deployment timeline (hinge events):\n";
  o += fmt::format("{:>10}  {:<{}}  {:<7} {:>9} {:>11} {:>11} {:>12} {:>13} {:>12}\n", "t [s]",
                   "panel", name_width, "event", "angle", "rate before", "rate after", "impulse",
                   "|hub w jump|", "dissipated");
  o += fmt::format("{:>10}  {:<{}}  {:<7} {:>9} {:>11} {:>11} {:>12} {:>13} {:>12}\n", "", "",
                   name_width, "", "[deg]", "[deg/s]", "[deg/s]", "[N m s]", "[deg/s]", "[J]");
  auto line = [&](const run::HingeEvent& e) {
    const bool release = e.kind == run::HingeEvent::Kind::kRelease;
    o += fmt::format("{:>10}  {:<{}}  {:<7} {:>9} {:>11} {:>11} {:>12} {:>13} {:>12}\n", Num(e.t),
                     PanelName(r, e.panel), name_width, run::ToString(e.kind),
                     Num(e.angle * kDegPerRad), release ? "-" : Num(e.rate_before * kDegPerRad),
                     release ? "-" : Num(e.rate_after * kDegPerRad), release ? "-" : Num(e.impulse),
                     release ? "-" : Num(e.w_jump_B.norm() * kDegPerRad),
                     release ? "-" : Num(e.energy_dissipated));
  };
  std::size_t hidden = 0;
  const std::vector<run::HingeEvent> events = ListedEvents(r, hidden);
  if (hidden > 0) {
    o += fmt::format(
        "  ({} hinges the appendages generated, free from t = {} s, not listed: their "
        "releases are in --json and the HDF5 file)\n",
        hidden, Num(r.profile().t_begin()));
  }
  for (std::size_t i = 0; i < events.size();) {
    // A run of stop impacts of one panel (bounces, which with restitution e < 1 can number
    // a hundred before the panel rests): the first kStopsShown, one summary line, the last.
    std::size_t j = i;
    while (j < events.size() && events[j].kind == run::HingeEvent::Kind::kStop &&
           events[j].panel == events[i].panel) {
      ++j;
    }
    constexpr std::size_t kStopsShown = 3;
    if (j - i <= kStopsShown + 2) {
      line(events[i]);
      ++i;
      continue;
    }
    for (std::size_t k = i; k < i + kStopsShown; ++k) line(events[k]);
    double hidden_energy = 0.0;
    for (std::size_t k = i + kStopsShown; k + 1 < j; ++k)
      hidden_energy += events[k].energy_dissipated;
    o += fmt::format(
        "{:>10}  {:<{}}  {} more stop impacts from t = {} to {} s, {} J dissipated "
        "(all in --json and the HDF5 file)\n",
        "...", PanelName(r, events[i].panel), name_width, j - i - kStopsShown - 1,
        Num(events[i + kStopsShown].t), Num(events[j - 2].t), Num(hidden_energy));
    line(events[j - 1]);
    i = j;
  }
  if (r.hinge_events.empty()) o += "  (no hinge events)\n";
  if (!r.hinge_events.empty() && events.empty()) o += "  (no other hinge events)\n";
  double dissipated = 0.0;
  for (const run::HingeEvent& e : r.hinge_events) dissipated += e.energy_dissipated;
  o += fmt::format("energy dissipated in the events: {} J\n", Num(dissipated));
  o += LockedLine(r);
  if (r.spin_axis_45_crossings.empty()) {
    o += "spin axis 45 deg from h_N: never\n";
  } else {
    o += fmt::format("spin axis 45 deg from h_N: first at {} s ({} crossing{})\n",
                     Num(r.spin_axis_45_crossings.front()), r.spin_axis_45_crossings.size(),
                     r.spin_axis_45_crossings.size() == 1 ? "" : "s");
  }
  return o;
}

std::string FormatCouplingComparison(const run::CouplingComparison& c) {
  std::string o = "exact vs quasi-rigid coupling (h_rel from the hinge rates vs h_rel = 0):\n";
  o += fmt::format("  max |w_exact - w_quasi| while deploying: {} rad/s ({} of max |w|)\n",
                   Num(c.max_w_difference_deploying),
                   Num(c.w_scale > 0 ? c.max_w_difference_deploying / c.w_scale : 0.0));
  o += fmt::format("  attitude offset at the end of deployment (t = {} s): {} rad ({} deg)\n",
                   Num(c.deployment_end), Num(c.attitude_offset_at_deployment_end),
                   Num(c.attitude_offset_at_deployment_end * kDegPerRad));
  o += fmt::format("  after deployment: max attitude difference {} rad, max |dH_B|/|H| {}\n",
                   Num(c.max_attitude_difference_after), Num(c.max_H_B_difference_after));
  o += fmt::format("  flips: exact {}, quasi-rigid {}\n", c.exact.flip_times.size(),
                   c.quasi_rigid.flip_times.size());
  return o;
}

namespace {

/// One stage row as a JSON object: a key per column of run::StageTable (null where the
/// column does not apply to the row), then the stage's predicted and observed flips.
std::string StageJson(const run::StageRow& row) {
  using Column = run::StageColumn;
  std::string o = "{";
  for (const Column& c : run::StageTable::Columns()) {
    o += (o.size() > 1 ? ", " : "") + math::JsonString(c.name) + ": ";
    if (c.applies && !c.applies(row)) {
      o += "null";
    } else if (c.type == Column::Type::kText) {
      o += math::JsonString(c.text(row));
    } else {
      double v[3];
      c.number(row, v);
      if (c.type == Column::Type::kFlag) {
        o += v[0] != 0.0 ? "true" : "false";
      } else if (c.type == Column::Type::kInteger) {
        o += std::to_string(static_cast<long long>(v[0]));
      } else if (c.width() == 1) {
        o += math::JsonNumber(v[0]);
      } else {
        o += fmt::format("[{}, {}, {}]", math::JsonNumber(v[0]), math::JsonNumber(v[1]),
                         math::JsonNumber(v[2]));
      }
    }
  }
  return o + ", \"predicted_flips\": " + JsonList(row.predicted_flips) +
         ", \"observed_flips\": " + JsonList(row.observed_flips) + "}";
}

/// One hinge event as a JSON object, a key per column of run::HingeEventTable.
std::string HingeEventJson(const run::MissionResult& r, const run::HingeEvent& e) {
  using Column = run::HingeEventColumn;
  std::vector<std::string> names;
  for (const model::Panel& p : r.profile().model.hinged.panels) names.push_back(p.name);
  std::string o = "{";
  for (const Column& c : run::HingeEventTable::Columns()) {
    o += (o.size() > 1 ? ", " : "") + math::JsonString(c.name) + ": ";
    if (c.type == Column::Type::kText) {
      o += math::JsonString(c.text(e, names));
      continue;
    }
    double v[3];
    c.number(e, v);
    if (c.type == Column::Type::kInteger) {
      o += std::to_string(static_cast<long long>(v[0]));
    } else if (c.width() == 1) {
      o += math::JsonNumber(v[0]);
    } else {
      o += fmt::format("[{}, {}, {}]", math::JsonNumber(v[0]), math::JsonNumber(v[1]),
                       math::JsonNumber(v[2]));
    }
  }
  return o + "}";
}

}  // namespace

std::string FormatJson(const run::MissionResult& r,
                       const run::CouplingComparison* c,
                       const run::TrajectorySchema& schema) {
  const auto& p = r.profile();
  std::string o = "{\n";
  o += fmt::format("  \"profile\": {},\n  \"source\": {},\n  \"model\": {},\n",
                   math::JsonString(p.name), math::JsonString(p.source),
                   math::JsonString(p.model.name));
  o += fmt::format("  \"mode\": {},\n  \"coupling\": {},\n  \"integrator\": {},\n",
                   math::JsonString(schedule::ToString(p.mode)),
                   math::JsonString(schedule::ToString(p.coupling)),
                   math::JsonString(p.integrator.method));
  o += fmt::format("  \"termination\": {},\n  \"steps\": {},\n  \"rhs_evaluations\": {},\n",
                   math::JsonString(r.message), r.stats.steps, r.stats.evaluations);
  o += fmt::format("  \"wall_seconds\": {},\n  \"max_h_N_drift\": {},\n",
                   math::JsonNumber(r.wall_seconds), math::JsonNumber(r.max_h_N_drift));
  o += "  \"outcome\": " + analysis::OutcomeJson(r.outcome) + ",\n";
  o += "  \"warnings\": " + schedule::ProfileWarningsJson(p) + ",\n";
  o += fmt::format("  \"flip_times\": {},\n  \"stages\": [\n", JsonList(r.flip_times));
  const std::vector<run::StageRow> rows = run::StageRows(r);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    o += "    " + StageJson(rows[i]) + (i + 1 < rows.size() ? "," : "") + "\n";
  }
  o += "  ],\n  \"danger_windows\": [";
  for (std::size_t i = 0; i < r.danger_windows.size(); ++i) {
    std::string w;
    for (const run::DangerWindowColumn& col : run::DangerWindowTable::Columns()) {
      w += (w.empty() ? "" : ", ") + math::JsonString(col.name) + ": " +
           math::JsonNumber(col.value(r.danger_windows[i]));
    }
    o += std::string(i ? ", " : "") + "{" + w + "}";
  }
  o += "]";
  // Hinge profiles only; empty lists otherwise. SI units, as in the HDF5 file.
  o += ",\n  \"hinge_events\": [";
  for (std::size_t i = 0; i < r.hinge_events.size(); ++i) {
    o += (i ? ",\n    " : "\n    ") + HingeEventJson(r, r.hinge_events[i]);
  }
  o += r.hinge_events.empty() ? "]" : "\n  ]";
  o += ",\n  \"latch_times\": {";
  for (std::size_t k = 0; k < r.latch_times.size(); ++k) {
    o += fmt::format("{}{}: {}", k ? ", " : "", math::JsonString(PanelName(r, static_cast<int>(k))),
                     math::JsonNumber(r.latch_times[k]));
  }
  o += "}";
  o += fmt::format(",\n  \"spin_axis_45_crossings\": {}", JsonList(r.spin_axis_45_crossings));
  o += ",\n  \"last_sample\": " + SampleJson(r.last_sample, 0, schema);
  if (c != nullptr) {
    o += fmt::format(
        ",\n  \"coupling_comparison\": {{\"max_w_difference_deploying\": {}, \"w_scale\": {}, "
        "\"deployment_end\": {}, \"attitude_offset_at_deployment_end\": {}, "
        "\"max_attitude_difference_after\": {}, \"max_H_B_difference_after\": {}}}",
        math::JsonNumber(c->max_w_difference_deploying), math::JsonNumber(c->w_scale),
        math::JsonNumber(c->deployment_end), math::JsonNumber(c->attitude_offset_at_deployment_end),
        math::JsonNumber(c->max_attitude_difference_after),
        math::JsonNumber(c->max_H_B_difference_after));
  }
  o += "\n}\n";
  return o;
}

}  // namespace deploysim::cli
