#pragma once

// The parts of the compiled module deploysim._deploysim (python/CMakeLists.txt): each
// Register* adds its functions and classes. A thin layer over the library API the CLI
// uses (docs/design.md 4): no physics here, only conversion to numpy and Python objects,
// the GIL and Ctrl-C. Library exceptions pass through pybind11's translation:
// std::invalid_argument -> ValueError (bad input: one line naming file, key, value and
// rule, as the CLI prints it), std::runtime_error -> RuntimeError.

#include <pybind11/pybind11.h>

namespace deploysim::python {

void RegisterProfiles(pybind11::module_& m);    // module.cc: Model, Profile, loaders
void RegisterSimulate(pybind11::module_& m);    // simulate.cc
void RegisterFreeBody(pybind11::module_& m);    // free_body.cc
void RegisterSweep(pybind11::module_& m);       // sweep.cc
void RegisterCrosscheck(pybind11::module_& m);  // crosscheck.cc

}  // namespace deploysim::python
