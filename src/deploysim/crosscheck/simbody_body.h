#pragma once

/// Private to the crosscheck module (not installed): the hub with hinged panels in
/// Simbody, as both Simbody models build it (simbody_satellite.cc: prescribed and spring
/// hinges; simbody_free_hinges.cc: free hinges with latches), and what both read from it.
/// A Free mobilizer for the hub on Ground, one Pin per panel on its parent body (the hub
/// or another panel) at the hinge point, its Z axis along the hinge axis.

#include <Simbody.h>

#include <string>
#include <vector>

#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/math/types.h"
#include "deploysim/model/model.h"

namespace deploysim::crosscheck::simtk {

/// The multibody system. Non-copyable: Simbody handles refer into `system`.
struct HingedSystem {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::MobilizedBody::Free hub;
  std::vector<SimTK::MobilizedBody::Pin> pins;  ///< panel order

  HingedSystem() = default;
  HingedSystem(const HingedSystem&) = delete;
  HingedSystem& operator=(const HingedSystem&) = delete;
};

/// Checks that the panels' parents form a tree and returns an order in which every
/// parent comes before its children. Throws std::invalid_argument naming `where`.
std::vector<std::size_t> TreeOrder(const model::HingedBody& body, const std::string& where);

/// Builds the hub and the panels of `body` into `sys` (pins in panel order).
void AddHingedBodies(HingedSystem& sys, const model::HingedBody& body, const std::string& where);

/// Kinetic energy about the system's centre of mass [J]: Simbody's less that of the
/// centre of mass's translation.
double KineticEnergyAboutCom(const HingedSystem& sys, const SimTK::State& s);
/// R_NB of the hub.
math::Mat3 HubRotation(const HingedSystem& sys, const SimTK::State& s);
/// The hub's angular velocity, B components [rad/s].
math::Vec3 HubAngularVelocity_B(const HingedSystem& sys, const SimTK::State& s);
/// The system's inertia about its centre of mass, B axes (symmetrized) [kg m^2].
math::Mat3 SystemInertia_B(const HingedSystem& sys, const SimTK::State& s);
/// The system's central angular momentum, N (Ground) components [kg m^2/s].
math::Vec3 Momentum_N(const HingedSystem& sys, const SimTK::State& s);

/// Sets the hub's six generalized speeds so that the system's central angular momentum
/// in Ground is h_N and its linear momentum p_N; with w_N given, the hub's angular
/// velocity is w_N instead and only the linear momentum is fitted. The momentum is
/// affine in the hub speeds (the hinge speeds are fixed): a linear solve by unit-speed
/// columns, then one refinement pass.
void FitHubVelocity(const HingedSystem& sys,
                    SimTK::State& s,
                    const math::Vec3* w_N,
                    const math::Vec3& h_N,
                    const math::Vec3& p_N);

/// Appends the sample of s at time label t_label to `tr`: H_B, h_N, w_NB_B, q_NB, the
/// kinetic energy about the centre of mass, hinge angles and rates.
void AppendSample(const HingedSystem& sys,
                  const SimTK::State& s,
                  double t_label,
                  SimbodyTrajectory& tr);

}  // namespace deploysim::crosscheck::simtk
