#include "deploysim/schedule/profile_warnings.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"

namespace deploysim::schedule {

namespace {

/// A derived quantity for a message, to 4 significant digits.
std::string Short(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string Deg(double rad) { return Short(rad * math::kDegreesPerRadian); }

struct Collector {
  std::string where;
  std::vector<std::string> lines;
  void Add(const std::string& key_value, const std::string& message) {
    lines.push_back(where + ": " + key_value + ": " + message);
  }
};

/// The earliest time a free hinge can be released (+inf: never): a release after a latch
/// cannot come before the waited panel's own release plus the delay.
double EarliestRelease(const Profile& p, std::size_t k, int depth = 0) {
  const HingePlan& h = p.hinges[k];
  if (h.kind != HingePlan::Kind::kFree) return std::numeric_limits<double>::infinity();
  const Release& re = h.drive.release;
  switch (re.kind) {
    case Release::Kind::kAtStart:
      return p.start;
    case Release::Kind::kAtTime:
      return std::max(re.time, p.start);
    case Release::Kind::kAfterLatch:
      // ValidateProfile refuses cycles; the depth bound only keeps this total.
      if (depth > static_cast<int>(p.hinges.size()) || re.panel < 0 ||
          static_cast<std::size_t>(re.panel) >= p.hinges.size()) {
        return std::numeric_limits<double>::infinity();
      }
      return EarliestRelease(p, static_cast<std::size_t>(re.panel), depth + 1) + re.delay;
  }
  return p.start;
}

void CheckRelease(const Profile& p, std::size_t k, const std::string& key, Collector& out) {
  const Release& re = p.hinges[k].drive.release;
  if (re.kind == Release::Kind::kAtTime && re.time >= p.until) {
    out.Add(key + ".release.at = " + Short(re.time),
            "at or after the run's end (until = " + Short(p.until) +
                " s): the panel is never released in this run");
    return;
  }
  const double earliest = EarliestRelease(p, k);
  if (re.kind == Release::Kind::kAfterLatch && earliest >= p.until && std::isfinite(earliest)) {
    out.Add(key + ".release.after_latch = " + p.model.hinged.panels[re.panel].name,
            "released at the earliest at " + Short(earliest) + " s, after the run's end (until = " +
                Short(p.until) + " s): the panel is never released in this run");
  }
}

/// The drive's torque at the start angle without motion (spring and constant motor), and
/// where the spring alone comes to rest.
void CheckDriveTowardsLatch(const FreeDrive& d,
                            double theta0,
                            const std::string& key,
                            Collector& out) {
  if (!d.latch.enabled || d.motor.kind == Motor::Kind::kServo ||
      d.motor.kind == Motor::Kind::kTorqueSpeed) {
    return;
  }
  const double to_latch = d.latch.angle - theta0;
  const double motor = d.motor.kind == Motor::Kind::kConstant ? d.motor.torque : 0.0;
  const double k = d.spring.stiffness;
  if (k == 0.0 && d.spring.preload == 0.0 && motor == 0.0) {
    out.Add(key + ".latch.angle_deg = " + Deg(d.latch.angle),
            "nothing drives the panel to its latch (no spring, no motor): only the spin's load "
            "moves it");
    return;
  }
  if (motor != 0.0 && k == 0.0) {
    if (motor * to_latch < 0.0) {
      out.Add(key + ".motor.torque = " + Short(motor),
              "the motor drives the panel away from its latch at " + Deg(d.latch.angle) +
                  " deg (starting at " + Deg(theta0) + " deg): it will not latch");
    }
    return;
  }
  if (k > 0.0) {
    // Spring, preload and a constant motor together rest where their torques cancel.
    const double rest = d.spring.rest_angle + (d.spring.preload + motor) / k;
    const double travel = rest - theta0;
    if (travel * to_latch <= 0.0 || std::abs(travel) < std::abs(to_latch)) {
      out.Add(key + ".spring.rest_angle_deg = " + Deg(d.spring.rest_angle),
              "the drive comes to rest at " + Deg(rest) + " deg, short of the latch at " +
                  Deg(d.latch.angle) + " deg (starting at " + Deg(theta0) +
                  " deg): the panel will not latch unless the spin's load carries it there");
      return;
    }
  }
  const double q0 = -k * (theta0 - d.spring.rest_angle) + d.spring.preload + motor;
  if (d.friction.torque >= std::abs(q0) && d.friction.torque > 0.0) {
    out.Add(key + ".friction.torque = " + Short(d.friction.torque),
            "at least the drive's torque at release (" + Short(std::abs(q0)) +
                " N m): the panel may never start to move");
  }
}

void CheckPrescribed(const Profile& p, const HingePlan& h, const std::string& key, Collector& out) {
  for (std::size_t m = 0; m < h.moves.size(); ++m) {
    const HingeMove& mv = h.moves[m];
    const std::string mk = key + ".prescribed[" + std::to_string(m) + "]";
    if (mv.t_begin >= p.until) {
      out.Add(mk + ".start = " + Short(mv.t_begin),
              "at or after the run's end (until = " + Short(p.until) +
                  " s): the move never happens in this run");
    } else if (mv.t_end > p.until && mv.kind == HingeMove::Kind::kTo) {
      // A rate move (a rotor) may run on past the end; a move to an angle stops short.
      out.Add(mk + ".until = " + Short(mv.t_end),
              "after the run's end (until = " + Short(p.until) +
                  " s): the run stops the panel part way through its move");
    }
  }
}

void CheckHinges(const Profile& p, Collector& out) {
  // Only a profile whose plans and initial configuration match its model (as
  // ValidateProfile requires) is checked; a result built by hand may have neither.
  const model::Configuration* initial = nullptr;
  for (const model::Configuration& c : p.model.configurations) {
    if (c.name == p.initial.configuration) initial = &c;
  }
  const std::size_t n = p.hinges.size();
  if (initial == nullptr || p.model.hinged.panels.size() != n ||
      static_cast<std::size_t>(initial->hinge_angles.size()) != n) {
    return;
  }
  const Eigen::VectorXd& theta0 = initial->hinge_angles;
  for (std::size_t k = 0; k < n; ++k) {
    const HingePlan& h = p.hinges[k];
    const std::string key = "hinges." + p.model.hinged.panels[k].name;
    if (h.kind == HingePlan::Kind::kPrescribed) CheckPrescribed(p, h, key, out);
    if (h.kind != HingePlan::Kind::kFree) continue;
    CheckRelease(p, k, key + ".free", out);
    CheckDriveTowardsLatch(h.drive, theta0[static_cast<Eigen::Index>(k)], key + ".free", out);
  }
}

void CheckSpin(const Profile& p, Collector& out) {
  const InitialState& in = p.initial;
  if (in.spin) {
    // In rpm the unit was chosen on purpose: only rad/s and deg/s are mistaken for it.
    if (in.spin->rate > kMaxPlausibleSpin && !in.spin->rate_in_rpm) {
      out.Add("initial.spin.rate = " + Short(in.spin->rate / math::kRadPerSecondPerRpm) + " rpm",
              "faster than spacecraft spin (at most ~60 rpm): check the unit");
    }
    return;
  }
  // A momentum has no unit to mistake (the seed's laboratory bodies spin at 70-300 rpm).
  if (!in.w_NB_B) return;
  const double w = in.w_NB_B->norm();
  if (w > kMaxPlausibleSpin) {
    out.Add("initial.angular_velocity (|w| = " + Short(w) +
                " rad/s = " + Short(w / math::kRadPerSecondPerRpm) + " rpm)",
            "faster than spacecraft spin (at most ~60 rpm): angular_velocity is in rad/s; "
            "angular_velocity_deg_s, angular_velocity_rpm or spin take other units");
  }
}

}  // namespace

std::vector<std::string> ProfileWarnings(const Profile& p) {
  Collector out;
  out.where = p.source.empty() ? "profile '" + p.name + "'" : p.source;
  CheckSpin(p, out);
  if (p.is_hinge_profile()) CheckHinges(p, out);
  if (!p.is_hinge_profile() && p.stages.empty()) return out.lines;  // not a valid profile
  const double duration = p.t_end() - p.t_begin();
  if (p.output.dt * kMinOutputSamples > duration) {
    out.Add("output.dt = " + Short(p.output.dt),
            "the " + Short(duration) + " s run is sampled fewer than " + Short(kMinOutputSamples) +
                " times: its plots will miss the motion");
  }
  return out.lines;
}

std::string ProfileWarningsJson(const Profile& p) {
  std::string o = "[";
  for (const std::string& w : ProfileWarnings(p)) {
    o += (o.size() > 1 ? ", " : "") + math::JsonString(w);
  }
  return o + "]";
}

}  // namespace deploysim::schedule
