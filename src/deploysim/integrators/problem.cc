#include "deploysim/integrators/problem.h"

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

}  // namespace deploysim::integrators
