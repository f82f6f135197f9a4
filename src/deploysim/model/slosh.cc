#include "deploysim/model/slosh.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/point_geometry.h"

namespace deploysim::model {

namespace {

using math::FormatNumber;
using math::Mat3;
using math::Vec3;

/// Two unit vectors closer to perpendicular than this (|cos|) count as perpendicular.
constexpr double kPerpendicularTolerance = 1e-9;

[[noreturn]] void SloshFail(const std::string& where, const std::string& what) {
  throw std::invalid_argument(where + "." + what);
}

bool Finite(const Vec3& v) { return v.allFinite(); }

/// The damping keys: exactly one form, each within its range.
void CheckDamping(const SloshSpec& s, const std::string& where) {
  if (s.damping.has_value() == s.damping_ratio.has_value()) {
    SloshFail(where, std::string(s.damping ? "damping, damping_ratio" : "damping") +
                         ": give exactly one of damping [N m s/rad] or damping_ratio (with "
                         "spin_rate and spin_radius)");
  }
  if (s.damping) {
    if (!(std::isfinite(*s.damping) && *s.damping >= 0.0)) {
      SloshFail(where, "damping = " + FormatNumber(*s.damping) + ": must be >= 0 [N m s/rad]");
    }
    if (s.spin_rate || s.spin_radius) {
      SloshFail(where, std::string(s.spin_rate ? "spin_rate" : "spin_radius") +
                           ": only with damping_ratio (it sets the frequency at which the ratio "
                           "is turned into the damper)");
    }
    return;
  }
  const double zeta = *s.damping_ratio;
  if (!(zeta >= 0.0 && zeta < 1.0)) {
    SloshFail(where, "damping_ratio = " + FormatNumber(zeta) + ": must be in [0, 1)");
  }
  if (!s.spin_rate) SloshFail(where, "spin_rate: required with damping_ratio [rad/s]");
  if (!(std::isfinite(*s.spin_rate) && *s.spin_rate > 0.0)) {
    SloshFail(where, "spin_rate = " + FormatNumber(*s.spin_rate) + ": must be > 0 [rad/s]");
  }
  if (!s.spin_radius) {
    SloshFail(where,
              "spin_radius: required with damping_ratio (the pivot's distance from the spin "
              "axis [m])");
  }
  if (!(std::isfinite(*s.spin_radius) && *s.spin_radius >= 0.0)) {
    SloshFail(where, "spin_radius = " + FormatNumber(*s.spin_radius) + ": must be >= 0 [m]");
  }
}

/// A tank's values within their ranges (SloshTank), with nothing it gives set besides.
void CheckTank(const SloshSpec& s, const std::string& where) {
  const SloshTank& t = *s.tank;
  if (s.mass != 0.0 || s.length != 0.0 || s.fixed_mass != 0.0 || !s.pivot.isZero(0.0) ||
      !s.fixed_point.isZero(0.0)) {
    SloshFail(where,
              "tank: gives mass, length, pivot, fixed_mass and fixed_point (rule: a tank or "
              "those, not both)");
  }
  if (!Finite(t.center)) SloshFail(where, "tank.center: must be finite [m]");
  for (const auto& [key, v] :
       {std::pair<const char*, double>{"diameter", t.diameter}, {"height", t.height}}) {
    if (!(std::isfinite(v) && v > 0.0 && v <= kMaxCoordinate)) {
      SloshFail(where, std::string("tank.") + key + " = " + FormatNumber(v) + ": must be > 0 [m]");
    }
  }
  if (!(t.fill_fraction > 0.0 && t.fill_fraction <= 1.0)) {
    SloshFail(where,
              "tank.fill_fraction = " + FormatNumber(t.fill_fraction) + ": must be in (0, 1]");
  }
  if (t.liquid_mass_full.has_value() == t.density.has_value()) {
    SloshFail(where, "tank: give exactly one of liquid_mass_full [kg] or density [kg/m^3]");
  }
  const double m = t.liquid_mass_full ? *t.liquid_mass_full : *t.density;
  if (!(std::isfinite(m) && m > 0.0 && m <= kMaxPartMass)) {
    SloshFail(where, std::string(t.liquid_mass_full ? "tank.liquid_mass_full" : "tank.density") +
                         " = " + FormatNumber(m) + ": must be > 0");
  }
  const double liquid = CylinderTankPendulum(t).liquid_mass;
  if (!(liquid <= kMaxPartMass)) {
    SloshFail(where, "tank.density = " + FormatNumber(*t.density) +
                         ": the liquid's mass must be at most " + FormatNumber(kMaxPartMass) +
                         " [kg]");
  }
}

/// The pendulum of the spec's tank placed in the parent's axes: the bottom is at
/// center + H/2 direction (unit), a point z above it at bottom - z direction.
void PlaceTank(SloshSpec& s) {
  const SloshTank& t = *s.tank;
  const SloshTankPendulum p = CylinderTankPendulum(t);
  const Vec3 bottom = t.center + 0.5 * t.height * s.direction;
  s.mass = p.mass;
  s.length = p.length;
  s.pivot = bottom - p.pivot_height * s.direction;
  s.fixed_mass = p.fixed_mass;
  s.fixed_point = bottom - p.fixed_height * s.direction;
}

/// The spec with unit direction and unit first axis (chosen if zero), checked; a tank's
/// pendulum placed.
SloshSpec Checked(SloshSpec s, const HingedBody& body, const std::string& where) {
  if (s.tank) {
    CheckTank(s, where);
    const double dn = s.direction.norm();
    if (!(std::isfinite(dn) && dn > 0.0))
      SloshFail(where, "direction: must be finite and non-zero");
    s.direction /= dn;
    PlaceTank(s);
  }
  if (!(std::isfinite(s.mass) && s.mass > 0.0 && s.mass <= kMaxPartMass)) {
    SloshFail(where, "mass = " + FormatNumber(s.mass) + ": must be > 0 [kg] (the pendulum's m1)");
  }
  if (!(std::isfinite(s.length) && s.length > 0.0 && s.length <= kMaxCoordinate)) {
    SloshFail(where,
              "length = " + FormatNumber(s.length) + ": must be > 0 [m] (the pendulum's L1)");
  }
  if (!(std::isfinite(s.fixed_mass) && s.fixed_mass >= 0.0 && s.fixed_mass <= kMaxPartMass)) {
    SloshFail(where, "fixed_mass = " + FormatNumber(s.fixed_mass) + ": must be >= 0 [kg]");
  }
  if (!Finite(s.pivot)) SloshFail(where, "pivot: must be finite [m]");
  if (!Finite(s.fixed_point)) SloshFail(where, "fixed_point: must be finite [m]");
  if (s.parent < -1 || s.parent >= static_cast<int>(body.panels.size())) {
    SloshFail(where, "parent = " + std::to_string(s.parent) +
                         ": no such panel (rule: -1 for the hub or a panel's index)");
  }
  const double dn = s.direction.norm();
  if (!(std::isfinite(dn) && dn > 0.0)) SloshFail(where, "direction: must be finite and non-zero");
  s.direction /= dn;
  if (s.axis.isZero(0.0)) {
    Eigen::Index least = 0;
    s.direction.cwiseAbs().minCoeff(&least);
    const Vec3 e = Vec3::Unit(least);
    s.axis = e - e.dot(s.direction) * s.direction;
  }
  const double an = s.axis.norm();
  if (!(std::isfinite(an) && an > 0.0) ||
      std::abs(s.axis.dot(s.direction)) > kPerpendicularTolerance * an) {
    SloshFail(where, "axis: must be finite, non-zero and perpendicular to direction");
  }
  s.axis /= an;
  CheckDamping(s, where);
  return s;
}

/// Adds a point mass m at x (inertia 0) to the element whose CoM is `at`: the composite's
/// mass, CoM and inertia about the new CoM (parallel-axis theorem).
void AddPointMass(MassElement& into, Vec3& at, double m, const Vec3& x) {
  if (m == 0.0) return;
  const double total = into.mass + m;
  const Vec3 c = (into.mass * at + m * x) / total;
  into.inertia_cm = into.inertia_cm + into.mass * geometry::PointInertia(at - c) +
                    m * geometry::PointInertia(x - c);
  into.mass = total;
  at = c;
}

}  // namespace

SloshTankPendulum CylinderTankPendulum(const SloshTank& t) {
  constexpr double kTwoXi1 = 3.68;  // 2 xi_1, xi_1 = 1.841 the first root of J1'
  constexpr double kMassDivisor = 4.4;
  constexpr double pi = 3.14159265358979323846;
  const double d = t.diameter;
  const double h = t.fill_fraction * t.height;
  SloshTankPendulum p;
  p.liquid_height = h;
  p.liquid_mass = t.liquid_mass_full ? t.fill_fraction * *t.liquid_mass_full
                                     : t.density.value() * pi * d * d / 4.0 * h;
  const double x = kTwoXi1 * h / d;
  p.mass = p.liquid_mass * d / (kMassDivisor * h) * std::tanh(x);
  p.length = d / kTwoXi1 / std::tanh(x);
  p.fixed_mass = p.liquid_mass - p.mass;
  p.liquid_com_height = 0.5 * h;
  const double h1 = 0.5 * h - d / kTwoXi1 * std::tanh(0.5 * x);  // above the liquid's CoM
  p.bob_height = p.liquid_com_height + h1;
  p.pivot_height = p.bob_height + p.length;
  p.fixed_height = p.liquid_com_height - p.mass * h1 / p.fixed_mass;
  return p;
}

double SloshInPlaneFrequency(double spin_rate, double spin_radius, double length) {
  return std::abs(spin_rate) * std::sqrt(spin_radius / length);
}

double SloshOutOfPlaneFrequency(double spin_rate, double spin_radius, double length) {
  return std::abs(spin_rate) * std::sqrt((spin_radius + length) / length);
}

double SloshDamping(const SloshSpec& spec) {
  if (spec.damping) return *spec.damping;
  const double w =
      SloshOutOfPlaneFrequency(spec.spin_rate.value(), spec.spin_radius.value(), spec.length);
  return 2.0 * spec.damping_ratio.value() * w * spec.mass * spec.length * spec.length;
}

Appendage AddSlosh(HingedBody& body, const SloshSpec& raw, const std::string& where) {
  const SloshSpec spec = Checked(raw, body, where);
  const double c = SloshDamping(spec);
  if (spec.parent < 0) {
    AddPointMass(body.hub.body, body.hub.com_B, spec.fixed_mass, spec.fixed_point);
  } else {
    Panel& p = body.panels[static_cast<std::size_t>(spec.parent)];
    AddPointMass(p.body, p.com_offset_B, spec.fixed_mass, spec.fixed_point);  // from its origin
  }
  Panel link;  // massless, on its hinge: the bob's second hinge rides on it
  link.name = spec.name + "_a";
  link.parent = spec.parent;
  link.hinge_point_B = spec.pivot;
  link.hinge_axis_B = spec.axis;
  link.body.mass = 0.0;
  link.body.inertia_cm.setZero();
  body.panels.push_back(link);
  const int link_index = static_cast<int>(body.panels.size()) - 1;
  Panel bob;
  bob.name = spec.name + "_b";
  bob.parent = link_index;
  bob.hinge_point_B.setZero();
  bob.hinge_axis_B = spec.direction.cross(spec.axis);
  bob.com_offset_B = spec.length * spec.direction;
  bob.body.mass = spec.mass;
  bob.body.inertia_cm.setZero();
  body.panels.push_back(bob);
  Appendage app;
  app.name = spec.name;
  app.kind = Appendage::Kind::kSlosh;
  app.root = -1;
  app.hinges = {link_index, link_index + 1};
  app.stiffness = {0.0, 0.0};
  app.damping = {c, c};
  return app;
}

}  // namespace deploysim::model
