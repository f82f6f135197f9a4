// A slosh pendulum (model/slosh.h) on a spinning hub, through the project's own equations:
// its two swings in the hub frame are modes of the equations linearized about the steady
// spin (analysis/linear_stability.h), at the frequencies of the centrifugal field,
// omega_in^2 = Omega^2 r / L1 (in the plane of rotation) and omega_out^2 = Omega^2 (r + L1) / L1
// (along the spin axis).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "crosscheck/free_hinge_fixtures.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/slosh.h"
#include "deploysim/run/mission.h"
#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Vec3;

constexpr double kBob = 10.0, kLength = 0.5;  // kg, m

/// A hub (1e3 kg, moments `hub_inertia`, a sphere) spinning about z, with an undamped
/// pendulum pivoted at r along x, hanging outward (+x), first hinge about the spin axis.
/// Distances are from the hub's CoM: for two bodies, the bob's motion relative to the
/// hub has the reduced mass in both its kinetic and its centrifugal energy, so the
/// frequencies are those of a pivot fixed at r; only the hub's finite inertia couples.
model::Model PendulumOnHub(double r, double hub_inertia) {
  model::Model md;
  md.name = "slosh_on_hub";
  md.kind = model::ModelKind::kHinged;
  md.hinged.hub.body.mass = 1e3;
  md.hinged.hub.body.inertia_cm = hub_inertia * math::Mat3::Identity();
  model::SloshSpec s;
  s.name = "tank";
  s.pivot = Vec3(r, 0, 0);
  s.direction = Vec3::UnitX();
  s.axis = Vec3::UnitZ();
  s.mass = kBob;
  s.length = kLength;
  s.damping = 0.0;
  md.appendages = {model::AddSlosh(md.hinged, s, "test")};
  md.hinged = model::ValidatedHingedBody(md.hinged, "test");
  testing::SetInitialConfiguration(md);
  return md;
}

/// The oscillating modes' frequencies [rad/s], ascending, each once.
std::vector<double> Frequencies(const model::Model& md, double spin) {
  namespace fx = crosscheck::free_hinge_fixtures;
  const schedule::Profile p = fx::HingeProfile(md, fx::AppendagePlans(md), Vec3(0, 0, spin), 1e-3);
  const analysis::SteadySpin s = RunMission(p).outcome.linear;
  EXPECT_TRUE(s.found) << s.reason;
  std::vector<double> w;
  for (const analysis::SpinMode& m : s.modes) {
    if (m.lambda.imag() > 0.0) w.push_back(m.lambda.imag());
  }
  std::sort(w.begin(), w.end());
  return w;
}

/// The mode of `w` nearest `expected`, relative to it.
double Nearest(const std::vector<double>& w, double expected) {
  double best = INFINITY;
  for (double x : w) {
    if (std::abs(x / expected - 1.0) < std::abs(best)) best = x / expected - 1.0;
  }
  return best;
}

// Pivot 1 m off the axis, L1 = 0.5 m, 1 rad/s: omega_in = sqrt(2), omega_out = sqrt(3)
// rad/s. The hub's rotation is the only coupling: the error falls as 1/I_hub (measured
// +1.11e-4 in the plane and +7.43e-5 out of it at I = 1e5 kg m^2, +1.11e-6 and +7.43e-7 at
// 1e7: ratio 0.0100; the bob's m1 r (r + L1) is 15 kg m^2). On the axis (r = 0):
// omega_out = Omega (measured 4e-16 from it at I = 1e7), the in-plane swing is free
// (omega_in = 0, no oscillating mode).
TEST(SloshDynamics, PendulumFrequenciesInTheCentrifugalField) {
  const double spin = 1.0;
  double previous[2] = {0.0, 0.0};
  for (double hub : {1e5, 1e7}) {
    const std::vector<double> w = Frequencies(PendulumOnHub(1.0, hub), spin);
    const double in = model::SloshInPlaneFrequency(spin, 1.0, kLength);
    const double out = model::SloshOutOfPlaneFrequency(spin, 1.0, kLength);
    const double e_in = Nearest(w, in), e_out = Nearest(w, out);
    std::printf(
        "I_hub %.0e: %zu modes; in-plane %.9f (%.9f, %+.2e), out-of-plane %.9f (%.9f, "
        "%+.2e)\n",
        hub, w.size(), in * (1 + e_in), in, e_in, out * (1 + e_out), out, e_out);
    EXPECT_LT(std::abs(e_in), 30.0 / hub);
    EXPECT_LT(std::abs(e_out), 30.0 / hub);
    if (hub > 1e5) {  // the coupling falls as 1/I_hub
      EXPECT_NEAR(e_in / previous[0], 1e-2, 2e-3);
      EXPECT_NEAR(e_out / previous[1], 1e-2, 2e-3);
    }
    previous[0] = e_in;
    previous[1] = e_out;
  }
  const std::vector<double> on_axis = Frequencies(PendulumOnHub(0.0, 1e7), spin);
  const double e = Nearest(on_axis, spin);
  std::printf("on the axis: %zu modes, out-of-plane %+.2e from Omega\n", on_axis.size(), e);
  EXPECT_LT(std::abs(e), 1e-12);
  for (double x : on_axis) EXPECT_GT(x, 0.5 * spin) << "an in-plane oscillation on the axis";
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
