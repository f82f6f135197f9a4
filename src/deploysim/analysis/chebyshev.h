#pragma once

/// Piecewise Chebyshev interpolation of a smooth vector function of time to rounding
/// accuracy, for cheap dense output of the closed-form flow (exact_flow.h).
///
/// On [a, b] the function is sampled at the Chebyshev-Lobatto points
/// t_j = (a + b)/2 + (b - a)/2 cos(pi j / N), j = 0..N, and the coefficients c_k of
/// p(x) = sum_k c_k T_k(x) (x the time mapped onto [-1, 1]) are the DCT-I of the values.
/// The degree starts at kStartDegree and doubles (the points are nested, so every value
/// is reused) until, for every component, the last kTailLength coefficients are below
/// kTailUlps * eps * scale_i, or have reached a plateau (no smaller than a quarter of
/// each of the 2 kTailLength coefficients before them: what is left is the rounding noise of the
/// values themselves, which no interpolant can follow) below kTailUlps * noise_i, a bound on that
/// noise supplied by the caller; the interpolant then agrees with the values to their own rounding.
/// If kMaxDegree does not suffice the interval is halved and each half fitted the same way (a
/// function steep in part of the interval, e.g. near the separatrix, gets short pieces there).
/// Trailing coefficients below a quarter of the threshold in every component are dropped. Values
/// are evaluated by Clenshaw's recurrence. The fit gives up (Build returns false) once it would
/// need more than `max_evaluations` function values.

#include <cstddef>
#include <functional>
#include <vector>

namespace deploysim::analysis {

class ChebyshevFit {
 public:
  static constexpr int kStartDegree = 16;
  static constexpr int kMaxDegree = 64;
  static constexpr int kTailLength = 4;
  static constexpr double kTailUlps = 4.0;
  static constexpr std::size_t kMaxComponents = 16;

  /// f(t, out) writes the `scale.size()` (1 to kMaxComponents) components of the
  /// function at t. scale_i > 0 is the magnitude of component i against which its
  /// coefficients are judged, noise_i >= 0 a bound on the rounding error of its values
  /// (see above). Requires a < b. Returns false (and holds no fit) if more than
  /// max_evaluations values would be needed. Reuses this object's storage.
  bool Build(const std::function<void(double, double*)>& f,
             double a,
             double b,
             const std::vector<double>& scale,
             const std::vector<double>& noise,
             std::size_t max_evaluations);

  /// The interpolant at t in [a, b] (clamped onto it): writes dim() components.
  /// Successive calls with ascending t are fastest (the piece is searched from the last).
  void Evaluate(double t, double* out) const;

  bool valid() const { return !pieces_.empty(); }
  std::size_t dim() const { return dim_; }
  std::size_t pieces() const { return pieces_.size(); }
  /// Largest degree over the pieces (after dropping negligible trailing coefficients).
  int max_degree() const;
  /// Function values used by the last Build.
  std::size_t evaluations() const { return evaluations_; }

 private:
  struct Piece {
    double a, b;           ///< Interval.
    double mid, inv_half;  ///< x = (t - mid) * inv_half.
    int degree;            ///< Coefficients 0..degree.
    std::size_t offset;    ///< Into coef_: coef_[offset + k * dim_ + i].
  };
  bool FitPiece(const std::function<void(double, double*)>& f, double a, double b, int depth);

  std::size_t dim_ = 0;
  std::size_t stride_ = 0;  ///< Row length of the value and coefficient arrays: dim_ padded to 4s.
  std::vector<double> threshold_;  ///< kTailUlps * eps * scale_i.
  std::vector<double> ceiling_;    ///< Largest accepted plateau: kTailUlps * noise_i.
  std::vector<Piece> pieces_;
  std::vector<double> coef_;
  std::vector<double> values_, values2_, coefs_tmp_, sums_, diffs_;
  std::size_t evaluations_ = 0;
  std::size_t max_evaluations_ = 0;
  mutable std::size_t cursor_ = 0;
};

}  // namespace deploysim::analysis
