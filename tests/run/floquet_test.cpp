// Floquet stability of periodic steady motions (analysis/floquet.h), against the physics:
// a damper riding a spinning rotor, modelled once with the platform as the hub (the
// motion is periodic in its frame) and once with the rotor as the hub (steady), gives the
// same rates; a rigid body's multipliers lie on the unit circle; a steady spin taken as a
// periodic orbit has the multipliers exp(lambda T) of its eigenvalues.

#include "deploysim/analysis/floquet.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <vector>

#include "crosscheck/free_hinge_fixtures.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/math/inertia.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/run/mission.h"
#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

/// A dual-spin craft with its nutation damper on the rotor: a platform (a 60 kg drum, radius
/// 0.6 m, 0.3 m long, symmetric about z) and a rotor (a 40 kg 1.6 x 1.6 x 0.3 m box, its
/// inertia symmetric about z) 0.5 m above it on a bearing along z through both centres;
/// on the rotor a 2 kg pendulum damper 0.8 m out along x, hinged about y near the system's
/// CoM height, its mass 0.3 m further out. `rotor_hub`: the rotor is the hub (the platform
/// a panel on the bearing: the motion is steady in the hub's frame); otherwise the
/// platform is the hub and the rotor a panel carrying the damper (periodic).
model::Model RotorDamperCraft(bool rotor_hub) {
  model::Model md;
  md.name = rotor_hub ? "rotor_hub" : "platform_hub";
  md.kind = model::ModelKind::kHinged;
  const double ia = 60.0 * 0.36 / 2.0, it = 60.0 * (3.0 * 0.36 + 0.09) / 12.0;
  const Mat3 platform = Vec3(it, it, ia).asDiagonal();
  const Mat3 rotor = model::BoxInertia(40.0, Vec3(1.6, 1.6, 0.3));
  const double z_damper = -0.5 * 60.0 / 102.0;  // from the rotor's centre
  model::Panel bearing;
  bearing.hinge_axis_B = Vec3::UnitZ();
  model::Panel damper;
  damper.name = "damper";
  damper.body.mass = 2.0;
  damper.body.inertia_cm = model::BoxInertia(2.0, Vec3(0.08, 0.08, 0.08));
  damper.hinge_point_B = Vec3(0.8, 0.0, z_damper);
  damper.hinge_axis_B = Vec3::UnitY();
  damper.com_offset_B = Vec3(0.3, 0.0, 0.0);
  if (rotor_hub) {
    md.hinged.hub.body = {40.0, rotor};
    bearing.name = "platform";
    bearing.body = {60.0, platform};
    bearing.hinge_point_B = Vec3(0.0, 0.0, -0.5);
    damper.parent = -1;
  } else {
    md.hinged.hub.body = {60.0, platform};
    bearing.name = "rotor";
    bearing.body = {40.0, rotor};
    bearing.hinge_point_B = Vec3(0.0, 0.0, 0.5);
    damper.parent = 0;
  }
  md.hinged.panels = {bearing, damper};
  testing::SetInitialConfiguration(md);
  return md;
}

/// The rotor spinning at w_r and the platform at w_p (absolute, about z), a transverse
/// rate that tilts H by nu0; the damper (spring 1 N m/rad, damping 2 N m s/rad) at rest.
/// `held`: a motor holds the rotor's rate relative to the platform (a prescribed steady
/// rate), else the bearing is free.
schedule::Profile RotorDamperProfile(
    bool rotor_hub, bool held, double w_r, double w_p, double nu0, double until) {
  const model::Model md = RotorDamperCraft(rotor_hub);
  const double rel = rotor_hub ? w_p - w_r : w_r - w_p;  // the bearing's rate
  schedule::HingePlan bearing;
  if (held) {
    bearing.kind = schedule::HingePlan::Kind::kPrescribed;
    schedule::HingeMove mv;
    mv.kind = schedule::HingeMove::Kind::kRate;
    mv.t_begin = 0.0;
    mv.t_end = 1e7;
    mv.rate = rel;
    bearing.moves = {mv};
  } else {
    bearing.kind = schedule::HingePlan::Kind::kFree;
  }
  const schedule::HingePlan damper = testing::SpringHinge(1.0, 0.0, 2.0);
  const double I_t = 40.0 * (2.56 + 0.09) / 12.0 + 60.0 * (3.0 * 0.36 + 0.09) / 12.0 +
                     2.0 * 1.1 * 1.1 + 100.0 * 0.3 * 0.2;  // roughly: sets the tilt only
  const double H = 40.0 * 5.12 / 12.0 * w_r + 10.8 * w_p + 2.0 * 1.21 * w_r;
  const double w_hub = rotor_hub ? w_r : w_p;
  schedule::Profile p = crosscheck::free_hinge_fixtures::HingeProfile(
      md, {bearing, damper}, Vec3(nu0 * H / I_t, 0.0, w_hub), until);
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-10;
  p.integrator.atol = 1e-12;
  p.output.dt = 0.1;
  p.initial.hinge_rates = Eigen::Vector2d(held ? 0.0 : rel, 0.0);
  return p;
}

