#pragma once

/// The Dzhanibekov flip, defined once for the whole project (the mission runner, the
/// sweep outcome, the spring-deployment replay and the Simbody satellite all use it).
///
/// The rule (docs/file_formats.md, "Flips"):
///  - The run's spin axis s is the principal axis of J_B(t0) nearest H_B(t0), signed
///    along H_B(t0) (InitialSpinAxis).
///  - At time t the flip function is g(t) = H_B(t) . a(t), where a(t) is the principal
///    axis of J_B(t) nearest s, signed along s (LocateSpinAxis).
///  - A located sign change of g is a flip when, at that time, a(t) is the intermediate
///    principal axis of J_B(t) (a body spinning about its minor or major axis only
///    wobbles; with two equal moments there is no intermediate axis) and |g| <=
///    kFlipResidual |H_B| there (a jump of g where two moments cross and the nearest axis
///    changes is not a flip).

#include <string>

#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/types.h"

namespace deploysim::analysis {

/// Two principal moments closer than this, relative to the largest, are equal: the axes
/// between them are not distinguished (the seed's half-open configuration).
inline constexpr double kDegenerateMoments = 1e-9;
/// A located sign change of the flip function counts only if |g| is at most this
/// fraction of |H_B| at the located time.
inline constexpr double kFlipResidual = 1e-6;

/// The role of a principal axis in J.
enum class AxisRole { kMinor, kIntermediate, kMajor, kDegenerate };
std::string ToString(AxisRole r);

/// The role of principal axis `index` (0 smallest moment) for ascending `moments`.
AxisRole RoleOf(const math::Vec3& moments, int index);

/// The body spin axis of a run: the principal axis of J_B(t0) nearest the initial
/// momentum H_B(t0), signed along it (unit, B components).
math::Vec3 InitialSpinAxis(const math::Mat3& J_B0, const math::Vec3& H_B0);

/// Where the spin axis is in J_B: the principal axis of J_B nearest `spin_axis_B`
/// (signed along it) and its role.
struct SpinAxisRole {
  math::Vec3 axis_B = math::Vec3::Zero();
  AxisRole role = AxisRole::kDegenerate;
};
SpinAxisRole LocateSpinAxis(const math::Mat3& J_B, const math::Vec3& spin_axis_B);
/// The same from an already computed principal decomposition of J_B.
SpinAxisRole LocateSpinAxis(const math::PrincipalAxes& principal_J_B,
                            const math::Vec3& spin_axis_B);

/// The flip function g = H_B . a (see the rule above) [kg m^2/s].
double FlipFunction(const math::Mat3& J_B, const math::Vec3& spin_axis_B, const math::Vec3& H_B);

/// The rate of the flip function, dg/dt = H_B' . a + H_B . a' [kg m^2/s^2], from the
/// rates of J_B and H_B seen in B. a' is the first-order change of the principal axis,
/// sum over the other axes e_j of (e_j . J_B' a) / (J_a - J_j) e_j; a term whose two
/// moments are equal (kDegenerateMoments) is left out (the axis is not defined there).
/// For the search of a crossing and return inside one step (integrators::EventFunction).
double FlipFunctionRate(const math::Mat3& J_B,
                        const math::Mat3& Jdot_B,
                        const math::Vec3& spin_axis_B,
                        const math::Vec3& H_B,
                        const math::Vec3& Hdot_B);

/// Whether a located sign change of FlipFunction at a time where the inertia is J_B and
/// the momentum H_B counts as a flip (the rule above).
bool IsFlip(const math::Mat3& J_B, const math::Vec3& spin_axis_B, const math::Vec3& H_B);

/// The flip function of a body of constant inertia whose spin axis is its intermediate
/// axis: the momentum component along the intermediate principal axis (the rule above
/// with J_B constant). Throws std::invalid_argument when two principal moments are equal
/// (kDegenerateMoments: no intermediate axis, no flip).
integrators::EventFunction FlipEvent(const math::InertiaTensor& J_B);

}  // namespace deploysim::analysis
