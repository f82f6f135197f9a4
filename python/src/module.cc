// deploysim._deploysim: the compiled half of the Python package (python/deploysim/ is the
// other). Model and Profile objects and their loaders: from files, or from text built
// by the package from Python dicts (the same readers, rules and messages).

#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "bindings.h"
#include "convert.h"
#include "deploysim/analysis/exact_flow.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/version.h"

namespace py = pybind11;

namespace deploysim::python {

namespace {

py::list Configurations(const model::Model& m) {
  py::list out;
  for (const model::Configuration& c : m.configurations) {
    py::dict d;
    d["name"] = c.name;
    if (m.kind == model::ModelKind::kTensors) {
      d["J_B"] = Mat(c.J_B);
    } else {
      d["hinge_angles"] = py::array_t<double>(c.hinge_angles.size(), c.hinge_angles.data());
    }
    out.append(d);
  }
  return out;
}

std::vector<std::string> PanelNames(const model::Model& m) {
  std::vector<std::string> names;
  for (const model::Panel& p : m.hinged.panels) names.push_back(p.name);
  return names;
}

py::list Stages(const schedule::Profile& p) {
  py::list out;
  for (const schedule::Stage& s : p.stages) {
    py::dict d;
    d["name"] = s.name;
    d["from"] = s.from;
    d["to"] = s.to;
    d["law"] = s.is_hold() ? std::string("hold") : schedule::ToString(s.law);
    d["t_begin"] = s.t_begin;
    d["t_end"] = s.t_end;
    out.append(d);
  }
  return out;
}

}  // namespace

void RegisterProfiles(py::module_& m) {
  py::class_<model::Model>(m, "Model",
                           "A spacecraft model (models/*.yaml): named inertia configurations "
                           "(kind tensors) or a hub with hinged panels (kind hinged).\n"
                           "Build one with deploysim.load_model(path) or "
                           "deploysim.model_from_dict(d).")
      .def_readonly("name", &model::Model::name, "the model's name")
      .def_readonly("description", &model::Model::description, "free text")
      .def_readonly("source", &model::Model::source, "file (or name) it was read from")
      .def_readonly("text", &model::Model::text, "the YAML text it was read from")
      .def_property_readonly(
          "kind",
          [](const model::Model& x) {
            return x.kind == model::ModelKind::kTensors ? "tensors" : "hinged";
          },
          "'tensors' or 'hinged'")
      .def_property_readonly("configurations", &Configurations,
                             "list of dicts: name and J_B [kg m^2] (3x3) for tensors models, "
                             "hinge_angles [rad] (one per panel) for hinged models")
      .def_property_readonly("panel_names", &PanelNames, "panel names in panel order (hinged)")
      .def("__repr__", [](const model::Model& x) {
        return "<deploysim.Model '" + x.name + "' (" +
               (x.kind == model::ModelKind::kTensors ? "tensors" : "hinged") + ") from " +
               x.source + ">";
      });

  py::class_<schedule::Profile>(
      m, "Profile",
      "A validated deployment profile (deployment_profiles/*.yaml): the model, the initial "
      "state, the stages or hinge plans, the integrator and output settings.\n"
      "Build one with deploysim.load_profile(path) or deploysim.profile_from_dict(d); "
      "deploysim.simulate(profile, ...) runs it.")
      .def_readonly("name", &schedule::Profile::name, "the profile's name")
      .def_readonly("description", &schedule::Profile::description, "free text")
      .def_readonly("source", &schedule::Profile::source, "file (or name) it was read from")
      .def_readonly("text", &schedule::Profile::text, "the YAML text it was read from")
      .def_readonly("model", &schedule::Profile::model, "the Model it runs")
      .def_property_readonly(
          "mode", [](const schedule::Profile& p) { return schedule::ToString(p.mode); },
          "'tensor' or 'geometry'")
      .def_property_readonly(
          "coupling", [](const schedule::Profile& p) { return schedule::ToString(p.coupling); },
          "'quasi-rigid' or 'exact'")
      .def_property_readonly("is_hinge_profile", &schedule::Profile::is_hinge_profile,
                             "True for a profile with hinge plans (`hinges:`)")
      .def_property_readonly("t_begin", &schedule::Profile::t_begin, "start time [s]")
      .def_property_readonly("t_end", &schedule::Profile::t_end, "end time [s]")
      .def_property_readonly(
          "method", [](const schedule::Profile& p) { return p.integrator.method; },
          "integrator (deploysim.methods())")
      .def_property_readonly(
          "rtol", [](const schedule::Profile& p) { return p.integrator.rtol; },
          "relative tolerance")
      .def_property_readonly(
          "atol", [](const schedule::Profile& p) { return p.integrator.atol; },
          "absolute tolerance, relative to |H_B(0)|")
      .def_property_readonly(
          "step", [](const schedule::Profile& p) { return p.integrator.step; },
          "fixed step [s] (initial step of adaptive methods; 0: automatic)")
      .def_property_readonly(
          "dt", [](const schedule::Profile& p) { return p.output.dt; },
          "output sampling interval [s]")
      .def_property_readonly("stages", &Stages,
                             "stage profiles: list of dicts name, from, to, law, t_begin [s], "
                             "t_end [s]")
      .def(
          "with_overrides",
          [](const schedule::Profile& p, std::optional<std::string> method,
             std::optional<double> rtol, std::optional<double> atol, std::optional<double> step,
             std::optional<double> dt, std::optional<std::string> coupling,
             std::optional<std::string> mode, std::optional<double> until) {
            io::ProfileOverrides o;
            o.method = std::move(method);
            o.rtol = rtol;
            o.atol = atol;
            o.step = step;
            o.output_dt = dt;
            o.coupling = std::move(coupling);
            o.mode = std::move(mode);
            o.until = until;
            schedule::Profile q = p;
            io::ApplyOverrides(q, o);
            return q;
          },
          py::arg("method") = py::none(), py::arg("rtol") = py::none(),
          py::arg("atol") = py::none(), py::arg("step") = py::none(), py::arg("dt") = py::none(),
          py::arg("coupling") = py::none(), py::arg("mode") = py::none(),
          py::arg("until") = py::none(),
          "A copy with the run settings overridden, as the CLI's --method, --rtol, --atol, "
          "--step [s], --dt [s], --coupling, --mode, --until [s] do, and re-validated "
          "(ValueError with the CLI's message otherwise).")
      .def("__repr__", [](const schedule::Profile& p) {
        return "<deploysim.Profile '" + p.name + "' from " + p.source + ", model '" + p.model.name +
               "', " + p.integrator.method + ">";
      });

  m.def("_load_model", &io::LoadModel, py::arg("path"));
  m.def("_load_profile", &io::LoadProfile, py::arg("path"));
  m.def("_model_from_text", &io::ReadModelText, py::arg("text"), py::arg("source"));
  m.def(
      "_profile_from_text",
      [](const std::string& text, const std::string& source, const std::string& base_dir,
         const model::Model* model) { return io::LoadProfileText(text, source, base_dir, model); },
      py::arg("text"), py::arg("source"), py::arg("base_dir"), py::arg("model") = py::none());
  m.def("methods", &analysis::StepperNames, "The integrator names (as `deploysim methods`).");
  m.attr("__version__") = kVersion;
  m.attr("build_id") = kBuildId;
}

}  // namespace deploysim::python

PYBIND11_MODULE(_deploysim, m) {
  m.doc() = "deploysim's compiled core (pybind11). Use the package `deploysim`, which wraps it.";
  deploysim::python::RegisterProfiles(m);
  deploysim::python::RegisterSimulate(m);
  deploysim::python::RegisterFreeBody(m);
  deploysim::python::RegisterSweep(m);
  deploysim::python::RegisterCrosscheck(m);
}
