// Sweep results as HDF5 (through io::Hdf5Writer and io::Hdf5Reader: no HDF5 here) and
// CSV (docs/sweeps.md "Results file").

#include "deploysim/sweep/results_file.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/io/atomic_file.h"
#include "deploysim/io/hdf5_reader.h"
#include "deploysim/io/hdf5_writer.h"
#include "deploysim/math/number_format.h"
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

/// An outcome column: its header and how a case's outcome fills it (one entry per
/// column, so that a header and its values cannot drift apart).
struct OutcomeColumn {
  const char* name;
  const char* units;
  std::string description;
  ColumnType type;
  std::function<void(Column&, const CaseOutcome&)> put;
};

template <typename F>
OutcomeColumn Int(const char* name, const char* units, std::string description, F f) {
  return {name, units, std::move(description), ColumnType::kInt,
          [f](Column& c, const CaseOutcome& o) { c.i.push_back(f(o)); }};
}
template <typename F>
OutcomeColumn Real(const char* name, const char* units, std::string description, F f) {
  return {name, units, std::move(description), ColumnType::kDouble,
          [f](Column& c, const CaseOutcome& o) { c.d.push_back(f(o)); }};
}
template <typename F>
OutcomeColumn Text(const char* name, std::string description, F f) {
  return {name, "none", std::move(description), ColumnType::kText,
          [f](Column& c, const CaseOutcome& o) { c.s.push_back(f(o)); }};
}

// The columns every sweep has, up to the deployment's timing.
std::vector<OutcomeColumn> MotionColumns(bool hinges) {
  using O = const CaseOutcome&;
  return {
      Int("flipped", "1", "1 if the body flipped at least once (Dzhanibekov flip), else 0",
          [](O o) -> std::int64_t { return o.flip_count > 0 ? 1 : 0; }),
      Int("flip_count", "1",
          "number of flips: sign changes of H_B along the spin axis while it is the "
          "intermediate principal axis",
          [](O o) -> std::int64_t { return o.flip_count; }),
      Real("first_flip_time", "s", "time of the first flip (NaN: no flip)",
           [](O o) { return o.first_flip_time; }),
      Real("first_flip_after_deploy", "s",
           "first_flip_time - deploy_end_time (NaN: no flip; < 0: during the deployment)",
           [](O o) {
             return o.flip_count > 0 ? o.first_flip_time - o.deploy_end_time : std::nan("");
           }),
      Real("max_spin_axis_angle", "rad",
           "largest angle between the body spin axis and h_N over the run",
           [](O o) { return o.max_spin_axis_angle; }),
      Real("final_spin_axis_angle", "rad", "angle between the body spin axis and h_N at the end",
           [](O o) { return o.final_spin_axis_angle; }),
      Text("final_class",
           "final motion: spin-minor | spin-major | spin-intermediate | tumbling | failed",
           [](O o) { return ToString(o.final_class); }),
      Text("final_axis",
           "body axis (+x ... -z) nearest the final circulation axis, signed along H_B",
           [](O o) {
             return o.final_class == MotionClass::kFailed ? "none" : AxisName(o.final_axis);
           }),
      Text("final_regime", "torque-free regime after the end (FreeBodySolution)",
           [](O o) {
             return o.final_class == MotionClass::kFailed
                        ? "none"
                        : analysis::ToString(static_cast<analysis::Regime>(o.final_regime));
           }),
      Real("final_cone_angle", "rad",
           "largest half-angle of the final momentum cone about its circulation axis",
           [](O o) { return o.final_cone_angle; }),
      Real("final_separatrix_distance", "1",
           "(D - I2) / (I3 - I1) of the torque-free motion after the end (D = M^2 / 2T): < 0 "
           "about the minor axis, > 0 about the major axis, 0 on the separatrix",
           [](O o) { return o.final_separatrix_distance; }),
      Real("predicted_flip_half_period", "s",
           "time between flips of the torque-free motion after the end (closed form; inf: it "
           "will not flip)",
           [](O o) { return o.predicted_flip_half_period; }),
      Int("will_flip", "1",
          "1 if the torque-free motion after the end flips (the spin axis is then the "
          "intermediate axis), whatever the simulated time",
          [](O o) -> std::int64_t { return WillFlip(o) ? 1 : 0; }),
      Real("energy_initial", "J",
           hinges ? "total energy (kinetic + spring) at the start"
                  : "total kinetic energy at the start",
           [](O o) { return o.energy_initial; }),
      Real(
          "energy_final", "J",
          hinges ? "total energy (kinetic + spring) at the end" : "total kinetic energy at the end",
          [](O o) { return o.energy_final; }),
      Real("energy_change", "1", "(energy_final - energy_initial) / energy_initial",
           [](O o) { return (o.energy_final - o.energy_initial) / o.energy_initial; }),
  };
}

