#pragma once

/// Events that change a free-hinge system (docs/design.md 2.7): releases, latches,
/// stop impacts, a panel coming to rest on a stop, a jam. Each is located on the dense
/// output, applied as an impulse on the hinge's conjugate momentum p_k (H_B and every
/// other p_j unchanged) and reported with what a mission analyst needs: the impulse, the
/// hub's angular-velocity jump (the latch shock) and the energy dissipated.

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/math/types.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::run {

struct HingeEvent {
  enum class Kind {
    kRelease,  ///< The hinge starts to move (no impulse).
    kLatch,    ///< Plastic impulse at the latch angle, then locked.
    kJam,      ///< Plastic impulse part-way (failure mode, schedule::Latch), then locked.
    kStop,     ///< Impact on a hard stop with restitution: theta'+ = -e theta'-.
    kRest,     ///< Came to rest on a stop (schedule::Stops): held there.
    kLiftOff,  ///< Left the stop it rested on: the torque holding it there pulled it away.
    kStick,    ///< Exact Coulomb friction stopped the hinge and holds it (schedule::Friction).
    kSlip,     ///< The torque holding a stuck hinge exceeded the friction torque: it moves.
  };
  Kind kind = Kind::kRelease;
  double t = 0.0;            ///< [s]
  int panel = 0;             ///< Panel (hinge) index in the model.
  double angle = 0.0;        ///< [rad] hinge angle at the event.
  double rate_before = 0.0;  ///< [rad/s] theta'_k just before.
  double rate_after = 0.0;   ///< [rad/s] just after.
  /// [N m s] the jump lambda of p_k: the angular impulse of the torque pair at the hinge.
  double impulse = 0.0;
  math::Vec3 w_jump_B = math::Vec3::Zero();  ///< [rad/s] hub w_NB_B+ - w_NB_B-.
  /// [J] kinetic energy lost: (M^-1)_kk lambda^2 / 2 (docs/design.md 2.7); 0 for a release.
  double energy_dissipated = 0.0;
  /// [J] impulsive work of the drives of the prescribed hinges moving at the event (they
  /// keep their rates through it): the kinetic energy jumps by drive_work -
  /// energy_dissipated. 0 when no prescribed hinge moves.
  double drive_work = 0.0;
};

/// Every kind, in declaration order (readers parse the names of ToString against them).
inline constexpr std::array<HingeEvent::Kind, 8> kHingeEventKinds = {
    HingeEvent::Kind::kRelease, HingeEvent::Kind::kLatch, HingeEvent::Kind::kJam,
    HingeEvent::Kind::kStop,    HingeEvent::Kind::kRest,  HingeEvent::Kind::kLiftOff,
    HingeEvent::Kind::kStick,   HingeEvent::Kind::kSlip};

/// "release", "latch", "jam", "stop", "rest", "lift-off", "stick", "slip".
std::string ToString(HingeEvent::Kind kind);

/// The kind named `name` (ToString's names); std::invalid_argument naming the valid ones.
HingeEvent::Kind ParseHingeEventKind(const std::string& name);

/// One column of the hinge event table, described once: the HDF5 group /events/hinge, its
/// reader, `analyze --json` and the Python package's event table are all derived from
/// HingeEventTable (docs/design.md 4, "Records described once").
struct HingeEventColumn {
  enum class Type { kReal, kInteger, kText, kVector3 };
  std::string name;         ///< HDF5 dataset, JSON key and Python column
  std::string units;        ///< as the HDF5 `units` attribute ("none" for text)
  std::string description;  ///< as the HDF5 `description` attribute
  Type type = Type::kReal;
  /// The event's value: numbers (one, three for kVector3) ...
  std::function<void(const HingeEvent& e, double* out)> number;
  /// ... or text; `panel_names`: the model's panel names, in panel order.
  std::function<std::string(const HingeEvent& e, const std::vector<std::string>& panel_names)> text;
  /// Readers: the value read back into the event (null: derived from other columns).
  std::function<void(HingeEvent& e, const double* in)> set_number;
  std::function<void(HingeEvent& e, const std::string& in)> set_text;
  /// A file written before the column existed reads this value (NaN: the column is
  /// required).
  double missing = std::numeric_limits<double>::quiet_NaN();
  /// Values per event: 3 for kVector3, else 1.
  int width() const { return type == Type::kVector3 ? 3 : 1; }
};

/// The hinge event table: the standard columns in file order, and Extend (a column added
/// by a test or an extension before any output is written reaches every output).
class HingeEventTable {
 public:
  static const std::vector<HingeEventColumn>& Columns();
  static void Extend(HingeEventColumn column);
};

/// The faults of a hinge profile's run (none for a stage profile).
std::vector<analysis::DeploymentFault> DeploymentFaults(const schedule::Profile& profile,
                                                        const std::vector<HingeEvent>& events,
                                                        double t_end);

}  // namespace deploysim::run
