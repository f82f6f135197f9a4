#pragma once

// A mission result for the trajectory file tests: random (but reproducible) values that
// use every bit of the doubles, so that a round trip that loses anything shows.

#include <cstddef>
#include <cstdint>
#include <random>
#include <utility>

#include "deploysim/math/types.h"
#include "deploysim/run/compiled_run.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::testing {

inline constexpr std::uint64_t kSeed = 20240611;
inline constexpr std::size_t kSamples = 7;
inline constexpr int kPanels = 2;

/// A mission result with random (but reproducible) values that use every bit of the
/// doubles, so that a round trip that loses anything shows.
inline run::MissionResult SyntheticResult(schedule::Mode mode) {
  using math::Mat3;
  using math::Quat;
  using math::Vec3;
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };

  run::MissionResult r;
  schedule::Profile p;
  p.name = "synthetic";
  p.source = "profiles/synthetic.yaml";
  p.text = "name: synthetic\n# a profile text with unicode: \xce\xb8 = 90\xc2\xb0\n";
  p.model.name = "synthetic_model";
  p.model.source = "models/synthetic_model.yaml";
  p.model.text = "name: synthetic_model\nkind: hinged\n# \xce\xb8 in degrees\n";
  p.mode = mode;
  p.coupling = mode == schedule::Mode::kGeometry ? schedule::Coupling::kExact
                                                 : schedule::Coupling::kQuasiRigid;
  p.model.kind = model::ModelKind::kHinged;
  p.model.hinged.panels.resize(kPanels);
  p.model.hinged.panels[0].name = "wing_\xce\xb8";  // UTF-8 survives
  p.model.hinged.panels[1].name = "boom";
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-11;
  p.integrator.atol = 1e-13;
  p.output.dt = 0.25;
  schedule::Stage hold;
  hold.name = "closed spin";
  hold.from = hold.to = "closed";
  hold.t_begin = 0.0;
  hold.t_end = 1.0;
  schedule::Stage move;
  move.name = "deploy";
  move.from = "closed";
  move.to = "open";
  move.law = schedule::Law::kMinimumJerk;
  move.t_begin = 1.0;
  move.t_end = 1.5;
  p.stages = {hold, move};

  run::Trajectory& t = r.trajectory;
  for (std::size_t k = 0; k < kSamples; ++k) {
    t.time.push_back(0.25 * static_cast<double>(k) + 1e-3 * u(rng));
    t.H_B.push_back(vec());
    t.w_NB_B.push_back(vec());
    t.q_NB.push_back(Quat(u(rng), u(rng), u(rng), u(rng)));
    Mat3 J;
    for (int i = 0; i < 9; ++i) J(i / 3, i % 3) = u(rng);  // not symmetric: order shows
    t.J_B.push_back(J);
    t.principal_moments.push_back(vec());
    t.h_rel_B.push_back(vec());
    t.h_N.push_back(vec());
    t.energy.push_back(u(rng));
    t.energy_rigid.push_back(u(rng));
    t.energy_spring.push_back(u(rng));
    t.euler_313.push_back(vec());
    t.spin_axis_angle.push_back(u(rng));
    for (auto* w :
         {&t.work_damper, &t.work_friction, &t.work_motor, &t.work_drive, &t.work_impacts}) {
      w->push_back(u(rng));
    }
    if (mode == schedule::Mode::kGeometry) {
      t.hinge_angles.push_back(Eigen::Vector2d(u(rng), u(rng)));
      t.hinge_rates.push_back(Eigen::Vector2d(u(rng), u(rng)));
    }
  }
  r.flip_times = {0.3, 0.7 + 1e-15, 1.1};
  // Stage reports: a rigid stage with predicted flips, a moving one without.
  run::StageReport a;
  a.index = 0;
  a.rigid = true;
  a.moments_end = vec();
  a.spin_axis_end = analysis::AxisRole::kIntermediate;
  a.regime = "minor-axis";
  a.one_minus_k2 = 6.6492854004460934e-6;
  a.separatrix_distance = -1.25e-7 * (1.0 + u(rng));
  a.predicted_flip_half_period = 0.4 + u(rng);
  a.predicted_flips = {0.3 + 1e-9, 0.7};
  a.observed_flips = {0.3, 0.7 + 1e-15};
  a.max_flip_time_difference = 1e-9;
  a.caveat = "intermediate-axis spin: unstable (flips), with or without dissipation";
  a.rigid_body_only = false;
  run::StageReport b;
  b.index = 1;
  b.rigid = false;
  b.moments_end = vec();
  b.spin_axis_end = analysis::AxisRole::kDegenerate;
  b.separatrix_distance = u(rng);
  b.predicted_flip_half_period = std::numeric_limits<double>::infinity();
  b.observed_flips = {1.1};
  b.caveat = "two principal moments are equal: \xce\xb8 neutral";
  b.rigid_body_only = true;
  r.stages = {a, b};
  // Hinge events of every kind, latch times (one never), 45-degree crossings.
  using Kind = run::HingeEvent::Kind;
  const Kind kinds[] = {Kind::kRelease, Kind::kStop,  Kind::kStop,
                        Kind::kRest,    Kind::kLatch, Kind::kJam};
  for (std::size_t i = 0; i < std::size(kinds); ++i) {
    run::HingeEvent e;
    e.kind = kinds[i];
    e.t = 0.2 * static_cast<double>(i) + 1e-3 * u(rng);
    e.panel = static_cast<int>(i % kPanels);
    e.angle = u(rng);
    e.rate_before = u(rng);
    e.rate_after = u(rng);
    e.impulse = u(rng);
    e.w_jump_B = vec();
    e.energy_dissipated = std::abs(u(rng));
    r.hinge_events.push_back(e);
  }
  r.latch_times = {0.8 + 1e-3 * u(rng), std::numeric_limits<double>::quiet_NaN()};
  r.spin_axis_45_crossings = {0.55 + 1e-3 * u(rng), 1.3};
  r.danger_windows = {{0.0, 0.75}, {1.25, 1.5}};
  r.stats.steps = 123;
  r.stats.rejected = 4;
  r.max_h_N_drift = 1.5e-14;
  r.message = "reached the end";
  r.run = run::CompiledRun::Uncompiled(std::move(p));
  return r;
}

}  // namespace deploysim::testing
