#include "deploysim/analysis/work_estimate.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"
#include "deploysim/model/mass_matrix.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/schedule/free_hinge_system.h"
#include "deploysim/schedule/hinge_motion.h"

namespace deploysim::analysis {

namespace {

// Largest |w|^2 = sum h_i^2 / I_i^2 of a rigid body with principal moments I (ascending)
// over every h with |h|^2 = M2 and sum h_i^2 / I_i = two_T: a linear programme in
// x_i = h_i^2 >= 0, whose optimum lies on a vertex (two x_i nonzero, or one).
double MaxRateSquaredOnEllipsoid(const math::Vec3& I, double M2, double two_T) {
  double best = 0.0;
  bool any = false;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double ai = 1.0 / I[i];
      const double aj = 1.0 / I[j];
      if (!(ai > aj)) continue;  // equal moments: the pair is one direction
      const double xi = (two_T - M2 * aj) / (ai - aj);
      // Rounding of two_T may put a vertex a hair outside: clamp it back.
      const double tol = 1e-9 * M2;
      if (!(xi >= -tol && xi <= M2 + tol)) continue;
      const double x = std::clamp(xi, 0.0, M2);
      best = std::max(best, x * ai * ai + (M2 - x) * aj * aj);
      any = true;
    }
  }
  // All moments equal (or no vertex found by rounding): |w| = M / I.
  if (!any) best = M2 / (I[0] * I[0]);
  return best;
}

// The largest rate at which H_B can turn in the body of a rigid body with inertia J and
// momentum H [rad/s]: |dH_B/dt| / M = |w x H| / M = sqrt(|w|^2 - (2T / M)^2) (the part of w
// across H), its largest |w| on the energy ellipsoid. What a Lie-group method resolves (it
// carries the spin about H exactly): 0 for a spin about a principal axis, about |w| for a
// flip.
double BodyFrameRate(const math::Mat3& J, const math::Vec3& H) {
  const double M2 = H.squaredNorm();
  if (!(M2 > 0.0)) return 0.0;
  const math::PrincipalAxes pa = math::PrincipalDecomposition(J);
  const math::Vec3 h = pa.axes.transpose() * H;
  const math::Vec3& I = pa.moments;
  const double two_T = h[0] * h[0] / I[0] + h[1] * h[1] / I[1] + h[2] * h[2] / I[2];
  const double across =
      std::sqrt(std::max(0.0, MaxRateSquaredOnEllipsoid(I, M2, two_T) - two_T * two_T / M2));
  // Near a principal axis i the body's w turns at the nutation (polhode) frequency
  // (M / I_i) sqrt(|(I_i - I_j)(I_i - I_k)| / (I_j I_k)): the error control follows it,
  // however small the nutation (a spin about the smallsat's minor axis: 435 steps in
  // 600 s where the nutation is 1.4 deg).
  int i = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(h[a]) > std::abs(h[i])) i = a;
  }
  const double Ij = I[(i + 1) % 3], Ik = I[(i + 2) % 3];
  const double nutation =
      std::sqrt(M2) / I[i] * std::sqrt(std::abs((I[i] - Ij) * (I[i] - Ik)) / (Ij * Ik));
  return std::max(across, nutation);
}

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) { return math::FormatSignificant(x); }

/// Steps per radian of the fastest motion that an adaptive method takes at tolerance
/// rtol: kStepsPerRadian rtol^(-1 / (q + 1)), q the order of its error estimate (a local
/// error ~ (h nu)^(q+1) held at rtol). The constant is measured: rkmk-rkf78 on the stiff
/// hinge spring trap (1e6 N m/rad, rtol 1e-11) takes 5.07 steps per radian of its
/// frequency, 0.214 rtol^(-1/8); with this estimate's rates the shipped examples and the
/// traps take from 0.3 to 3 times that, and 0.136 centres them (their table:
/// docs/design.md, "Cost known before the run").
constexpr double kStepsPerRadian = 0.136;
/// Lie-group methods (and `exact`) carry the spin itself exactly: what they resolve is
/// the motion of H_B in the body, at most this fraction of the body's rate for the
/// shipped examples' and the traps' spins (measured: the smallsat's rigid phases).
constexpr double kLieRateFraction = 0.13;
/// A damped mode's decay rate counts this much against an oscillation's frequency: it
/// dies out (measured: the dual-spin craft's and the flat spin's pendulum dampers).
constexpr double kDecayWeight = 0.25;
/// [rad] Stops closer than this make a panel rest at once (schedule::kContactTime: a
/// rebound at 1 mrad/s travels it within the contact time).
constexpr double kRattleGap = 1e-6;
/// The impacts a panel pressed on its stop makes before it rests: its speed falls as e^n
/// to schedule::kRestSpeed from about 1 rad/s (infinite at e = 1).
double Bounces(double e) {
  if (!(e > 0.0)) return 1.0;
  if (!(e < 1.0)) return std::numeric_limits<double>::infinity();
  return std::ceil(std::log(schedule::kRestSpeed) / std::log(e));
}
/// The cost of starting a segment, in steps (measured: a stiff spring with exact Coulomb
/// friction, 95000 slip ends in 600 s, took 122 s, 400 right-hand sides per step).
constexpr double kSegmentCost = 20.0;
/// The closed form (`exact`) on a constant stage: 8 steps per period of the motion.
constexpr double kExactStepsPerPeriod = 8.0;
/// Steps every segment between events costs at least (its first steps find the scale).
constexpr double kStepsPerSegment = 5.0;

