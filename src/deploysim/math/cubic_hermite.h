#pragma once

/// The smallest value of the cubic Hermite interpolant of a scalar function over one
/// step, from its values and derivatives at the step's ends: for tracking the extremum of
/// a smooth quantity along accepted integrator steps without extra right-hand sides.

namespace deploysim::math {

/// min over t in [t0, t1] of the cubic p with p(t0) = f0, p'(t0) = d0, p(t1) = f1,
/// p'(t1) = d1 (the ends included). Error O(h^4) of the step h = t1 - t0 (local).
double CubicHermiteMinimum(double t0, double f0, double d0, double t1, double f1, double d1);

/// The same minimum with where it is.
struct HermitePoint {
  double t = 0.0;
  double value = 0.0;
};
HermitePoint CubicHermiteMinimumAt(
    double t0, double f0, double d0, double t1, double f1, double d1);

}  // namespace deploysim::math
