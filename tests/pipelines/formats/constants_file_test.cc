#include "pipelines/formats/constants_file.h"

#include <gtest/gtest.h>

#include "tests/support/input_error_matchers.h"
#include "util/input_error.h"

namespace softbench {
namespace {

TEST(ConstantsFile, SampleFileHoldsTheThesisConstants) {
  const ConstantsFile file = LoadConstantsFile(
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/constants/thesis.yaml");
  const ActuatorConstants defaults;
  EXPECT_EQ(file.constants.axial_area_mm2, defaults.axial_area_mm2);
  EXPECT_EQ(file.constants.shear_area_factor_mm2_per_rad,
            defaults.shear_area_factor_mm2_per_rad);
  EXPECT_EQ(file.constants.linear_stiffness_n_per_mm,
            defaults.linear_stiffness_n_per_mm);
  EXPECT_EQ(file.constants.torsional_factor_n_per_rad,
            defaults.torsional_factor_n_per_rad);
  EXPECT_EQ(file.constants.natural_length_mm, defaults.natural_length_mm);
  EXPECT_EQ(file.variant, "small-angle");
}

std::string ConstantsError(const std::string& yaml) {
  return InputErrorOf([&] { ParseConstantsYaml(yaml, "c.yaml"); });
}

TEST(ConstantsFile, ErrorsNameTheKey) {
  const std::string base =
      "axial_area_mm2: 150\nshear_area_factor_mm2_per_rad: 100\n"
      "linear_stiffness_n_per_mm: 2.5\n";
  EXPECT_NE(ConstantsError(base).find("torsional_factor_n_per_rad: missing"),
            std::string::npos)
      << ConstantsError(base);
  EXPECT_EQ(ConstantsError(base + "torsional_factor_n_per_rad: 20\n"), "");
  EXPECT_NE(ConstantsError(base + "torsional_factor_n_per_rad: 20\nk_s: 3\n")
                .find("c.yaml:5: k_s: unknown key"),
            std::string::npos);
  EXPECT_NE(
      ConstantsError(base + "torsional_factor_n_per_rad: 20\nvariant: exact\n")
          .find("'exact' is not one of"),
      std::string::npos);
  EXPECT_NE(
      ConstantsError("axial_area_mm2: 150\nshear_area_factor_mm2_per_rad: 1\n"
                     "linear_stiffness_n_per_mm: -2\n"
                     "torsional_factor_n_per_rad: 20\n")
          .find("k_s must be"),
      std::string::npos);
}

}  // namespace
}  // namespace softbench