// The outcome measured from the motion: the verdict `analyze` prints for the case, in the
// same vocabulary (docs/design.md 2.8).
std::vector<OutcomeColumn> VerdictColumns() {
  using O = const CaseOutcome&;
  return {
      Text("outcome",
           "measured from the motion: incomplete | flipping | flat spin | transition | growing "
           "| decaying | tumbling | bounded",
           [](O o) { return OutcomeName(o); }),
      Real("nutation_rate", "1/s",
           "exponential rate of the final phase's nutation envelope, fitted where the "
           "nutation is small (> 0 growing; NaN: no fit)",
           [](O o) { return o.nutation_rate; }),
      Real("nutation_rate_sigma", "1/s", "standard error of nutation_rate",
           [](O o) { return o.nutation_rate_sigma; }),
      Real("nutation_time_constant", "s", "1 / |nutation_rate|",
           [](O o) { return analysis::TimeConstant(o.nutation_rate); }),
      Real("linear_growth_rate", "1/s",
           "the nutation mode's rate from the linearization of the final phase's steady spin "
           "(> 0 unstable; NaN: no steady spin)",
           [](O o) { return o.linear_growth_rate; }),
      Real("linear_time_constant", "s", "1 / |linear_growth_rate|",
           [](O o) { return analysis::TimeConstant(o.linear_growth_rate); }),
      Real("transition_time", "s",
           "when a transition (e.g. a flat spin) passed 45 deg (NaN: no transition)",
           [](O o) { return o.transition_time; }),
      Real("time_to_tumble", "s",
           "from the final phase's start to the spin axis 45 deg from h_N: measured, else "
           "predicted from linear_growth_rate (inf: the spin does not grow; NaN: unknown)",
           [](O o) { return o.time_to_tumble; }),
      Int("time_to_tumble_measured", "1",
          "1 if time_to_tumble was measured in the run, 0 if predicted",
          [](O o) -> std::int64_t { return o.time_to_tumble_measured; }),
  };
}

