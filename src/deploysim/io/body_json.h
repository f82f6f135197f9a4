#pragma once

/// The expanded body of a hinged model as one JSON object (docs/file_formats.md, "The
/// body"): the hub, every panel as the run moves it (the panels the model file's
/// appendages generated included: a beam's stub, links and segments) and the appendages'
/// records. The trajectory file stores it as the root attribute `body`, the Python
/// package as SimulationResult.body, so that a reader draws and describes the body the run
/// simulated without a second implementation of the appendages' expansion.
///
/// Units SI (kg, m, kg m^2, rad/s, N m/rad, N m s/rad); vectors in the parent's axes at
/// hinge angle 0 (model::Panel); NaN and infinities as null.

#include <string>

#include "deploysim/model/model.h"

namespace deploysim::io {

/// [kg/m^3] A point mass (a slosh pendulum's bob: the moving liquid) is drawn as a sphere
/// of this density (water's), so that its size tells its mass.
inline constexpr double kPointMassDrawDensity = 1000.0;

/// How a panel is drawn: `shape` and its dimensions [m], in the panel's axes.
///  - "rod": a generated beam part, a solid cylinder of `length` and `radius` along `axis`
///    (unit), centred on the CoM (a beam part's CoM is its middle, its hinge one end);
///  - "sphere": a point mass (a slosh bob), of `radius` (kPointMassDrawDensity);
///  - "none": a massless link (a two-plane joint's first hinge), nothing to draw;
///  - "box": the uniform box of the element's mass and inertia (the model file's `box:`
///    itself, or the equivalent box of its `inertia:`), found by the reader.
struct DrawnShape {
  std::string shape = "box";
  math::Vec3 axis = math::Vec3::UnitX();
  double length = 0.0;
  double radius = 0.0;
};

/// The drawn shape of panel k of m (a kHinged model).
DrawnShape PanelShape(const model::Model& m, int k);

/// The body of a kHinged model as a JSON object: {"hub": {...}, "panels": [...],
/// "appendages": [...]} (members in docs/file_formats.md, "The body"). Throws
/// std::invalid_argument for a model of another kind.
std::string BodyJson(const model::Model& m);

}  // namespace deploysim::io
