// simulate: run::RunMission (what `deploysim simulate` runs, without the file) with
// the GIL released, the trajectory handed to numpy without copies.

#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/io/body_json.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile_warnings.h"
#include "trajectory_arrays.h"

namespace py = pybind11;

namespace deploysim::python {

namespace {

py::dict MissionDict(run::MissionResult&& r, TrajectoryArrays&& samples) {
  const schedule::Profile& p = r.profile();
  const bool geometry = p.mode == schedule::Mode::kGeometry;
  py::dict d;
  d["trajectory"] = std::move(samples).ToDict();
  std::vector<double> predicted;
  for (const run::StageReport& a : r.stages) {
    predicted.insert(predicted.end(), a.predicted_flips.begin(), a.predicted_flips.end());
  }
  const py::list stages = StageRowDicts(r);
  d["flip_times"] = DoublesCopy(r.flip_times);
  d["predicted_flip_times"] = Doubles(std::move(predicted));
  d["spin_axis_45_times"] = DoublesCopy(r.spin_axis_45_crossings);
  d["stages"] = stages;
  d["danger_windows"] = DangerWindowArrays(r);
  d["hinge_events"] = HingeEventArrays(r);
  d["latch_times"] = DoublesCopy(r.latch_times);
  std::vector<std::string> panels;
  if (geometry) {
    for (const model::Panel& x : p.model.hinged.panels) panels.push_back(x.name);
  }
  d["panel_names"] = panels;
  d["spin_axis_B"] = Vec(r.spin_axis_B);
  py::dict stats;
  stats["steps"] = r.stats.steps;
  stats["rejected"] = r.stats.rejected;
  stats["evaluations"] = r.stats.evaluations;
  stats["dense_steps"] = r.stats.dense_steps;
  d["statistics"] = stats;
  d["termination"] = integrators::ToString(r.termination);
  d["reached_end"] = r.termination == integrators::Termination::kReachedEnd;
  d["message"] = r.message;
  d["max_h_N_drift"] = r.max_h_N_drift;
  d["wall_seconds"] = r.wall_seconds;
  d["energy_initial"] = r.energy_initial;
  d["energy_final"] = r.energy_final;
  d["max_spin_axis_angle"] = r.max_spin_axis_angle;
  d["final_time"] = r.final_state.t;
  d["final_J_B"] = Mat(r.final_J_B);
  d["profile"] = r.profile();
  // The verdict as the trajectory file and `analyze --json` hold it (JSON, parsed in
  // Python), and the profile's input warnings.
  d["outcome_json"] = analysis::OutcomeJson(r.outcome);
  d["warnings"] = schedule::ProfileWarnings(r.profile());
  // The body as the run moved it (the file's @body; appendages expanded): None for a
  // tensors model.
  d["body_json"] = r.profile().model.kind == model::ModelKind::kHinged
                       ? py::object(py::str(io::BodyJson(r.profile().model)))
                       : py::object(py::none());
  return d;
}

// The run's samples to the numpy arrays and, when asked, to `deploysim simulate`'s files
// in the same pass.
class Tee final : public run::SampleSink {
 public:
  Tee(run::SampleSink& arrays, run::SampleSink* files) : arrays_(arrays), files_(files) {}
  void Append(const run::Trajectory& block) override {
    arrays_.Append(block);
    if (files_ != nullptr) files_->Append(block);
  }

 private:
  run::SampleSink& arrays_;
  run::SampleSink* files_;
};

}  // namespace

/// The trajectory schema as the package describes it: one dict per column.
py::list TrajectoryColumns() {
  py::list out;
  for (const run::TrajectoryColumn& c : run::TrajectorySchema::Standard().columns()) {
    static const char* const kShapes[] = {"scalar", "vector3", "quaternion", "matrix3",
                                          "per-panel"};
    py::dict d;
    d["name"] = c.name;
    d["units"] = c.units;
    d["shape"] = kShapes[static_cast<int>(c.shape)];
    d["description"] = c.description;
    d["derived"] = c.storage == nullptr;
    out.append(d);
  }
  return out;
}

/// The hinge event table's columns as the package describes them: name, units, type.
py::list HingeEventColumns() {
  static const char* const kTypes[] = {"real", "integer", "text", "vector3"};
  py::list out;
  for (const run::HingeEventColumn& c : run::HingeEventTable::Columns()) {
    py::dict d;
    d["name"] = c.name;
    d["units"] = c.units;
    d["type"] = kTypes[static_cast<int>(c.type)];
    d["description"] = c.description;
    out.append(d);
  }
  return out;
}

/// A table's columns as the package describes them: name, units, description.
template <typename Column>
py::list DescribeColumns(const std::vector<Column>& columns) {
  py::list out;
  for (const Column& c : columns) {
    py::dict d;
    d["name"] = c.name;
    d["units"] = c.units;
    d["description"] = c.description;
    out.append(d);
  }
  return out;
}

void RegisterSimulate(py::module_& m) {
  m.def("_danger_window_columns",
        [] { return DescribeColumns(run::DangerWindowTable::Columns()); });
  m.def("_stage_columns", [] { return DescribeColumns(run::StageTable::Columns()); });
  m.def("_trajectory_columns", &TrajectoryColumns);
  m.def("_hinge_event_columns", &HingeEventColumns);
  m.def(
      "_simulate",
      [](const schedule::Profile& profile, py::object progress, const std::string& output,
         bool csv) {
        PythonPoll poll(std::move(progress));
        const bool geometry = profile.mode == schedule::Mode::kGeometry;
        const double span = profile.t_end() - profile.t_begin();
        const double expected = profile.output.dt > 0.0 ? span / profile.output.dt + 2.0 : 2.0;
        TrajectoryArrays samples(geometry ? profile.model.hinged.panels.size() : 0,
                                 expected < 1e7 ? static_cast<std::size_t>(expected) : 0);
        // The files of `deploysim simulate -o OUTPUT [--csv]`: written atomically, and only
        // for a run that reaches its end (otherwise the temporaries are removed).
        std::optional<io::TrajectoryOutputs> files;
        if (!output.empty()) files.emplace(output, csv ? output + ".csv" : "", profile);
        Tee sink(samples, files ? &*files : nullptr);
        run::MissionResult r;
        {
          py::gil_scoped_release release;
          try {
            // The streaming run of `deploysim simulate` (its HDF5 writer is a sink too).
            r = run::RunMission(profile, sink, [&poll](double f) {
              if (!poll.PollFraction(f, f >= 1.0)) throw PythonStop{};
            });
          } catch (const PythonStop&) {
          }
          if (files && !poll.stopped() && r.termination == integrators::Termination::kReachedEnd) {
            files->Finish(r);
            files->Commit();
          }
        }
        poll.Rethrow();
        return MissionDict(std::move(r), std::move(samples));
      },
      py::arg("profile"), py::arg("progress") = py::none(), py::arg("output") = std::string(),
      py::arg("csv") = false);
}

}  // namespace deploysim::python
