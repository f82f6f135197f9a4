#include "deploysim/math/inertia.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace deploysim::math {

namespace {

std::string Format(const Mat3& J) {
  std::ostringstream os;
  os.precision(10);
  os << "[[" << J(0, 0) << ", " << J(0, 1) << ", " << J(0, 2) << "], [" << J(1, 0) << ", "
     << J(1, 1) << ", " << J(1, 2) << "], [" << J(2, 0) << ", " << J(2, 1) << ", " << J(2, 2)
     << "]]";
  return os.str();
}

}  // namespace

PrincipalAxes PrincipalDecomposition(const Mat3& J) {
  PrincipalAxes p;
  const bool diagonal = J(0, 1) == 0.0 && J(0, 2) == 0.0 && J(1, 2) == 0.0 && J(1, 0) == 0.0 &&
                        J(2, 0) == 0.0 && J(2, 1) == 0.0;
  if (diagonal) {
    std::array<int, 3> idx{0, 1, 2};
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return J(a, a) < J(b, b); });
    for (int i = 0; i < 3; ++i) {
      p.moments[i] = J(idx[i], idx[i]);
      p.axes.col(i) = Vec3::Unit(idx[i]);
    }
  } else {
    Eigen::SelfAdjointEigenSolver<Mat3> es(J);  // eigenvalues ascending
    p.moments = es.eigenvalues();
    p.axes = es.eigenvectors();
  }
  if (p.axes.determinant() < 0.0) p.axes.col(2) = -p.axes.col(2);
  return p;
}

std::string InertiaTensor::Check(const Mat3& J, const std::string& what) {
  std::ostringstream os;
  os.precision(10);
  if (!J.allFinite()) {
    return what + " = " + Format(J) + ": every entry must be finite (rule: finite)";
  }
  const double scale = J.cwiseAbs().maxCoeff();
  const double asym = (J - J.transpose()).cwiseAbs().maxCoeff();
  if (scale == 0.0) return what + " is zero (rule: positive definite)";
  if (asym > kRelTolerance * scale) {
    os << what << " = " << Format(J) << " is not symmetric: max |J - J^T| = " << asym << " > "
       << kRelTolerance << " * max|J| (rule: symmetric)";
    return os.str();
  }
  const Mat3 S = 0.5 * (J + J.transpose());
  const Vec3 m = PrincipalDecomposition(S).moments;
  if (!(m[0] > 0.0)) {
    os << what << " = " << Format(J) << " has principal moments (" << m[0] << ", " << m[1] << ", "
       << m[2] << "); all must be > 0 (rule: positive definite)";
    return os.str();
  }
  // Ascending order: the only triangle inequality that can fail is m0 + m1 >= m2.
  if (m[0] + m[1] < m[2] * (1.0 - kRelTolerance)) {
    os << what << " has principal moments (" << m[0] << ", " << m[1] << ", " << m[2]
       << "): " << m[0] << " + " << m[1] << " < " << m[2]
       << " (rule: triangle inequality I_a + I_b >= I_c)";
    return os.str();
  }
  return {};
}

InertiaTensor InertiaTensor::FromMatrix(const Mat3& J, const std::string& what) {
  const std::string err = Check(J, what);
  if (!err.empty()) throw std::invalid_argument(err);
  return InertiaTensor(0.5 * (J + J.transpose()));
}

InertiaTensor InertiaTensor::FromPrincipalMoments(const Vec3& moments, const std::string& what) {
  return FromMatrix(moments.asDiagonal().toDenseMatrix(), what);
}

InertiaTensor::InertiaTensor(const Mat3& J) : J_(J), J_inv_(J.inverse()) {
  J_inv_ = 0.5 * (J_inv_ + J_inv_.transpose()).eval();
}

PrincipalAxes InertiaTensor::Principal() const { return PrincipalDecomposition(J_); }

}  // namespace deploysim::math
