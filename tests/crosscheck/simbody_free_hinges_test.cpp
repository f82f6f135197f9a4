// The independent Simbody model of free hinges (crosscheck/simbody_free_hinges.h):
// Simbody-internal invariants (energy and momentum, the damper's energy balance, the
// latch's closed form with an independently computed mass matrix, a stiff stop's
// convergence to the plastic latch), the events (release after a latch, stops, rest, jam,
// prescribed windows) and the major-axis rule. The profiles are built in C++.

#include "deploysim/crosscheck/simbody_free_hinges.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "crosscheck/free_hinge_fixtures.h"
#include "deploysim/analysis/flip_rule.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/math/inertia.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/laws.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using run::HingeEvent;
using schedule::HingePlan;
using namespace free_hinge_fixtures;  // NOLINT: the shared test builders

// ---- models and profiles ---------------------------------------------------------------

SimbodyFreeHingeOptions Accuracy(double accuracy) {
  SimbodyFreeHingeOptions o;
  o.accuracy = accuracy;
  return o;
}

double MaxRelativeEnergyChange(const SimbodyFreeHingeRun& r) {
  double d = 0.0;
  for (double E : r.total_energy) {
    d = std::max(d, std::abs(E - r.total_energy.front()) / r.total_energy.front());
  }
  return d;
}

std::vector<const HingeEvent*> EventsOf(const SimbodyFreeHingeRun& r, HingeEvent::Kind kind) {
  std::vector<const HingeEvent*> v;
  for (const HingeEvent& e : r.events) {
    if (e.kind == kind) v.push_back(&e);
  }
  return v;
}

/// Composite Boole integral (error O(h^6)) of samples f on a uniform grid of step h, at
/// every fourth index (entry m: the integral over [t_0, t_4m]).
std::vector<double> BooleCumulative(const std::vector<double>& f, double h) {
  std::vector<double> I{0.0};
  for (std::size_t i = 4; i < f.size(); i += 4) {
    I.push_back(I.back() + 2.0 * h / 45.0 *
                               (7.0 * f[i - 4] + 32.0 * f[i - 3] + 12.0 * f[i - 2] +
                                32.0 * f[i - 1] + 7.0 * f[i]));
  }
  return I;
}

/// Indices (in GetU order: hub 6, then the hinges) of the mobilities free at an event plus
/// hinge k.
std::vector<Eigen::Index> FreeIndices(const std::vector<bool>& free, int k, int hub_size) {
  std::vector<Eigen::Index> idx;
  for (int j = 0; j < hub_size; ++j) idx.push_back(j);
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (free[j] || static_cast<int>(j) == k) idx.push_back(hub_size + static_cast<Eigen::Index>(j));
  }
  return idx;
}

/// (R^-1)_kk of the matrix M restricted to `idx`, for the entry idx == hinge_index.
double RestrictedInverseEntry(const Eigen::MatrixXd& M,
                              const std::vector<Eigen::Index>& idx,
                              Eigen::Index hinge_index) {
  const auto m = static_cast<Eigen::Index>(idx.size());
  Eigen::MatrixXd R(m, m);
  Eigen::Index kk = -1;
  for (Eigen::Index a = 0; a < m; ++a) {
    if (idx[static_cast<std::size_t>(a)] == hinge_index) kk = a;
    for (Eigen::Index b = 0; b < m; ++b) {
      R(a, b) = M(idx[static_cast<std::size_t>(a)], idx[static_cast<std::size_t>(b)]);
    }
  }
  return R.inverse()(kk, kk);
}

/// (M^-1)_kk at an event from Simbody's full mass matrix (hub angular + linear, hinges),
/// restricted to the hub, the hinges free before the event and hinge k.
double SimbodyInverseMassEntry(const model::HingedBody& body,
                               const Eigen::VectorXd& angles,
                               const std::vector<bool>& free,
                               int k) {
  return RestrictedInverseEntry(SimbodyMassMatrix(body, angles), FreeIndices(free, k, 6), 6 + k);
}

/// The same from the project's mass properties (docs/design.md 2.5, 2.7; single-level panels):
/// M = [[J_B, Bm], [Bm^T, M_tt]] about the system CoM in (w_NB_B, theta'), Bm's columns
/// h_rel_B per unit rate, M_tt by polarization of T_rel. Eliminating the hub's translation
/// from Simbody's matrix gives the same (M^-1)_kk.
double MassPropertiesInverseMassEntry(const model::HingedBody& body,
                                      const Eigen::VectorXd& angles,
                                      const std::vector<bool>& free,
                                      int k) {
  const auto n = angles.size();
  Eigen::MatrixXd M(3 + n, 3 + n);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  M.topLeftCorner<3, 3>() = model::ComputeMassProperties(body, angles, zero).J_B;
  auto t_rel = [&](const Eigen::VectorXd& rate) {
    return model::ComputeMassProperties(body, angles, rate).relative_kinetic_energy;
  };
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::VectorXd ej = Eigen::VectorXd::Unit(n, j);
    const math::Vec3 column = model::ComputeMassProperties(body, angles, ej).h_rel_B;
    M.block<3, 1>(0, 3 + j) = column;
    M.block<1, 3>(3 + j, 0) = column.transpose();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::VectorXd ei = Eigen::VectorXd::Unit(n, i);
      M(3 + i, 3 + j) = i == j ? 2.0 * t_rel(ei) : t_rel(ei + ej) - t_rel(ei) - t_rel(ej);
    }
  }
  return RestrictedInverseEntry(M, FreeIndices(free, k, 3), 3 + k);
}

