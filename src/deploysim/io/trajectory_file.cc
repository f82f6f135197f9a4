// HDF5 trajectory files (docs/file_formats.md, "Trajectory files").

#include "deploysim/io/trajectory_file.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/atomic_file.h"
#include "deploysim/io/body_json.h"
#include "deploysim/io/hdf5_common.h"
#include "deploysim/io/hdf5_writer.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/schedule/profile_warnings.h"

#ifndef DEPLOYSIM_VERSION
#define DEPLOYSIM_VERSION "unknown"
#endif

namespace deploysim::io {

namespace {

using math::FormatNumber;
using run::Trajectory;

using hdf5::QuietErrors;
using hdf5::TextType;

/// Number of hinge angles per sample written for r (0: no /hinge_angles dataset).
std::size_t HingeColumns(const run::MissionResult& r) {
  if (r.profile().mode != schedule::Mode::kGeometry) return 0;
  return r.profile().model.hinged.panels.size();
}

/// The analysis of r fits its profile: one report per stage (a hinge profile: one per
/// phase, any number), ordered danger windows, latch times empty or one per panel, hinge
/// events naming panels of the model.
void CheckAnalysis(const std::string& path, const run::MissionResult& r) {
  if (!r.profile().is_hinge_profile() && r.stages.size() != r.profile().stages.size()) {
    throw std::invalid_argument(path + ": " + std::to_string(r.stages.size()) +
                                " stage reports for " + std::to_string(r.profile().stages.size()) +
                                " profile stages (rule: one report per stage)");
  }
  const std::size_t panels = r.profile().model.hinged.panels.size();
  if (!r.latch_times.empty() && r.latch_times.size() != panels) {
    throw std::invalid_argument(path + ": " + std::to_string(r.latch_times.size()) +
                                " latch times for " + std::to_string(panels) +
                                " panels (rule: none, or one per panel)");
  }
  for (const run::HingeEvent& e : r.hinge_events) {
    if (e.panel < 0 || static_cast<std::size_t>(e.panel) >= panels) {
      throw std::invalid_argument(path + ": hinge event at t = " + FormatNumber(e.t) +
                                  ": panel = " + std::to_string(e.panel) + " (rule: in [0, " +
                                  std::to_string(panels) + "))");
    }
  }
  for (const run::DangerWindow& d : r.danger_windows) {
    if (!(d.t_begin <= d.t_end)) {
      throw std::invalid_argument(path + ": danger window [" + FormatNumber(d.t_begin) + ", " +
                                  FormatNumber(d.t_end) + "] (rule: t_begin <= t_end)");
    }
  }
}

std::string IntegratorSettings(const schedule::Profile& p) {
  const schedule::IntegratorSpec& s = p.integrator;
  return "rtol=" + FormatNumber(s.rtol) + ", atol=" + FormatNumber(s.atol) +
         ", step=" + FormatNumber(s.step) + ", max_step=" + FormatNumber(s.max_step) +
         ", output_dt=" + FormatNumber(p.output.dt);
}

std::string StatisticsText(const integrators::Statistics& s) {
  return "steps=" + std::to_string(s.steps) + ", rejected=" + std::to_string(s.rejected) +
         ", evaluations=" + std::to_string(s.evaluations) +
         ", dense_steps=" + std::to_string(s.dense_steps);
}

/// The /stages table: one row per profile stage, its definition and its analysis
/// (run::StageReport; CheckAnalysis ensured one report per stage), or per phase of a hinge
/// profile; one dataset per column of run::StageTable.
void WriteStageTable(Hdf5Writer& w, const run::MissionResult& r) {
  const std::vector<run::StageRow> rows = run::StageRows(r);
  const std::size_t count = rows.size();
  for (const run::StageColumn& c : run::StageTable::Columns()) {
    const std::string path = "/stages/" + c.name;
    if (c.type == run::StageColumn::Type::kText) {
      std::vector<std::string> text;
      for (const run::StageRow& row : rows) text.push_back(c.text(row));
      w.Strings(path, text, c.description);
      continue;
    }
    std::vector<double> v(count * static_cast<std::size_t>(c.width()));
    for (std::size_t i = 0; i < count; ++i) c.number(rows[i], &v[i * c.width()]);
    if (c.type == run::StageColumn::Type::kInteger || c.type == run::StageColumn::Type::kFlag) {
      w.Integers(path, std::vector<long long>(v.begin(), v.end()), c.units, c.description);
    } else if (c.width() == 1) {
      w.Doubles(path, {count}, v, c.units, c.description);
    } else {
      w.Doubles(path, {count, 3}, v, c.units, c.description);
    }
  }
}

/// The hinge event table /events/hinge/* (one row per event, in time order), the latch
/// time of every panel and the model's panel names (geometry mode).
void WriteHingeOutputs(Hdf5Writer& w, const run::MissionResult& r, bool geometry) {
  const std::vector<model::Panel>& panels = r.profile().model.hinged.panels;
  std::vector<std::string> names;
  for (const model::Panel& p : panels) names.push_back(p.name);
  const std::size_t count = r.hinge_events.size();
  // One dataset per column of the table (run::HingeEventTable).
  for (const run::HingeEventColumn& c : run::HingeEventTable::Columns()) {
    const std::string path = "/events/hinge/" + c.name;
    if (c.type == run::HingeEventColumn::Type::kText) {
      std::vector<std::string> text;
      for (const run::HingeEvent& e : r.hinge_events) text.push_back(c.text(e, names));
      w.Strings(path, text, c.description);
      continue;
    }
    std::vector<double> v(count * static_cast<std::size_t>(c.width()));
    for (std::size_t i = 0; i < count; ++i) c.number(r.hinge_events[i], &v[i * c.width()]);
    if (c.type == run::HingeEventColumn::Type::kInteger) {
      w.Integers(path, std::vector<long long>(v.begin(), v.end()), c.units, c.description);
    } else if (c.width() == 1) {
      w.Doubles(path, {count}, v, c.units, c.description);
    } else {
      w.Doubles(path, {count, 3}, v, c.units, c.description);
    }
  }
  w.Doubles("/hinge_latch_time", {r.latch_times.size()}, r.latch_times, "s",
            "per panel, the time it locked (latch, jam or rest on a stop); NaN if it never "
            "did; empty for stage profiles");
  if (geometry) {
    w.Strings("/panel_names", names,
              "names of the model's panels in panel order (the columns of /hinge_angles, "
              "/hinge_rates and the entries of /hinge_latch_time)");
  }
}

/// /danger_windows: the intervals of the output grid in which the spin axis is the
/// intermediate principal axis of J_B(t) (flips possible).
void WriteDangerWindows(Hdf5Writer& w, const run::MissionResult& r) {
  const std::size_t count = r.danger_windows.size();
  for (const run::DangerWindowColumn& c : run::DangerWindowTable::Columns()) {
    std::vector<double> v;
    for (const run::DangerWindow& d : r.danger_windows) v.push_back(c.value(d));
    w.Doubles("/danger_windows/" + c.name, {count}, v, c.units, c.description);
  }
}

/// Column c of the samples of t, flattened row-major (Width values per sample).
std::vector<double> Flat(const run::TrajectoryColumn& c, const Trajectory& t, std::size_t panels) {
  const std::size_t width = run::Width(c, panels);
  std::vector<double> flat(width * t.size());
  if (width == 0) return flat;
  for (std::size_t k = 0; k < t.size(); ++k) c.values(t, k, &flat[k * width]);
  return flat;
}

/// Everything but the per-sample datasets: events, stages, danger windows, attributes.
void WriteAnalysis(Hdf5Writer& w, const run::MissionResult& r, bool geometry) {
  w.Doubles("/events/flip_time", {r.flip_times.size()}, r.flip_times, "s",
            "located flips: sign changes of H_B along the tracked spin axis while it is the "
            "intermediate principal axis (docs/file_formats.md, Flips)");
  std::vector<double> predicted;
  for (const run::StageReport& a : r.stages) {
    predicted.insert(predicted.end(), a.predicted_flips.begin(), a.predicted_flips.end());
  }
  w.Doubles("/events/predicted_flip_time", {predicted.size()}, predicted, "s",
            "closed-form flip times of the rigid stages, in stage order");
  w.Doubles("/events/spin_axis_45_time", {r.spin_axis_45_crossings.size()},
            r.spin_axis_45_crossings, "s",
            "times at which the angle between the initial spin axis (fixed in B) and h_N "
            "crosses 45 degrees, either way, located on the dense output (hinge profiles; "
            "empty for stage profiles)");
  WriteHingeOutputs(w, r, geometry);
  WriteStageTable(w, r);
  WriteDangerWindows(w, r);

  const schedule::Profile& p = r.profile();
  w.Attribute("/", "deploysim_version", DEPLOYSIM_VERSION);
  w.Attribute("/", "schema_version", std::to_string(kTrajectorySchemaVersion));
  w.Attribute("/", "profile_name", p.name);
  w.Attribute("/", "profile_source", p.source);
  w.Attribute("/", "profile_text", p.text);
  w.Attribute("/", "model_name", p.model.name);
  w.Attribute("/", "model_source", p.model.source);
  w.Attribute("/", "model_text", p.model.text);
  w.Attribute("/", "integrator", p.integrator.method);
  w.Attribute("/", "integrator_settings", IntegratorSettings(p));
  w.Attribute("/", "mode", schedule::ToString(p.mode));
  w.Attribute("/", "coupling", schedule::ToString(p.coupling));
  w.Attribute("/", "termination", integrators::ToString(r.termination));
  w.Attribute("/", "termination_message", r.message);
  w.Attribute("/", "statistics", StatisticsText(r.stats));
  w.Attribute("/", "max_h_N_drift", FormatNumber(r.max_h_N_drift));
  if (!r.outcome.headline.empty()) w.Attribute("/", "outcome", analysis::OutcomeJson(r.outcome));
  w.Attribute("/", "warnings", schedule::ProfileWarningsJson(p));
  // The body as the run moved it, appendages expanded (io/body_json.h): readers draw it
  // from here, not from model_text.
  if (p.model.kind == model::ModelKind::kHinged) w.Attribute("/", "body", BodyJson(p.model));
}

// ---- reading ----

/// The dataset `name` of `group` (absolute path `full`), which must exist, hold data of
/// the type class `type` (`what`, for the message) and have a units attribute; records
/// the units under `full`.
H5::DataSet OpenDataset(const std::string& path,
                        const H5::Group& group,
                        const std::string& full,
                        const std::string& name,
                        H5T_class_t type,
                        const char* what,
                        TrajectoryFile& out) {
  if (!group.nameExists(name)) throw std::runtime_error(path + ": " + full + ": missing dataset");
  H5::DataSet ds = group.openDataSet(name);
  if (ds.getTypeClass() != type) {
    throw std::runtime_error(path + ": " + full + ": expected " + what);
  }
  if (!ds.attrExists("units")) {
    throw std::runtime_error(path + ": " + full + ": missing units attribute");
  }
  std::string units;
  const H5::Attribute a = ds.openAttribute("units");
  a.read(a.getStrType(), units);
  out.units[full] = units;
  return ds;
}

/// The dimensions of a dataset.
std::vector<hsize_t> Dims(const H5::DataSet& ds) {
  const H5::DataSpace space = ds.getSpace();
  std::vector<hsize_t> dims(static_cast<std::size_t>(space.getSimpleExtentNdims()));
  space.getSimpleExtentDims(dims.data());
  return dims;
}

/// Reads one dataset of doubles whose shape is {any, trailing...} (a trailing 0: any);
/// returns the data and sets `rows`.
std::vector<double> ReadDoubles(const std::string& path,
                                const H5::Group& group,
                                const std::string& group_path,
                                const std::string& name,
                                const std::vector<hsize_t>& trailing,
                                hsize_t& rows,
                                TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  const H5::DataSet ds =
      OpenDataset(path, group, full, name, H5T_FLOAT, "floating-point data", out);
  const std::vector<hsize_t> dims = Dims(ds);
  bool ok = dims.size() == trailing.size() + 1;
  for (std::size_t i = 0; ok && i < trailing.size(); ++i) {
    ok = trailing[i] == 0 || dims[i + 1] == trailing[i];
  }
  if (!ok) throw std::runtime_error(path + ": " + full + ": unexpected shape");
  std::vector<double> data(static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints()));
  if (!data.empty()) ds.read(data.data(), H5::PredType::NATIVE_DOUBLE);
  rows = dims[0];
  return data;
}

/// Reads a 1-D dataset of integers.
std::vector<long long> ReadIntegers(const std::string& path,
                                    const H5::Group& group,
                                    const std::string& group_path,
                                    const std::string& name,
                                    TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  const H5::DataSet ds = OpenDataset(path, group, full, name, H5T_INTEGER, "integer data", out);
  const std::vector<hsize_t> dims = Dims(ds);
  if (dims.size() != 1) throw std::runtime_error(path + ": " + full + ": unexpected shape");
  std::vector<long long> data(static_cast<std::size_t>(dims[0]));
  if (!data.empty()) ds.read(data.data(), H5::PredType::NATIVE_LLONG);
  return data;
}

/// Reads a 1-D dataset of variable-length strings.
std::vector<std::string> ReadStrings(const std::string& path,
                                     const H5::Group& group,
                                     const std::string& group_path,
                                     const std::string& name,
                                     TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  const H5::DataSet ds =
      OpenDataset(path, group, full, name, H5T_STRING, "variable-length strings", out);
  if (!ds.getStrType().isVariableStr()) {
    throw std::runtime_error(path + ": " + full + ": expected variable-length strings");
  }
  return hdf5::ReadTextValues(ds);
}

H5::Group OpenGroup(const std::string& path, const H5::Group& parent, const std::string& name) {
  if (!parent.nameExists(name)) throw std::runtime_error(path + ": /" + name + ": missing group");
  return parent.openGroup(name);
}

/// The kind named `name` ("latch", ...: analysis::ToString); throws naming the file.
/// The table /events/hinge/* (all columns of one length), column by column of the table
/// (run::HingeEventTable); a column a file predates reads its `missing` value.
void ReadHingeEvents(const std::string& path, const H5::Group& g, TrajectoryFile& out) {
  using Column = run::HingeEventColumn;
  const std::string gp = "/events/hinge";
  hsize_t count = 0;
  ReadDoubles(path, g, gp, "time", {}, count, out);
  std::vector<HingeEventRow> rows(count);
  auto same_length = [&](const std::string& name, std::size_t size) {
    if (size != count) {
      throw std::runtime_error(path + ": " + gp + "/" + name + ": has " + std::to_string(size) +
                               " rows, " + gp + "/time has " + std::to_string(count));
    }
  };
  for (const Column& c : run::HingeEventTable::Columns()) {
    if (!g.nameExists(c.name) && !std::isnan(c.missing)) {
      for (HingeEventRow& row : rows) {
        const double v[3] = {c.missing, c.missing, c.missing};
        if (c.set_number) c.set_number(row.event, v);
      }
      continue;
    }
    if (c.type == Column::Type::kText) {
      const std::vector<std::string> text = ReadStrings(path, g, gp, c.name, out);
      same_length(c.name, text.size());
      for (std::size_t i = 0; i < count; ++i) {
        if (c.name == "panel_name") rows[i].panel_name = text[i];
        if (!c.set_text) continue;
        try {
          c.set_text(rows[i].event, text[i]);
        } catch (const std::invalid_argument& e) {
          throw std::runtime_error(path + ": " + gp + "/" + c.name + ": " + e.what());
        }
      }
      continue;
    }
    std::vector<double> v;
    if (c.type == Column::Type::kInteger) {
      const std::vector<long long> n = ReadIntegers(path, g, gp, c.name, out);
      v.assign(n.begin(), n.end());
    } else {
      hsize_t n = 0;
      v = ReadDoubles(path, g, gp, c.name,
                      c.width() == 1 ? std::vector<hsize_t>{} : std::vector<hsize_t>{3}, n, out);
    }
    same_length(c.name, v.size() / static_cast<std::size_t>(c.width()));
    if (!c.set_number) continue;
    for (std::size_t i = 0; i < count; ++i) c.set_number(rows[i].event, &v[i * c.width()]);
  }
  for (HingeEventRow& row : rows) out.hinge_events.push_back(std::move(row));
}

/// `path` can be opened for reading and holds an HDF5 file.
void CheckReadableHdf5(const std::string& path) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  }
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    throw std::runtime_error(path + ": not an HDF5 file");
  }
}

