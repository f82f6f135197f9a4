#pragma once

/// The unit conversions of the project, stated once: files and messages use degrees and
/// rpm, the equations radians and rad/s.

namespace deploysim::math {

inline constexpr double kPi = 3.14159265358979323846;
/// [rad] one turn
inline constexpr double kTwoPi = 2.0 * kPi;
/// [rad/deg]
inline constexpr double kRadiansPerDegree = kPi / 180.0;
/// [deg/rad]
inline constexpr double kDegreesPerRadian = 180.0 / kPi;
/// [rad/s per rpm]
inline constexpr double kRadPerSecondPerRpm = 2.0 * kPi / 60.0;

}  // namespace deploysim::math
