#include "deploysim/run/compiled_run.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/math/number_format.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/initial_spin.h"

namespace deploysim::run {

namespace {

std::string Where(const schedule::Profile& p) {
  return p.source.empty() ? "profile '" + p.name + "'" : p.source;
}

}  // namespace

void CheckRunSettings(const schedule::Profile& p) {
  using math::FormatNumber;
  const std::string where = Where(p);
  const std::string& method = p.integrator.method;
  std::string rule = analysis::MethodRuleViolated(method);
  if (!rule.empty()) {
    throw std::invalid_argument(where + ": integrator.method = " + method + ": " + rule);
  }
  rule = analysis::StepRuleViolated(method, p.integrator.step);
  if (!rule.empty()) {
    throw std::invalid_argument(where + ": integrator.step = " + FormatNumber(p.integrator.step) +
                                ": " + rule);
  }
  if (p.has_free_hinge() && !analysis::RunsFreeHinges(method)) {
    throw std::invalid_argument(where + ": integrator.method = " + method + ": " +
                                analysis::FreeHingeMethodRule());
  }
  if ((!p.stages.empty() || p.is_hinge_profile()) && p.output.dt > 0.0) {
    const double samples = (p.t_end() - p.t_begin()) / p.output.dt + 1.0;
    if (!(samples <= kMaxOutputSamples)) {
      throw std::invalid_argument(where + ": output.dt = " + FormatNumber(p.output.dt) +
                                  ": gives " + FormatNumber(std::ceil(samples)) +
                                  " output samples over " + FormatNumber(p.t_end() - p.t_begin()) +
                                  " s (at most " + FormatNumber(kMaxOutputSamples) + ")");
    }
  }
}

std::shared_ptr<const CompiledRun> CompiledRun::Compile(schedule::Profile profile,
                                                        const MomentumRule& rule) {
  std::shared_ptr<CompiledRun> run(new CompiledRun());
  schedule::Profile& p = run->profile_;
  p = std::move(profile);
  schedule::ValidateProfile(p);
  if (!p.is_hinge_profile()) {
    run->schedule_ = std::make_shared<const schedule::DeploymentSchedule>(p, schedule::kValidated);
  }
  if (p.initial.spin || rule) {
    // J_B(t0): the schedule's, or the free-hinge system's at the initial angles.
    const dynamics::InertiaSample s0 =
        run->schedule_ ? run->schedule_->Evaluate(p.t_begin()) : schedule::InitialInertia(p);
    if (p.initial.spin && !p.initial.H_B) {
      p.initial.H_B = schedule::SpinMomentum(s0, *p.initial.spin);
    }
    if (rule) {
      p.initial.H_B = rule(s0, InitialMomentum(p, s0));
      p.initial.w_NB_B.reset();
      p.initial.spin.reset();  // the rule's momentum is the run's own now
    }
  }
  CheckRunSettings(p);  // first: the estimate needs a known method
  run->work_ = analysis::EstimateWork(p, run->schedule_.get());
  analysis::CheckWork(p, run->work_);
  run->settings_ = SettingsOf(p);
  return run;
}

std::shared_ptr<const CompiledRun> CompiledRun::Uncompiled(schedule::Profile profile) {
  std::shared_ptr<CompiledRun> run(new CompiledRun());
  run->profile_ = std::move(profile);
  return run;
}

}  // namespace deploysim::run
