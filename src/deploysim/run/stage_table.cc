#include "deploysim/run/stage_table.h"

#include <stdexcept>
#include <utility>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/run/record_table.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::run {

std::vector<StageRow> StageRows(const MissionResult& r) {
  const schedule::Profile& p = r.profile();
  const bool phases = p.is_hinge_profile();
  std::vector<StageRow> rows;
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    const StageReport& a = r.stages[i];
    StageRow row;
    row.index = static_cast<int>(i);
    row.name = a.name;
    row.law = a.law;
    row.t_begin = a.t_begin;
    row.t_end = a.t_end;
    if (!phases && i < p.stages.size()) {
      // A stage profile's stage as its profile states it (the report's phase is the same).
      const schedule::Stage& s = p.stages[i];
      row.name = s.name;
      row.law = s.is_hold() ? "hold" : schedule::ToString(s.law);
      row.from = s.from;
      row.to = s.to;
      row.t_begin = s.t_begin;
      row.t_end = s.t_end;
    }
    row.rigid = a.rigid;
    row.moments_end = a.moments_end;
    row.spin_axis_role = analysis::ToString(a.spin_axis_end);
    row.regime = a.regime;
    row.one_minus_k2 = a.one_minus_k2;
    row.separatrix_distance = a.separatrix_distance;
    row.predicted_flip_half_period = a.predicted_flip_half_period;
    row.predicted_flip_count = static_cast<long long>(a.predicted_flips.size());
    row.observed_flip_count = static_cast<long long>(a.observed_flips.size());
    row.max_flip_time_difference = a.max_flip_time_difference;
    row.caveat = a.caveat;
    row.rigid_body_only = a.rigid_body_only;
    row.predicted_flips = a.predicted_flips;
    row.observed_flips = a.observed_flips;
    rows.push_back(std::move(row));
  }
  return rows;
}

