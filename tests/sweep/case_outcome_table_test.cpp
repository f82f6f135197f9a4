// The case outcome's table (sweep/case_outcome_table.h): the journal record it gives keeps
// its byte layout (journals written before the table read back), the results file's
// columns keep their order, and the table refuses fields that would break either.

#include "deploysim/sweep/case_outcome_table.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/sweep/journal.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using Place = CaseOutcomeField::Place;

/// An outcome whose fields all differ from each other and from their defaults, so that a
/// field moved, dropped or read into another shows.
CaseOutcome DistinctOutcome() {
  CaseOutcome o;
  o.termination = integrators::Termination::kStepSizeUnderflow;
  o.flip_count = 3;
  o.first_flip_time = 1.5;
  o.max_spin_axis_angle = 2.5;
  o.final_spin_axis_angle = 3.5;
  o.final_class = MotionClass::kTumbling;
  o.final_axis = 4;
  o.final_regime = 5;
  o.final_cone_angle = 4.5;
  o.energy_initial = 5.5;
  o.energy_final = 6.5;
  o.deploy_end_time = 7.5;
  o.deploy_duration = 8.5;
  o.end_time = 9.5;
  o.steps = 1001;
  o.rejected = 17;
  o.final_separatrix_distance = -0.25;
  o.predicted_flip_half_period = 10.5;
  o.latched_count = 2;
  o.all_latched = 1;
  o.max_latch_w_jump = 0.125;
  o.max_latch_impulse = 0.375;
  o.energy_dissipated_events = 11.5;
  o.outcome_class = 6;
  o.outcome_role_phase = 2;
  o.outcome_role_end = 3;
  o.outcome_phase_begin = 12.5;
  o.nutation_rate = 0.0625;
  o.nutation_rate_sigma = 0.03125;
  o.linear_growth_rate = -0.5;
  o.transition_time = 13.5;
  o.time_to_tumble = 14.5;
  o.time_to_tumble_measured = 7;
  o.run_time = 15.5;
  return o;
}

template <typename T>
void Append(std::vector<char>& bytes, const T& v) {
  const auto* p = reinterpret_cast<const char*>(&v);
  bytes.insert(bytes.end(), p, p + sizeof(T));
}

/// The payload of a journal record as journals of layout version 3 hold it, written out by
/// hand: the reference the table's record must match byte for byte.
std::vector<char> Version3Payload(const CaseOutcome& o) {
  std::vector<char> b;
  Append(b, static_cast<std::int32_t>(o.termination));
  Append(b, o.flip_count);
  for (double x : {o.first_flip_time, o.max_spin_axis_angle, o.final_spin_axis_angle}) {
    Append(b, x);
  }
  Append(b, static_cast<std::int32_t>(o.final_class));
  Append(b, o.final_axis);
  Append(b, o.final_regime);
  for (double x : {o.final_cone_angle, o.energy_initial, o.energy_final, o.deploy_end_time,
                   o.deploy_duration, o.end_time}) {
    Append(b, x);
  }
  Append(b, o.steps);
  Append(b, o.rejected);
  Append(b, o.final_separatrix_distance);
  Append(b, o.predicted_flip_half_period);
  Append(b, o.latched_count);
  Append(b, o.all_latched);
  for (double x : {o.max_latch_w_jump, o.max_latch_impulse, o.energy_dissipated_events}) {
    Append(b, x);
  }
  for (std::int32_t x : {o.outcome_class, o.outcome_role_phase, o.outcome_role_end}) Append(b, x);
  for (double x : {o.outcome_phase_begin, o.nutation_rate, o.nutation_rate_sigma,
                   o.linear_growth_rate, o.transition_time, o.time_to_tumble}) {
    Append(b, x);
  }
  Append(b, o.time_to_tumble_measured);
  Append(b, o.run_time);
  return b;
}

TEST(CaseOutcomeTable, TheJournalRecordKeepsItsLayout) {
  const CaseOutcome o = DistinctOutcome();
  const std::vector<char> payload = Version3Payload(o);
  ASSERT_EQ(payload.size(), 236u);
  EXPECT_EQ(CaseOutcomeTable::RecordPayloadSize(), payload.size());
  EXPECT_EQ(JournalRecordSize(), 8 + payload.size() + 8);  // index, payload, checksum
  const std::vector<char> record = EncodeRecords({{7, o}});
  ASSERT_EQ(record.size(), JournalRecordSize());
  std::uint64_t index = 0;
  std::memcpy(&index, record.data(), sizeof(index));
  EXPECT_EQ(index, 7u);
  EXPECT_EQ(std::vector<char>(record.begin() + 8, record.end() - 8), payload);
}

TEST(CaseOutcomeTable, EveryStoredFieldReadsBackFromTheJournal) {
  const CaseOutcome o = DistinctOutcome();
  const std::vector<CaseRecord> back = DecodeRecords(EncodeRecords({{2, o}, {5, CaseOutcome{}}}));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].first, 2u);
  EXPECT_EQ(Version3Payload(back[0].second), Version3Payload(o));
  EXPECT_EQ(back[1].first, 5u);
  EXPECT_EQ(Version3Payload(back[1].second), Version3Payload(CaseOutcome{}));
}