double StepsPerRadian(const integrators::StepperInfo& info, double rtol) {
  const int q = info.error_order > 0 ? info.error_order : info.order;
  return kStepsPerRadian * std::pow(rtol, -1.0 / (q + 1));
}

/// The cost of one step [s] on one core: a fixed part, the tree's kinematics (per panel),
/// the mass matrix's solve (per cube of the unknowns, 3 + free hinges). Measured on this
/// project's reference machine: the smallsat's stiff spring (2 panels, 1 free), the
/// 2048-panel tree with one free hinge, the chain of 64 free panels.
double SecondsPerStep(int panels, int free) {
  const double u = 3.0 + free;
  return 12e-6 + 7e-6 * panels + 1.1e-7 * u * u * u;
}

/// The panels a hinge run computes: those that can move and their ancestors (locked
/// subtrees under which nothing moves are merged into their parents, FreeHingeSystem).
int ComputedPanels(const schedule::Profile& profile) {
  const std::vector<model::Panel>& panels = profile.model.hinged.panels;
  std::vector<char> kept(panels.size(), 0);
  for (std::size_t k = 0; k < profile.hinges.size() && k < panels.size(); ++k) {
    if (profile.hinges[k].kind == schedule::HingePlan::Kind::kLocked) continue;
    for (int j = static_cast<int>(k); j >= 0 && !kept[static_cast<std::size_t>(j)];
         j = panels[static_cast<std::size_t>(j)].parent) {
      kept[static_cast<std::size_t>(j)] = 1;
    }
  }
  return static_cast<int>(std::count(kept.begin(), kept.end(), 1));
}

/// Per free-plan hinge: its own stiffest rate (diagonal of S), and the system's.
struct HingeRates {
  double stiffest = 0.0;
  std::vector<double> own;      ///< per panel (0 unless free)
  std::vector<double> inertia;  ///< per panel: its effective inertia S_aa (0 unless free)
  /// Per panel: its modal group's index (schedule::ModalGroupsOf), -1 for none.
  std::vector<int> group;
  /// Per modal group: its stiffest coordinate's own rate (its hinges' own rate too).
  std::vector<double> group_rate;
  int coordinates = 0;  ///< free hinges outside the groups plus the groups' coordinates
};

/// The map T from the coordinates to the hinge rates over `cols`: the identity for a
/// hinge outside the groups, a group's basis on its hinges' rows (FreeHingeSystem's
/// modal coordinates). Fills rates.group.
Eigen::MatrixXd CoordinateMap(const std::vector<int>& cols,
                              const std::vector<schedule::ModalGroup>& groups,
                              HingeRates& rates) {
  const auto m = static_cast<Eigen::Index>(cols.size());
  Eigen::Index n = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (int k : groups[g].hinges) rates.group[static_cast<std::size_t>(k)] = static_cast<int>(g);
    n += groups[g].basis.cols();
  }
  std::vector<Eigen::Index> first(groups.size(), 0);
  for (Eigen::Index a = 0; a < m; ++a) {
    n += rates.group[static_cast<std::size_t>(cols[static_cast<std::size_t>(a)])] < 0 ? 1 : 0;
  }
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m, n);
  Eigen::Index c = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    first[g] = c;
    c += groups[g].basis.cols();
  }
  for (Eigen::Index a = 0; a < m; ++a) {
    const int k = cols[static_cast<std::size_t>(a)];
    const int g = rates.group[static_cast<std::size_t>(k)];
    if (g < 0) {
      T(a, c++) = 1.0;
      continue;
    }
    const schedule::ModalGroup& mg = groups[static_cast<std::size_t>(g)];
    const auto row = std::find(mg.hinges.begin(), mg.hinges.end(), k) - mg.hinges.begin();
    T.row(a).segment(first[static_cast<std::size_t>(g)], mg.basis.cols()) = mg.basis.row(row);
  }
  return T;
}

