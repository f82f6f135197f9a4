// Valid model and profile files load with the right values; a few messages are checked
// word for word (the malformed-input corpus is bad_inputs_test.cpp).

#include "deploysim/io/yaml_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/math/quaternion.h"
#include "deploysim/model/mass_properties.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;
using math::Mat3;
using math::Vec3;

constexpr double kDeg = M_PI / 180.0;

const char* const kTensorModel = R"(name: wing_nut
description: "the wing nut of the seed thesis"
kind: tensors
configurations:
  default:
    principal_moments: [3.036e-6, 2.741e-6, 0.699e-6]
  tilted:
    tensor: [[2, 0.1, 0], [0.1, 3, 0], [0, 0, 4]]
)";

const char* const kHingedModel = R"(name: smallsat
kind: hinged
hub:
  mass: 80.0
  com: [0.01, 0, 0]
  box: [0.6, 0.6, 0.8]
panels:
  - name: wing_plus_x
    mass: 6.0
    box: [1.0, 0.02, 0.7]
    hinge_point: [0.3, 0, 0]
    hinge_axis: [0, 2, 0]
    com_offset: [0.5, 0, 0]
  - name: wing_minus_x
    mass: 6.0
    inertia: [[0.25, 0, 0], [0, 0.74, 0], [0, 0, 0.5]]
    hinge_point: [-0.3, 0, 0]
    hinge_axis: [0, -1, 0]
    com_offset: [-0.5, 0, 0]
configurations:
  closed: {hinge_angles_deg: [-90, 90]}
  half_open: {hinge_angles_deg: [-45, 45]}
  open: {hinge_angles_deg: [0, 0]}
)";

const char* const kTensorProfile = R"(name: wing_nut_flip
description: spin, then change the tensor smoothly
model: ../models/wing_nut.yaml
initial:
  attitude_wxyz: [2, 0, 0, 0]
  angular_momentum: [1.0e-8, 2.1252e-5, 1.0e-8]
stages:
  - {name: spin, hold: default, until: 10}
  - {to: tilted, law: smoothstep, until: 12.5}
  - {hold: tilted, until: 20}
integrator:
  method: rkf78
  rtol: 1.0e-12
  atol: 1.0e-14
  step: 0.01
  max_step: 0.5
output:
  dt: 0.05
  csv: true
)";

const char* const kGeometryProfile = R"(name: smallsat_deploy
model: smallsat.yaml
mode: geometry
coupling: exact
initial:
  attitude_wxyz: [0.5, 0.5, 0.5, 0.5]
  angular_velocity: [0.001, 0.52, 0.001]
stages:
  - {name: closed spin, hold: closed, start: 5, until: 60}
  - {name: half deploy, to: half_open, law: minimum-jerk, until: 75}
  - {name: full deploy, to: open, law: linear, until: 90}
  - {name: open, hold: open, until: 300}
)";

class YamlLoaderTest : public testing::TempDirTest {
 protected:
  /// Writes the two models and returns nothing; profiles refer to them.
  void WriteModels() {
    Write("models/wing_nut.yaml", kTensorModel);
    Write("smallsat.yaml", kHingedModel);
  }

