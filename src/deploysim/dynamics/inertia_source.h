#pragma once

/// Sources of the time-varying mass distribution seen by the reduced model
/// (docs/design.md section 2.1): J_B(t) [kg m^2] about the system centre of mass in B,
/// dJ_B/dt [kg m^2/s] and h_rel_B(t) [kg m^2/s], the angular momentum of the parts'
/// motion relative to B. Integrators query a source at every Runge-Kutta stage.

#include <functional>
#include <vector>

#include "deploysim/math/inertia.h"
#include "deploysim/math/types.h"

namespace deploysim::dynamics {

/// Everything the equations of motion need at one instant.
struct InertiaSample {
  math::Mat3 J_B;      ///< [kg m^2] inertia about the system CoM, B components.
  math::Mat3 Jdot_B;   ///< [kg m^2/s] rate of J_B seen in B.
  math::Vec3 h_rel_B;  ///< [kg m^2/s] momentum of motion relative to B.
  math::Mat3 J_inv_B;  ///< [1/(kg m^2)] inverse of J_B.
  /// [J] T_rel, the kinetic energy of the parts' motion relative to B, about the system
  /// CoM (docs/design.md 2.5; model::MassProperties). It enters the energy only, not the
  /// equations of motion. Zero wherever the source models no relative motion, in the same
  /// places as h_rel_B: constant and tensor-interpolated inertia, and quasi-rigid coupling
  /// (h_rel = 0 and T_rel = 0 by the model's assumption of an instantaneously rigid body,
  /// although the panels do move); FunctionInertia does not model it either (0).
  double relative_kinetic_energy = 0.0;
};

/// Total kinetic energy of the system about its CoM [J] (docs/design.md 2.7, T = 1/2 v^T M v):
///   T = 1/2 w.J_B w + w.h_rel_B + T_rel = 1/2 w.(H_B + h_rel_B) + T_rel,
/// with w = J_B^-1 (H_B - h_rel_B). Under quasi-rigid coupling, and for rigid or
/// tensor-interpolated sources, h_rel_B = 0 and T_rel = 0, so T = 1/2 w.J_B w. Its
/// rigid-body part 1/2 w.J_B w (the energy of the system turning rigidly at the hub's w)
/// is dynamics::KineticEnergy (rigid_body.h).
double TotalKineticEnergy(const InertiaSample& s, const math::Vec3& H_B);

/// Which one-sided limit to take at a breakpoint, where J's rate or h_rel may jump.
/// A step that ends at a breakpoint evaluates its last stages from the left.
enum class Side { kRight, kLeft };

/// Interface for J_B(t), dJ_B/dt and h_rel_B(t). Implementations must be consistent
/// (Jdot is the derivative of J) and smooth between breakpoints.
class InertiaSource {
 public:
  virtual ~InertiaSource() = default;

  /// The mass distribution at time t [s] (one-sided at breakpoints).
  virtual InertiaSample Evaluate(double t, Side side = Side::kRight) const = 0;

  /// Times in (t0, t1) where the source is not smooth; integrators step to them
  /// exactly and restart. Ascending. Default: none.
  virtual std::vector<double> Breakpoints(double t0, double t1) const;

  /// True when J_B is constant and h_rel_B is zero on [t0, t1], so the exact
  /// constant-inertia flow applies there. Default: false.
  virtual bool IsRigidOn(double t0, double t1) const;
};

/// Constant inertia, no relative motion: the classic free rigid body.
class ConstantInertia final : public InertiaSource {
 public:
  explicit ConstantInertia(const math::InertiaTensor& J_B);
  InertiaSample Evaluate(double t, Side side = Side::kRight) const override;
  bool IsRigidOn(double t0, double t1) const override;
  const math::InertiaTensor& inertia() const { return J_B_; }

 private:
  math::InertiaTensor J_B_;
  InertiaSample sample_;
};

/// A source defined by callables, for tests and synthetic studies: J(t) and its
/// derivative, h_rel(t), and optional breakpoints. J(t) is validated at every call
/// in debug builds only (it is on the hot path).
class FunctionInertia final : public InertiaSource {
 public:
  using MatFn = std::function<math::Mat3(double)>;
  using VecFn = std::function<math::Vec3(double)>;
  FunctionInertia(MatFn J_B, MatFn Jdot_B, VecFn h_rel_B, std::vector<double> breakpoints = {});
  InertiaSample Evaluate(double t, Side side = Side::kRight) const override;
  std::vector<double> Breakpoints(double t0, double t1) const override;

 private:
  MatFn J_B_;
  MatFn Jdot_B_;
  VecFn h_rel_B_;
  std::vector<double> breakpoints_;
};

/// A smooth, non-trivial J(t) for tests: J(t) = R(t) diag(m(t)) R(t)^T with principal
/// moments m(t) = m0 + dm sin(omega t) and axes rotating about a fixed body axis at
/// rate `axis_rate`, plus h_rel(t) = h0 cos(omega t). Valid (positive definite,
/// triangle inequalities) when m0 +- dm is.
FunctionInertia MakeSyntheticInertia(const math::Vec3& m0,
                                     const math::Vec3& dm,
                                     double omega,
                                     double axis_rate,
                                     const math::Vec3& h0);

}  // namespace deploysim::dynamics