HingeRates FreeHingeRates(const schedule::Profile& profile, double spin) {
  HingeRates out;
  const model::Model& model = profile.model;
  out.own.assign(profile.hinges.size(), 0.0);
  out.inertia.assign(profile.hinges.size(), 0.0);
  out.group.assign(profile.hinges.size(), -1);
  if (model.kind != model::ModelKind::kHinged) return out;
  std::vector<int> cols;
  for (std::size_t k = 0; k < profile.hinges.size(); ++k) {
    if (profile.hinges[k].kind == schedule::HingePlan::Kind::kFree)
      cols.push_back(static_cast<int>(k));
  }
  if (cols.empty()) return out;
  const Eigen::VectorXd& theta0 = model.configuration(profile.initial.configuration).hinge_angles;
  const model::PanelTree tree(model.hinged);
  model::TreePose pose;
  model::ComputePose(model.hinged, tree, theta0, pose);
  Eigen::MatrixXd M;
  model::ComputeMassMatrix(model.hinged, tree, pose, cols, M);
  const Eigen::Index m = static_cast<Eigen::Index>(cols.size());
  const Eigen::Matrix3d J = M.topLeftCorner<3, 3>();
  const Eigen::MatrixXd B = M.block(0, 3, 3, m);
  const Eigen::MatrixXd S = M.block(3, 3, m, m) - B.transpose() * J.ldlt().solve(B);
  Eigen::VectorXd K(m), C(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const schedule::FreeDrive& d =
        profile.hinges[static_cast<std::size_t>(cols[static_cast<std::size_t>(a)])].drive;
    const bool servo = d.motor.kind == schedule::Motor::Kind::kServo;
    K[a] = d.spring.stiffness + (servo ? d.motor.servo_stiffness : 0.0) + spin * spin * S(a, a);
    C[a] =
        d.damping + (servo ? d.motor.servo_damping : 0.0) +
        (d.friction.regularization_speed > 0.0 ? d.friction.torque / d.friction.regularization_speed
                                               : 0.0);
    const std::size_t k = static_cast<std::size_t>(cols[static_cast<std::size_t>(a)]);
    out.own[k] = std::sqrt(K[a] / S(a, a)) + kDecayWeight * C[a] / S(a, a);
    out.inertia[k] = S(a, a);
  }
  // In the coordinates the run integrates (modal groups: their modes' coordinates).
  const std::vector<schedule::ModalGroup> groups = schedule::ModalGroupsOf(model);
  const Eigen::MatrixXd T = CoordinateMap(cols, groups, out);
  out.coordinates = static_cast<int>(T.cols());
  const Eigen::MatrixXd Sc = T.transpose() * S * T;
  const Eigen::MatrixXd Kc = T.transpose() * K.asDiagonal() * T;
  const Eigen::MatrixXd Cc = T.transpose() * C.asDiagonal() * T;
  out.group_rate.assign(groups.size(), 0.0);
  for (Eigen::Index j = 0; j < T.cols(); ++j) {
    for (Eigen::Index a = 0; a < m; ++a) {
      const int g = out.group[static_cast<std::size_t>(cols[static_cast<std::size_t>(a)])];
      if (g < 0 || T(a, j) == 0.0) continue;
      double& r = out.group_rate[static_cast<std::size_t>(g)];
      r = std::max(r, std::sqrt(Kc(j, j) / Sc(j, j)) + kDecayWeight * Cc(j, j) / Sc(j, j));
    }
  }
  for (Eigen::Index a = 0; a < m; ++a) {
    const int g = out.group[static_cast<std::size_t>(cols[static_cast<std::size_t>(a)])];
    if (g >= 0)
      out.own[static_cast<std::size_t>(cols[static_cast<std::size_t>(a)])] =
          out.group_rate[static_cast<std::size_t>(g)];
  }
  double freq = 0.0, decay = 0.0;
  if (T.cols() <= 256) {
    // The generalized eigenvalues of (K, S), (C, S): S is SPD (the mass matrix is).
    using Solver = Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>;
    const Solver ek(Kc, Sc, Eigen::EigenvaluesOnly);
    const Solver ec(Cc, Sc, Eigen::EigenvaluesOnly);
    freq = std::sqrt(std::max(0.0, ek.eigenvalues().maxCoeff()));
    decay = std::max(0.0, ec.eigenvalues().maxCoeff());
  } else {
    // A long chain: the diagonal bound (the eigen solve would cost more than it saves).
    for (Eigen::Index a = 0; a < Sc.rows(); ++a) {
      freq = std::max(freq, std::sqrt(Kc(a, a) / Sc(a, a)));
      decay = std::max(decay, Cc(a, a) / Sc(a, a));
    }
  }
  out.stiffest = freq + kDecayWeight * decay;
  return out;
}

