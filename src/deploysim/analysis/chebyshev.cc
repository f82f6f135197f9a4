#include "deploysim/analysis/chebyshev.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace deploysim::analysis {

namespace {
// Blocks of kTailLength coefficients that must all be within a factor 4 of the tail for
// a plateau (a flat run of 12 coefficients: a still-decaying series drops by far more).
constexpr std::size_t kPlateauBlocks = 3;
// Halvings of the original interval before the fit gives up regardless of the budget.
constexpr int kMaxDepth = 12;

// cos(pi m / n) for m = 0 .. 2n-1, n = kStartDegree * 2^i <= kMaxDegree (built once).
const std::vector<double>& CosTable(int n) {
  static const std::vector<std::vector<double>> tables = [] {
    std::vector<std::vector<double>> t;
    const double pi = std::acos(-1.0);
    for (int m = ChebyshevFit::kStartDegree; m <= ChebyshevFit::kMaxDegree; m *= 2) {
      std::vector<double> c(2 * static_cast<std::size_t>(m));
      for (std::size_t i = 0; i < c.size(); ++i) c[i] = std::cos(pi * static_cast<double>(i) / m);
      t.push_back(std::move(c));
    }
    return t;
  }();
  std::size_t i = 0;
  for (int m = ChebyshevFit::kStartDegree; m < n; m *= 2) ++i;
  return tables[i];
}
// c[i] += a v[i] for a row of `stride` (a multiple of 4) values.
void Axpy(std::size_t stride, double a, const double* v, double* c) {
  for (std::size_t i = 0; i < stride; i += 4) {
    c[i] += a * v[i];
    c[i + 1] += a * v[i + 1];
    c[i + 2] += a * v[i + 2];
    c[i + 3] += a * v[i + 3];
  }
}

// Clenshaw's recurrence for rows of S coefficients (the first `dim` are written):
// b_k = c_k + 2 x b_{k+1} - b_{k+2}; p(x) = c_0 + x b_1 - b_2.
template <std::size_t S>
void Clenshaw(const double* c, int degree, double x, std::size_t dim, double* out) {
  double b1[S] = {}, b2[S] = {};
  const double x2 = 2.0 * x;
  for (int k = degree; k >= 1; --k) {
    const double* ck = c + static_cast<std::size_t>(k) * S;
    for (std::size_t i = 0; i < S; ++i) {
      const double bk = ck[i] + x2 * b1[i] - b2[i];
      b2[i] = b1[i];
      b1[i] = bk;
    }
  }
  for (std::size_t i = 0; i < dim; ++i) out[i] = c[i] + x * b1[i] - b2[i];
}

}  // namespace

bool ChebyshevFit::Build(const std::function<void(double, double*)>& f,
                         double a,
                         double b,
                         const std::vector<double>& scale,
                         const std::vector<double>& noise,
                         std::size_t max_evaluations) {
  if (!(a < b)) throw std::invalid_argument("ChebyshevFit: interval [a, b] needs a < b");
  if (scale.empty() || scale.size() > kMaxComponents)
    throw std::invalid_argument("ChebyshevFit: number of components must be 1 to 16");
  dim_ = scale.size();
  stride_ = (dim_ + 3) / 4 * 4;
  if (noise.size() != dim_)
    throw std::invalid_argument("ChebyshevFit: noise must have one entry per component");
  threshold_.resize(dim_);
  ceiling_.resize(dim_);
  for (std::size_t i = 0; i < dim_; ++i) {
    if (!(scale[i] > 0.0) || !std::isfinite(scale[i]))
      throw std::invalid_argument("ChebyshevFit: scale must be finite and > 0");
    if (!(noise[i] >= 0.0) || !std::isfinite(noise[i]))
      throw std::invalid_argument("ChebyshevFit: noise must be finite and >= 0");
    threshold_[i] = kTailUlps * std::numeric_limits<double>::epsilon() * scale[i];
    ceiling_[i] = std::max(threshold_[i], kTailUlps * noise[i]);
  }
  pieces_.clear();
  coef_.clear();
  cursor_ = 0;
  evaluations_ = 0;
  max_evaluations_ = max_evaluations;
  if (!FitPiece(f, a, b, 0)) {
    pieces_.clear();
    coef_.clear();
    return false;
  }
  return true;
}

