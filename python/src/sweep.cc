// Sweeps from Python: the cases of a SweepSpec on sweep::ParallelFor (the CLI's thread
// pool, the same per-case function sweep::SimulateCase), results as numpy columns (the
// /cases table of the results file and its /timing, sweep_arrays.h). Nothing is written
// unless an output is asked for, and then only once the sweep is complete (atomically), so
// a KeyboardInterrupt leaves nothing behind.

#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "deploysim/sweep/parallel.h"
#include "deploysim/sweep/results_file.h"
#include "deploysim/sweep/runner.h"
#include "deploysim/sweep/sweep_file.h"
#include "sweep_arrays.h"

namespace py = pybind11;

namespace deploysim::python {

void RegisterSweep(py::module_& m) {
  py::class_<sweep::SweepSpec>(m, "SweepSpec",
                               "A validated sweep (docs/sweeps.md): a base profile and grid / "
                               "Monte Carlo axes. deploysim.load_sweep(path) or "
                               "deploysim.sweep_from_dict(d); deploysim.run_sweep(spec) runs it.")
      .def_readonly("name", &sweep::SweepSpec::name, "the sweep's name")
      .def_readonly("source", &sweep::SweepSpec::source, "file (or name) it was read from")
      .def_readonly("text", &sweep::SweepSpec::text, "the YAML text it was read from")
      .def_readonly("base", &sweep::SweepSpec::base, "the base profile")
      .def_property_readonly("case_count", &sweep::SweepSpec::case_count, "number of cases")
      .def("__len__", &sweep::SweepSpec::case_count)
      .def("__repr__", [](const sweep::SweepSpec& s) {
        return "<deploysim.SweepSpec '" + s.name + "' from " + s.source + ", " +
               std::to_string(s.case_count()) + " cases>";
      });

  m.def("_load_sweep", &sweep::LoadSweep, py::arg("path"));
  m.def(
      "_sweep_from_text",
      [](const std::string& text, const std::string& source, const std::string& base_dir,
         const schedule::Profile* base) {
        return sweep::LoadSweepText(text, source, base_dir, base);
      },
      py::arg("text"), py::arg("source"), py::arg("base_dir"), py::arg("base") = py::none());
  m.def("hardware_threads", &sweep::HardwareThreads,
        "Worker threads a sweep uses by default (the hardware threads).");

  m.def(
      "_run_sweep",
      [](const sweep::SweepSpec& spec, int threads, py::object progress, const std::string& output,
         bool csv, double interval) {
        if (threads < 0 || threads > sweep::kMaxThreads) {
          throw std::invalid_argument("threads = " + std::to_string(threads) + ": must be in [0, " +
                                      std::to_string(sweep::kMaxThreads) +
                                      "] (0: all hardware threads)");
        }
        const std::size_t n = spec.case_count();
        std::vector<sweep::CaseOutcome> outcomes(n);
        std::atomic<std::size_t> finished{0};
        std::atomic<bool> cancel{false};
        PythonPoll poll(std::move(progress), interval);
        sweep::ParallelOptions parallel;
        parallel.threads = threads > 0 ? threads : sweep::HardwareThreads();
        parallel.cancelled = [&cancel] { return cancel.load(); };
        parallel.monitor_interval = 0.05;
        parallel.monitor = [&] {
          if (!poll.PollCount(finished.load(), n)) cancel.store(true);
        };
        const auto wall0 = std::chrono::steady_clock::now();
        {
          py::gil_scoped_release release;
          sweep::ParallelFor(
              n,
              [&](std::size_t i) {
                outcomes[i] = sweep::SimulateCase(spec, i);  // slot i is this worker's alone
                finished.fetch_add(1);
              },
              parallel);
        }
        poll.Rethrow();
        if (finished.load() != n) throw std::runtime_error("sweep: cases left undone (internal)");
        if (!poll.stopped()) poll.PollCount(n, n, true);
        poll.Rethrow();
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        if (!output.empty()) {
          sweep::RunInfo info;
          info.threads = parallel.threads;
          info.wall_seconds = wall;
          info.computed_cases = n;
          py::gil_scoped_release release;
          sweep::WriteSweepOutputs(output, csv ? output + ".csv" : "", spec, outcomes, info);
        }
        py::dict out = SweepArrays(spec, outcomes);
        out["wall_seconds"] = wall;
        out["threads"] = parallel.threads;
        return out;
      },
      py::arg("spec"), py::arg("threads") = 0, py::arg("progress") = py::none(),
      py::arg("output") = std::string(), py::arg("csv") = false, py::arg("interval") = 0.1);
}

}  // namespace deploysim::python
