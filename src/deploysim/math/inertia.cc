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

namespace {

/// Jacobi sweeps stop when the off-diagonal sum is below this fraction of the trace (the
/// double-double rounding floor of V^T J V is ~1e-32 of it).
constexpr double kOffDiagonalRelTol = 1e-31;
constexpr int kMaxSweeps = 6;

using DD = DoubleDouble;
using Col = std::array<DD, 3>;

DD Dot(const Col& a, const Col& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void Normalize(Col& a) {
  const DD n = Sqrt(Dot(a, a));
  for (DD& x : a) x /= n;
}

}  // namespace

PrincipalAxes PrincipalAxesDD::Rounded() const {
  PrincipalAxes p;
  for (int j = 0; j < 3; ++j) {
    p.moments[j] = static_cast<double>(moments[j]);
    for (int i = 0; i < 3; ++i) p.axes(i, j) = static_cast<double>(V[i][j]);
  }
  return p;
}

PrincipalAxesDD AccuratePrincipalDecomposition(const Mat3& J) {
  const PrincipalAxes p = PrincipalDecomposition(J);
  // Columns of the double axes, re-orthonormalised (Gram-Schmidt, right-handed).
  std::array<Col, 3> v;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) v[j][i] = p.axes(i, j);
  Normalize(v[0]);
  const DD d01 = Dot(v[0], v[1]);
  for (int i = 0; i < 3; ++i) v[1][i] -= d01 * v[0][i];
  Normalize(v[1]);
  v[2] = {v[0][1] * v[1][2] - v[0][2] * v[1][1], v[0][2] * v[1][0] - v[0][0] * v[1][2],
          v[0][0] * v[1][1] - v[0][1] * v[1][0]};
  // A = V^T J V (symmetric; upper triangle used).
  DD A[3][3];
  for (int a = 0; a < 3; ++a) {
    Col Jv;
    for (int i = 0; i < 3; ++i) Jv[i] = v[a][0] * J(i, 0) + v[a][1] * J(i, 1) + v[a][2] * J(i, 2);
    for (int b = 0; b <= a; ++b) A[b][a] = A[a][b] = Dot(v[b], Jv);
  }
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const DD off = Abs(A[0][1]) + Abs(A[0][2]) + Abs(A[1][2]);
    const DD trace = Abs(A[0][0]) + Abs(A[1][1]) + Abs(A[2][2]);
    if (off <= trace * kOffDiagonalRelTol) break;
    for (int pi = 0; pi < 2; ++pi) {
      for (int qi = pi + 1; qi < 3; ++qi) {
        if (A[pi][qi].hi() == 0.0) continue;
        // Rotation G = [c s; -s c] in the (p, q) plane zeroing A(p, q) (the smaller angle).
        const DD theta = (A[qi][qi] - A[pi][pi]) / (A[pi][qi] * 2.0);
        const DD t = (theta.hi() >= 0 ? 1.0 : -1.0) / (Abs(theta) + Sqrt(Square(theta) + 1.0));
        const DD c = 1.0 / Sqrt(Square(t) + 1.0);
        const DD s = t * c;
        const DD apq = A[pi][qi];
        A[pi][pi] -= t * apq;
        A[qi][qi] += t * apq;
        A[pi][qi] = A[qi][pi] = 0.0;
        const int r = 3 - pi - qi;
        const DD arp = A[r][pi], arq = A[r][qi];
        A[r][pi] = A[pi][r] = c * arp - s * arq;
        A[r][qi] = A[qi][r] = s * arp + c * arq;
        for (int i = 0; i < 3; ++i) {
          const DD vp = v[pi][i], vq = v[qi][i];
          v[pi][i] = c * vp - s * vq;
          v[qi][i] = s * vp + c * vq;
        }
      }
    }
  }
  // Ascending order, right-handed.
  int idx[3] = {0, 1, 2};
  std::sort(idx, idx + 3, [&A](int a, int b) { return A[a][a] < A[b][b]; });
  PrincipalAxesDD out;
  for (int j = 0; j < 3; ++j) {
    out.moments[j] = A[idx[j]][idx[j]];
    for (int i = 0; i < 3; ++i) out.V[i][j] = v[idx[j]][i];
  }
  const Mat3 axes = out.Rounded().axes;
  if (axes.determinant() < 0.0) {
    for (int i = 0; i < 3; ++i) out.V[i][2] = -out.V[i][2];
  }
  return out;
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
  if (scale > kMaxEntry) {
    os << what << " has an entry of magnitude " << scale
       << " kg m^2 (rule: |entry| <= " << kMaxEntry << " kg m^2)";
    return os.str();
  }
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
