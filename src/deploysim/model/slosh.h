#pragma once

/// Propellant slosh as an equivalent spherical pendulum (docs/appendages.md, "Propellant
/// slosh"): the first lateral slosh mode of the liquid in a tank moves like a pendulum of
/// mass m1 and length L1 on a pivot fixed in the tank; the rest of the liquid, m0, moves
/// with the tank as a rigid mass. The pendulum is a point mass (a bob, inertia 0) on two
/// orthogonal free hinges at the pivot (a massless link on the first, the bob on the
/// second: model.h Appendage), both perpendicular to the rest direction, without springs
/// and with a damper c each; m0 is added to the hub's (or the parent panel's) mass
/// properties at its point. This is the mechanical-analogue model of the propellant, not a
/// model of the flow: it holds for small slosh amplitudes of the first mode, as do the
/// parameters it is given.
///
/// Parameters (NASA SP-106, Abramson 1966, ch. 6; Dodge 2000, "The New Dynamic Behavior
/// of Liquids in Moving Containers", SwRI, ch. 3), for a liquid of mass m_liquid at rest
/// in a field of acceleration g:
///   - upright cylinder of diameter d, liquid depth h:
///       m1 / m_liquid = (d / 4.4 h) tanh(3.68 h / d),   L1 = (d / 3.68) coth(3.68 h / d)
///     (3.68 = 2 xi_1, xi_1 = 1.841 the first root of J1'; the slosh frequency is
///     omega^2 = g / L1 = (2 xi_1 g / d) tanh(2 xi_1 h / d)), m0 = m_liquid - m1;
///   - half-full sphere of radius R: L1 = 0.639 R (Budiansky 1960), the pivot at the
///     sphere's centre (the wall's pressure passes through it);
///   - the damping: a ratio zeta of the slosh mode, measured (or from Dodge's
///     correlations of the wall's boundary layer: ~0.1-1 % for bare tanks; baffles and
///     diaphragms much more).
///
/// In a spinning craft the liquid sits in the centrifugal field instead of gravity: the
/// pendulum's "down", `direction`, points outward from the spin axis, and the same
/// pendulum holds with g replaced by the centrifugal acceleration Omega^2 r at the pivot
/// (r its distance from the spin axis), to first order in L1 / r. Exactly, for a pivot
/// fixed at r on a body spinning steadily at Omega, the arm radial at rest, the linearized
/// swings in the spinning frame (Lagrangian of the bob with the centrifugal potential
/// -1/2 m1 Omega^2 rho_perp^2, rho_perp the bob's distance from the axis; the Coriolis
/// terms do not couple the two swings at first order) are:
///   - in the plane of rotation (the hinge axis along the spin axis):
///       omega_in^2 = Omega^2 r / L1
///     (the field at the pivot: the centrifugal pendulum absorber's, of order sqrt(r / L1));
///   - out of it (the bob moves along the spin axis):
///       omega_out^2 = Omega^2 (r + L1) / L1 = omega_in^2 + Omega^2
///     (bob at height z: rho_perp^2 = (r + L1 cos psi)^2, whose second derivative in psi
///     at 0 is -2 L1 (r + L1): a uniform field of strength Omega^2 (r + L1), the field at
///     the bob).
/// A tank on the spin axis (r = 0) has omega_in = 0 (the liquid may turn freely about the
/// axis) and omega_out = Omega. tests/run/slosh_dynamics_test.cpp checks both against
/// the modes of the project's linearized equations.
///
/// `damping_ratio` zeta is turned into the hinges' damper through omega_out (the swing
/// that moves along the spin axis, which the nutation drives: the one that matters for a
/// spinner's stability, and the only one that is not 0 on the axis):
///   c = 2 zeta omega_out m1 L1^2   [N m s/rad]
/// (m1 L1^2 is the bob's inertia about either hinge). The in-plane swing then has the ratio
/// zeta omega_out / omega_in.

#include <optional>
#include <string>

#include "deploysim/math/types.h"
#include "deploysim/model/model.h"

