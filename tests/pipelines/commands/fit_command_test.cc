// `softbench synth-forces` and `softbench fit` end to end through files.
#include "pipelines/commands/fit_command.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "pipelines/characterisation/force_log_manifest.h"
#include "pipelines/commands/synth_forces_command.h"
#include "pipelines/formats/constants_file.h"
#include "pipelines/synthetic/force_logs.h"
#include "tests/support/input_error_matchers.h"
#include "tests/support/report_page.h"
#include "tests/support/scratch_directory.h"
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
  // A manifest of only the tests at nominal theta = 0 of `manifest_path`,
  // written to `path` (beside the logs it names).
  static std::string ZeroAngleManifest(const std::string& manifest_path,
                                       const std::string& path) {
    const ForceLogManifest manifest = LoadForceLogManifest(manifest_path);
    ForceLogManifest zero_angle;
    zero_angle.columns = manifest.columns;
    for (size_t t = 0; t < manifest.tests.size(); ++t) {
      if (manifest.tests[t].nominal_theta_rad == 0.0) {
        zero_angle.tests.push_back(manifest.tests[t]);
        zero_angle.files.push_back(manifest.files[t]);
      }
    }
    std::ofstream(path) << ForceLogManifestYaml(zero_angle, "kpa", "");
    return path;
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
  // Every chart the report promises, found by its title.
  for (const char* title :
       {"Axial force against pressure", "Shear force against pressure",
        "Static offsets at zero pressure", "Static offsets against dL",
        "Effective areas against theta", "Residuals (measured - model)",
        "RMS residual per test"}) {
    EXPECT_TRUE(ChartTitled(html, title).is_object()) << title;
  }
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
  for (const fs::directory_entry& entry : fs::directory_iterator(dir())) {
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
  options.axial_weight = 2.0;  // a different fit, were it written
  EXPECT_THAT([&] { RunFit(options, out); },
              ::testing::ThrowsMessage<InstallationError>(
                  ::testing::HasSubstr("scripts/bootstrap.sh")));
  // An installation problem is neither bad input (2) nor a bug (1).
  std::string said;
  EXPECT_EQ(RunProgram("fit " + options.input_path + " --report " +
                           Path("report") + " --quiet",
                       &said),
            4)
      << said;
  EXPECT_NE(said.find("plotting library is missing"), std::string::npos)
      << said;
  unsetenv("SOFTBENCH_REPORT_ASSETS");
  EXPECT_EQ(Read(Path("report/fit.json")), before);
}

// Every file of `directory` (names and contents), to compare before and after.
std::map<std::string, std::string> DirectoryContents(
    const fs::path& directory) {
  std::map<std::string, std::string> contents;
  for (const auto& entry : fs::directory_iterator(directory)) {
    std::ifstream stream(entry.path());
    std::stringstream text;
    text << stream.rdbuf();
    contents[entry.path().filename().string()] = text.str();
  }
  return contents;
}

TEST_F(FitCommandTest, AKilledSynthForcesLeavesThePreviousLogsAsTheyWere) {
  Synthesize("logs", false);
  const auto before = DirectoryContents(Path("logs"));
  ASSERT_GT(before.size(), 2u);
  // Killed (SIGKILL: no handler runs) while it writes a thousand times more
  // rows than the logs before, with another seed.
  const std::string command = "timeout -s KILL 1.5 " +
                              std::string(SOFTBENCH_BINARY) +
                              " synth-forces -q --rate 40000 --seed 9 --out " +
                              Path("logs") + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 128 + SIGKILL) << "it was not killed mid-run";
  // It was writing beside the logs...
  bool staged = false;
  for (const auto& entry : fs::directory_iterator(dir())) {
    staged |= entry.path().filename().string().starts_with(".logs.");
  }
  EXPECT_TRUE(staged);
  // ...and the logs are the ones before, every file of them.
  EXPECT_EQ(DirectoryContents(Path("logs")), before);
}

