#include "trajectory_arrays.h"

#include <pybind11/numpy.h>

#include <limits>
#include <utility>

#include "convert.h"

namespace py = pybind11;

namespace deploysim::python {

TrajectoryArrays::TrajectoryArrays(std::size_t panels,
                                   std::size_t expected,
                                   const run::TrajectorySchema& schema)
    : schema_(schema), panels_(panels), flat_(schema.columns().size()) {
  for (std::size_t i = 0; i < flat_.size(); ++i) {
    flat_[i].reserve(run::Width(schema.columns()[i], panels) * expected);
  }
}

void TrajectoryArrays::Append(const run::Trajectory& block) {
  schema_.Check("simulate", block, panels_);
  for (std::size_t i = 0; i < flat_.size(); ++i) {
    const run::TrajectoryColumn& c = schema_.columns()[i];
    const std::size_t width = run::Width(c, panels_);
    if (width == 0) continue;
    std::vector<double>& v = flat_[i];
    std::size_t at = v.size();
    v.resize(at + width * block.size());
    for (std::size_t k = 0; k < block.size(); ++k, at += width) c.values(block, k, &v[at]);
  }
  rows_ += block.size();
}

py::dict TrajectoryArrays::ToDict() && {
  py::dict d;
  for (std::size_t i = 0; i < flat_.size(); ++i) {
    const run::TrajectoryColumn& c = schema_.columns()[i];
    py::list shape;
    shape.append(static_cast<py::ssize_t>(rows_));
    for (std::size_t n : run::RowShape(c, panels_)) shape.append(static_cast<py::ssize_t>(n));
    d[py::str(c.name)] = Doubles(std::move(flat_[i])).attr("reshape")(py::tuple(shape));
  }
  return d;
}

// The hinge event table, a column per run::HingeEventTable entry: numbers as numpy
// arrays ((E,) or (E, 3)), text as lists.
py::dict HingeEventArrays(const run::MissionResult& r) {
  using Column = run::HingeEventColumn;
  std::vector<std::string> names;
  for (const model::Panel& p : r.profile().model.hinged.panels) names.push_back(p.name);
  const std::size_t n = r.hinge_events.size();
  py::dict d;
  for (const Column& c : run::HingeEventTable::Columns()) {
    if (c.type == Column::Type::kText) {
      py::list text;
      for (const run::HingeEvent& e : r.hinge_events) text.append(c.text(e, names));
      d[c.name.c_str()] = text;
      continue;
    }
    std::vector<double> v(n * static_cast<std::size_t>(c.width()));
    for (std::size_t i = 0; i < n; ++i) c.number(r.hinge_events[i], &v[i * c.width()]);
    if (c.type == Column::Type::kInteger) {
      const std::vector<long long> k(v.begin(), v.end());
      d[c.name.c_str()] = py::array_t<long long>(static_cast<py::ssize_t>(n), k.data());
    } else if (c.width() == 1) {
      d[c.name.c_str()] = Doubles(std::move(v));
    } else {
      d[c.name.c_str()] =
          py::array_t<double>({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(3)}, v.data());
    }
  }
  return d;
}

py::list StageRowDicts(const run::MissionResult& r) {
  using Column = run::StageColumn;
  constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();
  py::list out;
  for (const run::StageRow& row : run::StageRows(r)) {
    py::dict d;
    for (const Column& c : run::StageTable::Columns()) {
      const bool applies = !c.applies || c.applies(row);
      if (c.type == Column::Type::kText) {
        d[c.name.c_str()] = applies ? py::object(py::str(c.text(row))) : py::object(py::none());
        continue;
      }
      double v[3];
      c.number(row, v);
      if (!applies) v[0] = v[1] = v[2] = kMissing;
      if (c.type == Column::Type::kFlag) {
        d[c.name.c_str()] = v[0] != 0.0;
      } else if (c.type == Column::Type::kInteger) {
        d[c.name.c_str()] = static_cast<long long>(v[0]);
      } else if (c.width() == 1) {
        d[c.name.c_str()] = v[0];
      } else {
        d[c.name.c_str()] = DoublesCopy({v[0], v[1], v[2]});
      }
    }
    d["predicted_flips"] = DoublesCopy(row.predicted_flips);
    d["observed_flips"] = DoublesCopy(row.observed_flips);
    out.append(d);
  }
  return out;
}

py::dict DangerWindowArrays(const run::MissionResult& r) {
  py::dict d;
  for (const run::DangerWindowColumn& c : run::DangerWindowTable::Columns()) {
    std::vector<double> v;
    for (const run::DangerWindow& w : r.danger_windows) v.push_back(c.value(w));
    d[c.name.c_str()] = DoublesCopy(v);
  }
  return d;
}

}  // namespace deploysim::python