/// The file's string attributes; its schema_version must be the one this deploysim reads.
void ReadRootAttributes(const std::string& path, const H5::H5File& file, TrajectoryFile& out) {
  for (int i = 0; i < file.getNumAttrs(); ++i) {
    const H5::Attribute a = file.openAttribute(static_cast<unsigned>(i));
    if (a.getTypeClass() != H5T_STRING) continue;
    std::string value;
    a.read(a.getStrType(), value);
    out.attributes[a.getName()] = value;
  }
  const auto version = out.attributes.find("schema_version");
  if (version == out.attributes.end() ||
      version->second != std::to_string(kTrajectorySchemaVersion)) {
    throw std::runtime_error(
        path + ": schema_version = " +
        (version == out.attributes.end() ? std::string("(missing)") : version->second) +
        ": this deploysim reads schema_version " + std::to_string(kTrajectorySchemaVersion));
  }
}

/// The per-sample dataset /<name> of shape {n, trailing...}: one row per output time.
std::vector<double> ReadSampleRows(const std::string& path,
                                   const H5::H5File& file,
                                   const std::string& name,
                                   const std::vector<hsize_t>& trailing,
                                   hsize_t n,
                                   TrajectoryFile& out) {
  hsize_t rows = 0;
  std::vector<double> flat = ReadDoubles(path, file, "", name, trailing, rows, out);
  if (rows != n) {
    throw std::runtime_error(path + ": /" + name + ": has " + std::to_string(rows) +
                             " rows, /time has " + std::to_string(n));
  }
  return flat;
}