/// How long free hinge k moves after its release [s] (inf: to the end), from its own rate
/// and effective inertia: a latching swing, half a period; a drive that presses the panel
/// onto a stop (its equilibrium beyond it) bounces to rest in t1 (1 + e) / (1 - e), t1 the
/// first swing (a quarter period, or sqrt(2 travel I / torque) for a motor alone) and e
/// the restitution (the flights shrink as e^n); exact Coulomb friction stops a spring's
/// swing after (A - mu / k) / (2 mu / k) half periods (A its first amplitude).
double MovingTime(const schedule::Profile& profile, std::size_t k, double own, double inertia) {
  constexpr double pi = 3.141592653589793;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const schedule::FreeDrive& d = profile.hinges[k].drive;
  if (!(own > 0.0)) return inf;
  if (d.latch.enabled) return pi / own;
  // Stops closer than a rebound travels in the contact time: it rests at once (a rattle).
  if (d.stops.max_angle - d.stops.min_angle < kRattleGap) return schedule::kContactTime;
  const double theta0 = profile.model.configuration(profile.initial.configuration)
                            .hinge_angles[static_cast<Eigen::Index>(k)];
  const double torque =
      d.spring.preload + (d.motor.kind == schedule::Motor::Kind::kConstant ? d.motor.torque : 0.0);
  const double k_s = d.spring.stiffness;
  const double eq = k_s > 0.0 ? d.spring.rest_angle + torque / k_s
                              : (torque > 0.0   ? inf
                                 : torque < 0.0 ? -inf
                                                : theta0);
  const double stop = eq > d.stops.max_angle   ? d.stops.max_angle
                      : eq < d.stops.min_angle ? d.stops.min_angle
                                               : std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(stop) && d.stops.restitution < 1.0 &&
      d.motor.kind != schedule::Motor::Kind::kServo) {
    const double t1 = k_s > 0.0
                          ? 0.5 * pi / own
                          : std::sqrt(2.0 * std::abs(stop - theta0) * inertia / std::abs(torque));
    const double e = d.stops.restitution;
    return t1 * (1.0 + e) / (1.0 - e);
  }
  const bool servo = d.motor.kind == schedule::Motor::Kind::kServo;
  const double k_all = k_s + (servo ? d.motor.servo_stiffness : 0.0);
  if (schedule::IsCoulomb(d.friction) && k_all > 0.0) {
    // The swing's first amplitude: from the start to the spring's equilibrium, or each of
    // a servo's planned moves (each starts a swing about its new target).
    double amplitude = std::abs(theta0 - eq);
    double swings = 1.0;
    if (servo) {
      amplitude = 0.0;
      double from = theta0;
      for (const schedule::HingeMove& mv : d.motor.follow) {
        const double to = mv.kind == schedule::HingeMove::Kind::kTo ? mv.angle : from;
        amplitude = std::max(amplitude, std::abs(to - from));
        from = to;
      }
      swings = std::max<double>(1.0, static_cast<double>(d.motor.follow.size()));
    }
    const double half = 2.0 * d.friction.torque / k_all;  // amplitude lost per half period
    return swings * pi / own * std::max(1.0, std::ceil((amplitude - 0.5 * half) / half));
  }
  // A damped swing is not cut short: the body's motion keeps driving it (a pendulum
  // damper follows the nutation; a small panel on a flipping body swings with it).
  return inf;
}

