// LoadModel: model files (docs/file_formats.md, "Models").

#include "deploysim/io/yaml_model.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/units.h"
#include "deploysim/model/appendages.h"
#include "deploysim/model/flexible_beam.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/slosh.h"

namespace deploysim::io {

namespace {

using math::kRadiansPerDegree;
using math::kRadPerSecondPerRpm;
using yaml::Fields;
using yaml::YamlDocument;
using yaml::YamlNode;

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
  if (!top.Has("panels") && top.Has("appendages")) return {};
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

/// A panel named by `key` (a parent), or -1 when the key is absent (the hub).
int ParentPanel(const Fields& f, const std::string& key, const std::vector<model::Panel>& panels) {
  if (!f.Has(key)) return -1;
  const std::string name = f.Text(key);
  for (std::size_t j = 0; j < panels.size(); ++j) {
    if (panels[j].name == name) return static_cast<int>(j);
  }
  std::vector<std::string> names;
  for (const model::Panel& p : panels) names.push_back(p.name);
  f.Fail(key,
         "no panel of that name (rule: a panel of the file's panels, or left out for the "
         "hub; panels: " +
             yaml::ShortList(names) + ")");
}

/// `appendages[k]` of kind beam (model/flexible_beam.h; docs/file_formats.md).
model::BeamSpec ReadBeam(const Fields& f,
                         const std::string& name,
                         const std::vector<model::Panel>& panels) {
  model::BeamSpec s;
  s.name = name;
  s.parent = ParentPanel(f, "parent", panels);
  s.root_point = f.Vector3("root");
  s.direction = f.Vector3("direction");
  if (f.Has("root_axis")) s.root_axis = f.Vector3("root_axis");
  s.length = f.Number("length");
  s.mass_per_length = f.Number("mass_per_length");
  s.radius = f.Number("radius");
  const std::vector<YamlNode> planes =
      yaml::SequenceElements(f.doc(), f.Get("bending"), f.Key("bending"), "bending planes");
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const Fields pf(f.doc(), planes[p], f.Key("bending[" + std::to_string(p) + "]"),
                    {"axis", "EI"});
    s.planes.push_back(model::BeamPlane{pf.Vector3("axis"), pf.Number("EI")});
  }
  s.damping_ratio = f.OptionalNumber("damping_ratio").value_or(0.0);
  if (f.Has("modes")) {
    const double k = f.Number("modes");
    if (!(k == std::floor(k) && k >= 1 && k <= model::kMaxBeamSegments)) {
      f.Fail("modes", "must be a whole number in [1, segments]");
    }
    s.modes = static_cast<int>(k);
  }
  const std::string count = f.RequireExactlyOne({"segments", "frequency_tolerance"});
  if (count == "segments") {
    const double n = f.Number("segments");
    if (!(n == std::floor(n) && n >= 2 && n <= model::kMaxBeamSegments)) {
      f.Fail("segments",
             "must be a whole number in [2, " + std::to_string(model::kMaxBeamSegments) + "]");
    }
    s.segments = static_cast<int>(n);
  } else {
    s.frequency_tolerance = f.Number("frequency_tolerance");
  }
  return s;
}

/// The keys of each appendage kind (docs/file_formats.md, "Appendages").
const std::vector<std::string> kBeamKeys = {"name",
                                            "kind",
                                            "parent",
                                            "root",
                                            "direction",
                                            "root_axis",
                                            "length",
                                            "mass_per_length",
                                            "radius",
                                            "bending",
                                            "damping_ratio",
                                            "segments",
                                            "frequency_tolerance",
                                            "modes"};

const std::vector<std::string> kSloshKeys = {
    "name",      "kind",          "parent",      "pivot",       "direction", "axis",
    "mass",      "length",        "fixed_mass",  "fixed_point", "damping",   "damping_ratio",
    "spin_rate", "spin_rate_rpm", "spin_radius", "tank"};

std::vector<std::string> AllAppendageKeys() {
  std::vector<std::string> keys;
  for (const std::vector<std::string>* kind : {&kBeamKeys, &kSloshKeys}) {
    for (const std::string& k : *kind) {
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    }
  }
  return keys;
}

/// `tank:` of a slosh appendage (model::SloshTank), instead of the pendulum's own keys:
/// `{shape: cylinder, center, diameter, height, liquid_mass_full | density, fill_fraction}`.
/// The ranges are model::AddSlosh's.
void ReadTank(const Fields& f, model::SloshSpec& s) {
  for (const char* key : {"pivot", "mass", "length", "fixed_mass", "fixed_point"}) {
    if (f.Has(key)) {
      f.Fail(key,
             "the tank gives the pendulum (rule: tank, or pivot, mass, length and "
             "optionally fixed_mass and fixed_point)");
    }
  }
  const Fields t = f.Mapping("tank", {"shape", "center", "diameter", "height", "liquid_mass_full",
                                      "density", "fill_fraction"});
  if (t.Text("shape") != "cylinder") {
    t.Fail("shape",
           "unknown tank shape (valid: cylinder: upright, flat-bottomed, its axis "
           "along direction)");
  }
  t.RequireExactlyOne("liquid_mass_full", "density");
  model::SloshTank tank;
  tank.center = t.Vector3("center");
  tank.diameter = t.Number("diameter");
  tank.height = t.Number("height");
  tank.liquid_mass_full = t.OptionalNumber("liquid_mass_full");
  tank.density = t.OptionalNumber("density");
  tank.fill_fraction = t.Number("fill_fraction");
  s.tank = tank;
}

/// `appendages[k]` of kind slosh (model/slosh.h; docs/file_formats.md): the ranges are
/// model::AddSlosh's, which names the keys in its messages.
model::SloshSpec ReadSlosh(const Fields& f,
                           const std::string& name,
                           const std::vector<model::Panel>& panels) {
  model::SloshSpec s;
  s.name = name;
  s.parent = ParentPanel(f, "parent", panels);
  s.direction = f.Vector3("direction");
  if (f.Has("axis")) s.axis = f.Vector3("axis");
  if (f.Has("tank")) {
    ReadTank(f, s);
  } else {
    s.pivot = f.Vector3("pivot");
    s.mass = f.Number("mass");
    s.length = f.Number("length");
  }
  if (f.Has("fixed_mass") != f.Has("fixed_point")) {
    f.Fail(f.Has("fixed_mass") ? "fixed_mass" : "fixed_point",
           "fixed_mass [kg] and fixed_point [m] come together (rule: both or neither)");
  }
  if (f.Has("fixed_mass")) {
    s.fixed_mass = f.Number("fixed_mass");
    s.fixed_point = f.Vector3("fixed_point");
  }
  s.damping = f.OptionalNumber("damping");
  s.damping_ratio = f.OptionalNumber("damping_ratio");
  if (f.Has("spin_rate") && f.Has("spin_rate_rpm")) {
    f.Fail("spin_rate_rpm", "give spin_rate [rad/s] or spin_rate_rpm, not both");
  }
  s.spin_rate = f.OptionalNumber("spin_rate");
  if (f.Has("spin_rate_rpm")) {
    const double rpm = f.Number("spin_rate_rpm");
    if (!(rpm > 0.0)) f.Fail("spin_rate_rpm", "must be > 0 [rpm]");
    s.spin_rate = rpm * kRadPerSecondPerRpm;
  }
  s.spin_radius = f.OptionalNumber("spin_radius");
  return s;
}

/// An appendage's `name`: a valid name, unique among the panels (generated ones included).
std::string AppendageName(const Fields& f, const model::HingedBody& body) {
  const std::string name = f.Name("name");
  for (const model::Panel& p : body.panels) {
    if (p.name == name) f.Fail("name", "also the name of a panel (rule: unique names)");
  }
  return name;
}

/// `appendages:` expanded into `body`'s panels (after the file's own).
std::vector<model::Appendage> ReadAppendages(const Fields& top, model::HingedBody& body) {
  std::vector<model::Appendage> out;
  if (!top.Has("appendages")) return out;
  const std::vector<YamlNode> nodes =
      yaml::SequenceElements(top.doc(), top.Get("appendages"), "appendages", "appendages");
  const std::vector<model::Panel> declared = body.panels;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const std::string key = "appendages[" + std::to_string(k) + "]";
    const std::string where = model::AppendageWhere(top.doc().path(), k);
    // The kind first, so that the mapping is read with its kind's own keys (an unknown key
    // is named against them); without a readable kind, against every kind's keys.
    std::string kind;
    for (const auto& [entry, value] : yaml::MappingEntries(top.doc(), nodes[k], key)) {
      if (entry == "kind" && value.IsPlainScalar()) kind = value.Scalar();
    }
    if (kind == "beam") {
      const Fields f(top.doc(), nodes[k], key, kBeamKeys);
      const std::string name = AppendageName(f, body);
      out.push_back(model::ExpandAppendage(body, ReadBeam(f, name, declared), where));
    } else if (kind == "slosh") {
      const Fields f(top.doc(), nodes[k], key, kSloshKeys);
      const std::string name = AppendageName(f, body);
      out.push_back(model::ExpandAppendage(body, ReadSlosh(f, name, declared), where));
    } else {
      const Fields any(top.doc(), nodes[k], key, AllAppendageKeys());
      (void)any.Text("kind");  // missing or not text: its own message
      any.Fail("kind", "unknown appendage kind (valid: beam, slosh)");
    }
  }
  return out;
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

/// A hinged configuration: one angle per panel of the file, then one per appendage with a
/// root hinge (a beam's; a slosh pendulum has none), in appendage order; the appendages'
/// generated hinges are at rest (0: a beam straight, a pendulum along its direction).
model::Configuration ReadHingedConfiguration(const YamlDocument& doc,
                                             const std::string& name,
                                             const YamlNode& node,
                                             const model::Model& m,
                                             std::size_t declared) {
  const Fields f(doc, node, yaml::JoinKey("configurations", name), {"hinge_angles_deg"});
  const YamlNode& angles = f.Get("hinge_angles_deg");
  const Eigen::VectorXd deg = yaml::ReadNumbers(doc, angles, f.Key("hinge_angles_deg"), -1);
  std::vector<int> roots;  // the appendages' root hinges, in appendage order
  for (const model::Appendage& a : m.appendages) {
    if (a.root >= 0) roots.push_back(a.root);
  }
  const std::size_t given = declared + roots.size();
  if (static_cast<std::size_t>(deg.size()) != given) {
    f.Fail(
        "hinge_angles_deg",
        "must have one hinge angle per panel (the model has " + std::to_string(declared) +
            " panels, in panel order" +
            (roots.empty()
                 ? std::string(")")
                 : ", then one per appendage with a root hinge (" + std::to_string(roots.size()) +
                       "; a slosh pendulum has none): " + std::to_string(given) + ")"));
  }
  model::Configuration c;
  c.name = name;
  c.hinge_angles = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.hinged.panels.size()));
  c.hinge_angles.head(static_cast<Eigen::Index>(declared)) =
      deg.head(static_cast<Eigen::Index>(declared)) * kRadiansPerDegree;
  for (std::size_t a = 0; a < roots.size(); ++a) {
    c.hinge_angles[roots[a]] = deg[static_cast<Eigen::Index>(declared + a)] * kRadiansPerDegree;
  }
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
  const Fields top(
      doc, doc.root(), "",
      {"name", "description", "kind", "configurations", "hub", "panels", "appendages"});
  model::Model m;
  m.source = path;
  m.text = doc.text();
  m.name = top.Name("name");
  m.description = top.OptionalText("description").value_or("");

  const std::string kind = top.Text("kind");
  std::size_t declared = 0;  // the file's own panels
  if (kind == "tensors") {
    m.kind = model::ModelKind::kTensors;
    for (const char* key : {"hub", "panels", "appendages"}) {
      if (top.Has(key)) top.Fail(key, "only allowed in models of kind: hinged");
    }
  } else if (kind == "hinged") {
    m.kind = model::ModelKind::kHinged;
    model::HingedBody body;
    body.hub = ReadHub(top);
    body.panels = ReadPanels(top);
    declared = body.panels.size();
    m.declared = body;  // what model::RebuildAppendages expands the appendages onto again
    m.appendages = ReadAppendages(top, body);
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
    m.configurations.push_back(m.kind == model::ModelKind::kTensors
                                   ? ReadTensorConfiguration(doc, name, node)
                                   : ReadHingedConfiguration(doc, name, node, m, declared));
  }
  return m;
}

}  // namespace deploysim::io