/// The first column of `schema` that `pick` selects (null if none).
template <class Pick>
const run::TrajectoryColumn* First(const run::TrajectorySchema& schema, Pick pick) {
  for (const run::TrajectoryColumn& c : schema.columns()) {
    if (pick(c)) return &c;
  }
  return nullptr;
}

/// Which per-sample datasets the file has: the free-hinge outputs come all or none (none
/// in files written before them), the per-panel ones in geometry mode only.
struct SampleLayout {
  bool hinge_outputs = false;
  bool ledger = false;  ///< the energy ledger's columns (none in files written before them)
  const run::TrajectoryColumn* first_per_panel = nullptr;  ///< null: not geometry mode
  std::size_t panels = 0;
};

SampleLayout LayoutOf(const H5::H5File& file, const run::TrajectorySchema& schema) {
  SampleLayout layout;
  const run::TrajectoryColumn* marker =
      First(schema, [](const run::TrajectoryColumn& c) { return c.free_hinge_output; });
  layout.hinge_outputs = marker != nullptr && file.nameExists(marker->name);
  const run::TrajectoryColumn* ledger =
      First(schema, [](const run::TrajectoryColumn& c) { return c.ledger_output; });
  layout.ledger = ledger != nullptr && file.nameExists(ledger->name);
  const run::TrajectoryColumn* per_panel = First(schema, [](const auto& c) {
    return c.shape == run::ColumnShape::kPerPanel && !c.free_hinge_output;
  });
  if (per_panel != nullptr && file.nameExists(per_panel->name)) layout.first_per_panel = per_panel;
  return layout;
}

