#pragma once

/// A compiled run: a profile read, validated once and turned into the immutable object
/// every consumer of a run takes (the run loop, the trajectory writer, the report, a sweep
/// case), as MuJoCo's mjModel is to its mjData. It holds the profile (with its initial
/// momentum resolved), the deployment schedule of a stage profile, the integrator
/// settings and the work estimate; the mutable state of a run lives in the run loop.
/// Nothing downstream validates again (docs/design.md 4, "The compiled run").

#include <cstdint>
#include <functional>
#include <memory>

#include "deploysim/analysis/work_estimate.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::run {

/// What a caller decides about H_B(t0) once the inertia at the start is known (a sweep's
/// nutation and spin rate): the momentum from J_B(t0) (s0) and the profile's own H_B(t0).
/// It may throw std::invalid_argument (the profile is then refused with its message).
using MomentumRule =
    std::function<math::Vec3(const dynamics::InertiaSample& s0, const math::Vec3& H_B)>;

class CompiledRun : public std::enable_shared_from_this<CompiledRun> {
 public:
  /// Validates `profile` once (schedule::ValidateProfile), builds a stage profile's
  /// schedule, resolves `initial.spin` (and `rule`, if given) to initial.H_B, checks the
  /// run settings (CheckRunSettings), estimates the work once and checks its limits
  /// (CheckWork). Throws
  /// std::invalid_argument with the rule's one-line message.
  static std::shared_ptr<const CompiledRun> Compile(schedule::Profile profile,
                                                    const MomentumRule& rule = {});

  /// A profile that is not compiled (not validated, no schedule, an empty estimate): what
  /// a result assembled by hand refers to (a report's test, a result read back), never
  /// something to run.
  static std::shared_ptr<const CompiledRun> Uncompiled(schedule::Profile profile);

  const schedule::Profile& profile() const { return profile_; }
  /// Stage profiles: their schedule (J_B(t), h_rel_B(t), the hinge angles); null for a
  /// hinge profile, whose free-hinge system is the run's own.
  const schedule::DeploymentSchedule* schedule() const { return schedule_.get(); }
  const analysis::WorkEstimate& work() const { return work_; }
  /// The `integrator:` section as the integrators take it.
  const integrators::IntegratorSettings& settings() const { return settings_; }
  /// The run as a shared handle (a result refers to the run it came from).
  std::shared_ptr<const CompiledRun> handle() const { return shared_from_this(); }

 private:
  CompiledRun() = default;

  schedule::Profile profile_;
  std::shared_ptr<const schedule::DeploymentSchedule> schedule_;
  analysis::WorkEstimate work_;
  integrators::IntegratorSettings settings_;
};

/// The rules on a profile's run settings that need the integrator registry: the
/// integrator method exists (StepperNames), fixed-step methods have integrator.step > 0,
/// free hinges need a method that runs them, and the output grid has at most
/// kMaxOutputSamples samples. Throws std::invalid_argument naming the key. (The work's
/// limits are CheckWork's, on the estimate that needs a known method.)
void CheckRunSettings(const schedule::Profile& profile);

/// Largest number of output samples a profile may ask for ((t_end - t_begin)/dt + 1).
inline constexpr double kMaxOutputSamples = 1e7;

}  // namespace deploysim::run
