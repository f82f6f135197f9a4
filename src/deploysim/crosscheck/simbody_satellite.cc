// The Simbody model of the satellite (docs/design.md 3). See simbody_satellite.h for the
// construction; everything Simbody-specific of the project is in this file.

#include "deploysim/crosscheck/simbody_satellite.h"

#include <Simbody.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "deploysim/run/mission.h"
#include "deploysim/crosscheck/simbody_body.h"
#include "deploysim/crosscheck/simtk_support.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::crosscheck {

namespace {

using simtk::AboutOrigin;
using simtk::ThrowIfOver;
using simtk::ToEigen;
using simtk::ToInertia;
using simtk::ToRotation;
using simtk::ToSimTK;
using simtk::Vec6;

using SimTK::Real;

// Two report times closer than this (relative to max(1, |t|)) are the same instant: a
// grid time that rounds next to a stage boundary is integrated to the boundary.
constexpr double kSameTime = 1e-9;
// Flip location: stop when the bracket is this narrow (relative to max(1, |t|)) [s].
constexpr double kFlipTimeTolerance = 1e-13;
constexpr std::uintmax_t kFlipMaxIterations = 100;
// Mass of the single body of a tensor-mode model [kg] (irrelevant to the rotation).
constexpr double kTensorBodyMass = 1.0;
// Relative tolerance within which a tensor-mode inertia counts as constant.
constexpr double kConstantInertiaTolerance = 1e-14;

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Exact = math::FormatNumber;

/// Which stage boundary the prescribed hinge motion is integrating towards: at that time
/// the schedule is evaluated from the left (a rate may jump there), elsewhere from the
/// right.
struct SegmentClock {
  double segment_end = std::numeric_limits<double>::infinity();
  dynamics::Side SideAt(double t) const {
    const double tol = kSameTime * std::max(1.0, std::abs(segment_end));
    return t >= segment_end - tol ? dynamics::Side::kLeft : dynamics::Side::kRight;
  }
};

/// Position-level prescribed motion of hinge k from the deployment schedule: q, qdot and
/// qddot are the schedule's hinge angle, rate and acceleration (consistent with its law).
class ScheduledHinge final : public SimTK::Motion::Custom::Implementation {
 public:
  ScheduledHinge(const schedule::DeploymentSchedule& schedule, int k, const SegmentClock& clock)
      : schedule_(schedule), k_(k), clock_(clock) {}
  SimTK::Motion::Level getLevel(const SimTK::State&) const override {
    return SimTK::Motion::Position;
  }
  void calcPrescribedPosition(const SimTK::State& s, int nq, Real* q) const override {
    Check(nq);
    const double t = s.getTime();
    q[0] = schedule_.HingeAngles(t, clock_.SideAt(t))[k_];
  }
  void calcPrescribedPositionDot(const SimTK::State& s, int nq, Real* qdot) const override {
    Check(nq);
    const double t = s.getTime();
    qdot[0] = schedule_.HingeRates(t, clock_.SideAt(t))[k_];
  }
  void calcPrescribedPositionDotDot(const SimTK::State& s, int nq, Real* qddot) const override {
    Check(nq);
    const double t = s.getTime();
    qddot[0] = schedule_.HingeAccelerations(t, clock_.SideAt(t))[k_];
  }