/// The stop impacts of the free hinges that a drive presses onto a stop (Bounces): each
/// is a segment of the run.
/// The events that cut the run into segments, each a restart of the integration: per free
/// hinge pressed onto a stop, its bounces (Bounces; at most one per two first flights over
/// the run: restitution near 1 bounces for the whole run); with exact
/// Coulomb friction and a spring or servo, two slip ends per period of its own rate (a
/// stiff spring with little friction swings, and stops, tens of thousands of times).
double Segments(const schedule::Profile& profile, const HingeRates& rates) {
  constexpr double pi = 3.141592653589793;
  const double T = profile.t_end() - profile.t_begin();
  double n = 0.0;
  for (std::size_t k = 0; k < profile.hinges.size(); ++k) {
    const schedule::HingePlan& h = profile.hinges[k];
    if (h.kind != schedule::HingePlan::Kind::kFree) continue;
    const schedule::FreeDrive& d = h.drive;
    const double own = rates.own[k];
    const double cycles = own > 0.0 ? own * T / (2.0 * pi) : 0.0;
    const bool servo = d.motor.kind == schedule::Motor::Kind::kServo;
    if (schedule::IsCoulomb(d.friction) && (d.spring.stiffness > 0.0 || servo)) {
      n += 2.0 * cycles;
    }
    if (!d.stops.any() || d.stops.max_angle - d.stops.min_angle < kRattleGap) continue;
    // Pressed onto a stop: the first flight from the start to it, t1 = sqrt(2 travel / a)
    // under the pressing acceleration a at the stop; a bounce at most every 2 t1.
    const double theta0 = profile.model.configuration(profile.initial.configuration)
                              .hinge_angles[static_cast<Eigen::Index>(k)];
    const double torque = d.spring.preload +
                          (d.motor.kind == schedule::Motor::Kind::kConstant ? d.motor.torque : 0.0);
    const double k_s = d.spring.stiffness;
    const double eq = k_s > 0.0
                          ? d.spring.rest_angle + torque / k_s
                          : (torque > 0.0 ? d.stops.max_angle + 1.0 : d.stops.min_angle - 1.0);
    const double stop = eq > d.stops.max_angle   ? d.stops.max_angle
                        : eq < d.stops.min_angle ? d.stops.min_angle
                                                 : std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(stop) || (k_s == 0.0 && torque == 0.0) || !(rates.inertia[k] > 0.0)) {
      continue;
    }
    const double press =
        (k_s > 0.0 ? k_s * std::abs(stop - eq) : std::abs(torque)) / rates.inertia[k];
    const double travel = std::max(std::abs(stop - theta0), kRattleGap);
    const double flights = T / (2.0 * std::sqrt(2.0 * travel / press));
    n += std::min(Bounces(d.stops.restitution), std::max(flights, 1.0));
  }
  return n;
}

/// The time the free hinges move [s]: the union over the free hinges of [release, release
/// + MovingTime]; after-latch releases wait for the estimate.
double FreeTime(const schedule::Profile& profile, const HingeRates& rates) {
  const double t0 = profile.t_begin(), t1 = profile.t_end();
  const std::size_t n = profile.hinges.size();
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<double> begin(n, inf), end(n, inf);
  // Releases after a latch resolve in at most n passes (the order has no cycle).
  for (std::size_t pass = 0; pass < n; ++pass) {
    for (std::size_t k = 0; k < n; ++k) {
      const schedule::HingePlan& h = profile.hinges[k];
      if (h.kind != schedule::HingePlan::Kind::kFree) continue;
      const schedule::Release& r = h.drive.release;
      double b = t0;
      if (r.kind == schedule::Release::Kind::kAtTime) b = std::max(t0, r.time);
      if (r.kind == schedule::Release::Kind::kAfterLatch) {
        b = end[static_cast<std::size_t>(r.panel)] + r.delay;
      }
      begin[k] = std::min(b, t1);
      end[k] = std::min(t1, begin[k] + MovingTime(profile, k, rates.own[k], rates.inertia[k]));
    }
  }
  std::vector<std::pair<double, double>> spans;
  for (std::size_t k = 0; k < n; ++k) {
    if (begin[k] < end[k]) spans.emplace_back(begin[k], end[k]);
  }
  std::sort(spans.begin(), spans.end());
  double total = 0.0, reach = -inf;
  for (const auto& [b, e] : spans) {
    const double from = std::max(b, reach);
    if (e > from) total += e - from;
    reach = std::max(reach, e);
  }
  return total;
}

}  // namespace