/// The profile started on the orbit `lin` found (its H_B at phase 0 tilted by nu0, the
/// damper at its angle there, at rest relative to the rotor as on the orbit), so that the
/// nutation mode starts at nu0 and the others are barely excited.
schedule::Profile OnTheOrbit(schedule::Profile p, const analysis::SteadySpin& lin, double nu0) {
  const Vec3 H = lin.y.head<3>();
  const Vec3 across = H.cross(Vec3::UnitX()).normalized();
  p.initial.w_NB_B.reset();
  p.initial.H_B = Eigen::AngleAxisd(nu0, across) * H;
  const Eigen::Index damper =
      lin.y.size() == 5 ? 3 : 4;  // held: (H, damper); free: (H, rotor, damper)
  p.model.configurations[0].hinge_angles[1] = lin.y[damper];
  return p;
}

analysis::SteadySpin Linear(bool rotor_hub, bool held, double w_r, double w_p, double nu0 = 1e-4) {
  return RunMission(RotorDamperProfile(rotor_hub, held, w_r, w_p, nu0, 1e-3)).outcome.linear;
}

// A rigid body tumbling along a polhode is periodic in B (the closed form's period): its
// multipliers are 1 (the flow, |H| and the energy: a rigid body neither grows nor decays).
// A steady spin about the minor axis, taken as a periodic orbit of any period T, has the
// multipliers exp(+-i w_n T) of its nutation (w_n the closed form's).
TEST(FloquetTest, RigidBodyMultipliersLieOnTheUnitCircle) {
  const Vec3 I(2.0, 3.0, 5.0);
  const analysis::ReducedFlow flow = analysis::FlowOf(Mat3(I.asDiagonal()), Vec3::Zero());
  const Vec3 H0(0.3, 0.0, 4.0);  // about the major axis, tumbling
  const analysis::FreeBodySolution exact(math::InertiaTensor::FromMatrix(Mat3(I.asDiagonal())), H0);
  analysis::OrbitProblem p;
  p.rhs = [&flow](double, const Eigen::VectorXd& y) { return flow.rhs(y); };
  p.scale = Eigen::Vector3d::Constant(H0.norm());
  p.advance = Eigen::Vector3d::Zero();
  p.period_guess = exact.period() * 1.001;
  p.phase = 0;
  p.momentum = H0.norm();
  const analysis::PeriodicOrbit orbit = analysis::SolvePeriodicOrbit(p, H0 + Vec3(1e-3, 0.0, 0.0));
  ASSERT_TRUE(orbit.found) << orbit.reason;
  EXPECT_LT(orbit.residual, 1e-10);
  EXPECT_NEAR(orbit.period,
              analysis::FreeBodySolution(math::InertiaTensor::FromMatrix(Mat3(I.asDiagonal())),
                                         Vec3(orbit.y0))
                  .period(),
              1e-9 * orbit.period);
  // The multiplier 1 of the energy and the flow's phase is defective (a neighbouring
  // polhode has another period): a rounding error e splits it by sqrt(e), differently on
  // each machine (measured 2.2e-6 under qemu-aarch64). The trace and the determinant
  // (the flow keeps volume) see e itself.
  const Eigen::MatrixXd& Mo = orbit.monodromy;
  std::printf("tumbling: trace - 3 %.2e, det - 1 %.2e\n", Mo.trace() - 3.0, Mo.determinant() - 1.0);
  EXPECT_NEAR(Mo.trace(), 3.0, 5e-11);        // measured -1.2e-11 (x86-64), 8.3e-12 (aarch64)
  EXPECT_NEAR(Mo.determinant(), 1.0, 5e-11);  // measured -1.7e-11
  const Eigen::VectorXcd mu = Eigen::EigenSolver<Eigen::MatrixXd>(Mo).eigenvalues();
  for (Eigen::Index i = 0; i < mu.size(); ++i) EXPECT_NEAR(std::abs(mu[i]), 1.0, 1e-5) << mu[i];
  // The steady spin about the minor axis (z: I = 5 is the major here; x, I = 2, the minor).
  const double M = 4.0, w = M / I[0];
  const double wn = w * std::sqrt((I[1] - I[0]) * (I[2] - I[0]) / (I[1] * I[2]));
  analysis::OrbitProblem q = p;
  q.period_fixed = true;
  q.phase = -1;
  q.period_guess = 1.7;
  q.momentum = M;
  const analysis::PeriodicOrbit spin = analysis::SolvePeriodicOrbit(q, Vec3(M, 1e-4, 0.0));
  ASSERT_TRUE(spin.found) << spin.reason;
  const Eigen::VectorXcd m2 = Eigen::EigenSolver<Eigen::MatrixXd>(spin.monodromy).eigenvalues();
  int oscillating = 0;
  for (Eigen::Index i = 0; i < m2.size(); ++i) {
    EXPECT_NEAR(std::abs(m2[i]), 1.0, 1e-9) << m2[i];
    if (std::abs(m2[i] - 1.0) < 1e-6) continue;
    ++oscillating;
    EXPECT_NEAR(std::abs(std::arg(m2[i])), std::abs(std::remainder(wn * 1.7, 2.0 * M_PI)), 1e-9);
  }
  EXPECT_EQ(oscillating, 2);
}