bool ChebyshevFit::FitPiece(const std::function<void(double, double*)>& f,
                            double a,
                            double b,
                            int depth) {
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  const std::size_t d = stride_;  // row length (components padded with zeros)
  // values_[j * d + i]: component i at x_j = cos(pi j / n); x_0 = 1 is t = b, x_n = a.
  auto t_at = [&](int j, int n) {
    if (j == 0) return b;
    if (j == n) return a;
    return mid + half * CosTable(n)[static_cast<std::size_t>(j)];
  };
  int n = kStartDegree;
  if (evaluations_ + static_cast<std::size_t>(n + 1) > max_evaluations_) return false;
  values_.assign(static_cast<std::size_t>(n + 1) * d, 0.0);  // padding stays 0
  for (int j = 0; j <= n; ++j) f(t_at(j, n), &values_[static_cast<std::size_t>(j) * d]);
  evaluations_ += static_cast<std::size_t>(n + 1);
  for (;;) {
    // DCT-I: c_k = (2/n) sum'' f_j cos(pi j k / n), c_0 and c_n halved.
    const std::size_t nn = static_cast<std::size_t>(n);
    // With cos(pi (n-j) k / n) = (-1)^k cos(pi j k / n), the sum runs over j <= n/2 of
    // e_j = f_j + f_{n-j} (even k) or o_j = f_j - f_{n-j} (odd k), e_{n/2} = f_{n/2},
    // o_{n/2} = 0 (its cosine vanishes for odd k), weight 1/2 at j = 0.
    const std::size_t half_n = nn / 2;
    sums_.assign((half_n + 1) * d, 0.0);
    diffs_.assign((half_n + 1) * d, 0.0);
    for (std::size_t j = 0; j < half_n; ++j) {
      const double* lo = &values_[j * d];
      const double* hi = &values_[(nn - j) * d];
      const double w = j == 0 ? 0.5 : 1.0;
      for (std::size_t i = 0; i < d; ++i) {
        sums_[j * d + i] = w * (lo[i] + hi[i]);
        diffs_[j * d + i] = w * (lo[i] - hi[i]);
      }
    }
    std::copy_n(&values_[half_n * d], d, &sums_[half_n * d]);
    coefs_tmp_.assign((nn + 1) * d, 0.0);
    const std::vector<double>& cos_tab = CosTable(n);
    for (std::size_t k = 0; k <= nn; ++k) {
      double* c = &coefs_tmp_[k * d];
      const std::vector<double>& g = k % 2 == 0 ? sums_ : diffs_;
      std::size_t m = 0;  // j k mod 2n
      for (std::size_t j = 0; j <= half_n; ++j) {
        Axpy(d, cos_tab[m], &g[j * d], c);
        m += k;
        if (m >= 2 * nn) m -= 2 * nn;
      }
      const double s = (k == 0 || k == nn) ? 1.0 / n : 2.0 / n;
      for (std::size_t i = 0; i < d; ++i) c[i] *= s;
    }
    // Per component: the tail (last kTailLength coefficients) below the threshold, or a
    // plateau (the tail no smaller than a quarter of each of the two blocks of
    // kTailLength coefficients before it: they have stopped decaying, they are the values'
    // rounding noise) below the ceiling.
    bool converged = true;
    for (std::size_t i = 0; i < dim_ && converged; ++i) {
      // Largest |c_k| over the blocks [n+1-4(l+1), n+1-4l), l = 0 (the tail), 1, 2.
      double block[kPlateauBlocks] = {};
      for (std::size_t l = 0; l < kPlateauBlocks; ++l)
        for (std::size_t k = nn + 1 - kTailLength * (l + 1); k < nn + 1 - kTailLength * l; ++k)
          block[l] = std::max(block[l], std::abs(coefs_tmp_[k * d + i]));
      const double tail = block[0];
      const bool below = tail <= threshold_[i];
      bool plateau = tail <= ceiling_[i];
      for (std::size_t l = 1; l < kPlateauBlocks; ++l)
        if (4.0 * tail < block[l]) plateau = false;
      if (!(below || plateau)) converged = false;
    }
    if (converged) {
      // Drop the trailing coefficients that are negligible in every component.
      std::size_t last = nn;
      while (last > 0) {
        bool small = true;
        for (std::size_t i = 0; i < dim_; ++i)
          if (std::abs(coefs_tmp_[last * d + i]) > 0.25 * threshold_[i]) small = false;
        if (!small) break;
        --last;
      }
      Piece p;
      p.a = a;
      p.b = b;
      p.mid = mid;
      p.inv_half = 1.0 / half;
      p.degree = static_cast<int>(last);
      p.offset = coef_.size();
      coef_.insert(coef_.end(), coefs_tmp_.begin(),
                   coefs_tmp_.begin() + static_cast<std::ptrdiff_t>((last + 1) * d));
      pieces_.push_back(p);
      return true;
    }
    if (n >= kMaxDegree) break;
    // Double the degree: the old points are the even ones of the new grid.
    const int n2 = 2 * n;
    if (evaluations_ + static_cast<std::size_t>(n) > max_evaluations_) return false;
    std::vector<double>& v2 = values2_;
    v2.assign(static_cast<std::size_t>(n2 + 1) * d, 0.0);
    for (int j = 0; j <= n2; ++j) {
      double* dst = &v2[static_cast<std::size_t>(j) * d];
      if (j % 2 == 0) {
        std::copy_n(&values_[static_cast<std::size_t>(j / 2) * d], d, dst);
      } else {
        f(t_at(j, n2), dst);
      }
    }
    evaluations_ += static_cast<std::size_t>(n);
    values_.swap(v2);
    n = n2;
  }
  if (depth >= kMaxDepth || !(a < mid && mid < b)) return false;
  return FitPiece(f, a, mid, depth + 1) && FitPiece(f, mid, b, depth + 1);
}

void ChebyshevFit::Evaluate(double t, double* out) const {
  std::size_t p = std::min(cursor_, pieces_.size() - 1);
  while (p + 1 < pieces_.size() && t > pieces_[p].b) ++p;
  while (p > 0 && t < pieces_[p].a) --p;
  cursor_ = p;
  const Piece& pc = pieces_[p];
  const double x = std::clamp((t - pc.mid) * pc.inv_half, -1.0, 1.0);
  const double* c = &coef_[pc.offset];
  switch (stride_) {
    case 4:
      Clenshaw<4>(c, pc.degree, x, dim_, out);
      break;
    case 8:
      Clenshaw<8>(c, pc.degree, x, dim_, out);
      break;
    case 12:
      Clenshaw<12>(c, pc.degree, x, dim_, out);
      break;
    default:
      Clenshaw<16>(c, pc.degree, x, dim_, out);
      break;
  }
}

int ChebyshevFit::max_degree() const {
  int m = 0;
  for (const Piece& p : pieces_) m = std::max(m, p.degree);
  return m;
}

}  // namespace deploysim::analysis