/// Angle [rad] between the body spin axis and h_N at sample i.
double SpinAngle(const SimbodyFreeHingeRun& r, std::size_t i, const math::Vec3& spin_axis_B) {
  const math::Vec3& H = r.trajectory.H_B[i];
  return std::acos(std::clamp(spin_axis_B.dot(H) / H.norm(), -1.0, 1.0));
}

// ---- conservation ----------------------------------------------------------------------

/// max |E - E0| / E0 (measured 1.1e-14) at accuracy 1e-14 over 10 s of undamped swinging;
/// max |h_N - h_N0| / |h_N0| at 1e-14 in every test (measured <= 4.4e-14).
constexpr double kUndampedEnergyTolerance = 1e-13;
constexpr double kMomentumTolerance = 2e-13;

TEST(SimbodyFreeHingesTest, UndampedSpringsConserveEnergyAndMomentum) {
  // Both wings released from stowed at t = 0, springs towards -20 deg (one with a preload:
  // its stored energy -preload (theta - rest) must be in Simbody's potential energy), no
  // damper: they swing through the deployed position and back.
  HingePlan preloaded = Free(0.4, -20 * kDeg);
  preloaded.drive.spring.preload = -0.05;
  const schedule::Profile p =
      HingeProfile(SmallSat(), {Free(0.6, -20 * kDeg), preloaded}, SmallSatSpin(), 10.0);
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 10, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  const double dE = MaxRelativeEnergyChange(r);
  std::printf("undamped springs: energy %.2e, h_N %.2e (%ld steps, %.2f s)\n", dE,
              r.max_momentum_drift, r.stats.steps, r.stats.wall_seconds);
  EXPECT_LE(dE, kUndampedEnergyTolerance);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  // They did swing: both past the deployed position.
  double min0 = 1.0, min1 = 1.0;
  for (const Eigen::VectorXd& a : r.trajectory.hinge_angles) {
    min0 = std::min(min0, a[0]);
    min1 = std::min(min1, a[1]);
  }
  EXPECT_LT(min0, 0.0);
  EXPECT_LT(min1, 0.0);
  ASSERT_EQ(EventsOf(r, HingeEvent::Kind::kRelease).size(), 2u);  // at the start
  EXPECT_EQ(r.events.size(), 2u);
}

/// |E0 - E(t) - integral c theta'^2| / E0 with Boole's rule on a 0.01 s grid (measured
/// 1.6e-13).
constexpr double kDamperBalanceTolerance = 1e-12;

TEST(SimbodyFreeHingesTest, DamperDissipatesTheIntegralOfCThetaDotSquared) {
  constexpr double c0 = 0.5, c1 = 0.2;
  const schedule::Profile p = HingeProfile(
      SmallSat(), {Free(0.6, -20 * kDeg, c0), Free(0.4, -20 * kDeg, c1)}, SmallSatSpin(), 8.0);
  constexpr double h = 0.01;
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 8, h), math::Vec3::UnitY(), Accuracy(1e-14));
  std::vector<double> power;
  for (const Eigen::VectorXd& u : r.trajectory.hinge_rates) {
    power.push_back(c0 * u[0] * u[0] + c1 * u[1] * u[1]);
  }
  const std::vector<double> dissipated = BooleCumulative(power, h);
  const double E0 = r.total_energy.front();
  double worst = 0.0;
  for (std::size_t m = 0; m < dissipated.size(); ++m) {
    worst = std::max(worst, std::abs(E0 - r.total_energy[4 * m] - dissipated[m]) / E0);
  }
  std::printf(
      "damper: E0 - E(t) vs integral c theta'^2: %.2e of E0 (dissipated %.4f J of "
      "%.4f J); h_N %.2e\n",
      worst, dissipated.back(), E0, r.max_momentum_drift);
  EXPECT_LE(worst, kDamperBalanceTolerance);
  EXPECT_GT(dissipated.back(), 0.1 * E0);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  for (std::size_t i = 1; i < r.total_energy.size(); ++i) {
    EXPECT_LE(r.total_energy[i], r.total_energy[i - 1] + 1e-14 * E0) << r.trajectory.time[i];
  }
}

// ---- latches -----------------------------------------------------------------------------

/// Latch energy and impulse against the closed form with (M^-1)_kk from Simbody's mass
/// matrix rebuilt at the event's angles, and that (M^-1)_kk against the one from the
/// project's mass properties (measured <= 1.6e-15 for all three).
constexpr double kClosedFormTolerance = 1e-13;
/// E(t_end) against E0 (plus the motors' work) minus the dissipated energies, no damper
/// (measured <= 7.3e-15).
constexpr double kBookkeepingTolerance = 1e-13;

