// The slosh pendulum (model/slosh.h) on a minor-axis spinner, the reduced free-hinge model
// against the project's generic Simbody model of free hinges (simbody_free_hinges.h: a Pin
// per generated hinge, the massless link as a massless body), with Simbody's own error
// beside every figure. The independent Simbody model built from the tank's numbers alone
// is in slosh_simbody_test.cpp.

#include <gtest/gtest.h>

#include <cstdio>

#include "crosscheck/free_hinge_fixtures.h"
#include "deploysim/crosscheck/free_hinge_crosscheck.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using namespace free_hinge_fixtures;  // NOLINT: the shared test builders

// H_B / |H| and attitude [rad], reduced (rkmk-rkf78 at rtol 1e-13) against Simbody at
// 1e-14 over 40 s (as long as the slosh takes to raise the nutation from 0.6 to 6 deg):
// measured 6.0e-14 and 9.5e-13 rad (Simbody's own error, 1e-12 against 1e-14: 9.8e-14 and
// 1.1e-11); total energy 2.4e-14 of E(t0). The bounds sit a few times above; the project's
// required figure is 1e-9. (Simbody at 1e-14 takes ~13 s here; the whole flat spin, ~5000 s,
// is the example's: deployment_profiles/spin_stabilized_tank.yaml.)
constexpr double kHTolerance = 3e-13;
constexpr double kAttitudeTolerance = 3e-12;
constexpr double kEnergyTolerance = 1e-13;

constexpr double kDamping = 2.0;  // [N m s/rad]

TEST(SloshCrosscheckTest, SloshPendulumOnAMinorAxisSpinner) {
  const model::Model m = SloshSpinner(kDamping);
  schedule::Profile p = HingeProfile(m, AppendagePlans(m), SloshSpinnerSpin(), 40.0);
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-13;
  p.integrator.atol = 1e-15;
  p.output.dt = 1.0;
  FreeHingeCrosscheckOptions o;
  o.accuracy = 1e-14;
  o.own_error_accuracy = 1e-12;
  const FreeHingeCrosscheckResult r = RunFreeHingeCrosscheck(p, o);
  std::printf(
      "slosh spinner, %.0f s: H_B %.2e (Simbody 1e-12 vs 1e-14: %.2e), attitude %.2e rad "
      "(%.2e), energy %.2e; max spin-axis angle %.1f deg; "
      "reduced %.3f s, Simbody %.2f s\n",
      p.t_end() - p.t_begin(), r.difference.max_H_B_relative, r.simbody_self.max_H_B_relative,
      r.difference.max_attitude, r.simbody_self.max_attitude, r.max_energy_difference,
      r.reduced.max_spin_axis_angle / kDeg, r.reduced.wall_seconds, r.simbody.stats.wall_seconds);
  EXPECT_LE(r.difference.max_H_B_relative, kHTolerance);
  EXPECT_LE(r.difference.max_attitude, kAttitudeTolerance);
  EXPECT_LE(r.max_energy_difference, kEnergyTolerance);
  // The slosh damper drains energy at constant |H|: the minor-axis spin's nutation grows
  // (the spin axis from 0.6 deg off h_N to 6.3 deg in 40 s, measured).
  EXPECT_GT(r.reduced.max_spin_axis_angle, 5 * kDeg);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
