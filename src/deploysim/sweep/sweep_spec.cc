#include "deploysim/sweep/sweep_spec.h"

#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "deploysim/run/mission.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/appendages.h"
#include "deploysim/model/flexible_beam.h"
#include "deploysim/model/model.h"
#include "deploysim/model/slosh.h"
#include "deploysim/schedule/free_hinge_system.h"
#include "deploysim/schedule/initial_spin.h"
#include "deploysim/schedule/laws.h"
#include "deploysim/sweep/rng.h"

namespace deploysim::sweep {

namespace {

using math::FormatNumber;

// Truncated normal draws: give up after this many rejections (the loader requires the
// bounds to hold a reasonable probability mass, so this is never reached in practice).
constexpr int kMaxRejections = 100000;

double Draw(const Distribution& d, Rng& rng, const std::string& where) {
  switch (d.kind) {
    case Distribution::Kind::kUniform:
      return rng.Uniform(d.a, d.b);
    case Distribution::Kind::kNormal:
      for (int k = 0; k < kMaxRejections; ++k) {
        const double x = d.a + d.b * rng.Normal();
        if (x >= d.min && x <= d.max) return x;
      }
      throw std::invalid_argument(where +
                                  ": the truncation bounds of the normal distribution "
                                  "reject nearly every draw");
    case Distribution::Kind::kChoice: {
      if (d.cumulative.empty()) {
        return d.choices.at(static_cast<std::size_t>(rng.Below(d.choices.size())));
      }
      const double u = rng.Uniform();
      std::size_t i = 0;
      while (i + 1 < d.choices.size() && !(u < d.cumulative[i])) ++i;
      return d.choices[i];
    }
  }
  return 0.0;
}

bool IsMove(const schedule::Profile& p, std::size_t i) {
  const schedule::Stage& st = p.stages[i];
  return !st.from.empty() ? st.from != st.to : (i > 0 && st.to != p.stages[i - 1].to);
}

// Two unit vectors closer than this are the same spin axis (both are columns of the same
// principal decomposition, possibly negated: equal in practice to the last bit).
constexpr double kSameAxis = 1e-12;

/// Sets (pass 0) or scales (pass 1) what a hinge parameter acts on, for one free hinge.
void ApplyToDrive(Parameter par, double v, int pass, schedule::FreeDrive& d) {
  using schedule::Motor;
  using schedule::Release;
  if (pass == 1) {
    if (par == Parameter::kSpringStiffnessScale) d.spring.stiffness *= v;
    if (par == Parameter::kMotorTorqueScale) {
      if (d.motor.kind == Motor::Kind::kTorqueSpeed) {
        d.motor.stall_torque *= v;
      } else {
        d.motor.torque *= v;
      }
    }
    return;
  }
  switch (par) {
    case Parameter::kSpringStiffness:
      d.spring.stiffness = v;
      break;
    case Parameter::kDamping:
      d.damping = v;
      break;
    case Parameter::kLatchAngle:
      d.latch.angle = v;
      break;
    case Parameter::kMotorTorque:
      d.motor = Motor{};
      d.motor.kind = Motor::Kind::kConstant;
      d.motor.torque = v;
      break;
    case Parameter::kReleaseTime:
      d.release.kind = Release::Kind::kAtTime;
      d.release.time = v;
      break;
    case Parameter::kReleaseDelay:
      d.release.delay = v;
      break;
    case Parameter::kFrictionTorque:
      d.friction.torque = v;
      break;
    case Parameter::kStickFraction:
      d.latch.jam_fraction = v;
      break;
    default:
      break;
  }
}

/// Sets (pass 0) or scales (pass 1) what an appendage parameter acts on in the spec of
/// one appendage (a new spec: the model's are shared by the base and every case).
void ApplyToAppendage(Parameter par, double v, int pass, model::Appendage& a) {
  if (a.beam) {
    model::BeamSpec s = *a.beam;
    if (pass == 0 && par == Parameter::kBendingStiffness) {
      for (model::BeamPlane& plane : s.planes) plane.bending_stiffness = v;
    } else if (pass == 1 && par == Parameter::kBendingStiffnessScale) {
      for (model::BeamPlane& plane : s.planes) plane.bending_stiffness *= v;
    } else if (pass == 0 && par == Parameter::kDampingRatio) {
      s.damping_ratio = v;
    } else {
      return;
    }
    a.beam = std::make_shared<const model::BeamSpec>(std::move(s));
  } else if (a.slosh) {
    model::SloshSpec s = *a.slosh;
    if (pass == 0 && par == Parameter::kDampingRatio) {
      s.damping_ratio = v;
    } else if (pass == 0 && par == Parameter::kFillFraction) {
      s.tank->fill_fraction = v;
    } else {
      return;
    }
    a.slosh = std::make_shared<const model::SloshSpec>(std::move(s));
  }
}

/// The appendage parameters (step 1 of the file comment of sweep_spec.h): the specs
/// changed, the appendages expanded again and their bending hinges' plans reset. A case
/// without one keeps the base's model as it is.
void ApplyAppendageParameters(const std::vector<Target>& targets,
                              const std::vector<double>& v,
                              schedule::Profile& p) {
  bool any = false;
  // Values: all-appendage targets, then per-appendage ones; then the factors.
  for (int pass = 0; pass < 2; ++pass) {
    for (int all = 1; all >= 0; --all) {
      for (std::size_t k = 0; k < targets.size(); ++k) {
        const Target& t = targets[k];
        if (!IsAppendageParameter(t.parameter) || (t.appendage < 0) != (all == 1)) continue;
        any = true;
        for (std::size_t i = 0; i < p.model.appendages.size(); ++i) {
          model::Appendage& a = p.model.appendages[i];
          if (t.appendage >= 0 && static_cast<std::size_t>(t.appendage) != i) continue;
          if (AppliesTo(t.parameter, a)) ApplyToAppendage(t.parameter, v[k], pass, a);
        }
      }
    }
  }
  if (!any) return;
  model::RebuildAppendages(p.model);
  schedule::SetAppendagePlans(p.model, p.hinges);
}

/// The free-hinge parameters of a hinge profile (step 2 of the file comment of
/// sweep_spec.h). The appendages' generated hinges are left alone: their springs and
/// dampers are the model's (step 1).
void ApplyHingeParameters(const std::vector<Target>& targets,
                          const std::vector<double>& v,
                          schedule::Profile& p) {
  using schedule::HingePlan;
  const std::size_t n = p.hinges.size();
  std::vector<char> generated(n, 0);
  for (const model::Appendage& a : p.model.appendages) {
    for (int h : a.hinges) generated.at(static_cast<std::size_t>(h)) = 1;
  }
  auto each = [&](const Target& t, const std::function<void(std::size_t)>& f) {
    for (std::size_t i = 0; i < n; ++i) {
      if (p.hinges[i].kind != HingePlan::Kind::kFree || generated[i]) continue;
      if (t.panel >= 0 && static_cast<std::size_t>(t.panel) != i) continue;
      f(i);
    }
  };
  // Values: all-panel targets, then per-panel ones; then the factors.
  for (int pass = 0; pass < 2; ++pass) {
    for (int all = 1; all >= 0; --all) {
      for (std::size_t k = 0; k < targets.size(); ++k) {
        const Target& t = targets[k];
        if (!IsHingeParameter(t.parameter) || (t.panel < 0) != (all == 1)) continue;
        each(t, [&](std::size_t i) { ApplyToDrive(t.parameter, v[k], pass, p.hinges[i].drive); });
      }
    }
  }
  // Failed latches, after every value (a jam drawn for the same panel wins: the panel
  // sticks before it reaches the latch).
  std::vector<char> failed(n, 0);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (targets[k].parameter != Parameter::kLatchFails || v[k] == 0.0) continue;
    each(targets[k], [&](std::size_t i) {
      schedule::Latch& la = p.hinges[i].drive.latch;
      if (la.jam_fraction > 0.0) return;
      la.enabled = false;
      failed[i] = 1;
    });
  }
  // A release waiting for a latch that failed never comes: past the end of the run.
  const double never = p.t_end() + (p.t_end() - p.t_begin());
  for (HingePlan& h : p.hinges) {
    schedule::Release& re = h.drive.release;
    if (h.kind == HingePlan::Kind::kFree && re.kind == schedule::Release::Kind::kAfterLatch &&
        re.panel >= 0 && failed[static_cast<std::size_t>(re.panel)]) {
      re = schedule::Release{};
      re.kind = schedule::Release::Kind::kAtTime;
      re.time = never;
    }
  }
}

/// Coupling, law and timing of a stage profile (steps 2-3 of the file comment of
/// sweep_spec.h).
void ApplyStageParameters(const std::vector<Target>& targets,
                          const std::vector<double>& v,
                          schedule::Profile& p) {
  // 2. Coupling, then law (all moves first, then single stages).
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (targets[k].parameter == Parameter::kCoupling) {
      p.coupling =
          io::ParseCoupling(CategoriesOf(Parameter::kCoupling).at(static_cast<std::size_t>(v[k])));
    }
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const Target& t = targets[k];
      if (t.parameter != Parameter::kLaw || (pass == 0) != (t.stage < 0)) continue;
      const schedule::Law law =
          schedule::ParseLaw(CategoriesOf(Parameter::kLaw).at(static_cast<std::size_t>(v[k])));
      for (std::size_t i = 0; i < p.stages.size(); ++i) {
        if (t.stage >= 0 && static_cast<std::size_t>(t.stage) != i) continue;
        if (IsMove(p, i)) p.stages[i].law = law;
      }
    }
  }
  // 3. Timing.
  std::vector<double> durations;
  for (const schedule::Stage& st : p.stages) durations.push_back(st.t_end - st.t_begin);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (targets[k].parameter != Parameter::kDeployDurationScale) continue;
    for (std::size_t i = 0; i < p.stages.size(); ++i) {
      if (IsMove(p, i)) durations[i] *= v[k];
    }
  }
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (targets[k].parameter == Parameter::kStageDuration) {
      durations.at(static_cast<std::size_t>(targets[k].stage)) = v[k];
    }
  }
  double t = p.stages.front().t_begin;
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    p.stages[i].t_begin = t;
    t += durations[i];
    p.stages[i].t_end = t;
  }
}

}  // namespace

