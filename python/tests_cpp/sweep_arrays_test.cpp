// One field added to the sweep's case outcome table, in one place
// (sweep::CaseOutcomeTable::Extend), is found in every output derived from it: the results
// file (HDF5) and its reader, its CSV, the journal's record read back, and the Python
// package's sweep arrays (python/src/sweep_arrays.h). (A case outcome has no JSON output.)

#include "sweep_arrays.h"

#include <gtest/gtest.h>
#include <pybind11/embed.h>
#include <pybind11/numpy.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "deploysim/math/number_format.h"
#include "deploysim/sweep/case_outcome_table.h"
#include "deploysim/sweep/journal.h"
#include "deploysim/sweep/results_file.h"
#include "deploysim/sweep/runner.h"
#include "deploysim/sweep/sweep_file.h"

namespace {

namespace py = pybind11;
using deploysim::sweep::CaseOutcome;
using deploysim::sweep::CaseOutcomeField;
using deploysim::sweep::CaseOutcomeTable;

/// The added field: the energy at the end over the energy at the start [1].
double Ratio(const CaseOutcome& o) { return o.energy_final / o.energy_initial; }

/// The added field's values as the journal reads them back, in the order read.
std::vector<double>& ReadBack() {
  static std::vector<double> values;
  return values;
}

class CaseOutcomeColumnsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    standard_record_size_ = deploysim::sweep::JournalRecordSize();
    CaseOutcomeField f;
    f.name = "energy_ratio";
    f.units = "1";
    f.description = "energy_final / energy_initial";
    f.real = Ratio;
    f.record.slot = static_cast<int>(CaseOutcomeTable::RecordFields().size());
    f.record.size = sizeof(double);
    f.record.put = [](const CaseOutcome& o, char* out) {
      const double r = Ratio(o);
      std::memcpy(out, &r, sizeof(r));
    };
    f.record.get = [](const char* in, CaseOutcome&) {
      double r;
      std::memcpy(&r, in, sizeof(r));
      ReadBack().push_back(r);
    };
    CaseOutcomeTable::Extend(f);
  }
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("deploysim_case_outcome_columns_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    // Two cases of the spring-driven wings: the hinge columns beside the added one.
    const std::string sweep = Path("s.yaml");
    std::ofstream(sweep) << "name: t\nbase: " << DEPLOYSIM_SOURCE_DIR
                         << "/deployment_profiles/smallsat_spring_deploy.yaml\n"
                            "grid:\n  - {parameter: spring_stiffness, values: [0.2, 2]}\n";
    spec_ = deploysim::sweep::LoadSweep(sweep);
    for (std::size_t i = 0; i < spec_.case_count(); ++i) {
      outcomes_.push_back(deploysim::sweep::SimulateCase(spec_, i));
    }
    ASSERT_EQ(outcomes_.size(), 2u);
    ASSERT_NE(Ratio(outcomes_[0]), Ratio(outcomes_[1]));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  static std::size_t standard_record_size_;
  std::filesystem::path dir_;
  deploysim::sweep::SweepSpec spec_;
  std::vector<CaseOutcome> outcomes_;
};

std::size_t CaseOutcomeColumnsTest::standard_record_size_ = 0;

TEST_F(CaseOutcomeColumnsTest, AnAddedFieldIsInTheResultsFile) {
  const std::string path = Path("r.h5");
  deploysim::sweep::WriteSweepResults(path, spec_, outcomes_, {});
  const deploysim::sweep::SweepTable t = deploysim::sweep::ReadSweepResults(path);
  ASSERT_EQ(t.columns.back(), "energy_ratio");  // after the standard columns
  EXPECT_EQ(t.columns[t.columns.size() - 2], "rejected");
  EXPECT_EQ(t.units.at("energy_ratio"), "1");
  const std::vector<double>& ratio = t.numbers.at("energy_ratio");
  ASSERT_EQ(ratio.size(), outcomes_.size());
  for (std::size_t i = 0; i < outcomes_.size(); ++i) {
    EXPECT_EQ(ratio[i], Ratio(outcomes_[i]));
    // The standard columns beside it, and the run time apart in /timing.
    EXPECT_EQ(t.numbers.at("max_latch_w_jump")[i], outcomes_[i].max_latch_w_jump);
    EXPECT_EQ(t.run_time[i], outcomes_[i].run_time);
  }
}