/// Column c's dataset, n rows, into the trajectory (a stored column) or out.derived.
void ReadColumn(const std::string& path,
                const H5::H5File& file,
                const run::TrajectoryColumn& c,
                hsize_t n,
                SampleLayout& layout,
                TrajectoryFile& out) {
  const bool per_panel = c.shape == run::ColumnShape::kPerPanel;
  std::vector<hsize_t> trailing;
  for (std::size_t d : run::RowShape(c, 0)) trailing.push_back(per_panel ? 0 : d);
  const std::vector<double> flat = ReadSampleRows(path, file, c.name, trailing, n, out);
  const std::size_t width = n == 0 ? 0 : flat.size() / n;
  if (per_panel && &c == layout.first_per_panel) {
    layout.panels = width;
  } else if (per_panel && n > 0 && width != layout.panels) {
    throw std::runtime_error(path + ": /" + c.name + ": has " + std::to_string(width) +
                             " columns, /" + layout.first_per_panel->name + " has " +
                             std::to_string(layout.panels));
  }
  if (!c.storage) {
    out.derived[c.name] = flat;
    return;
  }
  for (std::size_t k = 0; k < n; ++k) c.storage->push(out.trajectory, &flat[k * width], width);
}

/// The per-sample datasets of `schema`: /time, then every other one the file's layout has
/// (SampleLayout), with as many rows; the panel names in geometry mode.
void ReadSamples(const std::string& path,
                 const H5::H5File& file,
                 const run::TrajectorySchema& schema,
                 TrajectoryFile& out) {
  hsize_t n = 0;
  out.trajectory.time = ReadDoubles(path, file, "", "time", {}, n, out);
  SampleLayout layout = LayoutOf(file, schema);
  out.has_hinge_outputs = layout.hinge_outputs;
  const bool geometry = layout.first_per_panel != nullptr;
  for (const run::TrajectoryColumn& c : schema.columns()) {
    if (c.name == "time" || (c.free_hinge_output && !layout.hinge_outputs)) continue;
    if (c.ledger_output && !layout.ledger) continue;
    if (c.shape == run::ColumnShape::kPerPanel && !geometry) continue;
    ReadColumn(path, file, c, n, layout, out);
  }
  if (!geometry || !layout.hinge_outputs) return;
  out.panel_names = ReadStrings(path, file, "", "panel_names", out);
  if (n > 0 && out.panel_names.size() != layout.panels) {
    throw std::runtime_error(
        path + ": /panel_names: has " + std::to_string(out.panel_names.size()) + " names, /" +
        layout.first_per_panel->name + " has " + std::to_string(layout.panels) + " columns");
  }
}