bool IsCategorical(Parameter p) {
  return p == Parameter::kLaw || p == Parameter::kCoupling || p == Parameter::kLatchFails;
}

bool IsStageParameter(Parameter p) {
  return p == Parameter::kDeployDurationScale || p == Parameter::kStageDuration ||
         p == Parameter::kLaw || p == Parameter::kCoupling;
}

bool IsHingeParameter(Parameter p) {
  switch (p) {
    case Parameter::kSpringStiffness:
    case Parameter::kSpringStiffnessScale:
    case Parameter::kDamping:
    case Parameter::kLatchAngle:
    case Parameter::kMotorTorque:
    case Parameter::kMotorTorqueScale:
    case Parameter::kReleaseTime:
    case Parameter::kReleaseDelay:
    case Parameter::kFrictionTorque:
    case Parameter::kStickFraction:
    case Parameter::kLatchFails:
      return true;
    default:
      return false;
  }
}

bool IsAppendageParameter(Parameter p) {
  return p == Parameter::kBendingStiffness || p == Parameter::kBendingStiffnessScale ||
         p == Parameter::kDampingRatio || p == Parameter::kFillFraction;
}

bool AppliesTo(Parameter p, const model::Appendage& a) {
  switch (p) {
    case Parameter::kBendingStiffness:
    case Parameter::kBendingStiffnessScale:
      return a.beam != nullptr;
    case Parameter::kDampingRatio:
      return a.beam != nullptr || (a.slosh != nullptr && a.slosh->damping_ratio.has_value());
    case Parameter::kFillFraction:
      return a.slosh != nullptr && a.slosh->tank.has_value();
    default:
      return false;
  }
}