/// Checks every latch, jam and rest (plastic) of r against the closed form; returns the
/// total energy the events dissipated.
double CheckPlasticEvents(const SimbodyFreeHingeRun& r,
                          const model::HingedBody& body,
                          bool single_level) {
  double dissipated = 0.0;
  for (std::size_t i = 0; i < r.events.size(); ++i) {
    const HingeEvent& e = r.events[i];
    dissipated += e.energy_dissipated;
    if (e.kind == HingeEvent::Kind::kRelease || e.kind == HingeEvent::Kind::kStop) continue;
    const double minv =
        SimbodyInverseMassEntry(body, r.event_hinge_angles[i], r.event_free_hinges[i], e.panel);
    const double closed_form = e.rate_before * e.rate_before / (2.0 * minv);
    std::printf(
        "  %s of hinge %d at %.15f s: rate %+.6f rad/s, impulse %+.9e N m s, w jump "
        "%.3e rad/s, dE %.9e J (closed form %.1e)\n",
        run::ToString(e.kind).c_str(), e.panel, e.t, e.rate_before, e.impulse, e.w_jump_B.norm(),
        e.energy_dissipated, std::abs(e.energy_dissipated - closed_form) / closed_form);
    EXPECT_NEAR(e.energy_dissipated, closed_form, kClosedFormTolerance * closed_form);
    EXPECT_NEAR(e.impulse, -e.rate_before / minv, kClosedFormTolerance * std::abs(e.impulse));
    EXPECT_EQ(e.rate_after, 0.0);
    EXPECT_GT(e.w_jump_B.norm(), 0.0);
    if (single_level) {
      const double minv_mp = MassPropertiesInverseMassEntry(body, r.event_hinge_angles[i],
                                                            r.event_free_hinges[i], e.panel);
      EXPECT_NEAR(minv_mp, minv, kClosedFormTolerance * minv);
    }
  }
  return dissipated;
}

TEST(SimbodyFreeHingesTest, LatchesDissipateTheClosedFormAndKeepTheMomentum) {
  // The stiffer spring latches first, so the second latch's effective inertia is that of
  // the mass matrix restricted to the hinges still free (docs/design.md 2.7 pitfall).
  const schedule::Profile p = HingeProfile(
      SmallSat(), {WithLatch(Free(0.6, -20 * kDeg), 0.0), WithLatch(Free(0.3, -20 * kDeg), 0.0)},
      SmallSatSpin(), 20.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 20, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  const std::vector<const HingeEvent*> latches = EventsOf(r, HingeEvent::Kind::kLatch);
  ASSERT_EQ(latches.size(), 2u);
  EXPECT_EQ(latches[0]->panel, 0);
  EXPECT_EQ(latches[1]->panel, 1);
  EXPECT_EQ(r.latch_times[0], latches[0]->t);
  EXPECT_EQ(r.latch_times[1], latches[1]->t);
  const double dissipated = CheckPlasticEvents(r, body, true);
  // The full matrix (both hinges free) gives another (M^-1)_kk for the second latch.
  const std::size_t second = static_cast<std::size_t>(latches[1] - r.events.data());
  const double restricted =
      SimbodyInverseMassEntry(body, r.event_hinge_angles[second], r.event_free_hinges[second], 1);
  const double full = SimbodyInverseMassEntry(body, r.event_hinge_angles[second], {true, true}, 1);
  std::printf("second latch: full-matrix (M^-1)_kk / restricted = %.4f\n", full / restricted);
  EXPECT_GT(std::abs(full / restricted - 1.0), 0.01);
  const double E0 = r.total_energy.front();
  const double bookkeeping = std::abs(r.total_energy.back() - (E0 - dissipated)) / E0;
  std::printf(
      "latches: energy bookkeeping %.2e, h_N %.2e (%ld steps, %ld location "
      "integrations, %.2f s)\n",
      bookkeeping, r.max_momentum_drift, r.stats.steps, r.stats.location_integrations,
      r.stats.wall_seconds);
  EXPECT_LE(bookkeeping, kBookkeepingTolerance);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  // Locked at the latch angle from then on.
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      if (r.trajectory.time[i] <= r.latch_times[static_cast<std::size_t>(k)]) continue;
      EXPECT_NEAR(r.trajectory.hinge_angles[i][k], 0.0, 1e-12);
      EXPECT_EQ(r.trajectory.hinge_rates[i][k], 0.0);
    }
  }
}

/// The same latch time from a run with another output grid (another step sequence) at
/// accuracy 1e-14 (measured 4.9e-15 s), and from a run at 1e-12 (Simbody's own error;
/// measured 1.4e-12 s).
constexpr double kLatchTimeOtherGrid = 5e-14;
constexpr double kLatchTimeOtherAccuracy = 1e-11;

TEST(SimbodyFreeHingesTest, LatchTimesAreLocatedToTheIntegrationError) {
  const schedule::Profile p = HingeProfile(
      SmallSat(), {WithLatch(Free(0.6, -20 * kDeg), 0.0), WithLatch(Free(0.3, -20 * kDeg), 0.0)},
      SmallSatSpin(), 4.0);
  const math::Vec3 y = math::Vec3::UnitY();
  const SimbodyFreeHingeRun a = RunSimbodyFreeHinges(p, Grid(0, 4, 0.1), y, Accuracy(1e-14));
  const SimbodyFreeHingeRun b = RunSimbodyFreeHinges(p, Grid(0, 3.7, 0.037), y, Accuracy(1e-14));
  const SimbodyFreeHingeRun c = RunSimbodyFreeHinges(p, Grid(0, 4, 0.1), y, Accuracy(1e-12));
  for (std::size_t k = 0; k < 2; ++k) {
    const double other_grid = std::abs(a.latch_times[k] - b.latch_times[k]);
    const double other_accuracy = std::abs(a.latch_times[k] - c.latch_times[k]);
    std::printf("latch %zu at %.15f s: another grid %.1e s, accuracy 1e-12 %.1e s\n", k,
                a.latch_times[k], other_grid, other_accuracy);
    EXPECT_LE(other_grid, kLatchTimeOtherGrid);
    EXPECT_LE(other_accuracy, kLatchTimeOtherAccuracy);
    // The located state is on the latch angle.
    const std::size_t i = static_cast<std::size_t>(
        std::find_if(a.events.begin(), a.events.end(),
                     [&](const HingeEvent& e) {
                       return e.kind == HingeEvent::Kind::kLatch && e.panel == static_cast<int>(k);
                     }) -
        a.events.begin());
    ASSERT_LT(i, a.events.size());
    EXPECT_NEAR(a.events[i].angle, 0.0, 1e-12);
  }
}