/// /events: located and predicted flips; with the free-hinge outputs also the 45-degree
/// crossings, the latch times and the hinge event table.
void ReadEvents(const std::string& path, const H5::H5File& file, TrajectoryFile& out) {
  hsize_t rows = 0;
  const H5::Group events = OpenGroup(path, file, "events");
  out.flip_times = ReadDoubles(path, events, "/events", "flip_time", {}, rows, out);

  out.predicted_flip_times =
      ReadDoubles(path, events, "/events", "predicted_flip_time", {}, rows, out);
  if (out.has_hinge_outputs) {
    out.spin_axis_45_times =
        ReadDoubles(path, events, "/events", "spin_axis_45_time", {}, rows, out);
    out.hinge_latch_times = ReadDoubles(path, file, "", "hinge_latch_time", {}, rows, out);
    ReadHingeEvents(path, OpenGroup(path, events, "hinge"), out);
  }
}

/// The /stages table, one row per stage: one dataset per column of run::StageTable, each
/// with as many rows as t_begin (a column newer than the file reads the row's default; a
/// derived column is checked, not read back).
void ReadStages(const std::string& path, const H5::H5File& file, TrajectoryFile& out) {
  const H5::Group stages = OpenGroup(path, file, "stages");
  const std::string sp = "/stages";
  hsize_t count = 0;
  (void)ReadDoubles(path, stages, sp, "t_begin", {}, count, out);
  std::vector<run::StageRow> rows(static_cast<std::size_t>(count));
  for (const run::StageColumn& c : run::StageTable::Columns()) {
    if (c.since_hinge_outputs && !out.has_hinge_outputs) continue;
    auto check = [&](std::size_t n) {
      if (n != rows.size()) {
        throw std::runtime_error(path + ": /stages/" + c.name + ": has " + std::to_string(n) +
                                 " rows, /stages/t_begin has " + std::to_string(rows.size()));
      }
    };
    if (c.type == run::StageColumn::Type::kText) {
      const std::vector<std::string> v = ReadStrings(path, stages, sp, c.name, out);
      check(v.size());
      for (std::size_t i = 0; c.set_text && i < rows.size(); ++i) c.set_text(rows[i], v[i]);
    } else if (c.type == run::StageColumn::Type::kInteger ||
               c.type == run::StageColumn::Type::kFlag) {
      const std::vector<long long> v = ReadIntegers(path, stages, sp, c.name, out);
      check(v.size());
      for (std::size_t i = 0; c.set_number && i < rows.size(); ++i) {
        const double x = static_cast<double>(v[i]);
        c.set_number(rows[i], &x);
      }
    } else {
      hsize_t n = 0;
      const std::vector<hsize_t> trailing =
          c.width() == 1 ? std::vector<hsize_t>{} : std::vector<hsize_t>{3};
      const std::vector<double> v = ReadDoubles(path, stages, sp, c.name, trailing, n, out);
      check(static_cast<std::size_t>(n));
      for (std::size_t i = 0; c.set_number && i < rows.size(); ++i) {
        c.set_number(rows[i], &v[i * c.width()]);
      }
    }
  }
  out.stages = std::move(rows);
}