std::string UnitsOf(Parameter p) {
  switch (p) {
    case Parameter::kStageDuration:
      return "s";
    case Parameter::kSpinRate:
      return "rad/s";
    case Parameter::kNutation:
    case Parameter::kNutationAzimuth:
      return "rad";
    case Parameter::kLaw:
    case Parameter::kCoupling:
    case Parameter::kLatchFails:
      return "none";
    case Parameter::kDeployDurationScale:
    case Parameter::kPanelMassScale:
    case Parameter::kInertiaScale:
    case Parameter::kSpringStiffnessScale:
    case Parameter::kMotorTorqueScale:
    case Parameter::kStickFraction:
      return "1";
    case Parameter::kSpringStiffness:
      return "N m/rad";
    case Parameter::kDamping:
      return "N m s/rad";
    case Parameter::kLatchAngle:
      return "rad";
    case Parameter::kMotorTorque:
    case Parameter::kFrictionTorque:
      return "N m";
    case Parameter::kReleaseTime:
    case Parameter::kReleaseDelay:
      return "s";
    case Parameter::kBendingStiffness:
      return "N m^2";
    case Parameter::kBendingStiffnessScale:
    case Parameter::kDampingRatio:
    case Parameter::kFillFraction:
      return "1";
  }
  return "1";
}

