#include "deploysim/analysis/work_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::analysis {

namespace {

constexpr double kTwoPi = 6.283185307179586;

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

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) { return math::FormatSignificant(x); }

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
  if (profile.initial.H_B) {
    H0 = *profile.initial.H_B;
  } else if (profile.initial.w_NB_B) {
    const model::Configuration& c = model.configuration(profile.initial.configuration);
    const model::MassProperties mp = model::ComputeMassProperties(
        model.hinged, c.hinge_angles, Eigen::VectorXd::Zero(c.hinge_angles.size()));
    H0 = mp.J_B * *profile.initial.w_NB_B;
  }
  out.momentum = H0.norm();
  StageWork w;
  w.duration = profile.t_end() - profile.t_begin();
  w.max_rate = out.momentum / I_parts;
  for (std::size_t k = 0; k < profile.hinges.size() && k < model.hinged.panels.size(); ++k) {
    const schedule::HingePlan& h = profile.hinges[k];
    const double I_k = smallest_moment(model.hinged.panels[k].body.inertia_cm);
    double rate = 0.0;
    if (h.kind == schedule::HingePlan::Kind::kPrescribed) {
      for (const schedule::HingeMove& mv : h.moves) {
        const double d = std::max(mv.t_end - mv.t_begin, 1e-300);
        rate = std::max(rate, mv.kind == schedule::HingeMove::Kind::kRate
                                  ? std::abs(mv.rate)
                                  : 2.0 * std::abs(mv.angle) / d);
      }
    } else if (h.kind == schedule::HingePlan::Kind::kFree) {
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
  w.turns = w.max_rate * w.duration / kTwoPi;
  const bool adaptive = MakeStepper(profile.integrator.method)->info().adaptive;
  if (!adaptive && profile.integrator.step > 0.0) {
    w.fixed_steps = std::ceil(w.duration / profile.integrator.step);
  }
  out.finite = std::isfinite(w.turns) && std::isfinite(w.fixed_steps);
  out.turns = w.turns;
  out.fixed_steps = w.fixed_steps;
  out.stages.push_back(w);
  return out;
}

}  // namespace

WorkEstimate EstimateWork(const schedule::Profile& profile) {
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
    const schedule::DeploymentSchedule sched(profile);
    const dynamics::InertiaSample s0 = sched.Evaluate(profile.t_begin());
    H0 = s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B;
  }
  const double M = H0.norm();
  out.momentum = M;
  const bool adaptive = MakeStepper(profile.integrator.method)->info().adaptive;

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
    if (st.is_hold()) {
      const double I_min = I_of(st.to);
      if (k == 0) {
        // The initial state is known: the largest |w| on its energy ellipsoid.
        const math::PrincipalAxes pa = math::PrincipalDecomposition(J_prev);
        const math::Vec3 h = pa.axes.transpose() * H0;
        const math::Vec3& I = pa.moments;
        const double two_T = h[0] * h[0] / I[0] + h[1] * h[1] / I[1] + h[2] * h[2] / I[2];
        w.max_rate = std::sqrt(MaxRateSquaredOnEllipsoid(I, h.squaredNorm(), two_T));
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
    w.turns = w.max_rate * w.duration / kTwoPi;
    if (!adaptive && profile.integrator.step > 0.0) {
      w.fixed_steps = std::ceil(w.duration / profile.integrator.step);
    }
    out.finite = out.finite && std::isfinite(w.turns) && std::isfinite(w.fixed_steps);
    out.turns += w.turns;
    out.fixed_steps += w.fixed_steps;
    out.stages.push_back(w);
  }
  return out;
}

void CheckWork(const schedule::Profile& profile) {
  const WorkEstimate e = EstimateWork(profile);
  if (!e.finite || e.stages.empty()) return;
  const std::string where =
      profile.source.empty() ? "profile '" + profile.name + "'" : profile.source;
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
}

}  // namespace deploysim::analysis
