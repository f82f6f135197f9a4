#include "deploysim/model/flexible_beam.h"

#include <Eigen/Eigenvalues>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"
#include "deploysim/model/mass_matrix.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::model {

namespace {

using math::Mat3;
using math::Vec3;

using math::kPi;

/// Inertia about its CoM of a solid rod of circular section along unit d.
Mat3 RodInertia(double mass, double length, double radius, const Vec3& d) {
  const double transverse = mass * (length * length / 12.0 + radius * radius / 4.0);
  const double axial = mass * radius * radius / 2.0;
  const Mat3 dd = d * d.transpose();
  return transverse * (Mat3::Identity() - dd) + axial * dd;
}

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw std::invalid_argument(where + "." + what);
}

bool PositiveFinite(double x) { return std::isfinite(x) && x > 0.0; }

/// The spec with unit direction and unit plane axes, checked (message: where.key = value:
/// rule).
BeamSpec Checked(BeamSpec spec, const std::string& where) {
  using math::FormatNumber;
  if (!PositiveFinite(spec.length)) {
    Fail(where, "length = " + FormatNumber(spec.length) + ": must be > 0 [m]");
  }
  if (!PositiveFinite(spec.mass_per_length)) {
    Fail(where, "mass_per_length = " + FormatNumber(spec.mass_per_length) + ": must be > 0 [kg/m]");
  }
  if (!PositiveFinite(spec.radius) || spec.radius > spec.length) {
    Fail(where, "radius = " + FormatNumber(spec.radius) +
                    ": must be > 0 and at most the length [m] (a solid circular section)");
  }
  const double dn = spec.direction.norm();
  if (!PositiveFinite(dn)) Fail(where, "direction: must be finite and non-zero");
  spec.direction /= dn;
  if (spec.planes.empty() || spec.planes.size() > 2) {
    Fail(where, "bending: one or two planes are required (" + std::to_string(spec.planes.size()) +
                    " given)");
  }
  for (std::size_t p = 0; p < spec.planes.size(); ++p) {
    BeamPlane& plane = spec.planes[p];
    const std::string key = "bending[" + std::to_string(p) + "]";
    if (!PositiveFinite(plane.bending_stiffness)) {
      Fail(where, key + ".EI = " + FormatNumber(plane.bending_stiffness) + ": must be > 0 [N m^2]");
    }
    const double an = plane.axis.norm();
    if (!PositiveFinite(an) || std::abs(plane.axis.dot(spec.direction)) > 1e-9 * an) {
      Fail(where, key + ".axis: must be non-zero and perpendicular to direction");
    }
    plane.axis /= an;
  }
  if (spec.planes.size() == 2 && std::abs(spec.planes[0].axis.dot(spec.planes[1].axis)) > 1e-9) {
    Fail(where, "bending[1].axis: must be perpendicular to bending[0].axis");
  }
  if (spec.root_axis.isZero(0.0)) spec.root_axis = spec.planes[0].axis;
  if (!(spec.damping_ratio >= 0.0 && spec.damping_ratio < 1.0)) {
    Fail(where, "damping_ratio = " + FormatNumber(spec.damping_ratio) + ": must be in [0, 1)");
  }
  if (spec.segments != 0 && (spec.segments < 2 || spec.segments > kMaxBeamSegments)) {
    Fail(where, "segments = " + std::to_string(spec.segments) + ": must be in [2, " +
                    std::to_string(kMaxBeamSegments) + "]");
  }
  if (spec.modes < 0 || (spec.segments > 0 && spec.modes > spec.segments)) {
    Fail(where, "modes = " + std::to_string(spec.modes) +
                    ": must be at most the segments (rule: 1 <= modes <= segments)");
  }
  if (spec.segments == 0 && !(spec.frequency_tolerance > 0.0 && spec.frequency_tolerance < 0.5)) {
    Fail(where, "frequency_tolerance = " + FormatNumber(spec.frequency_tolerance) +
                    ": must be in (0, 0.5) (or give segments)");
  }
  return spec;
}

