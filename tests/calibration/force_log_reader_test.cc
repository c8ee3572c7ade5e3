#include "calibration/force_log_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "model/units.h"
#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

std::string WriteLog(const std::string& name, const std::string& text) {
  const std::string path =
      (TestScratch().dir() / ("softbench_" + name)).string();
  std::ofstream(path) << text;
  return path;
}

// A short well-formed test: zero pressure, a ramp up and down, in kPa.
std::string GoodLog() {
  std::string text = "time_s,pressure_kpa,fx_n,fy_n,fz_n,tx_nm,ty_nm,tz_nm\n";
  const double levels[] = {0, 10, 20, 30, 20, 10, 0};
  int row = 0;
  for (double p : levels) {
    for (int i = 0; i < 5; ++i, ++row) {
      text += std::to_string(0.01 * row) + "," + std::to_string(p) + ",0,1.5," +
              std::to_string(0.157 * p + 0.01 * (i - 2)) + ",0,0,0\n";
    }
  }
  return text;
}

// Reads `text` as one test; returns the InputError message, or "" on success.
std::string ReadError(const std::string& name, const std::string& text,
                      ForceTest* test = nullptr,
                      ForceLogReadSummary* summary = nullptr,
                      const ForceLogColumns& columns = ForceLogColumns()) {
  ForceTest local_test;
  ForceLogReadSummary local_summary;
  ForceLogReadOptions options;
  options.max_skipped_fraction = 0.2;
  return InputErrorOf([&] {
    ReadForceTestCsv(WriteLog(name, text), columns, options, 0,
                     test ? test : &local_test,
                     summary ? summary : &local_summary, nullptr, nullptr);
  });
}

TEST(ForceLogReader, SplitsRampsAndZeroPressureRows) {
  ForceTest test;
  ForceLogReadSummary summary;
  ASSERT_EQ(ReadError("good.csv", GoodLog(), &test, &summary), "");
  EXPECT_EQ(summary.rows, 35);
  EXPECT_EQ(summary.rows_skipped, 0);
  EXPECT_EQ(test.statistics.ZeroPressure().count, 10);
  EXPECT_EQ(test.statistics.Phase(RampPhase::kUp).count, 20);
  EXPECT_EQ(test.statistics.Phase(RampPhase::kDown).count, 15);
  EXPECT_NEAR(test.statistics.All().mean[2], 1.5, 1e-12);
  EXPECT_NEAR(test.statistics.max_pressure_mpa, 0.030, 1e-12);
}

TEST(ForceLogReader, MapsSensorAxesWithSigns) {
  ForceLogColumns columns;
  columns.shear = "fy_n";
  columns.shear_sign = -1.0;
  ForceTest test;
  ForceLogReadSummary summary;
  ASSERT_EQ(ReadError("signs.csv", GoodLog(), &test, &summary, columns), "");
  EXPECT_NEAR(test.statistics.All().mean[2], -1.5, 1e-12);
}

TEST(ForceLogReader, NamesAMissingColumn) {
  ForceLogColumns columns;
  columns.axial = "force_z";
  const std::string error =
      ReadError("missing.csv", GoodLog(), nullptr, nullptr, columns);
  EXPECT_NE(error.find("softbench_missing.csv"), std::string::npos) << error;
  EXPECT_NE(error.find("'force_z'"), std::string::npos) << error;
  EXPECT_NE(error.find("axial force"), std::string::npos) << error;
  // Two quantities mapped to one column.
  columns.axial = columns.shear;
  const std::string same =
      ReadError("same.csv", GoodLog(), nullptr, nullptr, columns);
  EXPECT_NE(same.find("header: the axial force and the shear force are both "
                      "column '" +
                      columns.shear + "'"),
            std::string::npos)
      << same;
}

TEST(ForceLogReader, CountsAndSkipsNonFiniteAndOutOfRangeRowsWithLines) {
  std::string text = GoodLog();
  text += "0.40,0,0,nan,0,0,0,0\n";   // line 37
  text += "0.41,0,0,0,inf,0,0,0\n";   // line 38
  text += "0.42,0,0,0,900,0,0,0\n";   // line 39: beyond the sensor
  text += "0.43,5000,0,0,0,0,0,0\n";  // line 40: beyond the regulator
  text += "0.44,0,0,0,abc,0,0,0\n";   // line 41
  ForceTest test;
  ForceLogReadSummary summary;
  ASSERT_EQ(ReadError("bad_rows.csv", text, &test, &summary), "");
  EXPECT_EQ(summary.rows, 35);
  EXPECT_EQ(summary.rows_skipped, 5);
  ASSERT_EQ(summary.skipped_examples.size(), 5u);
  EXPECT_NE(summary.skipped_examples[0].find(":37: shear force 'nan'"),
            std::string::npos)
      << summary.skipped_examples[0];
  EXPECT_NE(summary.skipped_examples[2].find(":39: a force beyond"),
            std::string::npos);
  EXPECT_NE(summary.skipped_examples[3].find(":40: pressure 5000"),
            std::string::npos);
  EXPECT_NE(summary.skipped_examples[4].find(":41: axial force 'abc'"),
            std::string::npos);
  // Skipped rows never reach the statistics.
  EXPECT_EQ(test.statistics.All().count, 35);
}

