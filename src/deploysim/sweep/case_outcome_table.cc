#include "deploysim/sweep/case_outcome_table.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/motion_outcome.h"

namespace deploysim::sweep {

const std::string& CaseOutcomeField::DescriptionFor(bool hinges) const {
  return hinges && !hinge_description.empty() ? hinge_description : description;
}

namespace {

using Field = CaseOutcomeField;
using Type = CaseOutcomeField::Type;
using Place = CaseOutcomeField::Place;
using O = const CaseOutcome&;

Field Make(std::string name, std::string units, std::string description, Type type) {
  Field f;
  f.name = std::move(name);
  f.units = std::move(units);
  f.description = std::move(description);
  f.type = type;
  return f;
}

/// Member m at `slot` of the record, its bytes as they are in memory.
template <typename T>
CaseFieldRecord Bytes(T CaseOutcome::*m, int slot) {
  CaseFieldRecord r;
  r.slot = slot;
  r.size = sizeof(T);
  r.put = [m](O o, char* out) { std::memcpy(out, &(o.*m), sizeof(T)); };
  r.get = [m](const char* in, CaseOutcome& o) { std::memcpy(&(o.*m), in, sizeof(T)); };
  return r;
}

/// An enumeration at `slot` of the record, as its int32 value.
template <typename E>
CaseFieldRecord EnumBytes(E CaseOutcome::*m, int slot) {
  CaseFieldRecord r;
  r.slot = slot;
  r.size = sizeof(std::int32_t);
  r.put = [m](O o, char* out) {
    const auto v = static_cast<std::int32_t>(o.*m);
    std::memcpy(out, &v, sizeof(v));
  };
  r.get = [m](const char* in, CaseOutcome& o) {
    std::int32_t v;
    std::memcpy(&v, in, sizeof(v));
    o.*m = static_cast<E>(v);
  };
  return r;
}

/// A real column stored in member m at `slot` of the record.
Field Real(double CaseOutcome::*m, int slot, std::string name, std::string units, std::string d) {
  Field f = Make(std::move(name), std::move(units), std::move(d), Type::kReal);
  f.real = [m](O o) { return o.*m; };
  f.record = Bytes(m, slot);
  return f;
}

/// An integer column stored in member m (int64 or int32) at `slot` of the record.
template <typename T>
Field Integer(T CaseOutcome::*m, int slot, std::string name, std::string d) {
  Field f = Make(std::move(name), "1", std::move(d), Type::kInteger);
  f.integer = [m](O o) { return static_cast<std::int64_t>(o.*m); };
  f.record = Bytes(m, slot);
  return f;
}

/// A real column computed from the stored fields.
Field DerivedReal(std::string name,
                  std::string units,
                  std::string d,
                  std::function<double(O)> value) {
  Field f = Make(std::move(name), std::move(units), std::move(d), Type::kReal);
  f.real = std::move(value);
  return f;
}

/// An integer column (a count or a flag) computed from the stored fields.
Field DerivedInteger(std::string name, std::string d, std::function<std::int64_t(O)> value) {
  Field f = Make(std::move(name), "1", std::move(d), Type::kInteger);
  f.integer = std::move(value);
  return f;
}

/// A text column; `record`: the field it is made from, when it is that field's only column.
Field Text(std::string name,
           std::string d,
           std::function<std::string(O)> value,
           CaseFieldRecord record = {}) {
  Field f = Make(std::move(name), "none", std::move(d), Type::kText);
  f.text = std::move(value);
  f.record = std::move(record);
  return f;
}

/// A stored field that is no column of its own (`place`: kRecord or kTiming).
Field Placed(Field f, Place place) {
  f.place = place;
  return f;
}

Field HingeOnly(Field f) {
  f.hinge_only = true;
  return f;
}

Field ForHinges(Field f, std::string hinge_description) {
  f.hinge_description = std::move(hinge_description);
  return f;
}

// The flips, and the spin axis's angle from h_N.
std::vector<Field> FlipFields() {
  return {
      DerivedInteger("flipped", "1 if the body flipped at least once (Dzhanibekov flip), else 0",
                     [](O o) -> std::int64_t { return o.flip_count > 0 ? 1 : 0; }),
      Integer(&CaseOutcome::flip_count, 1, "flip_count",
              "number of flips: sign changes of H_B along the spin axis while it is the "
              "intermediate principal axis"),
      Real(&CaseOutcome::first_flip_time, 2, "first_flip_time", "s",
           "time of the first flip (NaN: no flip)"),
      DerivedReal("first_flip_after_deploy", "s",
                  "first_flip_time - deploy_end_time (NaN: no flip; < 0: during the deployment)",
                  [](O o) {
                    return o.flip_count > 0 ? o.first_flip_time - o.deploy_end_time : std::nan("");
                  }),
      Real(&CaseOutcome::max_spin_axis_angle, 3, "max_spin_axis_angle", "rad",
           "largest angle between the body spin axis and h_N over the run"),
      Real(&CaseOutcome::final_spin_axis_angle, 4, "final_spin_axis_angle", "rad",
           "angle between the body spin axis and h_N at the end"),
  };
}

// The torque-free motion after the end.
std::vector<Field> FinalFields() {
  return {
      Text(
          "final_class",
          "final motion: spin-minor | spin-major | spin-intermediate | tumbling | failed",
          [](O o) { return ToString(o.final_class); }, EnumBytes(&CaseOutcome::final_class, 5)),
      Text(
          "final_axis",
          "body axis (+x ... -z) nearest the final circulation axis, signed along H_B",
          [](O o) {
            return o.final_class == MotionClass::kFailed ? "none" : AxisName(o.final_axis);
          },
          Bytes(&CaseOutcome::final_axis, 6)),
      Text(
          "final_regime", "torque-free regime after the end (FreeBodySolution)",
          [](O o) {
            return o.final_class == MotionClass::kFailed
                       ? "none"
                       : analysis::ToString(static_cast<analysis::Regime>(o.final_regime));
          },
          Bytes(&CaseOutcome::final_regime, 7)),
      Real(&CaseOutcome::final_cone_angle, 8, "final_cone_angle", "rad",
           "largest half-angle of the final momentum cone about its circulation axis"),
      Real(&CaseOutcome::final_separatrix_distance, 16, "final_separatrix_distance", "1",
           "(D - I2) / (I3 - I1) of the torque-free motion after the end (D = M^2 / 2T): < 0 "
           "about the minor axis, > 0 about the major axis, 0 on the separatrix"),
      Real(&CaseOutcome::predicted_flip_half_period, 17, "predicted_flip_half_period", "s",
           "time between flips of the torque-free motion after the end (closed form; inf: it "
           "will not flip)"),
      DerivedInteger("will_flip",
                     "1 if the torque-free motion after the end flips (the spin axis is then the "
                     "intermediate axis), whatever the simulated time",
                     [](O o) -> std::int64_t { return WillFlip(o) ? 1 : 0; }),
  };
}

// The energies (with the springs' for hinge profiles).
std::vector<Field> EnergyFields() {
  return {
      ForHinges(Real(&CaseOutcome::energy_initial, 9, "energy_initial", "J",
                     "total kinetic energy at the start"),
                "total energy (kinetic + spring) at the start"),
      ForHinges(Real(&CaseOutcome::energy_final, 10, "energy_final", "J",
                     "total kinetic energy at the end"),
                "total energy (kinetic + spring) at the end"),
      DerivedReal("energy_change", "1", "(energy_final - energy_initial) / energy_initial",
                  [](O o) { return (o.energy_final - o.energy_initial) / o.energy_initial; }),
  };
}

// The outcome measured from the motion: the verdict `analyze` prints for the case, in the
// same vocabulary (docs/design.md 2.8), and the fields its name is made from.
std::vector<Field> VerdictFields() {
  return {
      Text("outcome",
           "measured from the motion: incomplete | flipping | flat spin | transition | growing "
           "| decaying | tumbling | bounded",
           [](O o) { return OutcomeName(o); }),
      Placed(Integer(&CaseOutcome::outcome_class, 23, "outcome_class",
                     "analysis::OutcomeClass as an integer (outcome's name)"),
             Place::kRecord),
      Placed(Integer(&CaseOutcome::outcome_role_phase, 24, "outcome_role_phase",
                     "analysis::AxisRole of the spin axis at the final phase's start"),
             Place::kRecord),
      Placed(Integer(&CaseOutcome::outcome_role_end, 25, "outcome_role_end",
                     "analysis::AxisRole of the spin axis at the end"),
             Place::kRecord),
      Placed(Real(&CaseOutcome::outcome_phase_begin, 26, "outcome_phase_begin", "s",
                  "start of the final phase"),
             Place::kRecord),
      Real(&CaseOutcome::nutation_rate, 27, "nutation_rate", "1/s",
           "exponential rate of the final phase's nutation envelope, fitted where the "
           "nutation is small (> 0 growing; NaN: no fit)"),
      Real(&CaseOutcome::nutation_rate_sigma, 28, "nutation_rate_sigma", "1/s",
           "standard error of nutation_rate"),
      DerivedReal("nutation_time_constant", "s", "1 / |nutation_rate|",
                  [](O o) { return analysis::TimeConstant(o.nutation_rate); }),
      Real(&CaseOutcome::linear_growth_rate, 29, "linear_growth_rate", "1/s",
           "the nutation mode's rate from the linearization of the final phase's steady spin "
           "(> 0 unstable; NaN: no steady spin)"),
      DerivedReal("linear_time_constant", "s", "1 / |linear_growth_rate|",
                  [](O o) { return analysis::TimeConstant(o.linear_growth_rate); }),
      Real(&CaseOutcome::transition_time, 30, "transition_time", "s",
           "when a transition (e.g. a flat spin) passed 45 deg (NaN: no transition)"),
      Real(&CaseOutcome::time_to_tumble, 31, "time_to_tumble", "s",
           "from the final phase's start to the spin axis 45 deg from h_N: measured, else "
           "predicted from linear_growth_rate (inf: the spin does not grow; NaN: unknown)"),
      Integer(&CaseOutcome::time_to_tumble_measured, 32, "time_to_tumble_measured",
              "1 if time_to_tumble was measured in the run, 0 if predicted"),
  };
}

// The deployment's timing and the hinge events (hinge profiles).
std::vector<Field> DeploymentFields() {
  return {
      ForHinges(Real(&CaseOutcome::deploy_end_time, 11, "deploy_end_time", "s",
                     "end of the last move stage"),
                "last lock (latch, jam or rest on a stop) of a released panel (NaN: a released "
                "panel is still free at the end; start: nothing released)"),
      ForHinges(Real(&CaseOutcome::deploy_duration, 12, "deploy_duration", "s",
                     "total duration of the move stages"),
                "deploy_end_time - the first release (0: nothing released)"),
      Real(&CaseOutcome::end_time, 13, "end_time", "s", "end of the case's run"),
      HingeOnly(Integer(&CaseOutcome::latched_count, 18, "latched_count",
                        "latch events (panels caught by their latch)")),
      HingeOnly(Integer(&CaseOutcome::all_latched, 19, "all_latched",
                        "1 if every free panel that has a latch in the base profile latched")),
      HingeOnly(Real(&CaseOutcome::max_latch_w_jump, 20, "max_latch_w_jump", "rad/s",
                     "latch shock: largest |hub angular-velocity jump| over the latch, jam, "
                     "stop and rest events")),
      HingeOnly(Real(&CaseOutcome::max_latch_impulse, 21, "max_latch_impulse", "N m s",
                     "largest |impulse| over the latch, jam, stop and rest events")),
      HingeOnly(Real(&CaseOutcome::energy_dissipated_events, 22, "energy_dissipated_events", "J",
                     "energy dissipated by all hinge events")),
  };
}

// The integration, and the case's wall time.
std::vector<Field> RunFields() {
  return {
      Text(
          "termination", "why the integration stopped",
          [](O o) { return integrators::ToString(o.termination); },
          EnumBytes(&CaseOutcome::termination, 0)),
      Integer(&CaseOutcome::steps, 14, "steps", "accepted integrator steps"),
      Integer(&CaseOutcome::rejected, 15, "rejected", "rejected integrator step attempts"),
      Placed(Real(&CaseOutcome::run_time, 33, "run_time", "s",
                  "wall time of each case (varies from run to run)"),
             Place::kTiming),
  };
}

/// The field's value function for its type, and a whole record entry if it is stored;
/// std::logic_error naming what is missing.
void CheckField(const Field& f) {
  const bool value = f.type == Type::kReal      ? static_cast<bool>(f.real)
                     : f.type == Type::kInteger ? static_cast<bool>(f.integer)
                                                : static_cast<bool>(f.text);
  if (f.name.empty()) throw std::logic_error("CaseOutcomeTable: a field without a name");
  if (!value) throw std::logic_error("CaseOutcomeTable: '" + f.name + "' has no value");
  if (f.stored() && (f.record.size == 0 || !f.record.put || !f.record.get)) {
    throw std::logic_error("CaseOutcomeTable: '" + f.name + "' is stored without its bytes");
  }
  if (!f.stored() && f.place == Place::kRecord) {
    throw std::logic_error("CaseOutcomeTable: '" + f.name + "' is record-only but not stored");
  }
}

struct Table {
  std::vector<Field> fields;
  std::vector<const Field*> record;  // the stored fields by slot
  std::size_t payload = 0;