TEST(CaseOutcomeTable, RecordSlotsAreTakenInOrder) {
  const std::vector<const CaseOutcomeField*>& record = CaseOutcomeTable::RecordFields();
  ASSERT_EQ(record.size(), 34u);
  for (std::size_t i = 0; i < record.size(); ++i) {
    EXPECT_EQ(record[i]->record.slot, static_cast<int>(i)) << record[i]->name;
  }
  EXPECT_EQ(record.front()->name, "termination");
  EXPECT_EQ(record.back()->name, "run_time");
}

std::vector<std::string> Names(const std::vector<const CaseOutcomeField*>& fields) {
  std::vector<std::string> names;
  for (const CaseOutcomeField* f : fields) names.push_back(f->name);
  return names;
}

TEST(CaseOutcomeTable, ResultsColumnsKeepTheirOrder) {
  const std::vector<std::string> motion = {"flipped",
                                           "flip_count",
                                           "first_flip_time",
                                           "first_flip_after_deploy",
                                           "max_spin_axis_angle",
                                           "final_spin_axis_angle",
                                           "final_class",
                                           "final_axis",
                                           "final_regime",
                                           "final_cone_angle",
                                           "final_separatrix_distance",
                                           "predicted_flip_half_period",
                                           "will_flip",
                                           "energy_initial",
                                           "energy_final",
                                           "energy_change",
                                           "outcome",
                                           "nutation_rate",
                                           "nutation_rate_sigma",
                                           "nutation_time_constant",
                                           "linear_growth_rate",
                                           "linear_time_constant",
                                           "transition_time",
                                           "time_to_tumble",
                                           "time_to_tumble_measured",
                                           "deploy_end_time",
                                           "deploy_duration",
                                           "end_time"};
  const std::vector<std::string> hinge = {"latched_count", "all_latched", "max_latch_w_jump",
                                          "max_latch_impulse", "energy_dissipated_events"};
  const std::vector<std::string> run = {"termination", "steps", "rejected"};
  std::vector<std::string> stages = motion, hinges = motion;
  stages.insert(stages.end(), run.begin(), run.end());
  hinges.insert(hinges.end(), hinge.begin(), hinge.end());
  hinges.insert(hinges.end(), run.begin(), run.end());
  EXPECT_EQ(Names(CaseOutcomeTable::Of(Place::kCases, false)), stages);
  EXPECT_EQ(Names(CaseOutcomeTable::Of(Place::kCases, true)), hinges);
  EXPECT_EQ(Names(CaseOutcomeTable::Of(Place::kTiming, false)),
            std::vector<std::string>{"run_time"});
}

const CaseOutcomeField& Field(const std::string& name) {
  for (const CaseOutcomeField& f : CaseOutcomeTable::Fields()) {
    if (f.name == name) return f;
  }
  throw std::out_of_range(name);
}

TEST(CaseOutcomeTable, ValuesAndDescriptionsFollowTheField) {
  const CaseOutcome o = DistinctOutcome();
  EXPECT_EQ(Field("flipped").integer(o), 1);
  EXPECT_EQ(Field("first_flip_after_deploy").real(o), 1.5 - 7.5);
  EXPECT_EQ(Field("final_class").text(o), "tumbling");
  EXPECT_EQ(Field("final_class").units, "none");
  EXPECT_EQ(Field("termination").text(o), integrators::ToString(o.termination));
  EXPECT_EQ(Field("energy_change").real(o), (6.5 - 5.5) / 5.5);
  EXPECT_EQ(Field("time_to_tumble_measured").integer(o), 7);
  EXPECT_EQ(Field("max_latch_impulse").units, "N m s");
  EXPECT_TRUE(Field("max_latch_impulse").hinge_only);
  const CaseOutcomeField& energy = Field("energy_initial");
  EXPECT_EQ(energy.DescriptionFor(false), "total kinetic energy at the start");
  EXPECT_EQ(energy.DescriptionFor(true), "total energy (kinetic + spring) at the start");
  EXPECT_EQ(Field("end_time").DescriptionFor(true), Field("end_time").DescriptionFor(false));
}

TEST(CaseOutcomeTable, ExtendRefusesFieldsThatBreakTheOutputs) {
  const std::size_t fields = CaseOutcomeTable::Fields().size();
  CaseOutcomeField repeated = Field("flip_count");
  EXPECT_THROW(CaseOutcomeTable::Extend(repeated), std::logic_error);
  CaseOutcomeField f;
  f.name = "spin_ratio";
  f.units = "1";
  EXPECT_THROW(CaseOutcomeTable::Extend(f), std::logic_error);  // no value
  f.real = [](const CaseOutcome& o) { return o.final_spin_axis_angle / o.max_spin_axis_angle; };
  f.place = Place::kRecord;
  EXPECT_THROW(CaseOutcomeTable::Extend(f), std::logic_error);  // record-only, not stored
  f.place = Place::kCases;
  f.record = Field("end_time").record;  // a slot that is taken
  EXPECT_THROW(CaseOutcomeTable::Extend(f), std::logic_error);
  f.record.slot = 40;  // a gap in the record
  EXPECT_THROW(CaseOutcomeTable::Extend(f), std::logic_error);
  EXPECT_EQ(CaseOutcomeTable::Fields().size(), fields);
  EXPECT_EQ(CaseOutcomeTable::RecordFields().size(), 34u);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
