// A nutation that peaks a hair beyond 45 degrees: a torque-free body with moments
// (1, 2, 3) whose momentum starts in the x-z plane at beta from z, so that the angle between
// z (the spin axis) and h_N peaks at alpha = 45 deg + 1e-4 rad (sin^2 beta = sin^2 alpha
// (1/2 - 1/3) / (1 - 1/3), from the energy and momentum). Each peak crosses 45 degrees and
// back within ~0.14 s, often inside one step: every crossing must be found, by every
// method, at every tolerance, at the same time to the tolerance.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "deploysim/run/mission.h"
#include "deploysim/io/yaml_loader.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

class Grazing45Test : public testing::TempDirTest {
 public:
  std::vector<double> Crossings(const std::string& method, double rtol) {
    const double alpha = M_PI / 4 + kExcess;
    const double beta = std::asin(std::sin(alpha) / 2.0);
    Write("m.yaml",
          "name: box123\nkind: tensors\nconfigurations:\n  default:\n"
          "    principal_moments: [1.0, 2.0, 3.0]\n");
    char text[1024];
    std::snprintf(text, sizeof text,
                  "name: g45\nmodel: m.yaml\nmode: tensor\ncoupling: quasi-rigid\n"
                  "initial:\n  attitude_wxyz: [1, 0, 0, 0]\n"
                  "  angular_momentum: [%.17g, 0, %.17g]\n"
                  "stages:\n  - {name: spin, hold: default, until: 30}\n"
                  "integrator: {method: %s, rtol: %.17g, atol: %.17g}\noutput: {dt: 1.0}\n",
                  std::sin(beta), std::cos(beta), method.c_str(), rtol, rtol / 100);
    const schedule::Profile p = LoadProfile(Write("p.yaml", text));
    return run::RunMission(p).spin_axis_45_crossings;
  }
  static constexpr double kExcess = 1e-4;  // [rad] beyond 45 deg at the peaks
};

TEST_F(Grazing45Test, EveryCrossingOfAPeakJustBeyond45DegreesIsFound) {
  const std::vector<double> ref = Crossings("exact", 1e-12);
  ASSERT_EQ(ref.size(), 6u);  // three peaks in 30 s, each crossed out and back
  double worst = 0.0;
  for (const char* method : {"rkmk-rkf78", "rkmk-dopri5", "dopri5", "rkf78", "exact"}) {
    for (double rtol : {1e-6, 1e-8, 1e-10, 1e-12}) {
      const std::vector<double> t = Crossings(method, rtol);
      ASSERT_EQ(t.size(), ref.size()) << method << " rtol " << rtol;
      // The crossing time's error: the angle's (about rtol) over its rate there, which
      // goes as sqrt(excess). Measured up to 8.7 rtol / sqrt(excess).
      for (std::size_t i = 0; i < t.size(); ++i) {
        const double ratio = std::abs(t[i] - ref[i]) * std::sqrt(kExcess) / rtol;
        worst = std::max(worst, ratio);
        EXPECT_LT(ratio, 25.0) << method << " rtol " << rtol << " crossing " << i;
      }
    }
  }
  std::printf("largest crossing-time error: %.3g rtol / sqrt(excess)\n", worst);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