  /// The record's order from the slots: 0, 1, ... each taken once.
  void Index() {
    std::size_t stored = 0;
    for (const Field& f : fields) stored += f.stored() ? 1 : 0;
    record.assign(stored, nullptr);
    payload = 0;
    for (const Field& f : fields) {
      if (!f.stored()) continue;
      const auto slot = static_cast<std::size_t>(f.record.slot);
      if (slot >= stored || record[slot] != nullptr) {
        throw std::logic_error("CaseOutcomeTable: '" + f.name + "' takes record slot " +
                               std::to_string(slot) + ", which is taken or leaves a gap");
      }
      record[slot] = &f;
      payload += f.record.size;
    }
  }
};

Table& TheTable() {
  static Table table = [] {
    Table t;
    for (auto part :
         {FlipFields, FinalFields, EnergyFields, VerdictFields, DeploymentFields, RunFields}) {
      for (Field& f : part()) t.fields.push_back(std::move(f));
    }
    for (const Field& f : t.fields) CheckField(f);
    t.Index();
    return t;
  }();
  return table;
}

}  // namespace

const std::vector<CaseOutcomeField>& CaseOutcomeTable::Fields() { return TheTable().fields; }

const std::vector<const CaseOutcomeField*>& CaseOutcomeTable::RecordFields() {
  return TheTable().record;
}

std::size_t CaseOutcomeTable::RecordPayloadSize() { return TheTable().payload; }

std::vector<const CaseOutcomeField*> CaseOutcomeTable::Of(CaseOutcomeField::Place place,
                                                          bool hinges) {
  std::vector<const CaseOutcomeField*> out;
  for (const Field& f : Fields()) {
    if (f.place == place && f.In(hinges)) out.push_back(&f);
  }
  return out;
}

void CaseOutcomeTable::Extend(CaseOutcomeField field) {
  CheckField(field);
  Table& t = TheTable();
  for (const Field& f : t.fields) {
    if (f.name == field.name) {
      throw std::logic_error("CaseOutcomeTable: a field '" + field.name + "' exists");
    }
  }
  if (field.stored() && static_cast<std::size_t>(field.record.slot) != t.record.size()) {
    throw std::logic_error("CaseOutcomeTable: '" + field.name + "' must take record slot " +
                           std::to_string(t.record.size()) + ", the next one");
  }
  t.fields.push_back(std::move(field));
  t.Index();
}

}  // namespace deploysim::sweep