TEST(SimbodyFreeHingesTest, SkewChainLatchesTwice) {
  const schedule::Profile p = HingeProfile(
      SkewChain(), {WithLatch(Free(0.8, -20 * kDeg), 0.0), WithLatch(Free(0.5, 20 * kDeg), 0.0)},
      SmallSatSpin(), 15.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 15, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  ASSERT_EQ(EventsOf(r, HingeEvent::Kind::kLatch).size(), 2u);
  const double dissipated = CheckPlasticEvents(r, body, false);
  const double E0 = r.total_energy.front();
  const double bookkeeping = std::abs(r.total_energy.back() - (E0 - dissipated)) / E0;
  std::printf(
      "skew chain: latches at %.6f, %.6f s; energy bookkeeping %.2e, h_N %.2e "
      "(%ld steps, %.2f s)\n",
      r.latch_times[0], r.latch_times[1], bookkeeping, r.max_momentum_drift, r.stats.steps,
      r.stats.wall_seconds);
  EXPECT_LE(bookkeeping, kBookkeepingTolerance);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  EXPECT_NEAR(r.trajectory.hinge_angles.back()[0], 0.0, 1e-12);
  EXPECT_NEAR(r.trajectory.hinge_angles.back()[1], 0.0, 1e-12);
}

TEST(SimbodyFreeHingesTest, BranchedTreeLatchesEveryHinge) {
  const schedule::Profile p =
      HingeProfile(SkewTree(),
                   {WithLatch(Free(0.5, 20 * kDeg), 0.0), WithLatch(Free(0.8, -20 * kDeg), 0.0),
                    WithLatch(Free(0.3, -20 * kDeg), 0.0)},
                   SmallSatSpin(), 10.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 10, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  ASSERT_EQ(EventsOf(r, HingeEvent::Kind::kLatch).size(), 3u);
  const double dissipated = CheckPlasticEvents(r, body, false);
  const double E0 = r.total_energy.front();
  const double bookkeeping = std::abs(r.total_energy.back() - (E0 - dissipated)) / E0;
  std::printf(
      "branched tree: latches at %.6f, %.6f, %.6f s; energy bookkeeping %.2e, h_N "
      "%.2e (%ld steps, %.2f s)\n",
      r.latch_times[0], r.latch_times[1], r.latch_times[2], bookkeeping, r.max_momentum_drift,
      r.stats.steps, r.stats.wall_seconds);
  EXPECT_LE(bookkeeping, kBookkeepingTolerance);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.trajectory.hinge_angles.back()[k], 0.0, 1e-12);
}

// ---- motors ------------------------------------------------------------------------------

TEST(SimbodyFreeHingesTest, ConstantMotorsDoTheirWorkAndLatch) {
  // No springs: constant motor torques drive the wings from stowed to their latches. The
  // work of a constant torque is torque x swing, so the final energy is known exactly.
  HingePlan a = WithLatch(Free(0.0, 0.0), 0.0);
  a.drive.motor.kind = schedule::Motor::Kind::kConstant;
  a.drive.motor.torque = -0.08;
  HingePlan b = a;
  b.drive.motor.torque = -0.05;
  const schedule::Profile p = HingeProfile(SmallSat(), {a, b}, SmallSatSpin(), 15.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 15, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  ASSERT_EQ(EventsOf(r, HingeEvent::Kind::kLatch).size(), 2u);
  const double dissipated = CheckPlasticEvents(r, body, true);
  const double work = (-0.08 - 0.05) * (0.0 - 90 * kDeg);
  const double E0 = r.total_energy.front();
  const double bookkeeping =
      std::abs(r.total_energy.back() - (E0 + work - dissipated)) / (E0 + work);
  std::printf(
      "constant motors: latches at %.6f, %.6f s; work %.6f J; energy bookkeeping "
      "%.2e, h_N %.2e\n",
      r.latch_times[0], r.latch_times[1], work, bookkeeping, r.max_momentum_drift);
  EXPECT_LE(bookkeeping, kBookkeepingTolerance);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
}

/// E(t) - E0 against the integral of (motor + friction) theta' by Boole's rule on a 0.01 s
/// grid (measured 7.3e-13 of E0).
constexpr double kMotorBalanceTolerance = 5e-12;

TEST(SimbodyFreeHingesTest, TorqueSpeedMotorSpinsUpARotorAgainstFriction) {
  // A rotor (hinge through its CoM, along the hub's z) on a hub spinning about z: the
  // DC-motor line drives it towards its no-load speed; friction is regularized Coulomb.
  const model::Model m =
      MakeModel("rotor_sat", 85.0, math::Vec3(0.6, 1.0, 0.8),
                {MakePanel("rotor", -1, math::Vec3(0, 0, 0.2), math::Vec3::UnitZ(),
                           math::Vec3::Zero(), 5.0, math::Vec3(0.4, 0.4, 0.05))},
                Eigen::VectorXd::Zero(1));
  HingePlan rotor = Free(0.0, 0.0);
  rotor.drive.motor.kind = schedule::Motor::Kind::kTorqueSpeed;
  rotor.drive.motor.stall_torque = 0.2;
  rotor.drive.motor.no_load_speed = 3.0;
  rotor.drive.friction.torque = 0.01;
  rotor.drive.friction.regularization_speed = 0.5;
  const schedule::Profile p = HingeProfile(m, {rotor}, math::Vec3(0.01, 0.02, 0.3), 6.0);
  constexpr double h = 0.01;
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 6, h), math::Vec3::UnitZ(), Accuracy(1e-14));
  std::vector<double> power;
  for (const Eigen::VectorXd& u : r.trajectory.hinge_rates) {
    const double motor = 0.2 * (1.0 - u[0] / 3.0);
    const double friction = -0.01 * std::tanh(u[0] / 0.5);
    power.push_back((motor + friction) * u[0]);
  }
  const std::vector<double> work = BooleCumulative(power, h);
  const double E0 = r.total_energy.front();
  double worst = 0.0;
  for (std::size_t i = 0; i < work.size(); ++i) {
    worst = std::max(worst, std::abs(r.total_energy[4 * i] - E0 - work[i]) / E0);
  }
  const double rate = r.trajectory.hinge_rates.back()[0];
  std::printf(
      "rotor: rate %.6f rad/s after 6 s; E - E0 vs motor + friction work: %.2e of E0; "
      "h_N %.2e\n",
      rate, worst, r.max_momentum_drift);
  EXPECT_LE(worst, kMotorBalanceTolerance);
  EXPECT_GT(rate, 1.0);
  EXPECT_LT(rate, 3.0);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
}

