#pragma once

// A sweep's results as numpy arrays: the /cases columns of the results file
// (sweep::ResultColumns, the case outcome's from sweep::CaseOutcomeTable) and its /timing
// columns, with their units, roles and descriptions.

#include <pybind11/pybind11.h>

#include <vector>

#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_spec.h"

namespace deploysim::python {

/// With the GIL: {"columns": {name: array (N,)}, "units", "roles", "descriptions": {name:
/// text}} over the /cases columns in file order (numbers as float64 or int64 arrays, text
/// as object arrays), and each /timing column by its name (run_time: (N,) float64 [s]).
pybind11::dict SweepArrays(const sweep::SweepSpec& spec,
                           const std::vector<sweep::CaseOutcome>& outcomes);

}  // namespace deploysim::python
