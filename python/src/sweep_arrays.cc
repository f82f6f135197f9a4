#include "sweep_arrays.h"

#include <pybind11/numpy.h>

#include <cstdint>
#include <string>
#include <utility>

#include "convert.h"
#include "deploysim/sweep/results_file.h"

namespace py = pybind11;

namespace deploysim::python {

namespace {

/// The column's values as a numpy array (text: an object array of str).
py::object Values(sweep::ResultColumn&& c) {
  switch (c.type) {
    case sweep::ResultColumn::Type::kDouble:
      return Doubles(std::move(c.d));
    case sweep::ResultColumn::Type::kInt:
      return py::array_t<std::int64_t>(static_cast<py::ssize_t>(c.i.size()), c.i.data());
    case sweep::ResultColumn::Type::kText: {
      py::list l;
      for (const std::string& s : c.s) l.append(s);
      return py::module_::import("numpy").attr("array")(l, "object");
    }
  }
  return py::none();
}

}  // namespace

py::dict SweepArrays(const sweep::SweepSpec& spec,
                     const std::vector<sweep::CaseOutcome>& outcomes) {
  py::dict data;
  py::dict units;
  py::dict roles;
  py::dict descriptions;
  for (sweep::ResultColumn& c : sweep::ResultColumns(spec, outcomes)) {
    units[c.name.c_str()] = c.units;
    roles[c.name.c_str()] = c.role;
    descriptions[c.name.c_str()] = c.description;
    data[c.name.c_str()] = Values(std::move(c));
  }
  py::dict out;
  out["columns"] = data;
  out["units"] = units;
  out["roles"] = roles;
  out["descriptions"] = descriptions;
  for (sweep::ResultColumn& c : sweep::TimingColumns(spec, outcomes)) {
    out[c.name.c_str()] = Values(std::move(c));
  }
  return out;
}

}  // namespace deploysim::python