namespace {

/// A hinge profile: one "stage" over [start, until]. The hub's rate is bounded as for a
/// geometry-mode move (M over the sum of the parts' smallest moments); each hinge adds what
/// it can turn: a prescribed hinge its moves' rates (a rotor at a held rate: its turns), a
/// free hinge with a spring its natural frequency sqrt(k / I) (I: its panel's smallest moment,
/// a lower bound of its effective inertia), with a constant motor the rate the torque alone
/// would give it by the end, |tau| D / I, with a torque-speed motor its no-load speed.
WorkEstimate EstimateHingeWork(const schedule::Profile& profile) {
  WorkEstimate out;
  const model::Model& model = profile.model;
  if (model.kind != model::ModelKind::kHinged) return out;
  auto smallest_moment = [](const math::Mat3& J) {
    return math::PrincipalDecomposition(J).moments[0];
  };
  math::Vec3 H0 = math::Vec3::Zero();
  double I_parts = smallest_moment(model.hinged.hub.body.inertia_cm);
  for (const model::Panel& pn : model.hinged.panels) I_parts += smallest_moment(pn.body.inertia_cm);
  const model::Configuration& c0 = model.configuration(profile.initial.configuration);
  const math::Mat3 J0 = model::ComputeMassProperties(model.hinged, c0.hinge_angles,
                                                     Eigen::VectorXd::Zero(c0.hinge_angles.size()))
                            .J_B;
  if (profile.initial.H_B) {
    H0 = *profile.initial.H_B;
  } else if (profile.initial.w_NB_B) {
    H0 = J0 * *profile.initial.w_NB_B;
  }
  out.momentum = H0.norm();
  StageWork w;
  w.duration = profile.t_end() - profile.t_begin();
  w.max_rate = out.momentum / I_parts;
  const HingeRates rates = FreeHingeRates(profile, out.momentum / I_parts);
  // A modal group turns its hinges at its stiffest coordinate's rate at most.
  for (double r : rates.group_rate) w.max_rate += r;
  for (std::size_t k = 0; k < profile.hinges.size() && k < model.hinged.panels.size(); ++k) {
    const schedule::HingePlan& h = profile.hinges[k];
    if (rates.group[k] >= 0) continue;
    const double I_k = smallest_moment(model.hinged.panels[k].body.inertia_cm);
    double rate = 0.0;
    if (h.kind == schedule::HingePlan::Kind::kPrescribed) {
      for (const schedule::HingeMove& mv : h.moves) {
        const double d = std::max(mv.t_end - mv.t_begin, 1e-300);
        rate = std::max(rate, mv.kind == schedule::HingeMove::Kind::kRate
                                  ? std::abs(mv.rate)
                                  : 2.0 * std::abs(mv.angle) / d);
      }
    } else if (h.kind == schedule::HingePlan::Kind::kFree && I_k > 0.0) {
      // (A rod's segment has no inertia about its axis and no bound here: its swing is
      // the free hinges' stiffest rate's, in the steps.)
      const schedule::FreeDrive& d = h.drive;
      rate = std::sqrt(d.spring.stiffness / I_k);
      if (d.motor.kind == schedule::Motor::Kind::kConstant) {
        rate += std::abs(d.motor.torque) * w.duration / I_k;
      } else if (d.motor.kind == schedule::Motor::Kind::kTorqueSpeed) {
        rate += std::abs(d.motor.no_load_speed);
      }
    }
    w.max_rate += rate;
  }
  w.turns = w.max_rate * w.duration / math::kTwoPi;
  const integrators::StepperInfo info = MakeStepper(profile.integrator.method)->info();
  if (!info.adaptive && profile.integrator.step > 0.0) {
    w.fixed_steps = std::ceil(w.duration / profile.integrator.step);
  }
  out.finite = std::isfinite(w.turns) && std::isfinite(w.fixed_steps);
  out.turns = w.turns;
  out.fixed_steps = w.fixed_steps;
  out.stages.push_back(w);
  // Steps: the spin over the whole run, the free hinges while they move.
  out.hinge_rate = rates.stiffest;
  out.free_time = FreeTime(profile, rates);
  const double segments = Segments(profile, rates);
  // The shape state's coordinates (a modal group's count as its modes).
  int free_plans = rates.coordinates;
  const bool lie = info.lie_group || IsExact(profile.integrator.method);
  // A Lie-group method resolves H_B's motion in the body: before the release, and once the
  // latching hinges have latched (a deployment can make the spin axis intermediate).
  double spin = w.max_rate;
  if (lie) {
    Eigen::VectorXd latched = c0.hinge_angles;
    for (std::size_t k = 0; k < profile.hinges.size(); ++k) {
      const schedule::HingePlan& h = profile.hinges[k];
      if (h.kind == schedule::HingePlan::Kind::kFree && h.drive.latch.enabled) {
        latched[static_cast<Eigen::Index>(k)] = h.drive.latch.angle;
      }
    }
    const math::Mat3 J1 =
        model::ComputeMassProperties(model.hinged, latched, Eigen::VectorXd::Zero(latched.size()))
            .J_B;
    spin = std::max(BodyFrameRate(J0, H0), BodyFrameRate(J1, H0));
  }
  if (w.fixed_steps > 0.0) {
    out.steps = w.fixed_steps;
  } else {
    const integrators::StepperInfo free_info =
        IsExact(profile.integrator.method)
            ? MakeStepper(NumericalMethodOf(profile.integrator.method))->info()
            : info;
    // While hinges move the faster of the two motions sets the steps.
    out.steps =
        StepsPerRadian(info, profile.integrator.rtol) * spin * (w.duration - out.free_time) +
        StepsPerRadian(free_info, profile.integrator.rtol) * std::max(spin, out.hinge_rate) *
            out.free_time +
        kStepsPerSegment * (1 + 2 * free_plans + segments);
  }
  // A segment's start (its events, the holding torques, the first steps) costs about
  // kSegmentCost steps.
  out.seconds =
      (out.steps + kSegmentCost * segments) * SecondsPerStep(ComputedPanels(profile), free_plans);
  out.finite = out.finite && std::isfinite(out.steps);
  return out;
}

std::atomic<std::uint64_t> estimates{0};

}  // namespace