/// The /danger_windows table: one dataset per column of run::DangerWindowTable, of one
/// length (a derived column is checked, not read back).
void ReadDangerWindows(const std::string& path, const H5::H5File& file, TrajectoryFile& out) {
  const H5::Group windows = OpenGroup(path, file, "danger_windows");
  std::vector<run::DangerWindow> rows;
  bool first = true;
  for (const run::DangerWindowColumn& c : run::DangerWindowTable::Columns()) {
    hsize_t count = 0;
    const std::vector<double> v =
        ReadDoubles(path, windows, "/danger_windows", c.name, {}, count, out);
    if (first) rows.resize(v.size());
    first = false;
    if (v.size() != rows.size()) {
      throw std::runtime_error(path + ": /danger_windows: columns of different lengths");
    }
    for (std::size_t i = 0; c.set && i < rows.size(); ++i) c.set(rows[i], v[i]);
  }
  out.danger_windows = std::move(rows);
}

TrajectoryFile ReadContents(const std::string& path, const run::TrajectorySchema& schema) {
  TrajectoryFile out;
  CheckReadableHdf5(path);
  const H5::H5File file(path, H5F_ACC_RDONLY);
  ReadRootAttributes(path, file, out);
  ReadSamples(path, file, schema, out);
  ReadEvents(path, file, out);
  ReadStages(path, file, out);
  ReadDangerWindows(path, file, out);
  return out;
}

}  // namespace