// ---- releases, stops, rest, jam, prescribed windows ---------------------------------------

TEST(SimbodyFreeHingesTest, ReleaseAfterLatchThenBouncesOnAStopAndRests) {
  // wing_plus_x latches; wing_minus_x is released 1.5 s later and hits a stop at 0 with
  // restitution 0.3, its spring pressing it on the stop: it bounces until its rebound is
  // slower than kRestSpeed.
  HingePlan second = Free(3.0, -20 * kDeg);
  second.drive.release.kind = schedule::Release::Kind::kAfterLatch;
  second.drive.release.panel = 0;
  second.drive.release.delay = 1.5;
  second.drive.stops.min_angle = 0.0;
  second.drive.stops.restitution = 0.3;
  const schedule::Profile p = HingeProfile(
      SmallSat(), {WithLatch(Free(0.6, -20 * kDeg), 0.0), second}, SmallSatSpin(), 12.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 12, 0.1), math::Vec3::UnitY(), Accuracy(1e-14));
  const std::vector<const HingeEvent*> releases = EventsOf(r, HingeEvent::Kind::kRelease);
  ASSERT_EQ(releases.size(), 2u);
  EXPECT_EQ(releases[1]->panel, 1);
  EXPECT_NEAR(releases[1]->t, r.latch_times[0] + 1.5, 1e-14 * releases[1]->t);
  const std::vector<const HingeEvent*> stops = EventsOf(r, HingeEvent::Kind::kStop);
  const std::vector<const HingeEvent*> rests = EventsOf(r, HingeEvent::Kind::kRest);
  ASSERT_GE(stops.size(), 5u);
  ASSERT_EQ(rests.size(), 1u);
  for (const HingeEvent* e : stops) {
    EXPECT_EQ(e->panel, 1);
    EXPECT_NEAR(e->rate_after, -0.3 * e->rate_before, 1e-12 * std::abs(e->rate_before));
    EXPECT_NEAR(e->angle, 0.0, 1e-12);
    EXPECT_GE(std::abs(e->rate_after), schedule::kRestSpeed);
  }
  EXPECT_LT(0.3 * std::abs(rests[0]->rate_before), schedule::kRestSpeed);
  EXPECT_GT(rests[0]->t, stops.back()->t);
  std::printf(
      "release at %.15f s (latch + 1.5 s), %zu bounces from %.3e rad/s, rest at "
      "%.9f s (rate %.2e rad/s); %ld steps, %ld location integrations, %.2f s\n",
      releases[1]->t, stops.size(), stops.front()->rate_before, rests[0]->t, rests[0]->rate_before,
      r.stats.steps, r.stats.location_integrations, r.stats.wall_seconds);
  const double dissipated = CheckPlasticEvents(r, body, true);
  const double E0 = r.total_energy.front();
  EXPECT_NEAR(r.total_energy.back(), E0 - dissipated, kBookkeepingTolerance * E0);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
  EXPECT_NEAR(r.trajectory.hinge_angles.back()[1], 0.0, 1e-12);
  EXPECT_EQ(r.trajectory.hinge_rates.back()[1], 0.0);
}