// The damper on the rotor, with a motor holding the rotor's rate and with a free bearing:
// modelled with the platform as the hub, the steady motion is periodic in the hub's frame
// (Floquet); with the rotor as the hub it is steady (eigenvalues). Same craft, same state:
// the same rates, the nutation's and every mode's (measured within 1e-9). A despun rotor
// (not spinning) and a rotor turning with the platform (steady in both) included.
TEST(FloquetTest, DamperOnARotorHasTheRatesOfTheRotorAsHub) {
  const double w_p = 0.5;
  for (bool held : {true, false}) {
    for (double w_r : {0.0, w_p, 1.5, 4.0}) {
      const analysis::SteadySpin a = Linear(false, held, w_r, w_p);
      const analysis::SteadySpin b = Linear(true, held, w_r, w_p);
      ASSERT_TRUE(a.found) << a.reason;
      ASSERT_TRUE(b.found) << b.reason;
      EXPECT_EQ(a.motion, w_r == w_p ? "steady" : "periodic");
      EXPECT_EQ(b.motion, "steady");
      EXPECT_LT(a.residual, analysis::kSolutionResidual);
      std::printf(
          "%s rotor at %.2f rad/s: nutation rate %.10g (%s, T %.4g s) / %.10g (%s), "
          "%.2e\n",
          held ? "held" : "free", w_r, a.growth_rate, a.motion.c_str(), a.period, b.growth_rate,
          b.motion.c_str(), a.growth_rate / b.growth_rate - 1.0);
      // A free rotor turning with the platform is steady in both models, but the rotor-as-panel
      // model cannot hold the platform's momentum there (held, the rotor would have to turn
      // slowly): its steady spin is the one nearest the phase's state, off by ~nu^2 (measured
      // 2.7e-6 at nu = 1e-4 rad).
      const bool locked_free = !held && w_r == w_p;
      EXPECT_NEAR(a.growth_rate, b.growth_rate,
                  (locked_free ? 1e-5 : 1e-6) * std::abs(b.growth_rate));
      EXPECT_EQ(a.verdict, b.verdict);
      // Every mode the Floquet multipliers resolve (|mu| above 1e-6: the damper's fast
      // decay drops below the monodromy's error) has its steady counterpart's rate.
      for (const analysis::SpinMode& md : a.modes) {
        if (md.lambda.real() * a.period < std::log(1e-6)) continue;
        double nearest = 1e300;
        for (const analysis::SpinMode& mb : b.modes)
          nearest = std::min(nearest, std::abs(mb.lambda.real() - md.lambda.real()));
        EXPECT_LT(nearest, (locked_free ? 1e-5 : 1e-6) * std::max(std::abs(md.lambda.real()), 1e-3))
            << md.lambda;
      }
    }
  }
}

// The shortest of the cases above (a motor-held rotor, period 1.8 s), for the steps that
// leave the long ones out (tests/long_runs.txt): the periodic path of a hinge run.
TEST(FloquetTest, HeldRotorWithADamperIsPeriodic) {
  const analysis::SteadySpin a = Linear(false, true, 4.0, 0.5);
  const analysis::SteadySpin b = Linear(true, true, 4.0, 0.5);
  ASSERT_TRUE(a.found) << a.reason;
  EXPECT_EQ(a.motion, "periodic");
  EXPECT_EQ(static_cast<int>(a.orbit_axes.size()), analysis::kOrbitPoints);
  EXPECT_NEAR(a.growth_rate, b.growth_rate, 1e-6 * std::abs(b.growth_rate));
}