 private:
  static void Check(int nq) {
    if (nq != 1) std::abort();  // a Pin has exactly one q: broken internal invariant
  }
  const schedule::DeploymentSchedule& schedule_;
  int k_;
  const SegmentClock& clock_;
};

/// The multibody system with the clock its prescribed hinges read.
struct Satellite : simtk::HingedSystem {
  SegmentClock clock;
};

/// How the hinges move.
enum class Drive { kPrescribed, kSpring };

void RecordKnot(const Satellite& sat, const SimTK::State& s, HingeHistory& h) {
  if (!h.time.empty() && s.getTime() <= h.time.back()) return;
  sat.system.realize(s, SimTK::Stage::Acceleration);
  const auto n = static_cast<Eigen::Index>(sat.pins.size());
  Eigen::VectorXd q(n), u(n), udot(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto& pin = sat.pins[static_cast<std::size_t>(k)];
    q[k] = pin.getOneQ(s, 0);
    u[k] = pin.getOneU(s, 0);
    udot[k] = pin.getOneUDot(s, 0);
  }
  h.time.push_back(s.getTime());
  h.angle.push_back(q);
  h.rate.push_back(u);
  h.acceleration.push_back(udot);
}

/// The flip function: H_B along the principal axis of the system's central inertia (from
/// Simbody, in B) nearest the spin axis, and that axis's role.
struct FlipValue {
  double g = 0.0;
  bool intermediate = false;
  bool is_flip = false;  ///< A sign change located here counts (analysis::IsFlip).
};
FlipValue Flip(const Satellite& sat, const SimTK::State& s, const math::Vec3& spin_axis_B) {
  const math::Vec3 H_B = simtk::HubRotation(sat, s).transpose() * simtk::Momentum_N(sat, s);
  const math::Mat3 J_B = simtk::SystemInertia_B(sat, s);
  const analysis::SpinAxisRole r = analysis::LocateSpinAxis(J_B, spin_axis_B);
  return {H_B.dot(r.axis_B), r.role == analysis::AxisRole::kIntermediate,
          analysis::IsFlip(J_B, spin_axis_B, H_B)};
}

/// Advances `integ` exactly to t (interpolated reports are off).
void StepExactlyTo(SimTK::Integrator& integ, double t) {
  const double tol = kSameTime * std::max(1.0, std::abs(t));
  while (integ.getTime() < t - tol) {
    integ.stepTo(t);
    ThrowIfOver(integ);
  }
}

/// Time of the sign change of the flip function in (a.t, t_b], by toms748 on
/// integrations restarted from `a` at the same accuracy. NaN if the sign change is a jump
/// (not a flip by the rule of analysis/flip_rule.h).
double LocateFlip(const Satellite& sat,
                  const SimTK::State& a,
                  double t_b,
                  double g_a,
                  double g_b,
                  const math::Vec3& spin_axis_B,
                  double accuracy) {
  SimTK::RungeKuttaMersonIntegrator integ(sat.system);
  integ.setAccuracy(accuracy);
  integ.setAllowInterpolation(false);
  const double t_a = a.getTime();
  auto g = [&](double t) {
    if (t <= t_a) return g_a;
    integ.initialize(a);
    StepExactlyTo(integ, t);
    return Flip(sat, integ.getState(), spin_axis_B).g;
  };
  std::uintmax_t iterations = kFlipMaxIterations;
  const auto done = [](double lo, double hi) {
    return hi - lo <= kFlipTimeTolerance * std::max(1.0, std::abs(hi));
  };
  const std::pair<double, double> bracket =
      boost::math::tools::toms748_solve(g, t_a, t_b, g_a, g_b, done, iterations);
  const double t = 0.5 * (bracket.first + bracket.second);
  // The flip rule (analysis/flip_rule.h) at the located time.
  if (t <= t_a)
    return Flip(sat, a, spin_axis_B).is_flip ? t : std::numeric_limits<double>::quiet_NaN();
  integ.initialize(a);
  StepExactlyTo(integ, t);
  return Flip(sat, integ.getState(), spin_axis_B).is_flip
             ? t
             : std::numeric_limits<double>::quiet_NaN();
}

/// A report time of the Simbody run: a grid sample and/or a stage boundary.
struct Report {
  double t = 0.0;         ///< Integrate to this time.
  long grid_index = -1;   ///< Output sample index, or -1.
  bool boundary = false;  ///< Stage boundary: restart there.
};

std::vector<Report> Reports(const std::vector<double>& grid,
                            const std::vector<double>& boundaries) {
  std::vector<Report> r;
  for (std::size_t i = 0; i < grid.size(); ++i) r.push_back({grid[i], static_cast<long>(i), false});
  for (double b : boundaries) {
    auto it = std::min_element(r.begin(), r.end(), [b](const Report& x, const Report& y) {
      return std::abs(x.t - b) < std::abs(y.t - b);
    });
    if (it != r.end() && std::abs(it->t - b) <= kSameTime * std::max(1.0, std::abs(b))) {
      it->t = b;
      it->boundary = true;
    } else {
      r.push_back({b, -1, true});
    }
  }
  std::sort(r.begin(), r.end(), [](const Report& x, const Report& y) { return x.t < y.t; });
  return r;
}

void CheckInputs(const schedule::Profile& profile,
                 const std::vector<double>& grid,
                 const SimbodyOptions& options) {
  if (!(options.accuracy > 0.0 && options.accuracy < 1.0)) {
    throw std::invalid_argument("crosscheck: accuracy = " + Exact(options.accuracy) +
                                ": must be in (0, 1)");
  }
  if (grid.empty()) throw std::invalid_argument("crosscheck: empty output grid");
  const double t0 = profile.t_begin();
  const double t1 = profile.t_end();
  const double tol = kSameTime * std::max(1.0, std::abs(t1));
  if (std::abs(grid.front() - t0) > tol || grid.back() > t1 + tol ||
      !std::is_sorted(grid.begin(), grid.end())) {
    throw std::invalid_argument(
        "crosscheck: the output grid must be ascending, start at t_begin and end by t_end of " +
        profile.source);
  }
}

/// Runs `sat` from its initial state `s0` through the reports; restarts at boundaries
/// (prescribed drive: re-prescribe from the right and refit the hub velocity to the
/// momentum just before). Spring drive: records the hinge history at every step.
SimbodyRun RunIntegration(Satellite& sat,
                          SimTK::State s0,
                          const std::vector<Report>& reports,
                          const std::vector<double>& boundaries,
                          Drive drive,
                          const math::Vec3& spin_axis_B,
                          const SimbodyOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  SimbodyRun out;
  out.accuracy = options.accuracy;
  SimTK::RungeKuttaMersonIntegrator integ(sat.system);
  integ.setAccuracy(options.accuracy);
  integ.setAllowInterpolation(false);
  if (drive == Drive::kSpring) integ.setReturnEveryInternalStep(true);
  integ.initialize(s0);
  const math::Vec3 h_N0 = simtk::Momentum_N(sat, integ.getState());
  const double M = h_N0.norm();

  auto next_boundary = [&](double t) {
    for (double b : boundaries) {
      if (b > t + kSameTime * std::max(1.0, std::abs(b))) return b;
    }
    return std::numeric_limits<double>::infinity();
  };

  SimTK::State prev = integ.getState();
  FlipValue prev_flip = Flip(sat, prev, spin_axis_B);
  if (drive == Drive::kSpring) RecordKnot(sat, integ.getState(), out.history);
  for (const Report& r : reports) {
    if (drive == Drive::kSpring) {
      const double tol = kSameTime * std::max(1.0, std::abs(r.t));
      while (integ.getTime() < r.t - tol) {
        integ.stepTo(r.t);
        ThrowIfOver(integ);
        RecordKnot(sat, integ.getState(), out.history);
      }
    } else {
      StepExactlyTo(integ, r.t);
    }
    const SimTK::State& s = integ.getState();
    const FlipValue f = Flip(sat, s, spin_axis_B);
    if (options.locate_flips && prev_flip.intermediate && f.intermediate &&
        ((prev_flip.g < 0.0) != (f.g < 0.0)) && s.getTime() > prev.getTime()) {
      const double tf =
          LocateFlip(sat, prev, s.getTime(), prev_flip.g, f.g, spin_axis_B, options.accuracy);
      if (std::isfinite(tf)) out.flip_times.push_back(tf);
    }
    const bool restart = r.boundary && drive == Drive::kPrescribed && r.t < boundaries.back();
    if (restart) {
      SimTK::State s1 = s;
      const Vec6 m = simtk::CentralMomentum(sat.system, sat.matter, s1);
      sat.clock.segment_end = next_boundary(r.t);
      sat.system.prescribe(s1);
      simtk::FitHubVelocity(sat, s1, nullptr, m.head<3>(), m.tail<3>());
      integ.initialize(s1);  // keeps the integrator's statistics (cumulative)
      ++out.stats.restarts;
    }
    const SimTK::State& now = integ.getState();
    if (r.grid_index >= 0) {
      simtk::AppendSample(sat, now, r.t, out.trajectory);
      const math::Vec3 h_N = out.trajectory.h_N.back();
      out.max_momentum_drift = std::max(out.max_momentum_drift, (h_N - h_N0).norm() / M);
    }
    prev = now;
    prev_flip = Flip(sat, prev, spin_axis_B);
  }
  out.stats.steps = integ.getNumStepsTaken();
  out.stats.attempts = integ.getNumStepsAttempted();
  out.stats.realizations = integ.getNumRealizations();
  out.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

/// The validated hinged body of a geometry-mode profile (unit hinge axes).
model::HingedBody HingedBodyOf(const schedule::Profile& profile) {
  if (profile.model.kind != model::ModelKind::kHinged) {
    throw std::invalid_argument(profile.source + ": geometry mode needs a hinged model");
  }
  return model::ValidatedHingedBody(profile.model.hinged, profile.model.source);
}

/// Hub attitude at t0 and the state with time, attitude and zero translation set.
SimTK::State InitialState(Satellite& sat, const schedule::Profile& profile) {
  SimTK::State s = sat.system.realizeTopology();
  sat.system.realizeModel(s);
  s.updTime() = profile.t_begin();
  const math::Mat3 R_NB0 = profile.initial.q_NB.normalized().toRotationMatrix();
  sat.hub.setQToFitRotation(s, ToRotation(R_NB0));
  sat.hub.setQToFitTranslation(s, SimTK::Vec3(0));
  return s;
}

std::vector<double> InteriorBoundaries(const schedule::Profile& profile) {
  std::vector<double> b;
  for (const schedule::Stage& st : profile.stages) {
    if (st.t_end > profile.t_begin()) b.push_back(st.t_end);
  }
  return b;  // ascending; the last one is t_end
}

}  // namespace

math::Vec3 InitialMomentum(const schedule::Profile& profile) {
  if (profile.initial.H_B) return *profile.initial.H_B;
  if (!profile.initial.w_NB_B) {
    throw std::invalid_argument(profile.source +
                                ": initial: neither angular velocity nor momentum");
  }
  const math::Vec3& w = *profile.initial.w_NB_B;
  const schedule::DeploymentSchedule sched(profile);
  const double t0 = profile.t_begin();
  if (profile.mode == schedule::Mode::kGeometry) {
    // Exact coupling's h_rel whatever the profile's coupling (zero on a first hold).
    const model::MassProperties mp = model::ComputeMassProperties(
        HingedBodyOf(profile), sched.HingeAngles(t0), sched.HingeRates(t0));
    return mp.J_B * w + mp.h_rel_B;
  }
  return sched.Evaluate(t0).J_B * w;
}

SimbodyRun RunSimbodyPrescribed(const schedule::Profile& profile,
                                const std::vector<double>& grid,
                                const math::Vec3& spin_axis_B,
                                const SimbodyOptions& options) {
  CheckInputs(profile, grid, options);
  const schedule::DeploymentSchedule sched(profile);
  const double t0 = profile.t_begin();
  const std::vector<double> boundaries = InteriorBoundaries(profile);
  const math::Vec3 H_B0 = InitialMomentum(profile);
  const math::Mat3 R_NB0 = profile.initial.q_NB.normalized().toRotationMatrix();

  Satellite sat;
  sat.clock.segment_end = boundaries.front();
  if (profile.mode == schedule::Mode::kGeometry) {
    simtk::AddHingedBodies(sat, HingedBodyOf(profile), profile.source);
    for (std::size_t k = 0; k < sat.pins.size(); ++k) {
      SimTK::Motion::Custom(sat.pins[k], new ScheduledHinge(sched, static_cast<int>(k), sat.clock));
    }
  } else {
    const math::Mat3 J = sched.Evaluate(t0).J_B;
    for (double b : boundaries) {
      for (dynamics::Side side : {dynamics::Side::kLeft, dynamics::Side::kRight}) {
        if ((sched.Evaluate(b, side).J_B - J).norm() > kConstantInertiaTolerance * J.norm()) {
          throw std::invalid_argument(
              profile.source +
              ": crosscheck of a tensor-mode profile needs a constant inertia (Simbody cannot "
              "change a body's mass properties after realizeTopology); J_B changes at t = " +
              Exact(b) + " s");
        }
      }
    }
    sat.hub = SimTK::MobilizedBody::Free(
        sat.matter.Ground(), SimTK::Transform(),
        SimTK::Body::Rigid(AboutOrigin(kTensorBodyMass, math::Vec3::Zero(), J)),
        SimTK::Transform());
  }
  SimTK::State s = InitialState(sat, profile);
  sat.system.prescribe(s);
  simtk::FitHubVelocity(sat, s, nullptr, R_NB0 * H_B0, math::Vec3::Zero());
  return RunIntegration(sat, s, Reports(grid, boundaries), boundaries, Drive::kPrescribed,
                        spin_axis_B, options);
}

SimbodyRun RunSimbodySpring(const schedule::Profile& profile,
                            const SpringDrive& drive,
                            const std::vector<double>& grid,
                            const math::Vec3& spin_axis_B,
                            const SimbodyOptions& options) {
  CheckInputs(profile, grid, options);
  if (profile.mode != schedule::Mode::kGeometry) {
    throw std::invalid_argument(profile.source + ": spring deployment needs geometry mode");
  }
  auto require = [&](bool ok, const std::string& key, double value, const std::string& rule) {
    if (!ok) {
      throw std::invalid_argument("spring drive: " + key + " = " + Exact(value) + ": " + rule);
    }
  };
  require(drive.stiffness > 0.0 && std::isfinite(drive.stiffness), "stiffness", drive.stiffness,
          "must be finite and > 0");
  require(drive.overtravel > 0.0 && std::isfinite(drive.overtravel), "overtravel", drive.overtravel,
          "must be finite and > 0");
  require(drive.damping >= 0.0 && std::isfinite(drive.damping), "damping", drive.damping,
          "must be finite and >= 0");
  require(drive.stop_stiffness > 0.0 && std::isfinite(drive.stop_stiffness), "stop_stiffness",
          drive.stop_stiffness, "must be finite and > 0");
  require(drive.stop_dissipation >= 0.0 && std::isfinite(drive.stop_dissipation),
          "stop_dissipation", drive.stop_dissipation, "must be finite and >= 0");
  const model::HingedBody body = HingedBodyOf(profile);
  const Eigen::VectorXd& closed =
      profile.model.configuration(profile.stages.front().from).hinge_angles;
  const Eigen::VectorXd& open = profile.model.configuration(drive.open).hinge_angles;
  const math::Vec3 H_B0 = InitialMomentum(profile);
  const math::Mat3 R_NB0 = profile.initial.q_NB.normalized().toRotationMatrix();

  Satellite sat;
  simtk::AddHingedBodies(sat, body, profile.source);
  for (std::size_t k = 0; k < sat.pins.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double direction = open[i] >= closed[i] ? 1.0 : -1.0;  // sense of opening
    SimTK::Force::MobilityLinearSpring(sat.forces, sat.pins[k], SimTK::MobilizerQIndex(0),
                                       drive.stiffness, open[i] + direction * drive.overtravel);
    SimTK::Force::MobilityLinearDamper(sat.forces, sat.pins[k], SimTK::MobilizerUIndex(0),
                                       drive.damping);
    const double low = direction < 0.0 ? open[i] : -SimTK::Infinity;
    const double high = direction < 0.0 ? SimTK::Infinity : open[i];
    SimTK::Force::MobilityLinearStop(sat.forces, sat.pins[k], SimTK::MobilizerQIndex(0),
                                     drive.stop_stiffness, drive.stop_dissipation, low, high);
  }
  SimTK::State s = InitialState(sat, profile);
  for (std::size_t k = 0; k < sat.pins.size(); ++k) {
    sat.pins[k].setOneQ(s, 0, closed[static_cast<Eigen::Index>(k)]);
    sat.pins[k].setOneU(s, 0, 0.0);
  }
  simtk::FitHubVelocity(sat, s, nullptr, R_NB0 * H_B0, math::Vec3::Zero());
  const std::vector<double> end{profile.t_end()};
  return RunIntegration(sat, s, Reports(grid, end), end, Drive::kSpring, spin_axis_B, options);
}

}  // namespace deploysim::crosscheck