TEST_F(CaseOutcomeColumnsTest, AnAddedFieldIsInTheCsv) {
  const std::string path = Path("r.csv");
  deploysim::sweep::WriteSweepCsv(path, spec_, outcomes_);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_NE(line.find(",rejected [1],energy_ratio [1],run_time [s]"), std::string::npos) << line;
  for (const CaseOutcome& o : outcomes_) {
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_NE(line.find("," + deploysim::math::FormatNumber(Ratio(o)) + "," +
                        deploysim::math::FormatNumber(o.run_time)),
              std::string::npos)
        << line;
  }
}

TEST_F(CaseOutcomeColumnsTest, AnAddedFieldIsStoredInTheJournal) {
  EXPECT_EQ(deploysim::sweep::JournalRecordSize(), standard_record_size_ + sizeof(double));
  const std::string path = Path("r.h5.partial");
  const std::uint64_t fingerprint = deploysim::sweep::Fingerprint(spec_);
  {
    deploysim::sweep::JournalWriter w(path, fingerprint, outcomes_.size());
    for (std::size_t i = outcomes_.size(); i-- > 0;) w.Append(i, outcomes_[i]);
  }
  ReadBack().clear();
  const deploysim::sweep::JournalContents j =
      deploysim::sweep::ReadJournal(path, fingerprint, outcomes_.size());
  ASSERT_EQ(j.records.size(), outcomes_.size());
  EXPECT_FALSE(j.torn_tail);
  ASSERT_EQ(ReadBack().size(), outcomes_.size());
  for (std::size_t k = 0; k < j.records.size(); ++k) {
    const auto& [index, o] = j.records[k];
    EXPECT_EQ(ReadBack()[k], Ratio(outcomes_[index]));
    // The standard fields read back beside it, the last one (run_time) included.
    EXPECT_EQ(o.max_latch_w_jump, outcomes_[index].max_latch_w_jump);
    EXPECT_EQ(o.termination, outcomes_[index].termination);
    EXPECT_EQ(o.run_time, outcomes_[index].run_time);
  }
}

void ExpectTheAddedFieldInTheArrays(const deploysim::sweep::SweepSpec& spec,
                                    const std::vector<CaseOutcome>& outcomes) {
  const py::dict d = deploysim::python::SweepArrays(spec, outcomes);
  const py::dict columns = d["columns"];
  ASSERT_TRUE(columns.contains("energy_ratio"));
  const auto ratio = columns["energy_ratio"].cast<py::array_t<double>>();
  ASSERT_EQ(static_cast<std::size_t>(ratio.shape(0)), outcomes.size());
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    EXPECT_EQ(ratio.at(static_cast<py::ssize_t>(i)), Ratio(outcomes[i]));
  }
  EXPECT_EQ(d["units"]["energy_ratio"].cast<std::string>(), "1");
  EXPECT_EQ(d["roles"]["energy_ratio"].cast<std::string>(), "outcome");
  EXPECT_EQ(d["descriptions"]["energy_ratio"].cast<std::string>(), "energy_final / energy_initial");
  const py::list names(columns.attr("keys")());
  EXPECT_EQ(names[py::len(names) - 1].cast<std::string>(), "energy_ratio");
  EXPECT_EQ(d["run_time"].cast<py::array_t<double>>().size(), 2);
}

TEST_F(CaseOutcomeColumnsTest, AnAddedFieldIsInThePythonArrays) {
  const py::scoped_interpreter python;
  // A Python error is reported while the interpreter lives: its release needs it.
  try {
    ExpectTheAddedFieldInTheArrays(spec_, outcomes_);
  } catch (const py::error_already_set& e) {
    FAIL() << e.what();
  }
}

}  // namespace
