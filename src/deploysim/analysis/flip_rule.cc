#include "deploysim/analysis/flip_rule.h"

#include <cmath>
#include <stdexcept>

namespace deploysim::analysis {

namespace {

// Index of the principal axis most nearly parallel to v.
int NearestAxis(const math::PrincipalAxes& p, const math::Vec3& v) {
  int best = 0;
  double best_dot = -1.0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::abs(p.axes.col(i).dot(v));
    if (d > best_dot) {
      best_dot = d;
      best = i;
    }
  }
  return best;
}

}  // namespace

std::string ToString(AxisRole r) {
  switch (r) {
    case AxisRole::kMinor:
      return "minor";
    case AxisRole::kIntermediate:
      return "intermediate";
    case AxisRole::kMajor:
      return "major";
    case AxisRole::kDegenerate:
      return "degenerate";
  }
  return "?";
}

AxisRole RoleOf(const math::Vec3& moments, int index) {
  const double scale = moments[2];
  const bool low_tie = moments[1] - moments[0] <= kDegenerateMoments * scale;
  const bool high_tie = moments[2] - moments[1] <= kDegenerateMoments * scale;
  if (index == 1 && (low_tie || high_tie)) return AxisRole::kDegenerate;
  if (index == 0 && low_tie) return AxisRole::kDegenerate;
  if (index == 2 && high_tie) return AxisRole::kDegenerate;
  return index == 0 ? AxisRole::kMinor : index == 1 ? AxisRole::kIntermediate : AxisRole::kMajor;
}

math::Vec3 InitialSpinAxis(const math::Mat3& J_B0, const math::Vec3& H_B0) {
  const math::PrincipalAxes p = math::PrincipalDecomposition(J_B0);
  math::Vec3 s = p.axes.col(NearestAxis(p, H_B0));
  if (s.dot(H_B0) < 0.0) s = -s;
  return s;
}

SpinAxisRole LocateSpinAxis(const math::PrincipalAxes& p, const math::Vec3& spin_axis_B) {
  const int i = NearestAxis(p, spin_axis_B);
  SpinAxisRole r;
  r.axis_B = p.axes.col(i);
  if (r.axis_B.dot(spin_axis_B) < 0.0) r.axis_B = -r.axis_B;
  r.role = RoleOf(p.moments, i);
  return r;
}

SpinAxisRole LocateSpinAxis(const math::Mat3& J_B, const math::Vec3& spin_axis_B) {
  return LocateSpinAxis(math::PrincipalDecomposition(J_B), spin_axis_B);
}

double FlipFunction(const math::Mat3& J_B, const math::Vec3& spin_axis_B, const math::Vec3& H_B) {
  return H_B.dot(LocateSpinAxis(J_B, spin_axis_B).axis_B);
}

double FlipFunctionRate(const math::Mat3& J_B,
                        const math::Mat3& Jdot_B,
                        const math::Vec3& spin_axis_B,
                        const math::Vec3& H_B,
                        const math::Vec3& Hdot_B) {
  const math::PrincipalAxes p = math::PrincipalDecomposition(J_B);
  const int i = NearestAxis(p, spin_axis_B);
  math::Vec3 a = p.axes.col(i);
  const double sign = a.dot(spin_axis_B) < 0.0 ? -1.0 : 1.0;
  a *= sign;
  math::Vec3 a_dot = math::Vec3::Zero();
  for (int j = 0; j < 3; ++j) {
    const double gap = p.moments[i] - p.moments[j];
    if (j == i || std::abs(gap) <= kDegenerateMoments * p.moments[2]) continue;
    const math::Vec3 e = p.axes.col(j);
    a_dot += (e.dot(Jdot_B * a) / gap) * e;
  }
  return Hdot_B.dot(a) + H_B.dot(a_dot);
}

bool IsFlip(const math::Mat3& J_B, const math::Vec3& spin_axis_B, const math::Vec3& H_B) {
  const SpinAxisRole r = LocateSpinAxis(J_B, spin_axis_B);
  return r.role == AxisRole::kIntermediate &&
         std::abs(H_B.dot(r.axis_B)) <= kFlipResidual * H_B.norm();
}

integrators::EventFunction FlipEvent(const math::InertiaTensor& J_B) {
  const math::PrincipalAxes p = J_B.Principal();
  if (RoleOf(p.moments, 1) != AxisRole::kIntermediate) {
    throw std::invalid_argument(
        "flip event: two principal moments are equal, so there is no intermediate axis "
        "and no Dzhanibekov flip");
  }
  const math::Vec3 e = p.axes.col(1);
  return {"flip", [e](const integrators::State& s) { return s.H_B.dot(e); }};
}

}  // namespace deploysim::analysis