const std::vector<std::string>& CategoriesOf(Parameter p) {
  static const std::vector<std::string> kLaws = {schedule::ToString(schedule::Law::kStep),
                                                 schedule::ToString(schedule::Law::kLinear),
                                                 schedule::ToString(schedule::Law::kSmoothstep),
                                                 schedule::ToString(schedule::Law::kMinimumJerk)};
  static const std::vector<std::string> kCouplings = {
      schedule::ToString(schedule::Coupling::kQuasiRigid),
      schedule::ToString(schedule::Coupling::kExact)};
  static const std::vector<std::string> kNoYes = {"no", "yes"};
  static const std::vector<std::string> kNone;
  if (p == Parameter::kLaw) return kLaws;
  if (p == Parameter::kCoupling) return kCouplings;
  if (p == Parameter::kLatchFails) return kNoYes;
  return kNone;
}

std::size_t SweepSpec::grid_points() const {
  std::size_t n = 1;
  for (const GridAxis& a : grid) n *= a.values.size();
  return n;
}

std::size_t SweepSpec::samples() const { return monte_carlo ? monte_carlo->samples : 1; }

std::vector<Target> SweepSpec::targets() const {
  std::vector<Target> t;
  for (const GridAxis& a : grid) t.push_back(a.target);
  if (monte_carlo) {
    for (const MonteCarloParameter& m : monte_carlo->parameters) t.push_back(m.target);
  }
  return t;
}

CaseParameters ParametersOf(const SweepSpec& spec, std::size_t index) {
  const std::size_t count = spec.case_count();
  if (index >= count) {
    throw std::out_of_range("case index " + std::to_string(index) + " out of range (" +
                            std::to_string(count) + " cases)");
  }
  CaseParameters p;
  p.index = index;
  p.grid_index = index / spec.samples();
  p.sample_index = index % spec.samples();
  // Row-major: the last axis varies fastest.
  std::vector<double> grid_values(spec.grid.size());
  std::size_t rest = p.grid_index;
  for (std::size_t k = spec.grid.size(); k-- > 0;) {
    const std::size_t n = spec.grid[k].values.size();
    grid_values[k] = spec.grid[k].values[rest % n];
    rest /= n;
  }
  p.values = grid_values;
  if (spec.monte_carlo) {
    const MonteCarlo& mc = *spec.monte_carlo;
    for (std::size_t k = 0; k < mc.parameters.size(); ++k) {
      Rng rng(mc.seed, p.sample_index, k);
      p.values.push_back(Draw(mc.parameters[k].distribution, rng,
                              spec.source + ": monte_carlo.parameters[" + std::to_string(k) + "]"));
    }
  }
  return p;
}

std::string DescribeParameters(const SweepSpec& spec, const CaseParameters& p) {
  const std::vector<Target> targets = spec.targets();
  std::string s = "{";
  for (std::size_t k = 0; k < targets.size() && k < p.values.size(); ++k) {
    const Parameter par = targets[k].parameter;
    s += (k ? ", " : "") + targets[k].column + "=";
    if (IsCategorical(par)) {
      s += CategoriesOf(par).at(static_cast<std::size_t>(p.values[k]));
    } else {
      s += FormatNumber(p.values[k]);
    }
  }
  return s + "}";
}

math::Vec3 BaseSpinAxis(const schedule::Profile& base) {
  const dynamics::InertiaSample s0 = schedule::InitialInertia(base);
  const math::Vec3 H_B0 =
      base.initial.H_B ? *base.initial.H_B : math::Vec3(s0.J_B * *base.initial.w_NB_B + s0.h_rel_B);
  return analysis::InitialSpinAxis(s0.J_B, H_B0);
}

namespace {

/// Step 1 of the file comment of sweep_spec.h: panel masses and configuration inertias.
void ApplyModelParameters(const std::vector<Target>& targets,
                          const std::vector<double>& v,
                          schedule::Profile& p) {
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const Target& t = targets[k];
    if (t.parameter == Parameter::kPanelMassScale) {
      for (std::size_t i = 0; i < p.model.hinged.panels.size(); ++i) {
        if (t.panel >= 0 && static_cast<std::size_t>(t.panel) != i) continue;
        model::MassElement& b = p.model.hinged.panels[i].body;
        b.mass *= v[k];
        b.inertia_cm *= v[k];
      }
    } else if (t.parameter == Parameter::kInertiaScale) {
      math::Mat3 S = math::Mat3::Identity();
      if (t.axis >= 0) {
        S(t.axis, t.axis) = std::sqrt(v[k]);
      } else {
        S *= std::sqrt(v[k]);
      }
      for (model::Configuration& conf : p.model.configurations) {
        if (!t.configuration.empty() && conf.name != t.configuration) continue;
        conf.J_B = S * conf.J_B * S;
      }
    }
  }
}

