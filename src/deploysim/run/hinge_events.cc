#include "deploysim/run/hinge_events.h"

#include <stdexcept>
#include <utility>

#include "deploysim/run/record_table.h"

namespace deploysim::run {

std::string ToString(HingeEvent::Kind kind) {
  switch (kind) {
    case HingeEvent::Kind::kRelease:
      return "release";
    case HingeEvent::Kind::kLatch:
      return "latch";
    case HingeEvent::Kind::kJam:
      return "jam";
    case HingeEvent::Kind::kStop:
      return "stop";
    case HingeEvent::Kind::kRest:
      return "rest";
    case HingeEvent::Kind::kLiftOff:
      return "lift-off";
    case HingeEvent::Kind::kStick:
      return "stick";
    case HingeEvent::Kind::kSlip:
      return "slip";
  }
  return "unknown";
}

HingeEvent::Kind ParseHingeEventKind(const std::string& name) {
  std::string names;
  for (HingeEvent::Kind k : kHingeEventKinds) {
    if (ToString(k) == name) return k;
    names += (names.empty() ? "" : ", ") + ToString(k);
  }
  throw std::invalid_argument("'" + name + "' is not a hinge event kind (" + names + ")");
}

namespace {

using Column = HingeEventColumn;
using Type = HingeEventColumn::Type;

Column Make(std::string name, std::string units, std::string desc, Type type) {
  Column c;
  c.name = std::move(name);
  c.units = std::move(units);
  c.description = std::move(desc);
  c.type = type;
  return c;
}

/// A real column stored in the member `m`.
Column Real(double HingeEvent::*m, std::string name, std::string units, std::string desc) {
  Column c = Make(std::move(name), std::move(units), std::move(desc), Type::kReal);
  c.number = [m](const HingeEvent& e, double* out) { out[0] = e.*m; };
  c.set_number = [m](HingeEvent& e, const double* in) { e.*m = in[0]; };
  return c;
}

std::vector<Column> Standard() {
  std::vector<Column> t;
  t.push_back(Real(&HingeEvent::t, "time", "s",
                   "time of the hinge event (release, latch, jam, stop, rest, lift-off, stick, "
                   "slip), located on the dense output"));
  Column panel =
      Make("panel", "1", "index of the panel (hinge) in the model, from 0", Type::kInteger);
  panel.number = [](const HingeEvent& e, double* out) { out[0] = e.panel; };
  panel.set_number = [](HingeEvent& e, const double* in) { e.panel = static_cast<int>(in[0]); };
  t.push_back(panel);
  Column name = Make("panel_name", "none", "name of the panel in the model", Type::kText);
  name.text = [](const HingeEvent& e, const std::vector<std::string>& names) {
    return names.at(static_cast<std::size_t>(e.panel));
  };
  t.push_back(name);
  Column kind =
      Make("kind", "none",
           "release (starts to move), latch (plastic impulse at the latch angle, then "
           "locked), jam (plastic impulse part-way, then locked), stop (impact on a hard "
           "stop with restitution), rest (came to rest on a stop, then held), lift-off "
           "(left the stop it rested on), stick (exact Coulomb friction holds it) or slip "
           "(the held torque exceeded the friction)",
           Type::kText);
  kind.text = [](const HingeEvent& e, const std::vector<std::string>&) { return ToString(e.kind); };
  kind.set_text = [](HingeEvent& e, const std::string& in) { e.kind = ParseHingeEventKind(in); };
  t.push_back(kind);
  t.push_back(Real(&HingeEvent::angle, "angle", "rad", "hinge angle at the event"));
  t.push_back(
      Real(&HingeEvent::rate_before, "rate_before", "rad/s", "hinge rate just before the event"));
  t.push_back(
      Real(&HingeEvent::rate_after, "rate_after", "rad/s", "hinge rate just after the event"));
  t.push_back(Real(&HingeEvent::impulse, "impulse", "N m s",
                   "angular impulse of the torque pair at the hinge: the jump of the hinge's "
                   "conjugate momentum (0 for a release)"));
  Column jump = Make("w_jump_B", "rad/s",
                     "jump of the hub's angular velocity w_NB_B+ - w_NB_B- (the latch shock), B "
                     "components",
                     Type::kVector3);
  jump.number = [](const HingeEvent& e, double* out) {
    for (int i = 0; i < 3; ++i) out[i] = e.w_jump_B[i];
  };
  jump.set_number = [](HingeEvent& e, const double* in) {
    e.w_jump_B = math::Vec3(in[0], in[1], in[2]);
  };
  t.push_back(jump);
  t.push_back(Real(&HingeEvent::energy_dissipated, "energy_dissipated", "J",
                   "energy the impulse at the hinge dissipates: minus its work, "
                   "((rate_before)^2 - (rate_after)^2) / (2 (M^-1)_kk) (0 for a release)"));
  Column drive = Real(&HingeEvent::drive_work, "drive_work", "J",
                      "impulsive work of the drives of the prescribed hinges moving at the "
                      "event (they keep their rates); the kinetic energy jumps by drive_work - "
                      "energy_dissipated");
  drive.missing = 0.0;  // files from before it: no drive work recorded
  t.push_back(drive);
  return t;
}

std::vector<Column>& Table() {
  static std::vector<Column> table = Standard();
  return table;
}

}  // namespace

const std::vector<HingeEventColumn>& HingeEventTable::Columns() { return Table(); }

void HingeEventTable::Extend(HingeEventColumn column) {
  AppendColumn(Table(), std::move(column), "HingeEventTable");
}

std::vector<analysis::DeploymentFault> DeploymentFaults(const schedule::Profile& profile,
                                                        const std::vector<HingeEvent>& events,
                                                        double t_end) {
  std::vector<analysis::DeploymentFault> faults;
  for (std::size_t k = 0; k < profile.hinges.size(); ++k) {
    const schedule::HingePlan& plan = profile.hinges[k];
    if (plan.kind != schedule::HingePlan::Kind::kFree) continue;
    analysis::DeploymentFault f;
    f.panel = static_cast<int>(k);
    f.panel_name = profile.model.hinged.panels[k].name;
    f.latch_angle = plan.drive.latch.enabled ? plan.drive.latch.angle : f.latch_angle;
    bool released = false, latched = false;
    const HingeEvent* jam = nullptr;
    const HingeEvent* rest = nullptr;
    for (const HingeEvent& e : events) {
      if (e.panel != f.panel) continue;
      released |= e.kind == HingeEvent::Kind::kRelease;
      latched |= e.kind == HingeEvent::Kind::kLatch;
      if (e.kind == HingeEvent::Kind::kJam) jam = &e;
      if (e.kind == HingeEvent::Kind::kRest) rest = &e;
    }
    const schedule::Release& r = plan.drive.release;
    const bool due = r.kind != schedule::Release::Kind::kAtTime || r.time < t_end;
    if (!released && due && r.kind != schedule::Release::Kind::kAtStart) {
      f.kind = analysis::DeploymentFault::Kind::kNeverReleased;
    } else if (jam != nullptr) {
      f.kind = analysis::DeploymentFault::Kind::kJam;
      f.t = jam->t;
      f.angle = jam->angle;
    } else if (plan.drive.latch.enabled && released && !latched) {
      f.kind = rest != nullptr ? analysis::DeploymentFault::Kind::kRestsShort
                               : analysis::DeploymentFault::Kind::kNeverLatched;
      if (rest != nullptr) f.t = rest->t, f.angle = rest->angle;
    } else {
      continue;
    }
    faults.push_back(f);
  }
  return faults;
}

}  // namespace deploysim::run
