#include "trajectory_arrays.h"

#include <pybind11/numpy.h>

#include <utility>

#include "convert.h"

namespace py = pybind11;

namespace deploysim::python {

TrajectoryArrays::TrajectoryArrays(std::size_t panels,
                                   std::size_t expected,
                                   const analysis::TrajectorySchema& schema)
    : schema_(schema), panels_(panels), flat_(schema.columns().size()) {
  for (std::size_t i = 0; i < flat_.size(); ++i) {
    flat_[i].reserve(analysis::Width(schema.columns()[i], panels) * expected);
  }
}

void TrajectoryArrays::Append(const analysis::Trajectory& block) {
  schema_.Check("simulate", block, panels_);
  for (std::size_t i = 0; i < flat_.size(); ++i) {
    const analysis::TrajectoryColumn& c = schema_.columns()[i];
    const std::size_t width = analysis::Width(c, panels_);
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
    const analysis::TrajectoryColumn& c = schema_.columns()[i];
    py::list shape;
    shape.append(static_cast<py::ssize_t>(rows_));
    for (std::size_t n : analysis::RowShape(c, panels_)) shape.append(static_cast<py::ssize_t>(n));
    d[py::str(c.name)] = Doubles(std::move(flat_[i])).attr("reshape")(py::tuple(shape));
  }
  return d;
}

}  // namespace deploysim::python