TEST(ForceLogReader, RefusesALogThatIsMostlyUnusable) {
  std::string text = GoodLog();
  for (int i = 0; i < 10; ++i) text += "9,0,0,nan,0,0,0,0\n";
  const std::string error = ReadError("mostly_bad.csv", text);
  EXPECT_NE(error.find("10 of 45 rows are unusable"), std::string::npos)
      << error;
}

TEST(ForceLogReader, RefusesTimeGoingBackwards) {
  std::string text = GoodLog();
  text += "0.1,0,0,0,0,0,0,0\n";
  const std::string error = ReadError("unsorted.csv", text);
  EXPECT_NE(error.find(":37: time 0.1 s is before"), std::string::npos)
      << error;
}

TEST(ForceLogReader, RefusesATestWithoutZeroPressureRows) {
  std::string text = "time_s,pressure_kpa,fx_n,fy_n,fz_n\n";
  for (int i = 0; i < 10; ++i) {
    text += std::to_string(i) + ",20,0,0,3\n";
  }
  const std::string error = ReadError("no_zero.csv", text);
  EXPECT_NE(error.find("no rows at zero pressure"), std::string::npos) << error;
}

TEST(ForceLogReader, RefusesARowWithTheWrongFieldCount) {
  std::string text = GoodLog();
  text += "0.5,0,0,0\n";
  const std::string error = ReadError("short_row.csv", text);
  EXPECT_NE(error.find(":37: has 4 fields"), std::string::npos) << error;
}

TEST(ForceLogReader, ReadsACombinedLogAndRefusesInterleavedTests) {
  std::string header =
      "test_id,delta_length_mm,theta_deg,time_s,pressure_kpa,fy_n,fz_n\n";
  std::string a, b;
  for (int i = 0; i < 4; ++i) {
    a += "a,1,10," + std::to_string(i) + "," + std::to_string(10 * (i % 3)) +
         ",0.5,2\n";
    b += "b,-1,0," + std::to_string(i) + "," + std::to_string(10 * (i % 3)) +
         ",0.1,1\n";
  }
  ForceLogReadSummary summary;
  const std::vector<ForceTest> tests = ReadCombinedForceLog(
      WriteLog("combined.csv", header + a + b), ForceLogColumns(),
      ForceLogReadOptions(), &summary, nullptr, nullptr);
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_EQ(tests[0].id, "a");
  EXPECT_DOUBLE_EQ(tests[0].nominal_delta_length_mm, 1.0);
  EXPECT_NEAR(tests[0].nominal_theta_rad, 0.174533, 1e-6);
  EXPECT_EQ(tests[1].statistics.All().count, 4);
  EXPECT_EQ(summary.rows, 8);

  EXPECT_THAT(
      [&] {
        ReadCombinedForceLog(WriteLog("interleaved.csv", header + a + b + a),
                             ForceLogColumns(), ForceLogReadOptions(), &summary,
                             nullptr, nullptr);
      },
      ThrowsInputErrorWith("interleaved.csv",
                           ":10:", "test 'a' appears again"));
  std::string changed = a;
  changed.replace(changed.rfind("a,1,10"), 6, "a,2,10");
  EXPECT_THAT(
      [&] {
        ReadCombinedForceLog(WriteLog("changed.csv", header + changed),
                             ForceLogColumns(), ForceLogReadOptions(), &summary,
                             nullptr, nullptr);
      },
      ThrowsInputErrorWith("changed.csv", "",
                           "delta_length_mm changes within"));
}

// A bend of 90 deg or more, or a stretch of 100 mm, is no configuration a
// clamp can hold: a slip of unit (radians, micrometres) the fit would
// otherwise take at face value.
TEST(ForceLogReader, RefusesAConfigurationNoClampCanHold) {
  const std::string header =
      "test_id,delta_length_mm,theta_deg,time_s,pressure_kpa,fy_n,fz_n\n";
  const struct {
    std::string row, expected;
  } cases[] = {
      {"a,1,300,0,0,0,0\n", ":2: test 'a': a bend of 300"},
      {"a,1,-90,0,0,0,0\n", ":2: test 'a': a bend of -90"},
      {"a,2000,10,0,0,0,0\n", ":2: test 'a': a length change of 2000"},
  };
  for (const auto& c : cases) {
    ForceLogReadSummary summary;
    EXPECT_THAT(
        [&] {
          ReadCombinedForceLog(WriteLog("implausible.csv", header + c.row),
                               ForceLogColumns(), ForceLogReadOptions(),
                               &summary, nullptr, nullptr);
        },
        ThrowsInputErrorWith("implausible.csv", "", c.expected));
  }
  // A measured angle in the wrong unit is refused even beside a good
  // nominal one.
  ForceTest radians;
  radians.nominal_theta_rad = DegToRad(30.0);
  radians.measured_theta_rad = DegToRad(30.0 * 57.3);  // degrees twice
  ASSERT_TRUE(ImplausibleTest(radians));
  EXPECT_NE(ImplausibleTest(radians)->find("measured: a bend of"),
            std::string::npos);
  radians.measured_theta_rad.reset();
  radians.nominal_theta_rad = DegToRad(400.0);
  radians.measured_theta_rad = DegToRad(30.0);
  EXPECT_NE(ImplausibleTest(radians)->find("a bend of 400 deg"),
            std::string::npos);
  EXPECT_FALSE(ImplausibleConfiguration(-3.0, 30.0));
  EXPECT_FALSE(ImplausibleConfiguration(3.0, -89.9));
}

}  // namespace
}  // namespace softbench