  /// The message of the std::exception that f throws ("" if none).
  template <typename F>
  static std::string ErrorOf(F f) {
    try {
      f();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(YamlLoaderTest, LoadsTensorModel) {
  const std::string path = Write("wing_nut.yaml", kTensorModel);
  const model::Model m = LoadModel(path);
  EXPECT_EQ(m.name, "wing_nut");
  EXPECT_EQ(m.description, "the wing nut of the seed thesis");
  EXPECT_EQ(m.source, path);
  EXPECT_EQ(m.kind, model::ModelKind::kTensors);
  ASSERT_EQ(m.configurations.size(), 2u);
  EXPECT_EQ(m.configurations[0].name, "default");
  EXPECT_EQ(m.configurations[0].J_B,
            Vec3(3.036e-6, 2.741e-6, 0.699e-6).asDiagonal().toDenseMatrix());
  EXPECT_EQ(m.configurations[1].name, "tilted");
  Mat3 tilted;
  tilted << 2, 0.1, 0, 0.1, 3, 0, 0, 0, 4;
  EXPECT_EQ(m.configurations[1].J_B, tilted);
  EXPECT_EQ(m.configurations[1].hinge_angles.size(), 0);
}

TEST_F(YamlLoaderTest, LoadsHingedModel) {
  const std::string path = Write("smallsat.yaml", kHingedModel);
  const model::Model m = LoadModel(path);
  EXPECT_EQ(m.name, "smallsat");
  EXPECT_EQ(m.kind, model::ModelKind::kHinged);
  EXPECT_EQ(m.hinged.hub.body.mass, 80.0);
  EXPECT_EQ(m.hinged.hub.com_B, Vec3(0.01, 0, 0));
  EXPECT_EQ(m.hinged.hub.body.inertia_cm, model::BoxInertia(80.0, Vec3(0.6, 0.6, 0.8)));
  ASSERT_EQ(m.hinged.panels.size(), 2u);
  const model::Panel& p0 = m.hinged.panels[0];
  EXPECT_EQ(p0.name, "wing_plus_x");
  EXPECT_EQ(p0.body.mass, 6.0);
  EXPECT_EQ(p0.body.inertia_cm, model::BoxInertia(6.0, Vec3(1.0, 0.02, 0.7)));
  EXPECT_EQ(p0.hinge_point_B, Vec3(0.3, 0, 0));
  EXPECT_EQ(p0.hinge_axis_B, Vec3(0, 1, 0)) << "hinge axes are normalized on load";
  EXPECT_EQ(p0.com_offset_B, Vec3(0.5, 0, 0));
  const model::Panel& p1 = m.hinged.panels[1];
  EXPECT_EQ(p1.body.inertia_cm, Vec3(0.25, 0.74, 0.5).asDiagonal().toDenseMatrix());
  EXPECT_EQ(p1.hinge_axis_B, Vec3(0, -1, 0));
  EXPECT_EQ(m.hinged.hub.com_B, Vec3(0.01, 0, 0));
  ASSERT_EQ(m.configurations.size(), 3u);
  EXPECT_EQ(m.configurations[1].name, "half_open");
  ASSERT_EQ(m.configurations[1].hinge_angles.size(), 2);
  EXPECT_DOUBLE_EQ(m.configurations[0].hinge_angles[0], -90 * kDeg);
  EXPECT_DOUBLE_EQ(m.configurations[0].hinge_angles[1], 90 * kDeg);
  EXPECT_DOUBLE_EQ(m.configurations[1].hinge_angles[1], 45 * kDeg);
  EXPECT_EQ(m.configurations[2].hinge_angles, Eigen::Vector2d(0, 0));
}

// Panel trees: `parent: <panel name>` (default: the hub); a parent may come after its
// children.
const char* const kTreeModel = R"(name: tree
kind: hinged
hub: {mass: 80.0, box: [0.6, 0.6, 0.8]}
panels:
  - {name: tip, parent: mid, mass: 1.0, box: [0.4, 0.02, 0.5], hinge_point: [0.4, 0, 0], hinge_axis: [0, 0, 1], com_offset: [0.2, 0, 0]}
  - {name: root, mass: 2.0, box: [0.4, 0.02, 0.5], hinge_point: [0.3, 0, 0], hinge_axis: [0, 1, 0], com_offset: [0.2, 0, 0]}
  - {name: mid, parent: root, mass: 1.5, box: [0.4, 0.02, 0.5], hinge_point: [0.4, 0, 0], hinge_axis: [0, 1, 1], com_offset: [0.2, 0, 0]}
  - {name: side, parent: root, mass: 1.0, box: [0.4, 0.02, 0.5], hinge_point: [0.2, 0, 0.25], hinge_axis: [1, 0, 0], com_offset: [0, 0, 0.2]}
configurations:
  closed: {hinge_angles_deg: [0, 0, 0, 0]}
)";

TEST_F(YamlLoaderTest, LoadsPanelTrees) {
  const model::Model m = LoadModel(Write("tree.yaml", kTreeModel));
  ASSERT_EQ(m.hinged.panels.size(), 4u);
  EXPECT_EQ(m.hinged.panels[0].parent, 2);   // tip on mid
  EXPECT_EQ(m.hinged.panels[1].parent, -1);  // root on the hub
  EXPECT_EQ(m.hinged.panels[2].parent, 1);   // mid on root
  EXPECT_EQ(m.hinged.panels[3].parent, 1);   // side on root
  EXPECT_LT((m.hinged.panels[2].hinge_axis_B - Vec3(0, 1, 1) / std::sqrt(2.0)).norm(), 1e-16);
}

TEST(ProjectFilesTest, TwoSegmentWingsAreATree) {
  const model::Model m =
      LoadModel(std::string(DEPLOYSIM_SOURCE_DIR) + "/models/smallsat_two_segment.yaml");
  ASSERT_EQ(m.hinged.panels.size(), 4u);
  EXPECT_EQ(m.hinged.panels[0].parent, -1);  // inner_plus_x on the hub
  EXPECT_EQ(m.hinged.panels[1].parent, 0);   // outer_plus_x on inner_plus_x
  EXPECT_EQ(m.hinged.panels[2].parent, -1);
  EXPECT_EQ(m.hinged.panels[3].parent, 2);
}

TEST_F(YamlLoaderTest, RejectsUnknownParentsAndCycles) {
  const auto load = [&](const std::string& from, const std::string& to) {
    std::string text = kTreeModel;
    text.replace(text.find(from), from.size(), to);
    const std::string path = Write("tree.yaml", text);
    return ErrorOf([&] { (void)LoadModel(path); });
  };
  const std::string where = (dir() / "tree.yaml").string() + ": ";
  EXPECT_EQ(load("parent: mid,", "parent: middle,"),
            where +
                "panels[0].parent = middle: no panel of that name (rule: parent names another "
                "panel, or is left out for the hub; panels: tip, root, mid, side)");
  EXPECT_EQ(load("parent: mid,", "parent: tip,"),
            where +
                "panels[0] (tip).parent = tip: a panel cannot be its own parent (rule: panels "
                "form a tree)");
  EXPECT_EQ(load("{name: root,", "{name: root, parent: tip,"),
            where +
                "panels[0] (tip).parent = mid: the panels' parents form a cycle (tip -> mid -> "
                "root -> tip) (rule: panels form a tree)");
  EXPECT_EQ(load("parent: mid,", "parent: [mid],"),
            where + "panels[0].parent = [mid]: expected a string");
}

TEST_F(YamlLoaderTest, HubComDefaultsToTheOrigin) {
  std::string text = kHingedModel;
  text.erase(text.find("  com: [0.01, 0, 0]\n"), std::string("  com: [0.01, 0, 0]\n").size());
  EXPECT_EQ(LoadModel(Write("m.yaml", text)).hinged.hub.com_B, Vec3::Zero());
}

TEST_F(YamlLoaderTest, LoadsTensorProfile) {
  WriteModels();
  const std::string path = Write("profiles/wing_nut_flip.yaml", kTensorProfile);
  const schedule::Profile p = LoadProfile(path);
  EXPECT_EQ(p.name, "wing_nut_flip");
  EXPECT_EQ(p.description, "spin, then change the tensor smoothly");
  EXPECT_EQ(p.source, path);
  EXPECT_EQ(p.text, kTensorProfile);
  EXPECT_EQ(p.model.name, "wing_nut");
  EXPECT_EQ(fs::path(p.model.source), (dir() / "models/wing_nut.yaml").lexically_normal());
  EXPECT_EQ(p.mode, schedule::Mode::kTensor) << "the only mode of a tensor model";
  EXPECT_EQ(p.coupling, schedule::Coupling::kQuasiRigid) << "the only coupling in tensor mode";

  EXPECT_EQ(math::ToWxyz(p.initial.q_NB), math::Vec4(1, 0, 0, 0)) << "normalized on load";
  EXPECT_FALSE(p.initial.w_NB_B.has_value());
  ASSERT_TRUE(p.initial.H_B.has_value());
  EXPECT_EQ(*p.initial.H_B, Vec3(1.0e-8, 2.1252e-5, 1.0e-8));

  ASSERT_EQ(p.stages.size(), 3u);
  EXPECT_EQ(p.stages[0].name, "spin");
  EXPECT_TRUE(p.stages[0].is_hold());
  EXPECT_EQ(p.stages[0].from, "default");
  EXPECT_EQ(p.stages[0].t_begin, 0.0);
  EXPECT_EQ(p.stages[0].t_end, 10.0);
  EXPECT_EQ(p.stages[1].name, "to tilted") << "default name of a move";
  EXPECT_EQ(p.stages[1].from, "default");
  EXPECT_EQ(p.stages[1].to, "tilted");
  EXPECT_EQ(p.stages[1].law, schedule::Law::kSmoothstep);
  EXPECT_EQ(p.stages[1].t_begin, 10.0);
  EXPECT_EQ(p.stages[1].t_end, 12.5);
  EXPECT_EQ(p.stages[2].name, "hold tilted");
  EXPECT_EQ(p.stages[2].t_begin, 12.5);
  EXPECT_EQ(p.t_end(), 20.0);

  EXPECT_EQ(p.integrator.method, "rkf78");
  EXPECT_EQ(p.integrator.rtol, 1.0e-12);
  EXPECT_EQ(p.integrator.atol, 1.0e-14);
  EXPECT_EQ(p.integrator.step, 0.01);
  EXPECT_EQ(p.integrator.max_step, 0.5);
  EXPECT_EQ(p.output.dt, 0.05);
  EXPECT_TRUE(p.output.csv);
}

TEST_F(YamlLoaderTest, LoadsGeometryProfile) {
  WriteModels();
  const schedule::Profile p = LoadProfile(Write("deploy.yaml", kGeometryProfile));
  EXPECT_EQ(p.mode, schedule::Mode::kGeometry);
  EXPECT_EQ(p.coupling, schedule::Coupling::kExact);
  EXPECT_EQ(p.model.kind, model::ModelKind::kHinged);
  EXPECT_EQ(math::ToWxyz(p.initial.q_NB), math::Vec4(0.5, 0.5, 0.5, 0.5));
  ASSERT_TRUE(p.initial.w_NB_B.has_value());
  EXPECT_EQ(*p.initial.w_NB_B, Vec3(0.001, 0.52, 0.001));
  ASSERT_EQ(p.stages.size(), 4u);
  EXPECT_EQ(p.t_begin(), 5.0) << "start: on the first stage";
  EXPECT_EQ(p.stages[1].name, "half deploy");
  EXPECT_EQ(p.stages[1].from, "closed");
  EXPECT_EQ(p.stages[1].law, schedule::Law::kMinimumJerk);
  EXPECT_EQ(p.stages[2].from, "half_open");
  EXPECT_EQ(p.stages[2].to, "open");
  EXPECT_EQ(p.stages[2].law, schedule::Law::kLinear);
  EXPECT_TRUE(p.stages[3].is_hold());
  // Defaults of the optional blocks.
  const schedule::IntegratorSpec defaults;
  EXPECT_EQ(p.integrator.method, defaults.method);
  EXPECT_EQ(p.integrator.rtol, defaults.rtol);
  EXPECT_EQ(p.output.dt, schedule::OutputSpec().dt);
  EXPECT_FALSE(p.output.csv);
}

TEST_F(YamlLoaderTest, NonUnitQuaternionIsNormalized) {
  WriteModels();
  std::string text = kGeometryProfile;
  const std::string from = "[0.5, 0.5, 0.5, 0.5]";
  text.replace(text.find(from), from.size(), "[0, 3, 0, 4]");
  const schedule::Profile p = LoadProfile(Write("q.yaml", text));
  EXPECT_EQ(math::ToWxyz(p.initial.q_NB), math::Vec4(0, 0.6, 0, 0.8));
}

TEST_F(YamlLoaderTest, MessageFormatNamesFileKeyValueAndRule) {
  WriteModels();
  std::string text = kTensorProfile;
  text.replace(text.find("until: 20}"), 10, "until: 12}");
  const std::string path = Write("profiles/p.yaml", text);
  EXPECT_EQ(ErrorOf([&] { (void)LoadProfile(path); }),
            path +
                ": stages[2].until = 12: stage end times must increase (previous stage ends "
                "at 12.5)");

  std::string model = kHingedModel;
  model.replace(model.find("  mass: 80.0\n"), 13, "  mass: 80.0\n  colour: red\n");
  const std::string model_path = Write("m.yaml", model);
  EXPECT_EQ(ErrorOf([&] { (void)LoadModel(model_path); }),
            model_path + ": hub.colour = red: unknown key (allowed: mass, com, box, inertia)");
}

TEST_F(YamlLoaderTest, SyntaxErrorsReportLineAndColumn) {
  const std::string path =
      Write("broken.yaml", "name: x\nkind: tensors\nconfigurations: {a: [1, 2}\n");
  const std::string message = ErrorOf([&] { (void)LoadModel(path); });
  EXPECT_EQ(message.rfind(path + ": line 3, column ", 0), 0u) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
}

TEST_F(YamlLoaderTest, UnreadableFilesAreRuntimeErrors) {
  EXPECT_THROW((void)LoadModel(Path("missing.yaml")), std::runtime_error);
  EXPECT_THROW((void)LoadProfile(Path("missing.yaml")), std::runtime_error);
  EXPECT_THROW((void)LoadModel(dir().string()), std::runtime_error);
  const std::string message = ErrorOf([&] { (void)LoadProfile(Path("missing.yaml")); });
  EXPECT_EQ(message.rfind(Path("missing.yaml") + ": cannot read", 0), 0u) << message;
}

TEST_F(YamlLoaderTest, BadContentIsInvalidArgument) {
  const std::string path = Write(
      "m.yaml", "name: x\nkind: tensors\nconfigurations: {a: {principal_moments: [1, 1, 3]}}\n");
  EXPECT_THROW((void)LoadModel(path), std::invalid_argument);
}

TEST_F(YamlLoaderTest, OverridesReplaceSettingsAndRevalidate) {
  WriteModels();
  schedule::Profile p = LoadProfile(Write("deploy.yaml", kGeometryProfile));
  ProfileOverrides o;
  o.method = "rk4";
  o.step = 0.01;
  o.rtol = 1e-9;
  o.atol = 1e-11;
  o.output_dt = 0.5;
  o.coupling = "quasi-rigid";
  ApplyOverrides(p, o);
  EXPECT_EQ(p.integrator.method, "rk4");
  EXPECT_EQ(p.integrator.step, 0.01);
  EXPECT_EQ(p.integrator.rtol, 1e-9);
  EXPECT_EQ(p.integrator.atol, 1e-11);
  EXPECT_EQ(p.output.dt, 0.5);
  EXPECT_EQ(p.coupling, schedule::Coupling::kQuasiRigid);
  EXPECT_EQ(p.mode, schedule::Mode::kGeometry) << "unset overrides keep the profile's value";

  ProfileOverrides to_tensor;
  to_tensor.mode = "tensor";
  ApplyOverrides(p, to_tensor);
  EXPECT_EQ(p.mode, schedule::Mode::kTensor);
}

TEST_F(YamlLoaderTest, InvalidOverridesThrowAndLeaveTheProfileUnchanged) {
  WriteModels();
  const schedule::Profile original = LoadProfile(Write("profiles/flip.yaml", kTensorProfile));
  auto rejected = [&](const ProfileOverrides& o, const std::string& expected) {
    schedule::Profile p = original;
    const std::string message = ErrorOf([&] { ApplyOverrides(p, o); });
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.rfind(original.source + ": ", 0), 0u) << message;
    EXPECT_EQ(p.integrator.method, original.integrator.method);
    EXPECT_EQ(p.integrator.step, original.integrator.step);
    EXPECT_EQ(p.integrator.rtol, original.integrator.rtol);
    EXPECT_EQ(p.mode, original.mode);
    EXPECT_EQ(p.coupling, original.coupling);
  };
  ProfileOverrides o;
  o.method = "euler";
  rejected(o, "integrator.method = euler: unknown integrator");
  o = {};
  o.method = "thesis-euler";
  o.step = 0.0;
  rejected(o, "the fixed-step method thesis-euler needs integrator.step > 0");
  o = {};
  o.rtol = -1.0;
  rejected(o, "integrator.rtol = -1");
  o = {};
  o.mode = "geometry";
  rejected(o, "geometry mode needs a hinged model");
  o = {};
  o.coupling = "exact";
  rejected(o, "exact coupling needs mode geometry");
  o = {};
  o.coupling = "loose";
  rejected(o, "coupling = loose (override): unknown coupling (valid: quasi-rigid, exact)");
  o = {};
  o.output_dt = -0.1;
  rejected(o, "output.dt = -0.1: must be > 0");
}

TEST(ParseNamesTest, ModeAndCoupling) {
  EXPECT_EQ(ParseMode("tensor"), schedule::Mode::kTensor);
  EXPECT_EQ(ParseMode("geometry"), schedule::Mode::kGeometry);
  EXPECT_EQ(ParseCoupling("quasi-rigid"), schedule::Coupling::kQuasiRigid);
  EXPECT_EQ(ParseCoupling("exact"), schedule::Coupling::kExact);
  EXPECT_THROW((void)ParseMode("Tensor"), std::invalid_argument);
  EXPECT_THROW((void)ParseCoupling("quasi_rigid"), std::invalid_argument);
}

/// Every model and profile shipped with the project loads. Missing files are a failure,
/// not a skip: the folders exist and hold at least the files the README and the
/// benchmarks name.
TEST(ProjectFilesTest, ShippedModelsAndProfilesLoad) {
  for (const char* folder : {"models", "deployment_profiles"}) {
    const fs::path dir = fs::path(DEPLOYSIM_SOURCE_DIR) / folder;
    ASSERT_TRUE(fs::is_directory(dir)) << dir << " is missing";
    const bool models = std::string(folder) == "models";
    const std::vector<std::string> required =
        models ? std::vector<std::string>{"wing_nut.yaml", "smallsat.yaml", "asymmetric_sat.yaml",
                                          "smallsat_two_segment.yaml"}
               : std::vector<std::string>{"wing_nut.yaml", "smallsat_three_stage.yaml",
                                          "asymmetric_sat_deploy.yaml",
                                          "smallsat_two_segment_deploy.yaml"};
    for (const std::string& name : required) {
      EXPECT_TRUE(fs::exists(dir / name)) << (dir / name) << " is missing";
    }
    int loaded = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
      if (e.path().extension() != ".yaml") continue;
      const std::string path = e.path().string();
      if (models) {
        EXPECT_NO_THROW((void)LoadModel(path)) << path;
      } else {
        EXPECT_NO_THROW((void)LoadProfile(path)) << path;
      }
      ++loaded;
    }
    EXPECT_GE(loaded, 1) << "no *.yaml in " << dir;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
