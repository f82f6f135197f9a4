// The Dzhanibekov wing nut, in code: a rigid body spun about its intermediate axis
// flips every 3.56 s. Its inertia is a user-defined dynamics::InertiaSource; a numerical
// stepper (rkf78) integrates it for 40 s and the closed form (analysis::FreeBodySolution)
// checks every sample. Exits 1 when the error exceeds the stated bound.
//
// Only installed headers are used: #include <deploysim/...>, linked with
// deploysim::analysis (find_package(deploysim)).

#include <deploysim/analysis/exact_flow.h>
#include <deploysim/analysis/free_body_solution.h>
#include <deploysim/dynamics/inertia_source.h>
#include <deploysim/integrators/integrate.h>
#include <deploysim/math/inertia.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using deploysim::math::Mat3;
using deploysim::math::Vec3;

/// A body whose inertia never changes, written as a user would write any J(t): the
/// interface asks for J_B(t), its rate, the relative momentum and J_B^-1.
class RigidWingNut final : public deploysim::dynamics::InertiaSource {
 public:
  explicit RigidWingNut(const Vec3& principal_moments) {
    sample_.J_B = principal_moments.asDiagonal();
    sample_.Jdot_B = Mat3::Zero();
    sample_.h_rel_B = Vec3::Zero();
    sample_.J_inv_B = principal_moments.cwiseInverse().asDiagonal();
  }
  deploysim::dynamics::InertiaSample Evaluate(double /*t*/,
                                              deploysim::dynamics::Side /*side*/) const override {
    return sample_;
  }
  const Mat3& J_B() const { return sample_.J_B; }

 private:
  deploysim::dynamics::InertiaSample sample_;
};

// Largest error allowed against the closed form, relative to |H_B| (momentum) and in
// radians (attitude). rkf78 at rtol 1e-12 measures ~1e-10 here (the flips amplify the
// local errors); the bound leaves a few times that.
constexpr double kMomentumBound = 1e-9;
constexpr double kAttitudeBound = 1e-9;

}  // namespace

int main() {
  namespace ds = deploysim;
  const Vec3 moments(3.036e-6, 2.741e-6, 0.699e-6);  // [kg m^2] thesis 3.2, y intermediate
  const RigidWingNut body(moments);

  ds::integrators::State initial;
  initial.t = 0.0;
  initial.H_B = Vec3(1.0e-8, 2.1252e-5, 1.0e-8);  // [kg m^2/s] almost along body y
  initial.q_NB = ds::math::Quat::Identity();
  const double t_end = 40.0;  // [s]

  ds::integrators::IntegratorSettings settings;
  settings.tolerances.rtol = 1e-12;
  settings.tolerances.atol = 1e-14 * initial.H_B.norm();
  const auto stepper = ds::analysis::MakeStepper("rkf78");
  const std::vector<double> grid = ds::integrators::UniformGrid(0.0, t_end, 0.01);
  const ds::integrators::IntegrationResult run =
      ds::integrators::Integrate(*stepper, settings, body, initial, t_end, grid);
  if (run.termination != ds::integrators::Termination::kReachedEnd) {
    std::fprintf(stderr, "free_body: integration stopped: %s\n", run.message.c_str());
    return 1;
  }

  const ds::analysis::FreeBodySolution exact(ds::math::InertiaTensor::FromMatrix(body.J_B()),
                                             initial.H_B, initial.q_NB, initial.t);
  double momentum_error = 0.0;  // max |H_B - H_B exact| / |H_B|
  double attitude_error = 0.0;  // max rotation angle between q_NB and the exact q_NB [rad]
  for (const ds::integrators::State& s : run.samples) {
    momentum_error = std::max(momentum_error, (s.H_B - exact.H_B(s.t)).norm() / initial.H_B.norm());
    attitude_error = std::max(attitude_error, s.q_NB.angularDistance(exact.q_NB(s.t)));
  }
  const std::vector<double> flips = exact.FlipTimes(0.0, t_end);

  std::printf("wing nut, %zu samples over %g s, %ld rkf78 steps; %zu flips, period %.6f s\n",
              run.samples.size(), t_end, run.stats.steps, flips.size(), exact.period());
  std::printf(
      "max error vs closed form: momentum %.2e of |H_B| (bound %.0e), "
      "attitude %.2e rad (bound %.0e)\n",
      momentum_error, kMomentumBound, attitude_error, kAttitudeBound);
  if (!(momentum_error <= kMomentumBound && attitude_error <= kAttitudeBound)) {
    std::fprintf(stderr, "free_body: error above the bound\n");
    return 1;
  }
  return 0;
}