/// The initial-state parameters a case sets (unset: the base profile's value stands).
struct InitialParameters {
  std::optional<double> nutation, azimuth, spin_rate;
};

InitialParameters InitialParametersOf(const std::vector<Target>& targets,
                                      const std::vector<double>& v) {
  InitialParameters in;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    switch (targets[k].parameter) {
      case Parameter::kNutation:
        in.nutation = v[k];
        break;
      case Parameter::kNutationAzimuth:
        in.azimuth = v[k];
        break;
      case Parameter::kSpinRate:
        in.spin_rate = v[k];
        break;
      default:
        break;
    }
  }
  return in;
}

/// Step 4 of the file comment of sweep_spec.h: H_B(t0) of the case, from the profile's
/// H_B(t0) (H) with the nutation, azimuth and spin rate the case sets.
math::Vec3 InitialMomentum(const std::vector<Target>& targets,
                           const std::vector<double>& v,
                           math::Vec3 H,
                           const dynamics::InertiaSample& s0,
                           const math::Vec3& s) {
  const InitialParameters in = InitialParametersOf(targets, v);
  if (in.nutation || in.azimuth) H = schedule::TiltMomentum(H, s, s0.J_B, in.nutation, in.azimuth);
  if (in.spin_rate) H = schedule::ScaleToSpinRate(H, s, s0, *in.spin_rate);
  return H;
}

/// A hinge-profile case: its run measures angles from the same spin axis as the case
/// (run::RunMission: the principal axis nearest H_B(t0)); counts the latches expected.
void FinishHingeCase(const SweepSpec& spec,
                     const dynamics::InertiaSample& s0,
                     const math::Vec3& H_B,
                     Case& c) {
  const math::Vec3 run_axis = analysis::InitialSpinAxis(s0.J_B, H_B);
  if ((run_axis - c.spin_axis_B).norm() > kSameAxis) {
    throw std::invalid_argument(
        "initial: H_B(t0) is nearer another principal axis than the spin axis s (rule: a "
        "hinge-profile run measures its angles from the principal axis nearest H_B(t0); "
        "keep the nutation below the angle that takes H_B nearer another axis)");
  }
  c.latches_expected = 0;
  for (const schedule::HingePlan& h : spec.base.hinges) {
    if (h.kind == schedule::HingePlan::Kind::kFree && h.drive.latch.enabled) {
      ++c.latches_expected;
    }
  }
}

}  // namespace

Case BuildCase(const SweepSpec& spec, std::size_t index) {
  Case c;
  c.parameters = ParametersOf(spec, index);
  const std::vector<Target> targets = spec.targets();
  const std::vector<double>& v = c.parameters.values;
  schedule::Profile p = spec.base;
  const std::string where = (spec.source.empty() ? std::string("sweep") : spec.source) + ": case " +
                            std::to_string(index) + " " + DescribeParameters(spec, c.parameters);
  try {
    // 1. Model: the appendages, then panel and inertia factors.
    ApplyAppendageParameters(targets, v, p);
    ApplyModelParameters(targets, v, p);
    // 2-3. Hinges (free-hinge drives and failures), or coupling, law and timing.
    const bool hinges = p.is_hinge_profile();
    if (hinges) {
      ApplyHingeParameters(targets, v, p);
    } else {
      ApplyStageParameters(targets, v, p);
    }
    const math::Vec3 base_axis =
        spec.base_spin_axis_B ? *spec.base_spin_axis_B : BaseSpinAxis(spec.base);
    // 4. Initial state, once the case's J_B(t0) is known; validated and compiled once.
    c.run = run::CompiledRun::Compile(
        std::move(p), [&](const dynamics::InertiaSample& s0, const math::Vec3& H_B) {
          c.spin_axis_B = analysis::InitialSpinAxis(s0.J_B, base_axis);
          const math::Vec3 H = InitialMomentum(targets, v, H_B, s0, c.spin_axis_B);
          if (hinges) FinishHingeCase(spec, s0, H, c);
          return H;
        });
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
  return c;
}

}  // namespace deploysim::sweep
