// `softbench synth-forces` and `softbench fit` end to end through files.
#include "pipelines/commands/fit_command.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pipelines/characterisation/force_log_manifest.h"
#include "pipelines/commands/synth_forces_command.h"
#include "pipelines/formats/constants_file.h"
#include "tests/pipelines/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

class FitCommandTest : public ScratchDirectoryTest {
 protected:
  // Synthetic logs, only sensor noise, at a low rate.
  std::string Synthesize(const std::string& name, bool combined) const {
    SynthForcesCommandOptions options;
    options.output_directory = Path(name);
    options.noise_only = true;
    options.combined = combined;
    options.quiet = true;
    options.synthetic.sample_rate_hz = 40.0;
    options.synthetic.seed = 3;
    std::ostringstream out;
    EXPECT_EQ(RunSynthForces(options, out), 0);
    return Path(name) + "/manifest.yaml";
  }
  FitCommandOptions Fit(const std::string& input) const {
    FitCommandOptions options;
    options.input_path = input;
    options.quiet = true;
    return options;
  }
};

TEST_F(FitCommandTest, WritesConstantsThatRecoverTheTruthAndAReport) {
  FitCommandOptions options = Fit(Synthesize("logs", false));
  options.output_path = Path("constants.yaml");
  options.report_directory = Path("report");
  std::ostringstream out;
  ASSERT_EQ(RunFit(options, out), 0);
  EXPECT_NE(out.str().find("54 tests, 168480 rows (0 skipped)"),
            std::string::npos)
      << out.str();
  const ConstantsFile fitted = LoadConstantsFile(options.output_path);
  EXPECT_EQ(fitted.variant, "small-angle");
  const ActuatorConstants truth;
  EXPECT_NEAR(fitted.constants.axial_area_mm2, truth.axial_area_mm2, 0.5);
  EXPECT_NEAR(fitted.constants.shear_area_factor_mm2_per_rad,
              truth.shear_area_factor_mm2_per_rad, 0.6);
  EXPECT_NEAR(fitted.constants.linear_stiffness_n_per_mm,
              truth.linear_stiffness_n_per_mm, 0.005);
  EXPECT_NEAR(fitted.constants.torsional_factor_n_per_rad,
              truth.torsional_factor_n_per_rad, 0.05);
  for (const char* file :
       {"report.html", "fit.json", "models.csv", "configurations.csv",
        "tests.csv", "pressure_bins.csv"}) {
    EXPECT_TRUE(fs::exists(Path("report/") + file)) << file;
  }
  const std::string html = Read(Path("report/report.html"));
  EXPECT_NE(html.find("vegaEmbed('#chart5'"), std::string::npos);
  // The plotting libraries are inlined: the page needs no network.
  EXPECT_EQ(html.find("<script src="), std::string::npos);
  EXPECT_GT(html.size(), 800000u);
  // The page opens in headless Chromium with a clean console and draws
  // every chart (scripts/bootstrap.sh installs Debian's chromium).
  const std::string check = std::string(SOFTBENCH_SOURCE_DIR) +
                            "/report/check_in_chromium.sh " +
                            Path("report/report.html") + " >&2";
  EXPECT_EQ(std::system(check.c_str()), 0) << check;
  // Nothing but the report is left in its parent directory.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir_)) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
  }
}

TEST_F(FitCommandTest, CombinedLogGivesTheSameFitAsPerTestFiles) {
  const FitRun separate = RunFitAnalysis(
      FitAnalysisOptionsFromFlags(Fit(Synthesize("files", false))));
  FitCommandOptions combined_options = Fit(Path("combined") + "/forces.csv");
  Synthesize("combined", true);
  const FitRun combined =
      RunFitAnalysis(FitAnalysisOptionsFromFlags(combined_options));
  ASSERT_EQ(separate.fits.size(), combined.fits.size());
  EXPECT_EQ(separate.read.rows, combined.read.rows);
  for (size_t m = 0; m < separate.fits.size(); ++m) {
    ASSERT_TRUE(separate.fits[m].ok && combined.fits[m].ok);
    EXPECT_NEAR(separate.fits[m].constants.axial_area_mm2,
                combined.fits[m].constants.axial_area_mm2,
                1e-9 * separate.fits[m].constants.axial_area_mm2);
    EXPECT_NEAR(separate.fits[m].constants.linear_stiffness_n_per_mm,
                combined.fits[m].constants.linear_stiffness_n_per_mm, 1e-9);
  }
}

TEST_F(FitCommandTest, AFailedReportLeavesThePreviousOneWhole) {
  FitCommandOptions options = Fit(Synthesize("logs", false));
  options.report_directory = Path("report");
  std::ostringstream out;
  ASSERT_EQ(RunFit(options, out), 0);
  const std::string before = Read(Path("report/fit.json"));
  setenv("SOFTBENCH_REPORT_ASSETS", Path("nowhere").c_str(), 1);
  try {
    options.axial_weight = 2.0;  // a different fit, were it written
    RunFit(options, out);
    ADD_FAILURE() << "a report without its plotting libraries was written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scripts/bootstrap.sh"),
              std::string::npos)
        << e.what();
  }
  unsetenv("SOFTBENCH_REPORT_ASSETS");
  EXPECT_EQ(Read(Path("report/fit.json")), before);
}

TEST_F(FitCommandTest, SaysWhyConstantsCannotBeFitted) {
  // Only the tests at theta = 0 of the synthetic set.
  const std::string manifest_path = Synthesize("logs", false);
  ForceLogManifest manifest = LoadForceLogManifest(manifest_path);
  ForceLogManifest zero_angle;
  zero_angle.columns = manifest.columns;
  for (size_t t = 0; t < manifest.tests.size(); ++t) {
    if (manifest.tests[t].nominal_theta_rad == 0.0) {
      zero_angle.tests.push_back(manifest.tests[t]);
      zero_angle.files.push_back(manifest.files[t]);
    }
  }
  std::ofstream(Path("zero_angle.yaml"))
      << ForceLogManifestYaml(zero_angle, "kpa", "");
  FitCommandOptions options = Fit(Path("zero_angle.yaml"));
  options.output_path = Path("constants.yaml");
  std::ostringstream out;
  try {
    RunFit(options, out);
    ADD_FAILURE() << "unidentifiable constants were written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("W_y cannot be fitted"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(options.output_path));
  // The baseline has no angle terms and is still fitted and printed.
  EXPECT_NE(out.str().find("pressurized-spring"), std::string::npos);
}

TEST_F(FitCommandTest, NamesTheManifestLineOfABadEntry) {
  const std::string manifest_path = Path("bad.yaml");
  std::ofstream(manifest_path)
      << "pressure_unit: kpa\ntests:\n"
         "  - {id: a, file: a.csv, delta_length_mm: 1, theta_dg: 10}\n";
  try {
    LoadForceLogManifest(manifest_path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:3"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("theta_dg"), std::string::npos);
  }
  std::ofstream(manifest_path)
      << "pressure_unit: kpa\ntests:\n"
         "  - {id: a, file: missing.csv, delta_length_mm: 1, theta_deg: 10}\n";
  try {
    RunFitAnalysis(FitAnalysisOptionsFromFlags(Fit(manifest_path)));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.csv"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace softbench