// The deployment's timing, the hinge events (hinge profiles) and the integration.
std::vector<OutcomeColumn> RunColumns(bool hinges) {
  using O = const CaseOutcome&;
  std::vector<OutcomeColumn> cols{
      Real("deploy_end_time", "s",
           hinges ? "last lock (latch, jam or rest on a stop) of a released panel (NaN: a "
                    "released panel is still free at the end; start: nothing released)"
                  : "end of the last move stage",
           [](O o) { return o.deploy_end_time; }),
      Real("deploy_duration", "s",
           hinges ? "deploy_end_time - the first release (0: nothing released)"
                  : "total duration of the move stages",
           [](O o) { return o.deploy_duration; }),
      Real("end_time", "s", "end of the case's run", [](O o) { return o.end_time; }),
  };
  if (hinges) {
    cols.push_back(Int("latched_count", "1", "latch events (panels caught by their latch)",
                       [](O o) -> std::int64_t { return o.latched_count; }));
    cols.push_back(Int("all_latched", "1",
                       "1 if every free panel that has a latch in the base profile latched",
                       [](O o) -> std::int64_t { return o.all_latched; }));
    cols.push_back(Real("max_latch_w_jump", "rad/s",
                        "latch shock: largest |hub angular-velocity jump| over the latch, jam, "
                        "stop and rest events",
                        [](O o) { return o.max_latch_w_jump; }));
    cols.push_back(Real("max_latch_impulse", "N m s",
                        "largest |impulse| over the latch, jam, stop and rest events",
                        [](O o) { return o.max_latch_impulse; }));
    cols.push_back(Real("energy_dissipated_events", "J", "energy dissipated by all hinge events",
                        [](O o) { return o.energy_dissipated_events; }));
  }
  cols.push_back(Text("termination", "why the integration stopped",
                      [](O o) { return integrators::ToString(o.termination); }));
  cols.push_back(
      Int("steps", "1", "accepted integrator steps", [](O o) -> std::int64_t { return o.steps; }));
  cols.push_back(Int("rejected", "1", "rejected integrator step attempts",
                     [](O o) -> std::int64_t { return o.rejected; }));
  return cols;
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
  std::vector<OutcomeColumn> outcome_cols = MotionColumns(hinges);
  for (OutcomeColumn& c : VerdictColumns()) outcome_cols.push_back(std::move(c));
  for (OutcomeColumn& c : RunColumns(hinges)) outcome_cols.push_back(std::move(c));
  for (const OutcomeColumn& c : outcome_cols) {
    cols.push_back(Make(c.name, c.units, c.description, "outcome", c.type));
  }
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
    for (std::size_t j = 0; j < outcome_cols.size(); ++j) {
      outcome_cols[j].put(cols[first_outcome + j], outcomes[k]);
    }
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

void WriteContents(io::Hdf5Writer& out,
                   const SweepSpec& spec,
                   const std::vector<Column>& cols,
                   const std::vector<CaseOutcome>& outcomes,
                   const RunInfo& info) {
  std::vector<std::string> names;
  for (const Column& c : cols) {
    WriteColumn(out, "/cases", c);
    names.push_back(c.name);
  }
  Column rt = Make("run_time", "s", "wall time of each case (varies from run to run)", "timing",
                   ColumnType::kDouble);
  for (const CaseOutcome& o : outcomes) rt.d.push_back(o.run_time);
  WriteColumn(out, "/timing", rt);
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

/// Writes the CSV table into the temporary of `out` (complete, not yet committed).
void WriteCsvTemporary(io::AtomicFile& out,
                       const std::string& path,
                       const std::vector<Column>& cols,
                       const std::vector<CaseOutcome>& outcomes) {
  std::string text;
  for (const Column& c : cols) text += c.name + " [" + c.units + "],";
  text += "run_time [s]\n";
  for (std::size_t r = 0; r < outcomes.size(); ++r) {
    for (const Column& c : cols) {
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
      text += ',';
    }
    text += CsvNumber(outcomes[r].run_time) + '\n';
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
  const std::vector<Column> cols = ResultColumns(spec, outcomes);
  io::Hdf5Writer out(path);  // atomic: nothing at `path` unless Commit() succeeds
  WriteContents(out, spec, cols, outcomes, info);
  out.Close();
  std::optional<io::AtomicFile> csv;
  if (!csv_path.empty()) {
    csv.emplace(csv_path);
    WriteCsvTemporary(*csv, csv_path, cols, outcomes);
  }
  const io::SignalsHeld held;  // both files are renamed, or neither
  out.Commit();
  if (csv) csv->Commit();
}

void WriteSweepCsv(const std::string& path,
                   const SweepSpec& spec,
                   const std::vector<CaseOutcome>& outcomes) {
  const std::vector<Column> cols = ResultColumns(spec, outcomes);
  io::AtomicFile out(path);
  WriteCsvTemporary(out, path, cols, outcomes);
  out.Commit();
}

SweepTable ReadSweepResults(const std::string& path) { return ReadContents(path); }

}  // namespace deploysim::sweep
