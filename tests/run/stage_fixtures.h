#pragma once

// A tensor-mode stage profile for the run's tests: a body of two shapes, "stowed"
// diag(10, 12, 8) and "deployed" diag(30, 14, 40) kg m^2, the stages the test gives.

#include <string>

#include "deploysim/schedule/profile.h"

namespace deploysim::testing {

inline schedule::Stage MakeStage(const std::string& name,
                                 const std::string& from,
                                 const std::string& to,
                                 schedule::Law law,
                                 double t_begin,
                                 double t_end) {
  schedule::Stage st;
  st.name = name;
  st.from = from;
  st.to = to;
  st.law = law;
  st.t_begin = t_begin;
  st.t_end = t_end;
  return st;
}

/// The two-shape body at rest attitude spinning at w_NB_B, through `stages`.
inline schedule::Profile TwoShapeProfile(const std::string& name,
                                         const math::Vec3& w_NB_B,
                                         std::vector<schedule::Stage> stages) {
  schedule::Profile p;
  p.name = name;
  p.model.name = "two shapes";
  p.model.kind = model::ModelKind::kTensors;
  model::Configuration stowed, deployed;
  stowed.name = "stowed";
  stowed.J_B = math::Vec3(10.0, 12.0, 8.0).asDiagonal();
  deployed.name = "deployed";
  deployed.J_B = math::Vec3(30.0, 14.0, 40.0).asDiagonal();
  p.model.configurations = {stowed, deployed};
  p.mode = schedule::Mode::kTensor;
  p.initial.q_NB = math::Quat::Identity();
  p.initial.w_NB_B = w_NB_B;
  p.stages = std::move(stages);
  p.output.dt = 0.5;
  return p;
}

}  // namespace deploysim::testing
