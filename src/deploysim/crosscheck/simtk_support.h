#pragma once

/// Private to the crosscheck module (not installed: Simbody stays out of the public
/// headers): conversions between Eigen and SimTK, and the Simbody calls that both
/// Simbody models (simbody_satellite.cc, simbody_free_hinges.cc) make alike.

#include <Simbody.h>

#include <Eigen/Core>
#include <stdexcept>

#include "deploysim/math/number_format.h"
#include "deploysim/math/types.h"

namespace deploysim::crosscheck::simtk {

using Vec6 = Eigen::Matrix<double, 6, 1>;

inline SimTK::Vec3 ToSimTK(const math::Vec3& v) { return SimTK::Vec3(v[0], v[1], v[2]); }
inline math::Vec3 ToEigen(const SimTK::Vec3& v) { return math::Vec3(v[0], v[1], v[2]); }
inline math::Mat3 ToEigen(const SimTK::Mat33& m) {
  math::Mat3 r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = m(i, j);
  }
  return r;
}
inline SimTK::Rotation ToRotation(const math::Mat3& R) {
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m(i, j) = R(i, j);
  }
  return SimTK::Rotation(m);  // re-orthogonalizes an approximate rotation matrix
}
inline SimTK::Inertia ToInertia(const math::Mat3& I) {
  return SimTK::Inertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
}

/// Mass properties of a body whose CoM is at `com` (body frame) with inertia I_cm about
/// the CoM in body axes: Simbody wants the inertia about the body origin.
inline SimTK::MassProperties AboutOrigin(double mass,
                                         const math::Vec3& com,
                                         const math::Mat3& I_cm) {
  const SimTK::Inertia about_origin = ToInertia(I_cm).shiftFromMassCenter(-ToSimTK(com), mass);
  return SimTK::MassProperties(mass, ToSimTK(com), about_origin);
}

/// The system's central momentum (angular, linear) in Ground as a 6-vector.
inline Vec6 CentralMomentum(const SimTK::MultibodySystem& system,
                            const SimTK::SimbodyMatterSubsystem& matter,
                            const SimTK::State& s) {
  system.realize(s, SimTK::Stage::Velocity);
  const SimTK::SpatialVec m = matter.calcSystemCentralMomentum(s);
  Vec6 r;
  r << m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2];
  return r;
}

/// Throws std::runtime_error if Simbody's integrator gave up.
inline void ThrowIfOver(const SimTK::Integrator& integ) {
  if (integ.isSimulationOver()) {
    throw std::runtime_error(
        "Simbody: integration ended at t = " + math::FormatNumber(integ.getTime()) +
        " s: " + SimTK::Integrator::getTerminationReasonString(integ.getTerminationReason()));
  }
}

}  // namespace deploysim::crosscheck::simtk
