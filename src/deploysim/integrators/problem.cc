#include "deploysim/integrators/problem.h"

#include <cstring>

#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

Problem::Problem(const dynamics::InertiaSource& source, const math::Vec3& h_N)
    : source_(source), h_N_(h_N), momentum_scale_(h_N.norm() > 0.0 ? h_N.norm() : 1.0) {}

void Problem::SetSegment(double begin, double end) {
  segment_begin_ = begin;
  segment_end_ = end;
}

dynamics::InertiaSample Problem::Sample(double t) const {
  ++evaluations_;
  const dynamics::Side side = t >= segment_end_ ? dynamics::Side::kLeft : dynamics::Side::kRight;
  return source_.Evaluate(t, side);
}

bool SameBits(const State& a, const State& b) {
  // Bit equality (not ==, which would equate 0.0 and -0.0 and never NaNs).
  auto same = [](double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; };
  if (!same(a.t, b.t)) return false;
  for (int i = 0; i < 3; ++i) {
    if (!same(a.H_B[i], b.H_B[i])) return false;
  }
  for (int i = 0; i < 4; ++i) {
    if (!same(a.q_NB.coeffs()[i], b.q_NB.coeffs()[i])) return false;
  }
  return true;
}

}  // namespace deploysim::integrators
