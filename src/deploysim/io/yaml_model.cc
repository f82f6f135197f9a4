// LoadModel: model files (docs/file_formats.md, "Models").

#include <cmath>
#include <string>
#include <vector>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::io {

namespace {

using yaml::Fields;
using yaml::YamlDocument;
using yaml::YamlNode;

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

/// Validates J with math::InertiaTensor::Check; the message names the file and key.
void RequireValidInertia(const Fields& f, const std::string& key, const math::Mat3& J) {
  const std::string err = math::InertiaTensor::Check(J, f.doc().path() + ": " + f.Key(key));
  if (!err.empty()) throw std::invalid_argument(err);
}

double PositiveMass(const Fields& f) {
  const double mass = f.Number("mass");
  if (!(mass > 0.0)) f.Fail("mass", "must be > 0 [kg]");
  return mass;
}

/// `box: [x, y, z]` (solid cuboid edge lengths [m]) or `inertia: [[...]]` about the CoM.
math::Mat3 ElementInertia(const Fields& f, double mass) {
  f.RequireExactlyOne("box", "inertia");
  if (f.Has("box")) {
    const math::Vec3 size = f.Vector3("box");
    if ((size.array() < 0.0).any()) f.Fail("box", "edge lengths must be >= 0 [m]");
    const math::Mat3 J = model::BoxInertia(mass, size);
    RequireValidInertia(f, "box", J);
    return J;
  }
  const math::Mat3 J = f.Matrix3("inertia");
  RequireValidInertia(f, "inertia", J);
  return 0.5 * (J + J.transpose());
}

model::Hub ReadHub(const Fields& top) {
  const Fields f = top.Mapping("hub", {"mass", "com", "box", "inertia"});
  model::Hub hub;
  hub.body.mass = PositiveMass(f);
  hub.body.inertia_cm = ElementInertia(f, hub.body.mass);
  if (f.Has("com")) hub.com_B = f.Vector3("com");
  return hub;
}

std::vector<model::Panel> ReadPanels(const Fields& top) {
  const std::vector<YamlNode> nodes =
      yaml::SequenceElements(top.doc(), top.Get("panels"), "panels", "panels");
  if (nodes.empty()) top.Fail("panels", "at least one panel is required");
  std::vector<model::Panel> panels;
  std::vector<Fields> fields;  // of each panel, for the parents' messages
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Fields f(
        top.doc(), nodes[k], "panels[" + std::to_string(k) + "]",
        {"name", "mass", "box", "inertia", "hinge_point", "hinge_axis", "com_offset", "parent"});
    model::Panel p;
    p.name = f.Name("name");
    for (const model::Panel& other : panels) {
      if (other.name == p.name) f.Fail("name", "panel names must be unique");
    }
    p.body.mass = PositiveMass(f);
    p.body.inertia_cm = ElementInertia(f, p.body.mass);
    p.hinge_point_B = f.Vector3("hinge_point");
    p.hinge_axis_B = f.Vector3("hinge_axis");
    if (p.hinge_axis_B.isZero(0.0))
      f.Fail("hinge_axis", "must be non-zero (it is normalized on load)");
    p.com_offset_B = f.Vector3("com_offset");
    panels.push_back(p);
    fields.push_back(f);
  }
  // `parent: <panel name>` (default: the hub), resolved once every name is known (a parent
  // may come after its children). A panel naming itself or a cycle is refused by
  // model::ValidatedHingedBody.
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Fields& f = fields[k];
    if (!f.Has("parent")) continue;
    const std::string parent = f.Text("parent");
    for (std::size_t j = 0; j < panels.size(); ++j) {
      if (panels[j].name == parent) panels[k].parent = static_cast<int>(j);
    }
    if (panels[k].parent < 0) {
      std::vector<std::string> names;
      for (const model::Panel& p : panels) names.push_back(p.name);
      f.Fail("parent",
             "no panel of that name (rule: parent names another panel, or is left out "
             "for the hub; panels: " +
                 yaml::ShortList(names) + ")");
    }
  }
  return panels;
}

model::Configuration ReadTensorConfiguration(const YamlDocument& doc,
                                             const std::string& name,
                                             const YamlNode& node) {
  const Fields f(doc, node, yaml::JoinKey("configurations", name), {"principal_moments", "tensor"});
  f.RequireExactlyOne("principal_moments", "tensor");
  model::Configuration c;
  c.name = name;
  if (f.Has("principal_moments")) {
    const math::Vec3 m = f.Vector3("principal_moments");
    c.J_B = m.asDiagonal();
    RequireValidInertia(f, "principal_moments", c.J_B);
  } else {
    const math::Mat3 J = f.Matrix3("tensor");
    RequireValidInertia(f, "tensor", J);
    c.J_B = 0.5 * (J + J.transpose());
  }
  return c;
}

model::Configuration ReadHingedConfiguration(const YamlDocument& doc,
                                             const std::string& name,
                                             const YamlNode& node,
                                             std::size_t panels) {
  const Fields f(doc, node, yaml::JoinKey("configurations", name), {"hinge_angles_deg"});
  const YamlNode& angles = f.Get("hinge_angles_deg");
  const Eigen::VectorXd deg = yaml::ReadNumbers(doc, angles, f.Key("hinge_angles_deg"), -1);
  if (static_cast<std::size_t>(deg.size()) != panels) {
    f.Fail("hinge_angles_deg", "must have one hinge angle per panel (the model has " +
                                   std::to_string(panels) + " panels, in panel order)");
  }
  model::Configuration c;
  c.name = name;
  c.hinge_angles = deg * kRadiansPerDegree;
  return c;
}

}  // namespace

model::Model LoadModel(const std::string& path) {
  const std::string text = yaml::ReadTextFile(path);
  return ReadModelText(text, path);
}

model::Model ReadModelText(const std::string& text, const std::string& source) {
  const std::string& path = source;
  const YamlDocument doc(source, text);
  const Fields top(doc, doc.root(), "",
                   {"name", "description", "kind", "configurations", "hub", "panels"});
  model::Model m;
  m.source = path;
  m.text = doc.text();
  m.name = top.Name("name");
  m.description = top.OptionalText("description").value_or("");

  const std::string kind = top.Text("kind");
  if (kind == "tensors") {
    m.kind = model::ModelKind::kTensors;
    for (const char* key : {"hub", "panels"}) {
      if (top.Has(key)) top.Fail(key, "only allowed in models of kind: hinged");
    }
  } else if (kind == "hinged") {
    m.kind = model::ModelKind::kHinged;
    model::HingedBody body;
    body.hub = ReadHub(top);
    body.panels = ReadPanels(top);
    m.hinged = model::ValidatedHingedBody(body, path);
  } else {
    top.Fail("kind", "unknown model kind (valid: tensors, hinged)");
  }

  const auto entries = yaml::MappingEntries(doc, top.Get("configurations"), "configurations");
  if (entries.empty()) top.Fail("configurations", "at least one configuration is required");
  for (const auto& [name, node] : entries) {
    if (const std::string problem = yaml::NameProblem(name); !problem.empty()) {
      doc.Fail(yaml::JoinKey("configurations", name), "configuration name: " + problem);
    }
    m.configurations.push_back(
        m.kind == model::ModelKind::kTensors
            ? ReadTensorConfiguration(doc, name, node)
            : ReadHingedConfiguration(doc, name, node, m.hinged.panels.size()));
  }
  return m;
}

}  // namespace deploysim::io
