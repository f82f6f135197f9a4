#include "deploysim/integrators/butcher_tableau.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kCoefficientTolerance = 1e-15;

double Dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// Checks the order conditions up to order min(p, 4) for weights w (Butcher trees).
void ExpectOrderConditions(const ButcherTableau& t, const std::vector<double>& w, int p) {
  const int s = t.stages();
  std::vector<double> c2(s), c3(s), ac(s), ac2(s), cac(s), aac(s);
  for (int i = 0; i < s; ++i) {
    c2[i] = t.c[i] * t.c[i];
    c3[i] = c2[i] * t.c[i];
    for (int j = 0; j < i; ++j) {
      ac[i] += t.a[i][j] * t.c[j];
      ac2[i] += t.a[i][j] * t.c[j] * t.c[j];
    }
  }
  for (int i = 0; i < s; ++i) {
    cac[i] = t.c[i] * ac[i];
    for (int j = 0; j < i; ++j) aac[i] += t.a[i][j] * ac[j];
  }
  EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, kCoefficientTolerance) << t.name;
  if (p >= 2) {
    EXPECT_NEAR(Dot(w, t.c), 1.0 / 2, kCoefficientTolerance) << t.name;
  }
  if (p >= 3) {
    EXPECT_NEAR(Dot(w, c2), 1.0 / 3, kCoefficientTolerance) << t.name;
    EXPECT_NEAR(Dot(w, ac), 1.0 / 6, kCoefficientTolerance) << t.name;
  }
  if (p >= 4) {
    EXPECT_NEAR(Dot(w, c3), 1.0 / 4, kCoefficientTolerance) << t.name;
    EXPECT_NEAR(Dot(w, cac), 1.0 / 8, kCoefficientTolerance) << t.name;
    EXPECT_NEAR(Dot(w, ac2), 1.0 / 12, kCoefficientTolerance) << t.name;
    EXPECT_NEAR(Dot(w, aac), 1.0 / 24, kCoefficientTolerance) << t.name;
  }
  // Quadrature conditions up to the full order: sum b c^(k-1) = 1/k.
  for (int k = 1; k <= p; ++k) {
    double sum = 0.0;
    for (int i = 0; i < s; ++i) sum += w[i] * std::pow(t.c[i], k - 1);
    EXPECT_NEAR(sum, 1.0 / k, 1e-14) << t.name << " k=" << k;
  }
}

TEST(ButcherTableauTest, RowSumsEqualNodes) {
  for (const ButcherTableau* t :
       {&ExplicitEuler(), &ClassicRk4(), &DormandPrince54(), &Fehlberg78()}) {
    ASSERT_EQ(static_cast<int>(t->a.size()), t->stages()) << t->name;
    for (int i = 0; i < t->stages(); ++i) {
      ASSERT_EQ(static_cast<int>(t->a[i].size()), i) << t->name;
      // Rounding of the large Fehlberg coefficients: a few ulp.
      EXPECT_NEAR(std::accumulate(t->a[i].begin(), t->a[i].end(), 0.0), t->c[i], 1e-14)
          << t->name << " row " << i;
    }
  }
}

TEST(ButcherTableauTest, OrderConditions) {
  ExpectOrderConditions(ExplicitEuler(), ExplicitEuler().b, 1);
  ExpectOrderConditions(ClassicRk4(), ClassicRk4().b, 4);
  ExpectOrderConditions(DormandPrince54(), DormandPrince54().b, 5);
  ExpectOrderConditions(DormandPrince54(), DormandPrince54().b_hat, 4);
  ExpectOrderConditions(Fehlberg78(), Fehlberg78().b, 8);
  ExpectOrderConditions(Fehlberg78(), Fehlberg78().b_hat, 7);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
