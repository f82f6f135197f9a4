#pragma once

/// Body models, free of YAML (docs/design.md 2.5, 4). A model is either a set of named
/// inertia configurations (a rigid body has one; the seed's satellite has closed,
/// half-open and open tensors) or a hub with hinged panels whose named configurations
/// are hinge angles. Units: SI (kg, m, rad). Frame: B, the body (hub) frame.

#include <Eigen/Core>
#include <memory>
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

/// A panel on a revolute hinge (docs/design.md 2.5, 2.7). Panels form a tree: a panel's
/// parent is the hub or another panel (multi-segment arrays fold panel on panel).
/// The hinge point p_k and axis a_k are fixed in the parent's frame; at hinge angle 0 a
/// panel's axes equal its parent's, so with every hinge angle 0 all axes are B's and every
/// vector below is given in B axes. In B, R_Bk = R_B,parent(k) Rot(a_k, theta_k); the hinge
/// point is o_parent + R_B,parent p_k, where o_parent is the parent's origin: B's origin for
/// the hub (not its CoM), the parent's own hinge point for a panel; the CoM is
/// hinge_k + R_Bk r_k. For a child of the hub (parent = -1) this is the single-level
/// model: hinge point p_k in B, orientation Rot(a_k, theta_k), CoM p_k + Rot(a_k, theta_k) r_k.
struct Panel {
  std::string name;
  MassElement body;  ///< inertia_cm in the panel's axes (B's axes when every angle is 0).
  /// Index of the parent panel in HingedBody::panels, or -1 for the hub. The parents must
  /// form a tree (no cycle; ValidatedHingedBody checks it); they may come in any order.
  int parent = -1;
  /// p_k [m]: from the parent's origin (see above), in the parent's axes.
  math::Vec3 hinge_point_B = math::Vec3::Zero();
  math::Vec3 hinge_axis_B = math::Vec3::UnitX();  ///< a_k, unit, in the parent's axes.
  /// r_k [m], CoM - hinge point at theta_k = 0, in the panel's (= the parent's) axes.
  math::Vec3 com_offset_B = math::Vec3::Zero();
};

struct HingedBody {
  Hub hub;
  std::vector<Panel> panels;
};

struct BeamSpec;   // model/flexible_beam.h
struct SloshSpec;  // model/slosh.h

/// What a flexible element (model/flexible_beam.h) or a slosh pendulum (model/slosh.h)
/// generated: panels of the body whose hinges are free from the run's start, each with
/// the spring and damper the element's physics gives. A generated panel may be massless
/// (a link joining two hinges at one point: mass 0, inertia 0, CoM on its hinge, with a
/// child) or a point mass (inertia 0); ValidatedHingedBody accepts these only so.
struct Appendage {
  enum class Kind { kBeam, kSlosh };
  std::string name;
  Kind kind = Kind::kBeam;
  /// Its root panel: the beam's stub on its root hinge, which a profile may move like any
  /// panel (deploy the beam), or -1 (a slosh pendulum has none).
  int root = -1;
  std::vector<int> hinges;        ///< the generated free hinges (panel indices)
  std::vector<double> stiffness;  ///< [N m/rad] per hinge (its spring, rest angle 0)
  std::vector<double> damping;    ///< [N m s/rad] per hinge
  int segments = 0;               ///< a beam's N
  /// A beam's clamped chain: the first bending frequencies [rad/s] per plane (up to 3),
  /// and Euler-Bernoulli's for the same beam.
  std::vector<std::vector<double>> chain_frequencies, beam_frequencies;
  /// Empty: every generated hinge is a coordinate of its own. Otherwise the hinges move
  /// only as theta = modes q (one row per hinge of `hinges`, one column per coordinate q:
  /// a beam's first clamped modes per plane, each scaled to 1 at its largest hinge angle),
  /// a Ritz reduction of the chain (schedule::FreeHingeSystem's modal coordinates).
  Eigen::MatrixXd modes;
  /// What it was expanded from, as the model file gives it (model/appendages.h
  /// ExpandAppendage sets the one of its kind; null for an appendage made otherwise):
  /// kept so that it can be expanded again with changed parameters (RebuildAppendages, a
  /// sweep case). Immutable and shared by copies: a changed spec is a new one.
  std::shared_ptr<const BeamSpec> beam;
  std::shared_ptr<const SloshSpec> slosh;
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
  /// Flexible elements, expanded into panels after the file's own (kHinged only).
  std::vector<Appendage> appendages;
  /// kHinged: the file's own hub and panels before the appendages were expanded onto them
  /// (a slosh pendulum adds its fixed mass to the hub or a panel): what RebuildAppendages
  /// expands them onto again.
  HingedBody declared;

  /// The configuration called `name`; throws std::invalid_argument listing the valid ones.
  const Configuration& configuration(const std::string& name) const;
};

}  // namespace deploysim::model
