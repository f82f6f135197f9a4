#pragma once

/// Inertia tensors that validate themselves (docs/design.md section 1, STYLE.md):
/// finite, symmetric, positive definite, principal moments obeying the triangle
/// inequalities. Units: kg m^2. Invalid input throws std::invalid_argument whose
/// message names the violated rule and the offending values.

#include <array>
#include <string>

#include "deploysim/math/double_double.h"
#include "deploysim/math/types.h"

namespace deploysim::math {

/// Principal decomposition J = axes * diag(moments) * axes^T.
struct PrincipalAxes {
  Vec3 moments;  ///< [kg m^2] ascending: moments[0] <= moments[1] <= moments[2].
  Mat3 axes;     ///< Columns are unit principal axes in the tensor's frame; det = +1.
};

/// Principal decomposition in double-double: J = V diag(moments) V^T to ~1e-31 of |J|.
struct PrincipalAxesDD {
  std::array<DoubleDouble, 3> moments;           ///< [kg m^2] ascending.
  std::array<std::array<DoubleDouble, 3>, 3> V;  ///< V[i][j]: component i of unit axis j; det +1.
  /// The moments and axes rounded to double.
  PrincipalAxes Rounded() const;
};

/// A physically valid rotational inertia about a point, in some frame.
/// Class invariant: finite, exactly symmetric, positive definite, triangle inequalities.
class InertiaTensor {
 public:
  /// Relative tolerance for the symmetry and triangle-inequality checks.
  static constexpr double kRelTolerance = 1e-12;
  /// Largest |entry| [kg m^2] allowed: far above any spacecraft (a 1e12 kg body 1e6 m
  /// across has ~1e25), low enough that M^2, energies and products of inertias stay finite.
  static constexpr double kMaxEntry = 1e30;

  /// Validates J (throws std::invalid_argument naming the rule) and symmetrizes it.
  /// `what` names the quantity in error messages (e.g. "models/wing_nut.yaml: inertia").
  static InertiaTensor FromMatrix(const Mat3& J, const std::string& what = "inertia");

  /// Diagonal tensor from three principal moments (any order), validated.
  static InertiaTensor FromPrincipalMoments(const Vec3& moments,
                                            const std::string& what = "inertia");

  /// Returns an empty string when J is valid, else the message FromMatrix would throw.
  static std::string Check(const Mat3& J, const std::string& what = "inertia");

  const Mat3& matrix() const { return J_; }
  const Mat3& inverse() const { return J_inv_; }
  /// Principal moments (ascending) and right-handed principal axes.
  PrincipalAxes Principal() const;

 private:
  explicit InertiaTensor(const Mat3& J);
  Mat3 J_;
  Mat3 J_inv_;
};

/// Principal decomposition of a symmetric matrix: ascending eigenvalues, right-handed
/// orthonormal eigenvector columns. Exact (no rotation) for diagonal input, so a tensor
/// given by its principal moments keeps its body axes.
PrincipalAxes PrincipalDecomposition(const Mat3& J);

/// The principal decomposition of the symmetric J (double entries, taken as exact) to
/// double-double accuracy: the double decomposition's axes, re-orthonormalised in
/// double-double, then cyclic Jacobi rotations (Golub & Van Loan, Matrix Computations,
/// 4th ed., 8.5.2) on V^T J V in double-double until the off-diagonal part is below
/// kOffDiagonalRelTol of the trace. The double decomposition's O(eps) error is thus
/// removed: V is orthonormal and J V - V diag(moments) vanishes to ~1e-31 |J|. Needed
/// where the motion amplifies the moments' and axes' errors, like 1/(1 - k^2) near the
/// separatrix (analysis::FreeBodySolution). Diagonal input is exact (a permutation), as
/// for PrincipalDecomposition. Cost ~1.5 us on top of it.
PrincipalAxesDD AccuratePrincipalDecomposition(const Mat3& J);

}  // namespace deploysim::math