struct TrajectoryFileWriter::Impl {
  Impl(const std::string& p,
       const schedule::Profile& profile,
       const run::TrajectorySchema& schema_in)
      : path(p),
        geometry(profile.mode == schedule::Mode::kGeometry),
        panels(geometry ? profile.model.hinged.panels.size() : 0),
        schema(schema_in),
        writer(p) {
    for (const run::TrajectoryColumn* c : schema.Written(geometry)) {
      columns.push_back(c);
      handles.push_back(writer.GrowingDoubles("/" + c->name, run::RowShape(*c, panels), c->units,
                                              c->description));
    }
  }
  std::string path;
  bool geometry;
  std::size_t panels;
  const run::TrajectorySchema& schema;
  Hdf5Writer writer;
  std::vector<const run::TrajectoryColumn*> columns;  // column of each handle
  std::vector<std::size_t> handles;                   // GrowingDoubles handles
  bool finished = false;
};

TrajectoryFileWriter::TrajectoryFileWriter(const std::string& path,
                                           const schedule::Profile& profile,
                                           const run::TrajectorySchema& schema)
    : impl_(std::make_unique<Impl>(path, profile, schema)) {}

TrajectoryFileWriter::~TrajectoryFileWriter() = default;

void TrajectoryFileWriter::Append(const Trajectory& block) {
  if (impl_->finished) throw std::logic_error(impl_->path + ": Append after Finish");
  impl_->schema.Check(impl_->path, block, impl_->panels);
  for (std::size_t i = 0; i < impl_->handles.size(); ++i) {
    impl_->writer.AppendRows(impl_->handles[i], Flat(*impl_->columns[i], block, impl_->panels),
                             block.size());
  }
}