/// The chain of N segments appended to `body`; per plane, its hinges in root-to-tip order.
std::vector<std::vector<int>> AppendChain(HingedBody& body,
                                          const BeamSpec& spec,
                                          int n,
                                          int& root) {
  const double l = spec.length / n;
  const double m = spec.mass_per_length;
  const Vec3& d = spec.direction;
  const auto add = [&body](Panel p) {
    body.panels.push_back(std::move(p));
    return static_cast<int>(body.panels.size()) - 1;
  };
  Panel stub;
  stub.name = spec.name;
  stub.parent = spec.parent;
  stub.hinge_point_B = spec.root_point;
  stub.hinge_axis_B = spec.root_axis;
  stub.com_offset_B = d * (l / 4.0);
  stub.body.mass = m * l / 2.0;
  stub.body.inertia_cm = RodInertia(stub.body.mass, l / 2.0, spec.radius, d);
  root = add(stub);
  std::vector<std::vector<int>> hinges(spec.planes.size());
  int parent = root;
  for (int j = 1; j <= n; ++j) {
    const double len = j < n ? l : l / 2.0;
    const std::string tag = spec.name + "_" + std::to_string(j);
    Vec3 hinge_point = d * (j == 1 ? l / 2.0 : l);
    if (spec.planes.size() == 2) {
      Panel link;  // massless: the first plane's hinge, the segment turns on the second
      link.name = tag + "a";
      link.parent = parent;
      link.hinge_point_B = hinge_point;
      link.hinge_axis_B = spec.planes[0].axis;
      link.body.mass = 0.0;
      link.body.inertia_cm.setZero();
      parent = add(link);
      hinges[0].push_back(parent);
      hinge_point.setZero();
    }
    Panel seg;
    seg.name = spec.planes.size() == 2 ? tag + "b" : tag;
    seg.parent = parent;
    seg.hinge_point_B = hinge_point;
    seg.hinge_axis_B = spec.planes.back().axis;
    seg.com_offset_B = d * (len / 2.0);
    seg.body.mass = m * len;
    seg.body.inertia_cm = RodInertia(seg.body.mass, len, spec.radius, d);
    parent = add(seg);
    hinges.back().push_back(parent);
  }
  return hinges;
}

/// The beam alone on a stand-in hub (the clamped frequencies do not depend on the hub).
struct Chain {
  HingedBody body;
  std::vector<std::vector<int>> hinges;  // per plane
  int root = -1;
};

Chain StandAlone(const BeamSpec& spec, int n) {
  Chain c;
  c.body.hub.body.mass = 1.0;
  c.body.hub.body.inertia_cm = Mat3::Identity();
  BeamSpec alone = spec;
  alone.parent = -1;
  c.hinges = AppendChain(c.body, alone, n, c.root);
  return c;
}

/// The clamped chain's modes in plane p.
ClampedModes PlaneModes(const Chain& c, const BeamSpec& spec, int p) {
  const double k = spec.planes[static_cast<std::size_t>(p)].bending_stiffness /
                   (spec.length / static_cast<double>(c.hinges[0].size()));
  const std::vector<int>& cols = c.hinges[static_cast<std::size_t>(p)];
  return ComputeClampedModes(c.body,
                             Eigen::VectorXd::Zero(static_cast<Eigen::Index>(c.body.panels.size())),
                             cols, std::vector<double>(cols.size(), k));
}

/// The clamped chain's first `count` frequencies in plane p.
std::vector<double> PlaneFrequencies(const Chain& c, const BeamSpec& spec, int p, int count) {
  const Eigen::VectorXd w = PlaneModes(c, spec, p).frequencies;
  std::vector<double> out;
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(count, w.size()); ++i) out.push_back(w[i]);
  return out;
}

/// The smallest N whose first two frequencies in every plane are within the tolerance.
int SegmentsFor(const BeamSpec& spec, const std::string& where) {
  for (int n = 2; n <= kMaxBeamSegments; ++n) {
    const Chain c = StandAlone(spec, n);
    bool ok = true;
    for (int p = 0; p < static_cast<int>(spec.planes.size()) && ok; ++p) {
      const std::vector<double> w = PlaneFrequencies(c, spec, p, 2);
      for (int i = 0; i < 2; ++i) {
        const double exact = CantileverFrequency(spec, p, i + 1);
        ok = ok &&
             std::abs(w[static_cast<std::size_t>(i)] / exact - 1.0) <= spec.frequency_tolerance;
      }
    }
    if (ok) return n;
  }
  Fail(where, "frequency_tolerance = " + math::FormatNumber(spec.frequency_tolerance) +
                  ": no chain of up to " + std::to_string(kMaxBeamSegments) +
                  " segments meets it (rule: a coarser tolerance, or give segments)");
}

}  // namespace

double CantileverRoot(int n) {
  if (n < 1) throw std::invalid_argument("CantileverRoot: n must be >= 1");
  // cos x + 1 / cosh x = 0 (the same roots, well scaled): one root in ((n - 1) pi, n pi).
  const auto f = [](double x) { return std::cos(x) + 1.0 / std::cosh(x); };
  boost::uintmax_t iterations = 200;
  const auto bracket =
      boost::math::tools::toms748_solve(f, (n - 1) * kPi + (n == 1 ? 1.0 : 0.0), n * kPi,
                                        boost::math::tools::eps_tolerance<double>(), iterations);
  return 0.5 * (bracket.first + bracket.second);
}

double CantileverFrequency(const BeamSpec& spec, int plane, int n) {
  const double bl = CantileverRoot(n);
  const double L = spec.length;
  return bl * bl *
         std::sqrt(spec.planes[static_cast<std::size_t>(plane)].bending_stiffness /
                   (spec.mass_per_length * L * L * L * L));
}