// No verdict from a state that is not a motion: a rotor held at its rate for less than one
// turn (the phase ends before the motion repeats) has neither a steady nor a periodic
// motion, and the record says why instead of linearizing about the phase's start.
TEST(FloquetTest, NoVerdictWithoutAMotion) {
  schedule::Profile p = RotorDamperProfile(false, true, 1.5, 0.5, 1e-4, 1e-3);
  p.hinges[0].moves[0].t_end = 1.0;  // the rotor turns once in 6.3 s
  const analysis::SteadySpin s = RunMission(p).outcome.linear;
  EXPECT_FALSE(s.found);
  EXPECT_NE(s.reason.find("neither steady nor periodic"), std::string::npos) << s.reason;
  EXPECT_TRUE(s.modes.empty());
}

// The damper on the rotor, the rotor as a panel of the platform (the model a user writes):
// across the rotor's spin through the stability boundary (found by bisection on the
// Floquet rate), a despun rotor and cases 5 % from the boundary included, with a motor
// holding the rotor and with a free bearing, the sign of the Floquet rate is the trend of
// the run's nutation, and the rate fitted to the envelope is the Floquet rate of the run's
// own orbit to 1e-3 in every case (measured within 2e-4), within its stated uncertainty.
// Each run starts on the orbit with the nutation tilted by nu0 (OnTheOrbit): from the
// craft's own start (H along the bearing) the nutation is 6.5e-3 rad from the orbit's
// cone, and a growing one leaves the linear band before its partner mode has decayed.
TEST(FloquetTest, DamperOnARotorBoundaryHoldsInTheRuns) {
  const double w_p = 0.5;
  for (bool held : {true, false}) {
    double lo = 1.0, hi = 1.5;  // stable at 1.0, unstable at 1.5 (the test above)
    ASSERT_LT(Linear(false, held, lo, w_p).growth_rate, 0.0);
    ASSERT_GT(Linear(false, held, hi, w_p).growth_rate, 0.0);
    for (int i = 0; i < 12; ++i) {  // to 1.2e-4 rad/s
      const double mid = 0.5 * (lo + hi);
      (Linear(false, held, mid, w_p).growth_rate < 0.0 ? lo : hi) = mid;
    }
    const double boundary = 0.5 * (lo + hi);
    std::printf("%s rotor: boundary at %.8g rad/s (platform %.2g rad/s)\n", held ? "held" : "free",
                boundary, w_p);
    double worst = 0.0;
    for (double f : {0.0, 0.6, 0.8, 0.95, 1.05, 1.2, 1.4, 3.0}) {
      const double w_r = f * boundary;
      const analysis::SteadySpin lin = Linear(false, held, w_r, w_p);
      ASSERT_TRUE(lin.found) << lin.reason;
      // Growing from 1e-6 rad, decaying from 1e-4 rad: after the other modes have decayed
      // (FitStart), five e-folds in the linear band, or 1200 s of a slow decay (at least
      // 0.14 of an e-fold and 8 of the envelope's windows: enough to call it beyond doubt).
      const double nu0 = lin.growth_rate > 0.0 ? 1e-6 : 1e-4;
      const double until =
          30.0 + analysis::FitStart(lin, 0.0) + std::min(5.0 / std::abs(lin.growth_rate), 1200.0);
      schedule::Profile prof =
          OnTheOrbit(RotorDamperProfile(false, held, w_r, w_p, nu0, until), lin, nu0);
      const MissionResult r = RunMission(prof);
      const double sigma = r.outcome.linear.growth_rate;  // the orbit through the run's start
      const analysis::ExponentialFit& fit = r.outcome.trend;
      std::printf("  w_r %.4g (%.2f x, %s): Floquet %+.6g 1/s, run %+.6g +- %.2g 1/s (%s)\n", w_r,
                  f, r.outcome.linear.motion.c_str(), sigma, fit.rate, fit.rate_uncertainty,
                  r.outcome.outcome_name.c_str());
      const analysis::OutcomeClass c = r.outcome.outcome;
      ASSERT_NE(c, analysis::OutcomeClass::kBounded) << "w_r " << w_r;
      ASSERT_NE(c, analysis::OutcomeClass::kIncomplete) << "w_r " << w_r;
      EXPECT_EQ(c != analysis::OutcomeClass::kDecaying, lin.growth_rate > 0.0) << "w_r " << w_r;
      EXPECT_EQ(sigma > 0.0, lin.growth_rate > 0.0) << "w_r " << w_r;
      ASSERT_TRUE(fit.valid && fit.ceiling < 0.1) << "w_r " << w_r;
      EXPECT_NEAR(fit.rate, sigma, 3.0 * fit.rate_uncertainty) << "w_r " << w_r;
      EXPECT_NEAR(fit.rate, sigma, 1e-3 * std::abs(sigma)) << "w_r " << w_r;
      worst = std::max(worst, std::abs(fit.rate / sigma - 1.0));
    }
    std::printf("  the fits within %.2g of the Floquet rates\n", worst);
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