namespace {

using StageCol = StageColumn;
using StageType = StageColumn::Type;

StageCol MakeStageColumn(std::string name, std::string units, std::string desc, StageType type) {
  StageCol c;
  c.name = std::move(name);
  c.units = std::move(units);
  c.description = std::move(desc);
  c.type = type;
  return c;
}

template <typename T>
StageCol StageNumber(
    T StageRow::*m, std::string name, std::string units, std::string desc, StageType type) {
  StageCol c = MakeStageColumn(std::move(name), std::move(units), std::move(desc), type);
  c.number = [m](const StageRow& row, double* out) { out[0] = static_cast<double>(row.*m); };
  c.set_number = [m](StageRow& row, const double* in) { row.*m = static_cast<T>(in[0]); };
  return c;
}

StageCol StageText(std::string StageRow::*m, std::string name, std::string desc) {
  StageCol c = MakeStageColumn(std::move(name), "none", std::move(desc), StageType::kText);
  c.text = [m](const StageRow& row) { return row.*m; };
  c.set_text = [m](StageRow& row, const std::string& in) { row.*m = in; };
  return c;
}

bool IsProfileStage(const StageRow& row) { return !row.from.empty() || !row.to.empty(); }
bool IsRigidStage(const StageRow& row) { return row.rigid; }

void StageDefinition(std::vector<StageCol>& t) {
  t.push_back(
      StageNumber(&StageRow::index, "index", "1",
                  "position of the stage in the profile (hinge profiles: of the phase), from 0",
                  StageType::kInteger));
  t.push_back(
      StageNumber(&StageRow::t_begin, "t_begin", "s", "stage start time", StageType::kReal));
  t.push_back(StageNumber(&StageRow::t_end, "t_end", "s", "stage end time", StageType::kReal));
  t.push_back(StageText(&StageRow::name, "name",
                        "stage name (hinge profiles: the phase between hinge events, e.g. 'free: "
                        "wing_plus_x, wing_minus_x')"));
  t.push_back(
      StageText(&StageRow::law, "law",
                "interpolation law (hold for a hold; hinge profiles: free, prescribed or hold)"));
  StageCol from =
      StageText(&StageRow::from, "from", "configuration at the stage start (empty for a phase)");
  from.applies = IsProfileStage;
  t.push_back(from);
  StageCol to =
      StageText(&StageRow::to, "to", "configuration at the stage end (empty for a phase)");
  to.applies = IsProfileStage;
  t.push_back(to);
  t.push_back(
      StageNumber(&StageRow::rigid, "rigid", "1",
                  "1 if J_B is constant and h_rel_B = 0 over the stage (closed form applies), "
                  "else 0",
                  StageType::kFlag));
}

void StageAnalysis(std::vector<StageCol>& t) {
  StageCol moments =
      MakeStageColumn("moments_end", "kg m^2",
                      "principal moments of J_B at the stage end, ascending", StageType::kVector3);
  moments.number = [](const StageRow& row, double* out) {
    for (int i = 0; i < 3; ++i) out[i] = row.moments_end[i];
  };
  moments.set_number = [](StageRow& row, const double* in) {
    row.moments_end = math::Vec3(in[0], in[1], in[2]);
  };
  t.push_back(moments);
  t.push_back(
      StageText(&StageRow::spin_axis_role, "spin_axis_role",
                "role of the spin axis in J_B at the stage end: minor, intermediate, major or "
                "degenerate (two equal moments)"));
  StageCol regime =
      StageText(&StageRow::regime, "regime",
                "rigid stages: the closed-form regime of the free body; empty otherwise");
  regime.applies = IsRigidStage;
  t.push_back(regime);
  StageCol k2 =
      StageNumber(&StageRow::one_minus_k2, "one_minus_k2", "1",
                  "rigid stages: complementary parameter 1 - k^2 of the closed form (0 on the "
                  "separatrix); 0 otherwise",
                  StageType::kReal);
  k2.applies = IsRigidStage;
  t.push_back(k2);
  t.push_back(StageNumber(&StageRow::separatrix_distance, "separatrix_distance", "1",
                          "(D - I2) / (I3 - I1) at the stage end, D = |H|^2 / (w.J w): 0 on the "
                          "separatrix, < 0 on the minor-axis side",
                          StageType::kReal));
  StageCol half =
      StageNumber(&StageRow::predicted_flip_half_period, "predicted_flip_half_period", "s",
                  "rigid stages with the spin axis intermediate: closed-form time between "
                  "flips; inf otherwise",
                  StageType::kReal);
  half.applies = IsRigidStage;
  t.push_back(half);
}

void StageFlips(std::vector<StageCol>& t) {
  t.push_back(StageNumber(&StageRow::predicted_flip_count, "predicted_flip_count", "1",
                          "closed-form flips within the stage (rigid stages only; 0 otherwise)",
                          StageType::kInteger));
  t.push_back(StageNumber(&StageRow::observed_flip_count, "observed_flip_count", "1",
                          "flips located by the integrator within [t_begin, t_end)",
                          StageType::kInteger));
  t.push_back(
      StageNumber(&StageRow::max_flip_time_difference, "max_flip_time_difference", "s",
                  "max |observed - nearest predicted flip time| within the stage (0 if none)",
                  StageType::kReal));
  StageCol caveat = StageText(&StageRow::caveat, "caveat",
                              "which conclusions of the stage's stability verdict hold only for a "
                              "perfectly rigid body (major-axis rule: with energy dissipation a "
                              "minor-axis spin drifts into a flat spin about the major axis)");
  caveat.since_hinge_outputs = true;
  t.push_back(caveat);
  StageCol only =
      StageNumber(&StageRow::rigid_body_only, "rigid_body_only", "1",
                  "1 if the stage's verdict about the spin axis holds only without energy "
                  "dissipation (a minor-axis or degenerate spin), else 0",
                  StageType::kFlag);
  only.since_hinge_outputs = true;
  t.push_back(only);
}

std::vector<StageCol>& StageColumnsTable() {
  static std::vector<StageCol> table = [] {
    std::vector<StageCol> t;
    StageDefinition(t);
    StageAnalysis(t);
    StageFlips(t);
    return t;
  }();
  return table;
}

}  // namespace

const std::vector<StageColumn>& StageTable::Columns() { return StageColumnsTable(); }

void StageTable::Extend(StageColumn column) {
  AppendColumn(StageColumnsTable(), std::move(column), "StageTable");
}

}  // namespace deploysim::run