std::uint64_t WorkEstimateCount() { return estimates.load(); }

WorkEstimate EstimateWork(const schedule::Profile& profile,
                          const schedule::DeploymentSchedule* schedule) {
  ++estimates;
  if (profile.is_hinge_profile()) return EstimateHingeWork(profile);
  WorkEstimate out;
  if (profile.stages.empty()) return out;
  const model::Model& model = profile.model;
  const bool hinged = model.kind == model::ModelKind::kHinged;
  // J_B of a named configuration (hinged: the mass properties at its hinge angles, at rest).
  auto config_J = [&](const std::string& name) -> math::Mat3 {
    const model::Configuration& c = model.configuration(name);
    if (!hinged) return c.J_B;
    return model::ComputeMassProperties(model.hinged, c.hinge_angles,
                                        Eigen::VectorXd::Zero(c.hinge_angles.size()))
        .J_B;
  };
  auto smallest_moment = [](const math::Mat3& J) {
    return math::PrincipalDecomposition(J).moments[0];
  };

  // H_B(t0): given, or J_B(t0) w + h_rel_B(t0) from the schedule (single runs only: a
  // sweep case always has H_B).
  math::Vec3 H0 = math::Vec3::Zero();
  if (profile.initial.H_B) {
    H0 = *profile.initial.H_B;
  } else if (profile.initial.w_NB_B) {
    const dynamics::InertiaSample s0 =
        schedule ? schedule->Evaluate(profile.t_begin())
                 : schedule::DeploymentSchedule(profile).Evaluate(profile.t_begin());
    H0 = s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B;
  }
  const double M = H0.norm();
  out.momentum = M;
  const integrators::StepperInfo info = MakeStepper(profile.integrator.method)->info();
  const bool adaptive = info.adaptive;
  const bool lie = info.lie_group || IsExact(profile.integrator.method);

  // Geometry-mode moves: J_B >= the sum of the parts' own inertias about their CoMs (the
  // parallel-axis terms are positive semi-definite), so its smallest moment is at least
  // the sum of theirs, whatever the hinge angles.
  double parts_bound = -1.0;
  auto parts_smallest = [&] {
    if (parts_bound < 0.0) {
      parts_bound = smallest_moment(model.hinged.hub.body.inertia_cm);
      for (const model::Panel& pn : model.hinged.panels) {
        parts_bound += smallest_moment(pn.body.inertia_cm);
      }
    }
    return parts_bound;
  };

  math::Mat3 J_prev = math::Mat3::Zero();
  std::string prev_name;
  double I_prev = 0.0;
  auto I_of = [&](const std::string& name) {
    if (name != prev_name || prev_name.empty()) {
      J_prev = config_J(name);
      I_prev = smallest_moment(J_prev);
      prev_name = name;
    }
    return I_prev;
  };

  for (std::size_t k = 0; k < profile.stages.size(); ++k) {
    const schedule::Stage& st = profile.stages[k];
    StageWork w;
    w.duration = st.t_end - st.t_begin;
    double lie_rate = -1.0;  // the first hold's: known from its state
    if (st.is_hold()) {
      const double I_min = I_of(st.to);
      if (k == 0) {
        // The initial state is known: the largest |w| on its energy ellipsoid.
        const math::PrincipalAxes pa = math::PrincipalDecomposition(J_prev);
        const math::Vec3 h = pa.axes.transpose() * H0;
        const math::Vec3& I = pa.moments;
        const double two_T = h[0] * h[0] / I[0] + h[1] * h[1] / I[1] + h[2] * h[2] / I[2];
        w.max_rate = std::sqrt(MaxRateSquaredOnEllipsoid(I, h.squaredNorm(), two_T));
        lie_rate = BodyFrameRate(J_prev, H0);
      } else {
        w.max_rate = M / I_min;
      }
    } else {
      // Tensor mode: J_B is a convex combination of the end tensors, and the smallest
      // moment is concave in J_B. The panels' relative momentum h_rel_B turns the hub by
      // about their hinge travel over the stage (a fraction of a turn): left out.
      const double I_min = profile.mode == schedule::Mode::kGeometry && hinged
                               ? parts_smallest()
                               : std::min(I_of(st.from), I_of(st.to));
      w.max_rate = M / I_min;
    }
    w.turns = w.max_rate * w.duration / math::kTwoPi;
    if (!adaptive && profile.integrator.step > 0.0) {
      w.fixed_steps = std::ceil(w.duration / profile.integrator.step);
    }
    const double resolved =
        lie ? (lie_rate >= 0.0 ? lie_rate : kLieRateFraction * w.max_rate) : w.max_rate;
    // `exact` on a hold: the closed form's steps, kExactStepsPerPeriod per period.
    const double per_radian = IsExact(profile.integrator.method) && st.is_hold()
                                  ? kExactStepsPerPeriod / math::kTwoPi
                                  : StepsPerRadian(info, profile.integrator.rtol);
    out.steps +=
        w.fixed_steps > 0.0 ? w.fixed_steps : per_radian * resolved * w.duration + kStepsPerSegment;
    out.finite = out.finite && std::isfinite(w.turns) && std::isfinite(w.fixed_steps);
    out.turns += w.turns;
    out.fixed_steps += w.fixed_steps;
    out.stages.push_back(w);
  }
  const int panels = hinged ? static_cast<int>(model.hinged.panels.size()) : 0;
  out.seconds = out.steps * SecondsPerStep(panels, 0);
  out.finite = out.finite && std::isfinite(out.steps);
  return out;
}

