#include "deploysim/io/body_json.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"

namespace deploysim::io {

namespace {

using math::JsonNumber;
using math::JsonString;

using math::kPi;

std::string Vec(const math::Vec3& v) {
  return "[" + JsonNumber(v[0]) + ", " + JsonNumber(v[1]) + ", " + JsonNumber(v[2]) + "]";
}

/// Rows of M: [[M00, M01, M02], ...].
std::string Mat(const math::Mat3& M) {
  return "[" + Vec(M.row(0).transpose()) + ", " + Vec(M.row(1).transpose()) + ", " +
         Vec(M.row(2).transpose()) + "]";
}

std::string Numbers(const std::vector<double>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + JsonNumber(v[i]);
  return o + "]";
}

std::string Integers(const std::vector<int>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + std::to_string(v[i]);
  return o + "]";
}

std::string NumberLists(const std::vector<std::vector<double>>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + Numbers(v[i]);
  return o + "]";
}

/// The appendage panel k belongs to (its root stub or a generated hinge), or null.
const model::Appendage* AppendageOf(const model::Model& m, int k) {
  for (const model::Appendage& a : m.appendages) {
    if (a.root == k) return &a;
    for (int h : a.hinges) {
      if (h == k) return &a;
    }
  }
  return nullptr;
}

std::string ShapeJson(const DrawnShape& s) {
  std::string o = "{\"shape\": " + JsonString(s.shape);
  if (s.shape == "rod") {
    o += ", \"axis\": " + Vec(s.axis) + ", \"length\": " + JsonNumber(s.length);
  }
  if (s.shape == "rod" || s.shape == "sphere") o += ", \"radius\": " + JsonNumber(s.radius);
  return o + "}";
}

/// Per bending plane, the first mode's damping ratio of a beam's stiffness-proportional
/// damping (model/flexible_beam.h: c = 2 zeta k / omega_1 on every hinge of the plane,
/// hence zeta = omega_1 c / (2 k)); the hinges interleave the planes root to tip.
std::vector<double> DampingRatios(const model::Appendage& a) {
  std::vector<double> zeta;
  for (std::size_t p = 0; p < a.chain_frequencies.size(); ++p) {
    if (p >= a.hinges.size() || a.chain_frequencies[p].empty() || !(a.stiffness[p] > 0.0)) {
      zeta.push_back(std::nan(""));
      continue;
    }
    zeta.push_back(a.chain_frequencies[p].front() * a.damping[p] / (2.0 * a.stiffness[p]));
  }
  return zeta;
}

std::string AppendageJson(const model::Appendage& a) {
  return "{\"name\": " + JsonString(a.name) +
         ", \"kind\": " + JsonString(a.kind == model::Appendage::Kind::kBeam ? "beam" : "slosh") +
         ", \"root\": " + std::to_string(a.root) + ", \"hinges\": " + Integers(a.hinges) +
         ", \"stiffness\": " + Numbers(a.stiffness) + ", \"damping\": " + Numbers(a.damping) +
         ", \"segments\": " + std::to_string(a.segments) +
         ", \"planes\": " + std::to_string(a.chain_frequencies.size()) +
         ", \"modes\": " + std::to_string(a.modes.cols()) +
         ", \"damping_ratio\": " + Numbers(DampingRatios(a)) +
         ", \"chain_frequencies\": " + NumberLists(a.chain_frequencies) +
         ", \"beam_frequencies\": " + NumberLists(a.beam_frequencies) + "}";
}

std::string PanelJson(const model::Model& m, int k) {
  const model::Panel& p = m.hinged.panels[static_cast<std::size_t>(k)];
  const model::Appendage* a = AppendageOf(m, k);
  return "{\"name\": " + JsonString(p.name) + ", \"parent\": " + std::to_string(p.parent) +
         ", \"mass\": " + JsonNumber(p.body.mass) + ", \"inertia\": " + Mat(p.body.inertia_cm) +
         ", \"hinge_point\": " + Vec(p.hinge_point_B) + ", \"hinge_axis\": " + Vec(p.hinge_axis_B) +
         ", \"com_offset\": " + Vec(p.com_offset_B) +
         ", \"appendage\": " + (a != nullptr ? JsonString(a->name) : std::string("null")) +
         ", \"drawn\": " + ShapeJson(PanelShape(m, k)) + "}";
}

}  // namespace

DrawnShape PanelShape(const model::Model& m, int k) {
  const model::Panel& p = m.hinged.panels.at(static_cast<std::size_t>(k));
  const model::Appendage* a = AppendageOf(m, k);
  DrawnShape s;
  if (a == nullptr) return s;  // the model file's own panel: its box
  if (p.body.mass == 0.0) {
    s.shape = "none";
  } else if (p.body.inertia_cm.isZero(0.0)) {
    s.shape = "sphere";
    s.radius = std::cbrt(3.0 * p.body.mass / (4.0 * kPi * kPointMassDrawDensity));
  } else if (a->kind == model::Appendage::Kind::kBeam && p.com_offset_B.norm() > 0.0) {
    // A uniform rod from its hinge to 2 r: axial moment m radius^2 / 2.
    s.shape = "rod";
    s.axis = p.com_offset_B.normalized();
    s.length = 2.0 * p.com_offset_B.norm();
    s.radius = std::sqrt(2.0 * s.axis.dot(p.body.inertia_cm * s.axis) / p.body.mass);
  }
  return s;
}

std::string BodyJson(const model::Model& m) {
  if (m.kind != model::ModelKind::kHinged) {
    throw std::invalid_argument("BodyJson: model '" + m.name + "' is not a hinged model");
  }
  const model::Hub& hub = m.hinged.hub;
  std::string o = "{\"hub\": {\"mass\": " + JsonNumber(hub.body.mass) +
                  ", \"com\": " + Vec(hub.com_B) + ", \"inertia\": " + Mat(hub.body.inertia_cm) +
                  ", \"drawn\": {\"shape\": \"box\"}}, \"panels\": [";
  for (std::size_t k = 0; k < m.hinged.panels.size(); ++k) {
    o += (k ? ", " : "") + PanelJson(m, static_cast<int>(k));
  }
  o += "], \"appendages\": [";
  for (std::size_t i = 0; i < m.appendages.size(); ++i) {
    o += (i ? ", " : "") + AppendageJson(m.appendages[i]);
  }
  return o + "]}";
}

}  // namespace deploysim::io
