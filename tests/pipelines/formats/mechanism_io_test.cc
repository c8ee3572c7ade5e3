#include "pipelines/formats/mechanism_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "model/equilibrium.h"
#include "pipelines/formats/builtin_mechanisms.h"
#include "tests/model/thesis_mechanisms.h"
#include "tests/support/input_error_matchers.h"
#include "util/input_error.h"
#include "util/text_file.h"

namespace softbench {
namespace {

void ExpectSameMechanism(const Mechanism& a, const Mechanism& b) {
  ASSERT_EQ(a.NumHeads(), b.NumHeads());
  ASSERT_EQ(a.NumActuators(), b.NumActuators());
  for (int h = 0; h < a.NumHeads(); ++h) {
    EXPECT_EQ(a.heads[h].name, b.heads[h].name);
    EXPECT_LT((a.heads[h].rest_mm - b.heads[h].rest_mm).norm(), 1e-9);
  }
  for (int k = 0; k < a.NumActuators(); ++k) {
    const Actuator& x = a.actuators[k];
    const Actuator& y = b.actuators[k];
    EXPECT_NEAR(x.rotation_rad, y.rotation_rad, 1e-12);
    EXPECT_EQ(x.anchor.kind, y.anchor.kind);
    EXPECT_EQ(x.anchor.index, y.anchor.index);
    EXPECT_EQ(x.head, y.head);
    EXPECT_LT((a.AnchorRestPosition(x) - b.AnchorRestPosition(y)).norm(), 1e-9);
  }
}

TEST(MechanismIo, BundledFilesMatchTheSpecGeometry) {
  ExpectSameMechanism(LoadMechanism("delta"), testing::DeltaMechanism());
  ExpectSameMechanism(LoadMechanism("floating"), testing::FloatingMechanism());
}

// Every file of samples/mechanisms/ is a built-in mechanism of its name,
// byte for byte, and there are no others.
TEST(MechanismIo, BuiltinNamesReadTheSampleFiles) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(
           std::string(SOFTBENCH_SOURCE_DIR) + "/samples/mechanisms")) {
    if (entry.path().extension() == ".yaml") {
      files.push_back(entry.path().stem().string());
      const BuiltinMechanism* builtin = nullptr;
      for (const BuiltinMechanism& b : BuiltinMechanisms()) {
        if (b.name == files.back()) builtin = &b;
      }
      ASSERT_NE(builtin, nullptr) << entry.path();
      EXPECT_EQ(builtin->yaml,
                ReadTextFile(entry.path().string(), "mechanism", 1 << 20));
    }
  }
  std::sort(files.begin(), files.end());
  EXPECT_EQ(BuiltinMechanismNames(), files);
  for (const std::string& name : BuiltinMechanismNames()) {
    ExpectSameMechanism(LoadMechanism(name),
                        LoadMechanism(std::string(SOFTBENCH_SOURCE_DIR) +
                                      "/samples/mechanisms/" + name + ".yaml"));
  }
}

// The message thrown for `yaml`, or "" when it parses.
std::string MechanismError(const std::string& yaml) {
  return InputErrorOf([&] { ParseMechanismYaml(yaml, "m.yaml"); });
}

constexpr char kValid[] = R"(name: one
heads:
  - {name: h, rest_mm: [0, 0]}
anchors:
  - {name: a, position_mm: [0, -27]}
actuators:
  - {name: '1', rotation_deg: 0, anchor: a, head: h}
)";

TEST(MechanismIo, ParsesAUserWrittenFile) {
  EXPECT_EQ(MechanismError(kValid), "");
  EXPECT_EQ(ParseMechanismYaml(kValid, "m.yaml").NumActuators(), 1);
}

TEST(MechanismIo, ErrorsNameTheLineAndTheField) {
  std::string yaml = kValid;
  yaml.replace(yaml.find("anchor: a,"), 10, "anchor: b,");
  EXPECT_EQ(MechanismError(yaml).rfind("m.yaml:7: anchor: 'b' is neither", 0),
            0)
      << MechanismError(yaml);

  yaml = kValid;
  yaml.replace(yaml.find("rotation_deg: 0"), 15, "rotation_deg: up");
  EXPECT_EQ(
      MechanismError(yaml).rfind("m.yaml:7: rotation_deg: 'up' is not", 0), 0)
      << MechanismError(yaml);

  yaml = kValid;
  yaml.replace(yaml.find("rest_mm"), 7, "rest");
  EXPECT_EQ(MechanismError(yaml).rfind("m.yaml:3: rest: unknown key", 0), 0)
      << MechanismError(yaml);

  yaml = kValid;
  yaml.replace(yaml.find("[0, -27]"), 8, "[0, -27");
  EXPECT_NE(MechanismError(yaml).find("not valid YAML"), std::string::npos)
      << MechanismError(yaml);

  yaml = kValid;
  yaml.replace(yaml.find("rotation_deg: 0"), 15, "rotation_deg: 90");
  EXPECT_EQ(
      MechanismError(yaml).rfind("m.yaml:7: actuator '1': rotation_deg 90", 0),
      0)
      << MechanismError(yaml);
  EXPECT_NE(MechanismError(yaml).find("set rotation_deg to 0 "),
            std::string::npos)
      << MechanismError(yaml);

  EXPECT_NE(MechanismError("name: x\nheads: []\nactuators: []\n").find("heads"),
            std::string::npos);
  EXPECT_NE(MechanismError("- 1\n- 2\n").find("a mechanism file is a map"),
            std::string::npos);

  yaml = std::string(kValid) +
         "  - {name: '1', rotation_deg: 0, anchor: a, head: h}\n";
  EXPECT_EQ(MechanismError(yaml).rfind(
                "m.yaml:8: name: actuator '1' is named twice", 0),
            0)
      << MechanismError(yaml);
  yaml = std::string(kValid) + "actuators: []\n";
  EXPECT_EQ(MechanismError(yaml).rfind("m.yaml:8: actuators: given twice", 0),
            0)
      << MechanismError(yaml);
  yaml = kValid;
  yaml.replace(yaml.find("- {name: h, rest_mm: [0, 0]}"), 28, "- h");
  EXPECT_EQ(
      MechanismError(yaml).rfind("m.yaml:3: heads entry: must be a map", 0), 0)
      << MechanismError(yaml);
}

TEST(MechanismIo, UnknownNameOrMissingFileSaysWhatToGive) {
  const std::string message = InputErrorOf([&] { LoadMechanism("tripod"); });
  EXPECT_NE(message.find("'delta', 'floating'"), std::string::npos);
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

TEST(MechanismIo, DocumentedExampleParsesAndSolves) {
  const std::string doc =
      ReadTextFile(std::string(SOFTBENCH_SOURCE_DIR) + "/docs/file-formats.md",
                   "doc", 1 << 20);
  const size_t begin = doc.find("```yaml\n") + 8;
  const std::string yaml = doc.substr(begin, doc.find("```", begin) - begin);
  const Mechanism chain = ParseMechanismYaml(yaml, "docs/file-formats.md");
  ASSERT_EQ(chain.NumHeads(), 2);
  const EquilibriumProblem problem(chain, ForceModel::SmallAngle({}));
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  EXPECT_TRUE(solver.Solve(Eigen::Vector3d(0.04, 0.0, 0.02), &x).converged());
  EXPECT_GT(x[1], 0.0);  // the bottom actuator pushes h1 toward +z
}

}  // namespace
}  // namespace softbench