std::string DescribeWork(const WorkEstimate& e) {
  std::string s = "estimated " + Num(e.steps) + " steps";
  if (e.hinge_rate > 0.0) {
    s +=
        " (free hinges up to " + Num(e.hinge_rate) + " rad/s for about " + Num(e.free_time) + " s)";
  }
  return s + ", about " + Num(e.seconds) + " s on one core";
}

void CheckWork(const schedule::Profile& profile, const WorkEstimate& e) {
  if (e.stages.empty()) return;
  const std::string where =
      profile.source.empty() ? "profile '" + profile.name + "'" : profile.source;
  if (!e.finite || !std::isfinite(e.momentum) || !std::isfinite(e.seconds)) {
    // Every number was finite (ValidateProfile), so a product or a square overflowed.
    throw std::invalid_argument(
        where + ": the run's work overflows (|H_B(t0)| = " + Num(e.momentum) + " kg m^2/s, " +
        Num(e.turns) + " turns, " + Num(e.steps) +
        " steps; rule: the initial spin, the inertias and the hinges' parameters must keep "
        "these finite: a value of 1e154 or more overflows when squared)");
  }
  // The stage that asks the most, for the message.
  std::size_t worst = 0;
  for (std::size_t k = 1; k < e.stages.size(); ++k) {
    if (e.stages[k].turns > e.stages[worst].turns) worst = k;
  }
  if (!(e.turns <= kMaxTurns)) {
    const StageWork& w = e.stages[worst];
    const std::string stage = profile.is_hinge_profile()
                                  ? std::string("the run, hub and hinges")
                                  : "stage '" + profile.stages[worst].name + "'";
    throw std::invalid_argument(
        where + ": the run asks for up to " + Num(e.turns) + " turns of the body (" + stage +
        ": |w| up to " + Num(w.max_rate) + " rad/s for " + Num(w.duration) + " s; rule: at most " +
        Num(kMaxTurns) + " turns per run: shorten the stages or lower the spin)");
  }
  if (!(e.fixed_steps <= kMaxFixedSteps)) {
    throw std::invalid_argument(where + ": integrator.step = " + Num(profile.integrator.step) +
                                ": gives " + Num(e.fixed_steps) + " steps over " +
                                Num(profile.t_end() - profile.t_begin()) + " s (rule: at most " +
                                Num(kMaxFixedSteps) + " steps of a fixed-step method per run)");
  }
  if (!(e.seconds <= kMaxRunSeconds)) {
    throw std::invalid_argument(
        where + ": the run is " + DescribeWork(e) + " (rule: at most " + Num(kMaxRunSeconds) +
        " s estimated per run: shorten the run (until), loosen integrator.rtol, soften the "
        "stiffest hinge (its stiffness or damping), or free fewer panels)");
  }
}

}  // namespace deploysim::analysis