void TrajectoryFileWriter::Finish(const run::MissionResult& r) {
  CheckAnalysis(impl_->path, r);
  WriteAnalysis(impl_->writer, r, impl_->geometry);
  impl_->writer.Close();
  impl_->finished = true;
}

void TrajectoryFileWriter::Commit() {
  if (!impl_->finished) throw std::logic_error(impl_->path + ": Commit before Finish");
  impl_->writer.Commit();
}

void WriteTrajectoryFile(const std::string& path,
                         const run::MissionResult& r,
                         const run::TrajectorySchema& schema) {
  schema.Check(path, r.trajectory, HingeColumns(r));
  CheckAnalysis(path, r);
  TrajectoryFileWriter w(path, r.profile(), schema);  // atomic: nothing at `path` unless Commit()
  w.Append(r.trajectory);
  w.Finish(r);
  w.Commit();
}

TrajectoryOutputs::TrajectoryOutputs(const std::string& h5_path,
                                     const std::string& csv_path,
                                     const schedule::Profile& profile)
    : h5_(h5_path, profile) {
  if (!csv_path.empty()) {
    csv_.emplace(csv_path, profile.mode == schedule::Mode::kGeometry
                               ? profile.model.hinged.panels.size()
                               : std::size_t{0});
  }
}

void TrajectoryOutputs::Append(const Trajectory& block) {
  h5_.Append(block);
  if (csv_) csv_->Append(block);
}

void TrajectoryOutputs::Finish(const run::MissionResult& r) {
  h5_.Finish(r);
  if (csv_) csv_->Finish();
}

void TrajectoryOutputs::Commit() {
  const SignalsHeld held;  // both files are renamed, or neither
  h5_.Commit();
  if (csv_) csv_->Commit();
}

TrajectoryFile ReadTrajectoryFile(const std::string& path, const run::TrajectorySchema& schema) {
  const QuietErrors quiet;
  // As in WriteTrajectoryFile: translate HDF5's exceptions to std::runtime_error.
  try {
    return ReadContents(path, schema);
  } catch (const H5::Exception& e) {
    hdf5::Throw(path, e);
  }
}

}  // namespace deploysim::io