TEST(SimbodyFreeHingesTest, PrescribedWindowsAndAJam) {
  // wing_plus_x is prescribed: linear from stowed to 0 on [1, 3] s (its rate jumps at both
  // ends), then 10 deg/s on [4, 5] s; wing_minus_x is free and jams half-way to its latch.
  HingePlan prescribed;
  prescribed.kind = HingePlan::Kind::kPrescribed;
  schedule::HingeMove to;
  to.kind = schedule::HingeMove::Kind::kTo;
  to.t_begin = 1.0;
  to.t_end = 3.0;
  to.angle = 0.0;
  to.law = schedule::Law::kLinear;
  schedule::HingeMove rate;
  rate.kind = schedule::HingeMove::Kind::kRate;
  rate.t_begin = 4.0;
  rate.t_end = 5.0;
  rate.rate = 10 * kDeg;
  prescribed.moves = {to, rate};
  const schedule::Profile p = HingeProfile(
      SmallSat(), {prescribed, WithLatch(Free(0.5, -20 * kDeg), 0.0, 0.5)}, SmallSatSpin(), 6.0);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "test");
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 6, 0.05), math::Vec3::UnitY(), Accuracy(1e-14));
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
    const double t = r.trajectory.time[i];
    double expected = 90 * kDeg;
    double expected_rate = 0.0;
    if (t >= 1.0 && t < 3.0) {
      expected = 90 * kDeg * (1.0 - (t - 1.0) / 2.0);
      expected_rate = -45 * kDeg;
    } else if (t >= 3.0 && t < 4.0) {
      expected = 0.0;
    } else if (t >= 4.0 && t < 5.0) {
      expected = 10 * kDeg * (t - 4.0);
      expected_rate = 10 * kDeg;
    } else if (t >= 5.0) {
      expected = 10 * kDeg;
    }
    EXPECT_NEAR(r.trajectory.hinge_angles[i][0], expected, 1e-13) << t;
    EXPECT_NEAR(r.trajectory.hinge_rates[i][0], expected_rate, 1e-13) << t;
  }
  const std::vector<const HingeEvent*> jams = EventsOf(r, HingeEvent::Kind::kJam);
  ASSERT_EQ(jams.size(), 1u);
  EXPECT_EQ(jams[0]->panel, 1);
  EXPECT_NEAR(jams[0]->angle, 45 * kDeg, 1e-12);
  EXPECT_TRUE(std::isnan(r.latch_times[1]));
  EXPECT_NEAR(r.trajectory.hinge_angles.back()[1], 45 * kDeg, 1e-12);
  // The jam's effective inertia excludes the prescribed hinge (not free).
  CheckPlasticEvents(r, body, true);
  std::printf("prescribed + jam: jam at %.9f s; h_N %.2e across the rate jumps\n", jams[0]->t,
              r.max_momentum_drift);
  EXPECT_LE(r.max_momentum_drift, kMomentumTolerance);
}

TEST(SimbodyFreeHingesTest, AHingeReleasedOnItsStopLeavesItOrRestsOnIt) {
  // Both wings deployed (0) on a stop at 0: wing_plus_x's spring pulls it off the stop
  // (rest 30 deg; stiff enough to beat the centrifugal load, which turns a deployed wing
  // towards negative angles), wing_minus_x's presses it on the stop (rest -20 deg): it
  // rests at once.
  HingePlan away = Free(3.0, 30 * kDeg);
  away.drive.stops.min_angle = 0.0;
  HingePlan pressed = Free(0.6, -20 * kDeg);
  pressed.drive.stops.min_angle = 0.0;
  pressed.drive.stops.restitution = 0.5;
  const schedule::Profile p = HingeProfile(SmallSat(0.0), {away, pressed}, SmallSatSpin(), 2.0);
  const SimbodyFreeHingeRun r =
      RunSimbodyFreeHinges(p, Grid(0, 2, 0.1), math::Vec3::UnitY(), Accuracy(1e-12));
  const std::vector<const HingeEvent*> rests = EventsOf(r, HingeEvent::Kind::kRest);
  ASSERT_EQ(rests.size(), 1u);
  EXPECT_EQ(rests[0]->panel, 1);
  EXPECT_EQ(rests[0]->t, 0.0);
  EXPECT_EQ(rests[0]->impulse, 0.0);
  EXPECT_TRUE(EventsOf(r, HingeEvent::Kind::kStop).empty());
  EXPECT_GT(r.trajectory.hinge_angles.back()[0], 1 * kDeg);
  EXPECT_EQ(r.trajectory.hinge_angles.back()[1], 0.0);
}

// ---- the stiff stop -----------------------------------------------------------------------

TEST(SimbodyFreeHingesTest, StiffStopConvergesToThePlasticLatch) {
  // wing_plus_x latches at 0 (wing_minus_x locked): plastic, and with compliant latches of
  // growing stiffness (critically damped). After the contact transient, the difference
  // falls as 1 / stiffness.
  const schedule::Profile p = HingeProfile(
      SmallSat(), {WithLatch(Free(0.6, -20 * kDeg), 0.0), Locked()}, SmallSatSpin(), 8.0);
  const std::vector<double> grid = Grid(0, 8, 0.05);
  const math::Vec3 y = math::Vec3::UnitY();
  const SimbodyFreeHingeRun plastic = RunSimbodyFreeHinges(p, grid, y, Accuracy(1e-13));
  const double t_latch = plastic.latch_times[0];
  ASSERT_TRUE(std::isfinite(t_latch));
  const double t_settled = t_latch + 3.0;
  const double H = plastic.trajectory.H_B.front().norm();
  std::printf(
      "stiff stop vs plastic latch (latch at %.6f s; max over t >= latch + 3 s):\n"
      "  stiffness [N m/rad]   H_B / |H|     w [rad/s]    attitude [rad]  steps   "
      "wall [s]\n",
      t_latch);
  std::vector<double> errors;
  for (double k : {1e2, 1e3, 1e4, 1e5, 1e6}) {
    SimbodyFreeHingeOptions o = Accuracy(1e-13);
    o.compliant_latch.stiffness = k;
    const SimbodyFreeHingeRun r = RunSimbodyFreeHinges(p, grid, y, o);
    double dH = 0.0, dw = 0.0, datt = 0.0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      if (grid[i] < t_settled) continue;
      dH = std::max(dH, (r.trajectory.H_B[i] - plastic.trajectory.H_B[i]).norm() / H);
      dw = std::max(dw, (r.trajectory.w_NB_B[i] - plastic.trajectory.w_NB_B[i]).norm());
      datt = std::max(datt, r.trajectory.q_NB[i].angularDistance(plastic.trajectory.q_NB[i]));
    }
    std::printf("  %9.0e          %11.3e   %11.3e   %11.3e   %6ld   %.2f\n", k, dH, dw, datt,
                r.stats.steps, r.stats.wall_seconds);
    errors.push_back(dw);
    EXPECT_EQ(EventsOf(r, HingeEvent::Kind::kLatch).size(), 1u);
  }
  // error ~ 1 / stiffness: a factor 10 per decade (measured 9.9 ... 10.0).
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double ratio = errors[i - 1] / errors[i];
    EXPECT_GT(ratio, 8.0) << i;
    EXPECT_LT(ratio, 12.5) << i;
  }
  EXPECT_LT(errors.back(), 5e-8);  // measured 1.9e-8 rad/s at 1e6 N m/rad
}

