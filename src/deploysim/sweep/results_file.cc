// Sweep results as HDF5 (through io::Hdf5Writer and io::Hdf5Reader: no HDF5 here) and
// CSV (docs/sweeps.md "Results file").

#include "deploysim/sweep/results_file.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "deploysim/io/atomic_file.h"
#include "deploysim/io/hdf5_reader.h"
#include "deploysim/io/hdf5_writer.h"
#include "deploysim/math/number_format.h"
#include "deploysim/sweep/case_outcome_table.h"
#include "deploysim/version.h"

namespace deploysim::sweep {

namespace {

using math::FormatNumber;

using ColumnType = ResultColumn::Type;
using Column = ResultColumn;

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

Column Make(std::string name,
            std::string units,
            std::string description,
            std::string role,
            ColumnType type) {
  Column c;
  c.name = std::move(name);
  c.units = std::move(units);
  c.description = std::move(description);
  c.role = std::move(role);
  c.type = type;
  return c;
}

}  // namespace

namespace {

ColumnType TypeOf(const CaseOutcomeField& f) {
  switch (f.type) {
    case CaseOutcomeField::Type::kReal:
      return ColumnType::kDouble;
    case CaseOutcomeField::Type::kInteger:
      return ColumnType::kInt;
    case CaseOutcomeField::Type::kText:
      return ColumnType::kText;
  }
  return ColumnType::kDouble;
}

/// The column of field f (`hinges`: a sweep over a hinge profile), without values.
Column Header(const CaseOutcomeField& f, std::string role, bool hinges) {
  return Make(f.name, f.units, f.DescriptionFor(hinges), std::move(role), TypeOf(f));
}

/// Appends the value of field f in outcome o to its column c.
void PutValue(const CaseOutcomeField& f, const CaseOutcome& o, Column& c) {
  switch (c.type) {
    case ColumnType::kDouble:
      c.d.push_back(f.real(o));
      break;
    case ColumnType::kInt:
      c.i.push_back(f.integer(o));
      break;
    case ColumnType::kText:
      c.s.push_back(f.text(o));
      break;
  }
}

}  // namespace

std::vector<ResultColumn> ResultColumns(const SweepSpec& spec,
                                        const std::vector<CaseOutcome>& outcomes) {
  const std::size_t n = spec.case_count();
  if (outcomes.size() != n) {
    throw std::invalid_argument("sweep results: " + std::to_string(outcomes.size()) +
                                " outcomes for " + std::to_string(n) + " cases");
  }
  std::vector<Column> cols;
  cols.push_back(Make("case_index", "1",
                      "case number i (grid point i / samples, sample i % samples)", "index",
                      ColumnType::kInt));
  cols.push_back(Make("grid_index", "1", "grid point, row-major over the grid axes (last fastest)",
                      "index", ColumnType::kInt));
  cols.push_back(
      Make("sample_index", "1", "Monte Carlo sample at the grid point", "index", ColumnType::kInt));
  const std::vector<Target> targets = spec.targets();
  for (const Target& t : targets) {
    cols.push_back(Make(t.column, UnitsOf(t.parameter), t.description, "parameter",
                        IsCategorical(t.parameter) ? ColumnType::kText : ColumnType::kDouble));
  }
  const std::size_t first_outcome = cols.size();
  const bool hinges = spec.base.is_hinge_profile();
  const std::vector<const CaseOutcomeField*> outcome_fields =
      CaseOutcomeTable::Of(CaseOutcomeField::Place::kCases, hinges);
  for (const CaseOutcomeField* f : outcome_fields) cols.push_back(Header(*f, "outcome", hinges));
  for (std::size_t k = 0; k < n; ++k) {
    const CaseParameters p = ParametersOf(spec, k);
    cols[0].i.push_back(static_cast<std::int64_t>(p.index));
    cols[1].i.push_back(static_cast<std::int64_t>(p.grid_index));
    cols[2].i.push_back(static_cast<std::int64_t>(p.sample_index));
    for (std::size_t t = 0; t < targets.size(); ++t) {
      Column& c = cols[3 + t];
      if (c.type == ColumnType::kText) {
        c.s.push_back(CategoriesOf(targets[t].parameter).at(static_cast<std::size_t>(p.values[t])));
      } else {
        c.d.push_back(p.values[t]);
      }
    }
    for (std::size_t j = 0; j < outcome_fields.size(); ++j) {
      PutValue(*outcome_fields[j], outcomes[k], cols[first_outcome + j]);
    }
  }
  return cols;
}

std::vector<ResultColumn> TimingColumns(const SweepSpec& spec,
                                        const std::vector<CaseOutcome>& outcomes) {
  const bool hinges = spec.base.is_hinge_profile();
  std::vector<Column> cols;
  for (const CaseOutcomeField* f : CaseOutcomeTable::Of(CaseOutcomeField::Place::kTiming, hinges)) {
    cols.push_back(Header(*f, "timing", hinges));
    for (const CaseOutcome& o : outcomes) PutValue(*f, o, cols.back());
  }
  return cols;
}

namespace {

// ---- HDF5 ----

void WriteColumn(io::Hdf5Writer& out, const std::string& group, const Column& c) {
  const std::string path = group + "/" + c.name;
  switch (c.type) {
    case ColumnType::kDouble:
      out.Doubles(path, {c.d.size()}, c.d, c.units, c.description);
      break;
    case ColumnType::kInt:
      out.Integers(path, std::vector<long long>(c.i.begin(), c.i.end()), c.units, c.description);
      break;
    case ColumnType::kText:
      out.Strings(path, c.s, c.description);
      break;
  }
  out.Attribute(path, "role", c.role);
}

std::string IntegratorSettings(const schedule::Profile& p) {
  const schedule::IntegratorSpec& s = p.integrator;
  return "rtol=" + FormatNumber(s.rtol) + ", atol=" + FormatNumber(s.atol) +
         ", step=" + FormatNumber(s.step) + ", max_step=" + FormatNumber(s.max_step);
}

/// `cols`: the /cases columns, then the /timing ones (role `timing`).
void WriteContents(io::Hdf5Writer& out,
                   const SweepSpec& spec,
                   const std::vector<Column>& cols,
                   const RunInfo& info) {
  std::vector<std::string> names;
  for (const Column& c : cols) {
    if (c.role == "timing") {
      WriteColumn(out, "/timing", c);
    } else {
      WriteColumn(out, "/cases", c);
      names.push_back(c.name);
    }
  }
  out.Attribute("/timing", "threads", std::to_string(info.threads));
  out.Attribute("/timing", "ranks", std::to_string(info.ranks));
  out.Attribute("/timing", "wall_seconds", FormatNumber(info.wall_seconds));
  out.Attribute("/timing", "resumed_cases", std::to_string(info.resumed_cases));
  out.Attribute("/timing", "computed_cases", std::to_string(info.computed_cases));

  std::vector<std::string> grid_columns, grid_shape;
  for (const GridAxis& a : spec.grid) {
    grid_columns.push_back(a.target.column);
    grid_shape.push_back(std::to_string(a.values.size()));
  }
  const schedule::Profile& b = spec.base;
  const std::pair<const char*, std::string> root[] = {
      {"deploysim_version", kVersion},
      {"deploysim_build", kBuildId},
      {"schema_version", std::to_string(kResultsSchemaVersion)},
      {"kind", "deploysim sweep results"},
      {"sweep_name", spec.name},
      {"sweep_description", spec.description},
      {"sweep_source", spec.source},
      {"sweep_text", spec.text},
      {"profile_name", b.name},
      {"profile_source", b.source},
      {"profile_text", b.text},
      {"model_name", b.model.name},
      {"integrator", b.integrator.method},
      {"integrator_settings", IntegratorSettings(b)},
      {"case_count", std::to_string(spec.case_count())},
      {"columns", Join(names)},
      {"grid_columns", Join(grid_columns)},
      {"grid_shape", Join(grid_shape)},
      {"monte_carlo_samples", std::to_string(spec.samples())},
      {"monte_carlo_seed", spec.monte_carlo ? std::to_string(spec.monte_carlo->seed) : ""},
      {"tumble_angle", FormatNumber(spec.outcome.tumble_angle)},
      {"latch_shock_limit", spec.outcome.latch_shock_limit
                                ? FormatNumber(*spec.outcome.latch_shock_limit)
                                : std::string()},
  };
  for (const auto& [name, value] : root) out.Attribute("/", name, value);
}

SweepTable ReadContents(const std::string& path) {
  const io::Hdf5Reader file(path);
  SweepTable t;
  t.attributes = file.Attributes("/");
  if (t.attributes["kind"] != "deploysim sweep results" ||
      t.attributes["schema_version"] != std::to_string(kResultsSchemaVersion)) {
    throw std::runtime_error(path + ": not a deploysim sweep results file of schema_version " +
                             std::to_string(kResultsSchemaVersion));
  }
  const std::string& columns = t.attributes["columns"];
  std::size_t start = 0;
  while (start <= columns.size()) {
    const std::size_t comma = std::min(columns.find(',', start), columns.size());
    t.columns.push_back(columns.substr(start, comma - start));
    start = comma + 1;
  }
  for (const std::string& name : t.columns) {
    const std::string dataset = "/cases/" + name;
    if (!file.Exists(dataset)) throw std::runtime_error(path + ": " + dataset + ": missing");
    t.units[name] = file.Attribute(dataset, "units");
    std::size_t rows = 0;
    if (file.KindOf(dataset) == io::Hdf5Reader::Kind::kText) {
      t.texts[name] = file.Strings(dataset);
      rows = t.texts[name].size();
    } else {
      t.numbers[name] = file.Numbers(dataset);
      rows = t.numbers[name].size();
    }
    if (name == t.columns.front()) t.rows = rows;
    if (rows != t.rows) throw std::runtime_error(path + ": " + dataset + ": wrong length");
  }
  t.run_time = file.Numbers("/timing/run_time");
  t.timing = file.Attributes("/timing");
  return t;
}

std::string CsvNumber(double x) { return FormatNumber(x); }

}  // namespace

namespace {

/// The /cases columns, then the /timing ones.
std::vector<Column> AllColumns(const SweepSpec& spec, const std::vector<CaseOutcome>& outcomes) {
  std::vector<Column> cols = ResultColumns(spec, outcomes);
  for (Column& c : TimingColumns(spec, outcomes)) cols.push_back(std::move(c));
  return cols;
}

/// Writes the CSV table of `cols` (`rows` rows) into the temporary of `out` (complete, not
/// yet committed).
void WriteCsvTemporary(io::AtomicFile& out,
                       const std::string& path,
                       const std::vector<Column>& cols,
                       std::size_t rows) {
  std::string text;
  for (const Column& c : cols)
    text += (&c == &cols.front() ? "" : ",") + c.name + " [" + c.units + "]";
  text += '\n';
  for (std::size_t r = 0; r < rows; ++r) {
    for (const Column& c : cols) {
      if (&c != &cols.front()) text += ',';
      switch (c.type) {
        case ColumnType::kDouble:
          text += CsvNumber(c.d[r]);
          break;
        case ColumnType::kInt:
          text += std::to_string(c.i[r]);
          break;
        case ColumnType::kText:
          text += c.s[r];
          break;
      }
    }
    text += '\n';
  }
  std::ofstream f(out.temporary_path());
  out.Reserve(text.size());  // a full disk or the size limit, reported by name
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  f.close();
  if (!f) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  out.ReleaseReserve();
}

}  // namespace

void WriteSweepResults(const std::string& path,
                       const SweepSpec& spec,
                       const std::vector<CaseOutcome>& outcomes,
                       const RunInfo& info) {
  WriteSweepOutputs(path, "", spec, outcomes, info);
}

void WriteSweepOutputs(const std::string& path,
                       const std::string& csv_path,
                       const SweepSpec& spec,
                       const std::vector<CaseOutcome>& outcomes,
                       const RunInfo& info) {
  const std::vector<Column> cols = AllColumns(spec, outcomes);
  io::Hdf5Writer out(path);  // atomic: nothing at `path` unless Commit() succeeds
  WriteContents(out, spec, cols, info);
  out.Close();
  std::optional<io::AtomicFile> csv;
  if (!csv_path.empty()) {
    csv.emplace(csv_path);
    WriteCsvTemporary(*csv, csv_path, cols, outcomes.size());
  }
  const io::SignalsHeld held;  // both files are renamed, or neither
  out.Commit();
  if (csv) csv->Commit();
}

void WriteSweepCsv(const std::string& path,
                   const SweepSpec& spec,
                   const std::vector<CaseOutcome>& outcomes) {
  io::AtomicFile out(path);
  WriteCsvTemporary(out, path, AllColumns(spec, outcomes), outcomes.size());
  out.Commit();
}

SweepTable ReadSweepResults(const std::string& path) { return ReadContents(path); }

}  // namespace deploysim::sweep