namespace deploysim::model {

/// A tank that gives a slosh pendulum its parameters (SloshSpec::tank): an upright circular
/// cylinder with a flat bottom, its axis along the spec's `direction`, the bottom on the
/// side `direction` points to (the liquid's "down": outward from the spin axis in a
/// spinner), filled to the fraction f of its volume. The liquid's depth is h = f H and its
/// mass m_liquid = f liquid_mass_full, or density pi d^2 / 4 h. From the first slosh mode
/// (NASA SP-106, Abramson 1966, ch. 6; Dodge 2000, ch. 3; 3.68 = 2 xi_1, xi_1 = 1.841):
///   m1 = m_liquid (d / 4.4 h) tanh(3.68 h / d),   L1 = (d / 3.68) coth(3.68 h / d);
///   the bob at the height of the spring-mass analogue's mass (the pendulum of the same
///   force and moment has its bob there), h1 = h/2 - (d / 3.68) tanh(1.84 h / d) above the
///   liquid's centre of mass, so the pivot is at h1 + L1 = h/2 + (d / 3.68) csch(3.68 h / d)
///   above it ((d / 3.68) csch(3.68 h / d) above the free surface: coth 2a - tanh a =
///   csch 2a);
///   m0 = m_liquid - m1 at h0 = -m1 h1 / m0 above the liquid's centre of mass. The handbook
///   fixes h0 with every mode so that the model's centre of mass is the liquid's; with the
///   first mode alone (the second has 3 % of m1) the same condition gives this h0, which
///   keeps the liquid's centre of mass at rest exactly. m0 is a point mass: the liquid's
///   own rotational inertia (less than that of the liquid frozen) is left out.
struct SloshTank {
  math::Vec3 center = math::Vec3::Zero();  ///< [m] the cylinder's centre, on its axis at
                                           ///< mid-height (parent's axes, from its origin)
  double diameter = 0.0;                   ///< d [m] > 0
  double height = 0.0;                     ///< H [m] > 0, bottom to top inside
  /// Exactly one: the liquid's mass when full [kg] > 0, or its density [kg/m^3] > 0.
  std::optional<double> liquid_mass_full;
  std::optional<double> density;
  double fill_fraction = 0.0;  ///< f in (0, 1]: the share of the volume the liquid fills
};

/// The pendulum of a tank (SloshTank), heights along -direction (up).
struct SloshTankPendulum {
  double liquid_mass = 0.0;    ///< m_liquid [kg]
  double liquid_height = 0.0;  ///< h [m]
  double mass = 0.0;           ///< m1 [kg]
  double length = 0.0;         ///< L1 [m]
  double fixed_mass = 0.0;     ///< m0 [kg]
  /// [m] above the tank's bottom: the liquid's centre of mass (h/2), the bob, the pivot,
  /// and m0.
  double liquid_com_height = 0.0, bob_height = 0.0, pivot_height = 0.0, fixed_height = 0.0;
};

/// The formulas of SloshTank for a tank of valid values (AddSlosh checks them).
SloshTankPendulum CylinderTankPendulum(const SloshTank& tank);

/// An equivalent slosh pendulum, as an analyst has it. Positions are in the parent's axes
/// from the parent's origin (model.h Panel: B's origin for the hub, the parent's hinge
/// point for a panel).
struct SloshSpec {
  std::string name;
  int parent = -1;                             ///< panel the tank is fixed to, -1: the hub
  math::Vec3 pivot = math::Vec3::Zero();       ///< [m] the pendulum's pivot
  math::Vec3 direction = math::Vec3::UnitX();  ///< rest direction, pivot to bob (normalized)
  /// The first hinge's axis (unit after normalizing, perpendicular to direction); the second
  /// is direction x axis. Zero: the axis of B's x, y, z least aligned with direction, made
  /// perpendicular to it. For a spinner give the spin axis: the first hinge is then the
  /// swing in the plane of rotation, the second the swing along the spin axis. Two hinges
  /// are singular where the bob lies along the first axis (the first hinge then turns it
  /// about itself): for large motions (a tumble) choose a direction the field at the tank
  /// never takes (models/spin_stabilized_tank.yaml shows how).
  math::Vec3 axis = math::Vec3::Zero();
  double mass = 0.0;                            ///< m1 [kg] > 0, the bob
  double length = 0.0;                          ///< L1 [m] > 0
  double fixed_mass = 0.0;                      ///< m0 [kg] >= 0, rigid with the tank
  math::Vec3 fixed_point = math::Vec3::Zero();  ///< [m] where m0 sits
  /// Instead of mass, length, pivot, fixed_mass and fixed_point (which must then be left at
  /// 0): the tank they follow from (SloshTank), placed on expansion.
  std::optional<SloshTank> tank;
  /// Exactly one of: the hinges' damper c [N m s/rad] >= 0, or the damping ratio zeta in
  /// [0, 1) with the spin rate Omega [rad/s] > 0 and the pivot's distance r [m] >= 0 from
  /// the spin axis at which omega_out is evaluated (c = 2 zeta omega_out m1 L1^2).
  std::optional<double> damping;
  std::optional<double> damping_ratio;
  std::optional<double> spin_rate;
  std::optional<double> spin_radius;
};

/// omega_in = Omega sqrt(r / L1) [rad/s]: the pendulum's swing in the plane of rotation
/// (see above).
double SloshInPlaneFrequency(double spin_rate, double spin_radius, double length);

/// omega_out = Omega sqrt((r + L1) / L1) [rad/s]: its swing along the spin axis.
double SloshOutOfPlaneFrequency(double spin_rate, double spin_radius, double length);

/// The hinges' damper c [N m s/rad] of a checked spec: `damping`, or
/// 2 zeta omega_out m1 L1^2.
double SloshDamping(const SloshSpec& spec);

/// Appends the pendulum to `body` (the link `<name>_a` on the first hinge, the bob
/// `<name>_b` on the second) and adds m0 to the hub's or the parent's mass, CoM and inertia
/// (parallel-axis theorem, exactly). Returns the Appendage: kind kSlosh, root -1, the two
/// hinges with spring 0 and damper c each. Throws std::invalid_argument "<where>.<key> =
/// <value>: <rule>" for a spec outside its ranges (mass > 0, length > 0, fixed_mass >= 0,
/// damping >= 0, damping_ratio in [0, 1) with spin_rate > 0 and spin_radius >= 0, exactly
/// one damping form, axis perpendicular to direction, parent an existing panel; a tank's
/// diameter and height > 0, fill_fraction in (0, 1], exactly one of liquid_mass_full and
/// density, each > 0, and nothing it gives set besides).
Appendage AddSlosh(HingedBody& body, const SloshSpec& spec, const std::string& where);

}  // namespace deploysim::model