// ---- the major-axis rule -------------------------------------------------------------------

/// The located 45-degree crossing: the angle there on a run that ends at that time
/// (another step sequence; measured 3.6e-15 rad), and the crossing time at accuracy 1e-14
/// against 1e-12 (Simbody's own error; measured 5.4e-13 relative).
constexpr double kCrossingAngleTolerance = 1e-11;
constexpr double kCrossingTimeRelativeTolerance = 1e-11;

TEST(SimbodyFreeHingesTest, PendulumDamperTurnsAMinorAxisSpinIntoAFlatSpin) {
  const schedule::Profile p = HingeProfile(PendulumDamperSpinner(), {Free(0.2, 0.0, 2.0)},
                                           math::Vec3(0.1, 0.0, 1.0), 300.0);
  const math::Vec3 z = math::Vec3::UnitZ();
  SimbodyFreeHingeOptions o = Accuracy(1e-12);
  o.spin_axis_angles = {kPi / 4};
  const SimbodyFreeHingeRun r = RunSimbodyFreeHinges(p, Grid(0, 300, 1.0), z, o);
  // At the start z is the minor axis of the whole system.
  EXPECT_EQ(analysis::LocateSpinAxis(r.J_B.front(), z).role, analysis::AxisRole::kMinor);
  // Energy only decreases; |H| is kept.
  for (std::size_t i = 1; i < r.total_energy.size(); ++i) {
    EXPECT_LE(r.total_energy[i], r.total_energy[i - 1]) << r.trajectory.time[i];
  }
  EXPECT_LE(r.max_momentum_drift, 1e-10);
  // It ends in a flat spin: D = |H|^2 / 2T approaches the largest principal moment of the
  // whole system, and H_B the major axis.
  auto gap = [&](std::size_t i) {
    const math::Vec3& H = r.trajectory.H_B[i];
    const double D = H.squaredNorm() / (2.0 * r.trajectory.kinetic_energy[i]);
    const Eigen::SelfAdjointEigenSolver<math::Mat3> es(r.J_B[i]);
    return (es.eigenvalues()[2] - D) / es.eigenvalues()[2];
  };
  const std::size_t last = r.trajectory.size() - 1;
  const Eigen::SelfAdjointEigenSolver<math::Mat3> es(r.J_B[last]);
  const math::Vec3 major = es.eigenvectors().col(2);
  const math::Vec3& H_end = r.trajectory.H_B[last];
  const double axis_angle = std::acos(std::abs(major.dot(H_end)) / H_end.norm());
  std::printf(
      "pendulum damper: D/J_max gap %.3e at 0 s, %.3e at 150 s, %.3e at 300 s; H_B "
      "%.2f deg from the major axis; D0/J_min %.4f\n",
      gap(0), gap(150), gap(last), axis_angle / kDeg,
      r.trajectory.H_B[0].squaredNorm() / (2.0 * r.trajectory.kinetic_energy[0]) /
          Eigen::SelfAdjointEigenSolver<math::Mat3>(r.J_B[0]).eigenvalues()[0]);
  EXPECT_GT(gap(0), 0.3);                // measured 0.40
  EXPECT_LT(gap(last), 1e-2);            // measured 5.2e-3
  EXPECT_LT(gap(last), 0.6 * gap(150));  // measured 0.44
  EXPECT_LT(axis_angle, 10 * kDeg);      // measured 5.8 deg
  // The spin axis passes 45 degrees from h_N once, on the way out.
  ASSERT_GE(r.spin_axis_crossings.size(), 1u);
  const SpinAxisCrossing& x = r.spin_axis_crossings.front();
  EXPECT_TRUE(x.increasing);
  EXPECT_EQ(x.angle, kPi / 4);
  for (const SpinAxisCrossing& c : r.spin_axis_crossings) EXPECT_GE(c.t, x.t);
  // Located: a run that ends exactly there sees the spin axis at 45 degrees.
  const SimbodyFreeHingeRun to_crossing = RunSimbodyFreeHinges(p, {0.0, x.t}, z, Accuracy(1e-12));
  const double angle_there = SpinAngle(to_crossing, 1, z);
  // Simbody's own error in the crossing time: at accuracy 1e-14.
  SimbodyFreeHingeOptions fine = Accuracy(1e-14);
  fine.spin_axis_angles = {kPi / 4};
  const double t_fine_end = std::ceil(x.t) + 1.0;
  const SimbodyFreeHingeRun f = RunSimbodyFreeHinges(p, Grid(0, t_fine_end, 1.0), z, fine);
  ASSERT_GE(f.spin_axis_crossings.size(), 1u);
  const double dt_rel = std::abs(f.spin_axis_crossings.front().t - x.t) / x.t;
  std::printf(
      "45 deg crossing at %.12f s (%zu crossings); angle there on a restarted run "
      "%.2e rad off; accuracy 1e-14 gives %.12f s (%.1e relative); runtimes %.2f s, "
      "%.2f s (1e-14, %.0f s)\n",
      x.t, r.spin_axis_crossings.size(), std::abs(angle_there - kPi / 4),
      f.spin_axis_crossings.front().t, dt_rel, r.stats.wall_seconds, f.stats.wall_seconds,
      t_fine_end);
  EXPECT_NEAR(angle_there, kPi / 4, kCrossingAngleTolerance);
  EXPECT_LE(dt_rel, kCrossingTimeRelativeTolerance);
}

