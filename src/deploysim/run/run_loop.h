#pragma once

/// The one run loop of a mission (docs/design.md 4): a compiled run's body — the stage
/// schedule of a stage profile, the hub with its hinges of a hinge profile — is a source
/// of J_B(t) and h_rel_B(t) with, for a hinged body, discrete changes (releases, latches,
/// stops) and free motion between them. The loop integrates it segment by segment:
///   - where nothing is free, the rigid-body path (integrators::Integrate with the body as
///     the inertia source; `exact` uses the closed form wherever nothing moves), the
///     phase boundaries (stage ends, prescribed windows) inside it, the spin-axis extrema
///     located in closed form on rigid intervals and on the cubic Hermite interpolant
///     elsewhere;
///   - where hinges are free, the body's own free segment (hinge_body.h).
/// Samples, flips, 45-degree crossings, extrema and phases go to one RunRecorder. The
/// mutable state of the run (RunState) lives apart from the compiled run, which the loop
/// never changes.

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/analysis/linear_stability.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/types.h"
#include "deploysim/run/compiled_run.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/run_recorder.h"

namespace deploysim::run {

/// What a run changes as it goes (the compiled run stays as compiled).
struct RunState {
  double t = 0.0;
  integrators::State y;               ///< H_B, q_NB at t
  Eigen::VectorXd x;                  ///< the free hinges' shape state (empty when none is free)
  WorkLedger work;                    ///< the work done on the system from t0 to t
  math::Vec3 s = math::Vec3::Zero();  ///< the spin axis that flips and angles refer to
  double M = 0.0;                     ///< |H_B(t0)|
  integrators::IntegratorSettings settings;
  std::optional<RunRecorder> recorder;
  /// The output grid (the full grid, or none for an outcome-only run) and the index of
  /// its next time not yet sampled.
  std::optional<integrators::UniformGridTimes> full_grid;
  std::optional<WindowTimes> grid;
  std::size_t next_out = 0;
  integrators::Statistics stats;
  integrators::Termination termination = integrators::Termination::kReachedEnd;
  std::string message;
  MissionResult out;

  RunRecorder& rec() { return *recorder; }
  void AddStats(const integrators::Statistics& more);
  /// Records a termination other than reaching the end: true then (the run stops).
  bool Stopped(integrators::Termination how, const std::string& why);
};

/// How a segment ended.
enum class SegmentEnd { kReached, kHingeEvent, kStopped };

/// What the loop integrates: J_B(t), h_rel_B(t) and what a sample shows of the body, its
/// phases, and (a hinged body) its discrete changes and free segments.
class RunBody {
 public:
  virtual ~RunBody() = default;
  /// J_B(t) and h_rel_B(t) while no hinge is free (the rigid-body path).
  virtual const dynamics::InertiaSource& source() const = 0;
  /// The state at t0: st.y (and st.x, the free shape state, if any).
  virtual void Start(RunState& st) = 0;
  /// A state's sample at t (side: which limit of J_B at a breakpoint); its work is the
  /// loop's to fill.
  virtual RunSample SampleOf(double t,
                             const math::Vec3& H_B,
                             const math::Quat& q_NB,
                             const Eigen::VectorXd& x,
                             dynamics::Side side) const = 0;
  /// A sample on the output grid of the rigid path (default: SampleOf, J_B's right limit,
  /// the left at the run's end t1).
  virtual RunSample GridSample(double t, const math::Vec3& H_B, const math::Quat& q_NB, double t1);
  /// The times in (t0, t1) where one phase ends and the next begins on the rigid path
  /// (stage ends, prescribed windows), ascending.
  virtual std::vector<double> PhaseBoundaries(double t0, double t1) const = 0;
  /// The phase that begins at t.
  virtual PhaseInfo Describe(double t) const = 0;
  /// The steady spin of the phase that opens at `start` (linear_stability.h).
  virtual analysis::SteadySpin Steady(const RunSample& start, const PhaseInfo& info) const = 0;

  // A hinged body's discrete changes (a stage body has none).
  /// Frees what is due at st.t; true if anything changed (the open phase is then closed).
  virtual bool ChangesDue(RunState& /*st*/, bool /*started*/) { return false; }
  /// True while a hinge is free or held (the free segment integrates then).
  virtual bool FreeMotion() const { return false; }
  /// The next time after t something changes that ends a segment (a release) ...
  virtual double NextChange(double /*t*/, double t1) const { return t1; }
  /// ... and, in free motion, a prescribed window's boundary too.
  virtual double NextFreeChange(double t, double t1) const { return NextChange(t, t1); }
  /// Integrates the free motion to t_next or its first hinge event.
  virtual SegmentEnd FreeSegment(RunState& /*st*/, double /*t_next*/) {
    throw std::logic_error("RunBody::FreeSegment: this body has no free motion");
  }

  /// Opens a phase at `start` with its steady spin.
  void OpenPhase(RunState& st, const RunSample& start);
};

/// Runs `body` for the compiled run (RunMission picks the body).
MissionResult RunLoop(const CompiledRun& run,
                      RunBody& body,
                      SampleSink* sink,
                      const std::function<void(double)>& progress,
                      const RunOptions& options);

}  // namespace deploysim::run
