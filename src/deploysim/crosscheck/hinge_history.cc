#include "deploysim/crosscheck/hinge_history.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/model/mass_properties.h"

namespace deploysim::crosscheck {

HingeHistorySource::HingeHistorySource(model::HingedBody body, HingeHistory history)
    : body_(std::move(body)), history_(std::move(history)) {
  const HingeHistory& h = history_;
  const auto n = static_cast<Eigen::Index>(body_.panels.size());
  if (h.size() < 2) throw std::invalid_argument("hinge history: needs at least 2 knots");
  if (h.angle.size() != h.size() || h.rate.size() != h.size() ||
      h.acceleration.size() != h.size()) {
    throw std::invalid_argument(
        "hinge history: angle, rate and acceleration need one entry per knot");
  }
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (h.angle[i].size() != n || h.rate[i].size() != n || h.acceleration[i].size() != n) {
      throw std::invalid_argument("hinge history: knot " + std::to_string(i) + " does not have " +
                                  std::to_string(n) + " panels");
    }
    if (i > 0 && !(h.time[i] > h.time[i - 1])) {
      throw std::invalid_argument("hinge history: knot times must increase strictly (knot " +
                                  std::to_string(i) + ")");
    }
  }
}

HingeState HingeHistorySource::Interpolate(double t, dynamics::Side side) const {
  const HingeHistory& h = history_;
  if (t < h.time.front()) return {h.angle.front(), Eigen::VectorXd::Zero(h.angle.front().size())};
  if (t > h.time.back()) return {h.angle.back(), Eigen::VectorXd::Zero(h.angle.back().size())};
  // Interval i with t_i <= t < t_{i+1} (from the left at a knot: t_i < t <= t_{i+1}),
  // clamped to the first and last intervals at the ends.
  const auto it = side == dynamics::Side::kRight
                      ? std::upper_bound(h.time.begin(), h.time.end(), t)
                      : std::lower_bound(h.time.begin(), h.time.end(), t);
  const auto last = static_cast<std::ptrdiff_t>(h.size()) - 2;
  const std::size_t i =
      static_cast<std::size_t>(std::clamp<std::ptrdiff_t>((it - h.time.begin()) - 1, 0, last));
  const double dt = h.time[i + 1] - h.time[i];
  const double s = (t - h.time[i]) / dt;
  const double s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
  const double A0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
  const double A1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
  const double A2 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5);
  const double A3 = 0.5 * (s3 - 2.0 * s4 + s5);
  const double A4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
  const double A5 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
  // d/ds of the basis.
  const double D0 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4;
  const double D1 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4;
  const double D2 = s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4;
  const double D3 = 1.5 * s2 - 4.0 * s3 + 2.5 * s4;
  const double D4 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4;
  const double D5 = 30.0 * s2 - 60.0 * s3 + 30.0 * s4;
  const Eigen::VectorXd& p0 = h.angle[i];
  const Eigen::VectorXd& p1 = h.angle[i + 1];
  const Eigen::VectorXd& v0 = h.rate[i];
  const Eigen::VectorXd& v1 = h.rate[i + 1];
  const Eigen::VectorXd& a0 = h.acceleration[i];
  const Eigen::VectorXd& a1 = h.acceleration[i + 1];
  HingeState r;
  r.angle = A0 * p0 + (dt * A1) * v0 + (dt * dt * A2) * a0 + (dt * dt * A3) * a1 + (dt * A4) * v1 +
            A5 * p1;
  r.rate = (D0 / dt) * p0 + D1 * v0 + (dt * D2) * a0 + (dt * D3) * a1 + D4 * v1 + (D5 / dt) * p1;
  return r;
}

dynamics::InertiaSample HingeHistorySource::Evaluate(double t, dynamics::Side side) const {
  const HingeState hs = Interpolate(t, side);
  const model::MassProperties mp = model::ComputeMassProperties(body_, hs.angle, hs.rate);
  dynamics::InertiaSample s;
  s.J_B = mp.J_B;
  s.Jdot_B = mp.Jdot_B;
  s.h_rel_B = mp.h_rel_B;
  s.relative_kinetic_energy = mp.relative_kinetic_energy;
  s.J_inv_B = mp.J_B.inverse();
  return s;
}

std::vector<double> HingeHistorySource::Breakpoints(double t0, double t1) const {
  const std::vector<double>& k = history_.time;
  std::vector<double> r;
  auto it = std::upper_bound(k.begin(), k.end(), t0);
  for (; it != k.end() && *it < t1; ++it) r.push_back(*it);
  return r;
}

}  // namespace deploysim::crosscheck