// The size synth-forces states before writing is what it writes, within
// 3 %, as separate logs and as one combined log (at a rate above the one
// the estimate samples, so it extrapolates).
TEST_F(FitCommandTest, SynthForcesStatesTheSizeItWrites) {
  for (const bool combined : {false, true}) {
    ForceLogFilesOptions options;
    options.synthetic.sample_rate_hz = combined ? 150.0 : 40.0;
    options.combined = combined;
    options.progress = false;
    const ForceLogFilesSize size = EstimateForceLogFiles(options);
    const std::string directory = Path(combined ? "combined" : "separate");
    const ForceLogFiles written = WriteForceLogFiles(directory, options);
    EXPECT_EQ(size.tests, written.tests);
    EXPECT_EQ(size.rows, written.rows);
    int64_t bytes = 0;
    for (const auto& entry : fs::directory_iterator(directory)) {
      if (entry.path().extension() == ".csv") bytes += entry.file_size();
    }
    EXPECT_NEAR(static_cast<double>(size.bytes), static_cast<double>(bytes),
                0.03 * static_cast<double>(bytes))
        << (combined ? "combined" : "separate");
  }
  std::string err;
  ASSERT_EQ(RunProgram("synth-forces --rate 40 --out " + Path("said"), &err),
            0);
  EXPECT_NE(err.find("writing 54 tests, "), std::string::npos) << err;
  EXPECT_NE(err.find(" MB, to " + Path("said")), std::string::npos) << err;
}

TEST_F(FitCommandTest, SaysWhyConstantsCannotBeFitted) {
  // Only the tests at theta = 0 of the synthetic set.
  const std::string manifest_path = Synthesize("logs", false);
  FitCommandOptions options =
      Fit(ZeroAngleManifest(manifest_path, Path("zero_angle.yaml")));
  options.output_path = Path("constants.yaml");
  std::ostringstream out;
  const std::string message = InputErrorOf([&] { RunFit(options, out); });
  EXPECT_NE(message.find("W_y cannot be fitted"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(options.output_path));
  // The baseline has no angle terms and is still fitted and printed.
  EXPECT_NE(out.str().find("pressurized-spring"), std::string::npos);
}

// With the rig's imperfections the measured angles of the theta = 0 tests
// jitter by tenths of a degree: W_y and k_theta then get numbers with
// plausible standard errors that mean nothing, and must not be written.
TEST_F(FitCommandTest, RefusesBendConstantsFromTestsThatNeverBent) {
  SynthForcesCommandOptions synth;
  synth.output_directory = Path("rig");
  synth.quiet = true;
  // Enough rows that the jitter's fit looks precise (8 % standard error).
  synth.synthetic.sample_rate_hz = 200.0;
  std::ostringstream out;
  ASSERT_EQ(RunSynthForces(synth, out), 0);
  FitCommandOptions options = Fit(ZeroAngleManifest(
      Path("rig/manifest.yaml"), Path("rig/zero_angle.yaml")));
  options.output_path = Path("constants.yaml");
  const std::string message = InputErrorOf([&] { RunFit(options, out); });
  EXPECT_NE(message.find("W_y and k_theta, which act through the bend, are not "
                         "identifiable"),
            std::string::npos)
      << message;
  EXPECT_FALSE(fs::exists(options.output_path));
}

TEST_F(FitCommandTest, NamesTheManifestLineOfABadEntry) {
  const std::string manifest_path = Path("bad.yaml");
  std::ofstream(manifest_path)
      << "pressure_unit: kpa\ntests:\n"
         "  - {id: a, file: a.csv, delta_length_mm: 1, theta_dg: 10}\n";
  EXPECT_THAT([&] { LoadForceLogManifest(manifest_path); },
              ThrowsInputErrorWith("bad.yaml", "bad.yaml:3", "theta_dg"));
  std::ofstream(manifest_path)
      << "pressure_unit: kpa\ntests:\n"
         "  - {id: a, file: missing.csv, delta_length_mm: 1, theta_deg: 10}\n";
  EXPECT_THAT(
      [&] { RunFitAnalysis(FitAnalysisOptionsFromFlags(Fit(manifest_path))); },
      ThrowsInputErrorWith("missing.csv", "", ""));
}

}  // namespace
}  // namespace softbench