double SouthwellCoefficient(double rho) {
  const double b = CantileverRoot(1);
  const double sigma = (std::cosh(b) + std::cos(b)) / (std::sinh(b) + std::sin(b));
  const auto phi = [&](double x) {
    return std::cosh(b * x) - std::cos(b * x) - sigma * (std::sinh(b * x) - std::sin(b * x));
  };
  const auto dphi = [&](double x) {
    return b * (std::sinh(b * x) + std::sin(b * x) - sigma * (std::cosh(b * x) - std::cos(b * x)));
  };
  using Quad = boost::math::quadrature::gauss_kronrod<double, 61>;
  const double num = Quad::integrate(
      [&](double x) { return (rho * (1.0 - x) + 0.5 * (1.0 - x * x)) * dphi(x) * dphi(x); }, 0.0,
      1.0, 10, 1e-14);
  const double den =
      Quad::integrate([&](double x) { return phi(x) * phi(x); }, 0.0, 1.0, 10, 1e-14);
  return num / den;
}

Eigen::VectorXd ClampedFrequencies(const HingedBody& body,
                                   const Eigen::VectorXd& theta,
                                   const std::vector<int>& columns,
                                   const std::vector<double>& stiffness) {
  return ComputeClampedModes(body, theta, columns, stiffness).frequencies;
}

ClampedModes ComputeClampedModes(const HingedBody& body,
                                 const Eigen::VectorXd& theta,
                                 const std::vector<int>& columns,
                                 const std::vector<double>& stiffness) {
  const PanelTree tree(body);
  TreePose pose;
  ComputePose(body, tree, theta, pose);
  Eigen::MatrixXd M;
  ComputeMassMatrix(body, tree, pose, columns, M, /*hub_held=*/true);
  const auto m = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index i = 0; i < m; ++i) K(i, i) = stiffness[static_cast<std::size_t>(i)];
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M.bottomRightCorner(m, m),
                                                                      Eigen::ComputeEigenvectors);
  if (eig.info() != Eigen::Success) {
    throw std::runtime_error("ClampedModes: the generalized eigenproblem did not converge");
  }
  ClampedModes out;
  out.frequencies = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  out.shapes = eig.eigenvectors();
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::Index at = 0;
    out.shapes.col(j).cwiseAbs().maxCoeff(&at);
    out.shapes.col(j) /= out.shapes(at, j);
  }
  return out;
}

Appendage AddBeam(HingedBody& body, const BeamSpec& raw, const std::string& where) {
  const BeamSpec spec = Checked(raw, where);
  const int n = spec.segments > 0 ? spec.segments : SegmentsFor(spec, where);
  if (spec.modes > n) {
    Fail(where, "modes = " + std::to_string(spec.modes) + ": more than the chain's " +
                    std::to_string(n) + " segments (rule: 1 <= modes <= segments)");
  }
  const double l = spec.length / n;
  Appendage app;
  app.name = spec.name;
  app.kind = Appendage::Kind::kBeam;
  app.segments = n;
  const Chain alone = StandAlone(spec, n);
  std::vector<double> k(spec.planes.size()), c(spec.planes.size());
  for (std::size_t p = 0; p < spec.planes.size(); ++p) {
    const int pi = static_cast<int>(p);
    app.chain_frequencies.push_back(PlaneFrequencies(alone, spec, pi, 3));
    std::vector<double> exact;
    for (int i = 1; i <= 3; ++i) exact.push_back(CantileverFrequency(spec, pi, i));
    app.beam_frequencies.push_back(exact);
    k[p] = spec.planes[p].bending_stiffness / l;
    c[p] = 2.0 * spec.damping_ratio * k[p] / app.chain_frequencies.back().front();
  }
  const std::vector<std::vector<int>> hinges = AppendChain(body, spec, n, app.root);
  // Root to tip, a two-plane joint's two hinges together.
  for (int j = 0; j < n; ++j) {
    for (std::size_t p = 0; p < hinges.size(); ++p) {
      app.hinges.push_back(hinges[p][static_cast<std::size_t>(j)]);
      app.stiffness.push_back(k[p]);
      app.damping.push_back(c[p]);
    }
  }
  if (spec.modes > 0) {
    // The first `modes` clamped modes of each plane, on that plane's rows.
    const auto planes = static_cast<Eigen::Index>(spec.planes.size());
    const Eigen::Index kk = spec.modes;
    app.modes = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(app.hinges.size()), planes * kk);
    for (Eigen::Index p = 0; p < planes; ++p) {
      const ClampedModes cm = PlaneModes(alone, spec, static_cast<int>(p));
      for (Eigen::Index j = 0; j < n; ++j) {
        app.modes.row(j * planes + p).segment(p * kk, kk) = cm.shapes.row(j).head(kk);
      }
    }
  }
  return app;
}

}  // namespace deploysim::model
