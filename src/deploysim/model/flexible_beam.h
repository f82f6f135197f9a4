#pragma once

/// A flexible appendage (a boom, a whip antenna, a wing) as a uniform Euler-Bernoulli
/// cantilever, expanded into a chain of rigid segments on spring-damper hinges: the
/// free-hinge machinery then moves it like any other panel (docs/design.md 2.9).
///
/// The chain is the rigid finite element method's (Kruszewski; Wittbrodt, Adamiec-Wojcik
/// and Wojciech, "Dynamics of Flexible Multibody Systems: Rigid Finite Element Method",
/// Springer 2006, ch. 2): the beam of length L is cut into N elements of length l = L/N;
/// the bending flexibility of element j is lumped into one hinge at its middle,
/// s_j = (j - 1/2) l from the root, of stiffness k = EI / l (the moment that bends an
/// element of length l through the angle theta is EI theta / l). The rigid bodies lie
/// between the hinges: a root stub [0, l/2], N - 1 segments of length l and a tip half
/// segment [L - l/2, L], each with its share of the beam's mass. The clamped chain's
/// bending frequencies converge to the Euler-Bernoulli ones as N grows, with an error
/// ~ 1/N^2 (measured in tests/model/flexible_beam_test.cpp; docs/appendages.md tables it).
///
/// Bending in two planes: each joint then has two hinges at one point, the first carrying
/// a massless link (model.h), the second the segment. The stub is a panel of its own on a
/// root hinge, so a profile can deploy the whole appendage (prescribe or free the root
/// hinge, latch it); left out of the profile it is locked, as any panel.
///
/// Damping: stiffness-proportional (Rayleigh) damping C = (2 zeta / omega_1) K, i.e. a
/// damper c = 2 zeta k / omega_1 on every bending hinge, omega_1 the clamped chain's own
/// first frequency in that plane. It gives the first mode the damping ratio zeta exactly
/// and mode i the ratio zeta omega_i / omega_1 (the usual choice for structures whose
/// test gives one ratio; Hughes 1986 ch. 12 discusses it for spacecraft appendages).

#include <string>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/model/model.h"

namespace deploysim::model {

/// One bending plane: bending about `axis` (a hinge axis, perpendicular to the beam).
struct BeamPlane {
  math::Vec3 axis = math::Vec3::UnitZ();  ///< in the parent's axes; made unit and
                                          ///< perpendicular to the beam on expansion.
  double bending_stiffness = 0.0;         ///< EI [N m^2] > 0.
};

/// A uniform cantilever beam, as an analyst has it.
struct BeamSpec {
  std::string name;
  int parent = -1;                             ///< panel it is fixed to, -1: the hub
  math::Vec3 root_point = math::Vec3::Zero();  ///< [m] from the parent's origin, its axes
  math::Vec3 direction = math::Vec3::UnitX();  ///< along the beam, root to tip (normalized)
  math::Vec3 root_axis = math::Vec3::Zero();   ///< root hinge axis; 0: the first plane's
  double length = 0.0;                         ///< L [m] > 0
  double mass_per_length = 0.0;                ///< m [kg/m] > 0
  double radius = 0.0;                         ///< [m] > 0: solid circular section (inertia)
  std::vector<BeamPlane> planes;               ///< one or two (perpendicular)
  double damping_ratio = 0.0;                  ///< zeta of the first mode, in [0, 1)
  int segments = 0;                            ///< N >= 2; 0: chosen by frequency_tolerance
  /// When segments is 0: the smallest N whose clamped chain gives the first two bending
  /// frequencies of every plane within this relative error of Euler-Bernoulli's.
  double frequency_tolerance = 0.0;
  /// 0: the chain's every hinge is a coordinate. K > 0: the chain moves only in the span of
  /// its first K clamped modes per plane (a Ritz reduction of the chain, Appendage::modes).
  int modes = 0;
};

/// Most segments of one beam: a 2-plane beam of kMaxBeamSegments is a chain of
/// 2 kMaxBeamSegments + 1 panels (mass_properties.h kMaxPanelDepth).
inline constexpr int kMaxBeamSegments = 100;

/// Appends the beam's panels to `body` (its stub, then per joint the link of a two-plane
/// joint and the segment) and returns what was generated: the bending hinges' springs
/// and dampers and the chain's clamped frequencies. Throws std::invalid_argument naming
/// `where` and the rule for a spec outside its ranges, or when no N up to
/// kMaxBeamSegments meets frequency_tolerance.
Appendage AddBeam(HingedBody& body, const BeamSpec& spec, const std::string& where);

/// beta_n L of the uniform clamped-free Euler-Bernoulli beam (n >= 1): the n-th root of
/// cos x cosh x = -1 (1.8751, 4.6941, 7.8548, ...). omega_n = (beta_n L)^2 sqrt(EI / (m L^4)).
double CantileverRoot(int n);

/// The first Euler-Bernoulli bending frequency of the spec's plane p [rad/s].
double CantileverFrequency(const BeamSpec& spec, int plane, int n);

/// The Southwell coefficient S of the uniform cantilever's first mode on a hub of radius
/// r (root at r from the spin axis, the beam radial): the first-order centrifugal
/// stiffening omega^2 = omega_0^2 + S Omega^2 out of the plane of rotation (in the plane
/// S - 1), from the Rayleigh quotient with the exact mode shape phi:
///   S = int_0^1 [rho (1 - x) + (1 - x^2) / 2] phi'(x)^2 dx / int_0^1 phi(x)^2 dx,
/// rho = r / L (1.193 for rho = 0, slope ~1.57 in rho; cf. Wright, Smith, Thresher and
/// Wang, J. Appl. Mech. 49 (1982) 197-202; Hodges and Rutkowski, AIAA J. 19 (1981)).
double SouthwellCoefficient(double hub_radius_over_length);

/// The clamped modes of a chain of free hinges (ComputeClampedModes).
struct ClampedModes {
  Eigen::VectorXd frequencies;  ///< [rad/s], ascending
  /// One column per mode (the hinge angles over `columns`), scaled to 1 at its largest.
  Eigen::MatrixXd shapes;
};

/// The bending frequencies [rad/s], ascending, of a chain of free hinges with springs
/// `stiffness` (one per column) with the hub held still (clamped): the generalized
/// eigenvalues of K v = omega^2 M v, M the hinges' block of the mass matrix at `theta`.
Eigen::VectorXd ClampedFrequencies(const HingedBody& body,
                                   const Eigen::VectorXd& theta,
                                   const std::vector<int>& columns,
                                   const std::vector<double>& stiffness);

/// ClampedFrequencies with the mode shapes.
ClampedModes ComputeClampedModes(const HingedBody& body,
                                 const Eigen::VectorXd& theta,
                                 const std::vector<int>& columns,
                                 const std::vector<double>& stiffness);

}  // namespace deploysim::model
