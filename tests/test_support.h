#pragma once

/// Shared fixtures for the tests: the reference problems of docs/design.md section 6.

#include <array>
#include <vector>

#include "deploysim/math/inertia.h"
#include "deploysim/math/types.h"

namespace deploysim::testing {

/// Wing nut (thesis 3.2): principal moments [kg m^2] along body x, y, z.
inline math::Vec3 WingNutMoments() { return math::Vec3(3.036e-6, 2.741e-6, 0.699e-6); }
inline math::Vec3 WingNutH0() { return math::Vec3(1e-8, 2.1252e-5, 1e-8); }

/// Flip times of the wing nut from 40-digit arithmetic (docs/design.md section 6) [s].
constexpr double kWingNutFirstFlip = 1.7338627960581041;
constexpr double kWingNutHalfPeriod = 3.5570245874804300;
constexpr double kWingNutPeriod = 7.1140491749608600;
constexpr double kWingNutLambda = 4.1308713587499453;
constexpr double kWingNutOneMinusK2 = 6.6492854004460934e-6;
inline std::vector<double> WingNutFlipTimes(double t_end) {
  std::vector<double> t;
  for (int i = 0;; ++i) {
    const double ti = kWingNutFirstFlip + i * kWingNutHalfPeriod;
    if (ti > t_end) break;
    t.push_back(ti);
  }
  return t;
}

}  // namespace deploysim::testing
