#pragma once

/// The initial spin of a profile as analysts state it (a body axis, a spin rate and a
/// nutation angle) turned into the angular momentum H_B(t0) a run starts from; the same
/// rules give the sweeps' spin_rate and nutation parameters (sweep/sweep_spec.h).
///
/// The rules (docs/file_formats.md, "Initial state"):
///  - rate: the component of the angular velocity w_NB_B(t0) along the axis s;
///  - nutation: the angle of H_B(t0) from s, tilted towards the transverse part of the
///    momentum a pure spin about s has (s not principal) or, when there is none, towards
///    the next principal axis of J_B(t0) after the one nearest s (ascending moments,
///    cyclic), then turned about s by the azimuth.

#include <optional>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/math/types.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::schedule {

/// J_B, h_rel_B (and the rest of dynamics::InertiaSample) at the profile's start: stage
/// profiles through DeploymentSchedule, hinge profiles with every hinge at its initial
/// angle and the free hinges at rest until released (FreeHingeSystem). The profile's
/// model and plans must be valid (ValidateProfile).
dynamics::InertiaSample InitialInertia(const Profile& p);

/// H tilted from the unit axis s by `nutation` [rad] (unset: its present tilt), towards
/// its transverse direction (or the next principal axis of J_B) turned about s by
/// `azimuth` [rad] (unset: 0); |H| unchanged.
math::Vec3 TiltMomentum(const math::Vec3& H,
                        const math::Vec3& s,
                        const math::Mat3& J_B,
                        std::optional<double> nutation,
                        std::optional<double> azimuth);

/// H scaled so that the angular velocity it gives (w = J^-1 (H - h_rel)) has the
/// component `rate` [rad/s] along s. Throws std::invalid_argument when w has none.
math::Vec3 ScaleToSpinRate(const math::Vec3& H,
                           const math::Vec3& s,
                           const dynamics::InertiaSample& s0,
                           double rate);

/// H_B(t0) of an InitialSpin: a pure spin `rate` about `axis_B`, tilted to `nutation`
/// about the azimuth, then scaled back to `rate` along the axis.
math::Vec3 SpinMomentum(const dynamics::InertiaSample& s0, const InitialSpin& spin);

}  // namespace deploysim::schedule
