#pragma once

/// Body models, free of YAML (DESIGN.md 2.5, 4). A model is either a set of named
/// inertia configurations (a rigid body has one; the seed's satellite has closed,
/// half-open and open tensors) or a hub with hinged panels whose named configurations
/// are hinge angles. Units: SI (kg, m, rad). Frame: B, the body (hub) frame.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "deploysim/math/types.h"

namespace deploysim::model {

/// A rigid element: mass and inertia about its own centre of mass.
struct MassElement {
  double mass = 0.0;  ///< [kg] > 0.
  /// [kg m^2] about its CoM, B axes (panels: at hinge angle 0).
  math::Mat3 inertia_cm = math::Mat3::Zero();
};

/// The hub: the body whose frame is B.
struct Hub {
  MassElement body;
  math::Vec3 com_B = math::Vec3::Zero();  ///< [m] CoM of the hub in B.
};

/// A panel on a revolute hinge fixed in the hub (DESIGN.md 2.5, panel k).
/// At hinge angle theta the panel's orientation in B is Rot(a_k, theta) (its theta = 0
/// orientation), and its CoM is at p_k + Rot(a_k, theta) r_k.
struct Panel {
  std::string name;
  MassElement body;                               ///< inertia_cm at theta = 0, B axes.
  math::Vec3 hinge_point_B = math::Vec3::Zero();  ///< p_k [m].
  math::Vec3 hinge_axis_B = math::Vec3::UnitX();  ///< a_k, unit.
  math::Vec3 com_offset_B = math::Vec3::Zero();   ///< r_k [m], CoM - hinge point at theta = 0.
};

struct HingedBody {
  Hub hub;
  std::vector<Panel> panels;
};

enum class ModelKind {
  kTensors,  ///< Named inertia tensors (one for a plain rigid body).
  kHinged,   ///< Hub + hinged panels; configurations are hinge angles.
};

/// A named configuration: an inertia tensor (kTensors) or hinge angles (kHinged).
struct Configuration {
  std::string name;
  math::Mat3 J_B = math::Mat3::Zero();  ///< [kg m^2] about the CoM (kTensors).
  Eigen::VectorXd hinge_angles;         ///< [rad], one per panel (kHinged).
};

struct Model {
  std::string name;
  std::string description;
  std::string source;  ///< File it was read from (for messages), or empty.
  std::string text;    ///< The model file's own text (stored in trajectory files), or empty.
  ModelKind kind = ModelKind::kTensors;
  HingedBody hinged;                          ///< Only for kHinged.
  std::vector<Configuration> configurations;  ///< In file order; names unique.

  /// The configuration called `name`; throws std::invalid_argument listing the valid ones.
  const Configuration& configuration(const std::string& name) const;
};

}  // namespace deploysim::model