// ---- flips ---------------------------------------------------------------------------------

/// Flip times of the rigid (all hinges locked) deployed small satellite against the closed
/// form, and H_B / |H|, over 150 s at accuracy 1e-12: measured 8.7e-8 s and 1.1e-8.
/// Simbody's own integration error: at accuracies 1e-11, 1e-12, 1e-13, 1e-14 the flip
/// times are off by 9.6e-7, 8.7e-8, 8.0e-9, 7.7e-10 s and H_B by 1.2e-7, 1.1e-8, 9.9e-10,
/// 9.5e-11 (it falls with the accuracy; the location itself is to 1e-13 s).
constexpr double kRigidFlipTolerance = 3e-7;
constexpr double kRigidMomentumTolerance = 3e-8;

TEST(SimbodyFreeHingesTest, LockedHingesFlipLikeTheClosedForm) {
  // Deployed and locked: y is the intermediate axis; the spin flips (Dzhanibekov).
  const schedule::Profile p =
      HingeProfile(SmallSat(0.0), {Locked(), Locked()}, SmallSatSpin(), 150.0);
  const math::Vec3 y = math::Vec3::UnitY();
  const SimbodyFreeHingeRun r = RunSimbodyFreeHinges(p, Grid(0, 150, 0.5), y, Accuracy(1e-12));
  const analysis::FreeBodySolution exact(math::InertiaTensor::FromMatrix(r.J_B.front()),
                                         r.trajectory.H_B.front(), r.trajectory.q_NB.front());
  const std::vector<double> flips = exact.FlipTimes(0.0, 150.0);
  ASSERT_GE(flips.size(), 2u);
  ASSERT_EQ(r.flip_times.size(), flips.size());
  double dt = 0.0, dH = 0.0;
  for (std::size_t i = 0; i < flips.size(); ++i)
    dt = std::max(dt, std::abs(r.flip_times[i] - flips[i]));
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
    dH = std::max(dH, (r.trajectory.H_B[i] - exact.H_B(r.trajectory.time[i])).norm() /
                          exact.momentum_magnitude());
  }
  std::printf(
      "locked hinges: %zu flips, max |t - t_exact| %.2e s, H_B %.2e (%ld steps, %ld realizations, "
      "%.2f s)\n",
      flips.size(), dt, dH, r.stats.steps, r.stats.realizations, r.stats.wall_seconds);
  EXPECT_LE(dt, kRigidFlipTolerance);
  EXPECT_LE(dH, kRigidMomentumTolerance);
  EXPECT_TRUE(r.events.empty());
  for (const Eigen::VectorXd& a : r.trajectory.hinge_angles) EXPECT_EQ(a.norm(), 0.0);
}

// ---- inputs ---------------------------------------------------------------------------------

TEST(SimbodyFreeHingesTest, RefusesWhatItCannotRun) {
  const schedule::Profile p =
      HingeProfile(SmallSat(), {Free(0.6, 0.0), Free(0.6, 0.0)}, SmallSatSpin(), 1.0);
  const math::Vec3 y = math::Vec3::UnitY();
  const std::vector<double> grid = Grid(0, 1, 0.5);
  EXPECT_THROW(RunSimbodyFreeHinges(p, grid, y, Accuracy(0.0)), std::invalid_argument);
  EXPECT_THROW(RunSimbodyFreeHinges(p, {0.5, 1.0}, y, Accuracy(1e-10)), std::invalid_argument);
  EXPECT_THROW(RunSimbodyFreeHinges(p, grid, math::Vec3(0, 2, 0), Accuracy(1e-10)),
               std::invalid_argument);
  schedule::Profile one_plan = p;
  one_plan.hinges.pop_back();
  EXPECT_THROW(RunSimbodyFreeHinges(one_plan, grid, y, Accuracy(1e-10)), std::invalid_argument);
  schedule::Profile cycle = p;
  cycle.model.hinged.panels[0].parent = 1;
  cycle.model.hinged.panels[1].parent = 0;
  EXPECT_THROW(RunSimbodyFreeHinges(cycle, grid, y, Accuracy(1e-10)), std::invalid_argument);
  // Exact Coulomb friction sticks and slips at events the Simbody model does not have.
  schedule::Profile coulomb = p;
  coulomb.hinges[0].drive.friction.torque = 0.01;
  try {
    RunSimbodyFreeHinges(coulomb, grid, y, Accuracy(1e-10));
    ADD_FAILURE() << "accepted exact Coulomb friction";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exact Coulomb friction"), std::string::npos) << e.what();
  }
  SimbodyFreeHingeOptions bad_latch = Accuracy(1e-10);
  bad_latch.compliant_latch.stiffness = -1.0;
  EXPECT_THROW(RunSimbodyFreeHinges(p, grid, y, bad_latch), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
