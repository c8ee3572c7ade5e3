// Issue 30, from the command line as a user meets it: each class of bad
// input that hung, crashed, changed an earlier result or blamed the wrong
// thing now gives one line naming the file, place or flag and the cause, or
// a correct answer.
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/scratch_directory.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

class NeverSilentTest : public ScratchDirectoryTest {
 protected:
  // Runs `arguments`, expects exit 2 and one line on stderr holding every
  // one of `words`.
  void ExpectOneLineError(const std::string& arguments,
                          const std::vector<std::string>& words) const {
    std::string err;
    EXPECT_EQ(RunProgram(arguments, &err), 2) << arguments << "\n" << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << arguments << "\n"
                                                           << err;
    for (const std::string& word : words) {
      EXPECT_NE(err.find(word), std::string::npos)
          << arguments << "\nmissing: " << word << "\n"
          << err;
    }
  }
};

const std::string kSamples = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";

// Every file of a folder with its bytes, to see that it did not change.
std::vector<std::pair<std::string, std::string>> Snapshot(
    const std::string& folder) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::ifstream stream(entry.path(), std::ios::binary);
    files.emplace_back(entry.path().filename().string(),
                       std::string(std::istreambuf_iterator<char>(stream), {}));
  }
  std::sort(files.begin(), files.end());
  return files;
}

// A device or a FIFO is read forever, and a 100 GB sparse file for minutes
// (validate hashed /dev/zero without end): refused at once, each named.
TEST_F(NeverSilentTest, ValidateRefusesADeviceAFifoAndAHugeSparseFile) {
  const std::string plan = kSamples + "/delta/plan.yaml";
  ExpectOneLineError(
      "validate /dev/zero --plan " + plan + " --out " + Path("r"),
      {"/dev/zero: is a device, not a regular file"});
  const std::string fifo = Path("fifo.mp4");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  ExpectOneLineError(
      "validate " + fifo + " --plan " + plan + " --out " + Path("r"),
      {"is a pipe (FIFO), not a regular file"});
  const std::string sparse = Path("sparse.mp4");
  std::ofstream(sparse).close();
  fs::resize_file(sparse, std::uintmax_t{100} << 30);
  ExpectOneLineError(
      "validate " + sparse + " --plan " + plan + " --out " + Path("r"),
      {"sparse.mp4: FFmpeg cannot read it as a video"});
  EXPECT_FALSE(fs::exists(Path("r")));
}

// Absurd pressures and maps are refused before any work, never an internal
// error or an allocation that fails after minutes.
TEST_F(NeverSilentTest, WorkspaceRefusesAbsurdLevelsUpFront) {
  ExpectOneLineError("workspace --max 1e308 --step 5e307 --pressure-unit psi",
                     {"--max: 1e+308 psi is above 100 MPa"});
  ExpectOneLineError("workspace --max 6 --step 0.001 --pressure-unit psi",
                     {"--step: 6001 levels for 3 actuators make 2.16e+11 "
                      "configurations"});
  ExpectOneLineError("workspace --max 60 --step 0.5 --pressure-unit psi",
                     {"--max:", "lie beyond the characterised 6 psi"});
  ExpectOneLineError("workspace --max nan --step 1 --pressure-unit psi",
                     {"--max: 'nan' is not a finite number"});
}

// 1000 psi moves the model's head 133 mm: an answer, marked beyond reach.
TEST_F(NeverSilentTest, PredictMarksAHeadBeyondTheMechanismsReach) {
  std::string err, out;
  ASSERT_EQ(RunProgram("predict --pressure-unit psi --pressures 1000,0,0", &err,
                       &out),
            0)
      << err;
  EXPECT_NE(out.find("BEYOND REACH: 131.7 mm from the nearest position"),
            std::string::npos)
      << out;
  EXPECT_NE(err.find("beyond the mechanism's reach"), std::string::npos) << err;
  ExpectOneLineError("predict --pressure-unit psi --pressures 1e300,0,0",
                     {"--pressures: 1e+300 psi is above 100 MPa"});
}

// A plan test at 1e300 psi was scored `ok` with empty model columns.
TEST_F(NeverSilentTest, APlanTestAtAnImpossiblePressureIsNamed) {
  std::ifstream stream(kSamples + "/delta/plan.yaml");
  std::string plan(std::istreambuf_iterator<char>(stream), {});
  const std::string from = "pressures: [6, 3, 0]";
  ASSERT_NE(plan.find(from), std::string::npos);
  plan.replace(plan.find(from), from.size(), "pressures: [1e300, 3, 0]");
  const std::string path = Write("plan.yaml", plan);
  ExpectOneLineError(
      "validate " + kSamples + "/delta/delta.mp4 --plan " + path + " --out " +
          Path("r"),
      {"plan.yaml:", "pressures", "1e+300 psi is above 100 MPa"});
}

// A fit refused after reading its logs (bending not identifiable) left an
// earlier report changed or removed.
TEST_F(NeverSilentTest, ARefusedFitLeavesTheEarlierReportAsItWas) {
  std::string err;
  ASSERT_EQ(RunProgram("-q synth-forces --rate 20 --out " + Path("logs"), &err),
            0)
      << err;
  ASSERT_EQ(RunProgram("-q fit " + Path("logs/manifest.yaml") + " --out " +
                           Path("k.yaml") + " --report " + Path("rep"),
                       &err),
            0)
      << err;
  const auto report = Snapshot(Path("rep"));
  const std::string constants = Read(Path("k.yaml"));
  // Only the tests at 0 degrees: W_y and k_theta cannot be told apart.
  std::ifstream stream(Path("logs/manifest.yaml"));
  std::string manifest, line;
  while (std::getline(stream, line)) {
    if (line.find("theta_deg:") == std::string::npos ||
        line.find("theta_deg: 0,") != std::string::npos) {
      manifest += line + "\n";
    }
  }
  std::ofstream(Path("logs/flat.yaml")) << manifest;
  ExpectOneLineError("-q fit " + Path("logs/flat.yaml") + " --out " +
                         Path("k.yaml") + " --report " + Path("rep"),
                     {"flat.yaml: small-angle constants not written"});
  EXPECT_EQ(Snapshot(Path("rep")), report);
  EXPECT_EQ(Read(Path("k.yaml")), constants);
}

// A manifest whose pressure_unit contradicts its column's name was "366 of
// 390 rows are unusable", with no word about the unit.
TEST_F(NeverSilentTest, AManifestsUnitThatContradictsItsColumnIsNamed) {
  std::string err;
  ASSERT_EQ(RunProgram("-q synth-forces --rate 5 --out " + Path("logs"), &err),
            0)
      << err;
  std::ifstream stream(Path("logs/manifest.yaml"));
  std::string manifest(std::istreambuf_iterator<char>(stream), {});
  const std::string from = "pressure_unit: kpa";
  ASSERT_NE(manifest.find(from), std::string::npos);
  manifest.replace(manifest.find(from), from.size(), "pressure_unit: psi");
  std::ofstream(Path("logs/manifest.yaml")) << manifest;
  ExpectOneLineError(
      "fit " + Path("logs/manifest.yaml") + " --out " + Path("k.yaml"),
      {"manifest.yaml:3: pressure_unit: is psi, but the pressure column "
       "'pressure_kpa' is in kpa; set pressure_unit: kpa"});
}

// Each flag is blamed for its own value; third-party libraries print
// nothing of their own.
TEST_F(NeverSilentTest, FlagsAreBlamedByNameAndLibrariesStayQuiet) {
  ExpectOneLineError("calibrate-camera " + dir().string() +
                         " --board 9x6 --square-mm 0 --out " + Path("c.yaml"),
                     {"--square-mm: 0 is not a square's side"});
  // The fit's options were "fit: fit: loss scale ...", under no flag.
  ExpectOneLineError("fit " + dir().string() +
                         "/none.csv --loss huber "
                         "--loss-scale -1 --pressure-unit kpa",
                     {"--loss-scale: must be > 0 N"});
  // A plan whose times run for years failed allocating its frame times.
  const std::string long_plan =
      Write("long.yaml",
            "mechanism: delta\npressure_unit: psi\ntests:\n  - {id: a, "
            "pressures: [1, 1, 1], actuate_s: 1e9, release_s: 2e9}\n");
  ExpectOneLineError("render --plan " + long_plan + " --out " + Path("v.mp4") +
                         " --truth " + Path("t.csv"),
                     {"long.yaml: the video would last 2e+09 s"});
  // A plan without times had its length read from times not yet given: it
  // started rendering a day's hold (2.6 million frames).
  const std::string day_plan =
      Write("day.yaml",
            "mechanism: delta\npressure_unit: psi\ntests:\n  - {id: a, "
            "pressures: [1, 1, 1]}\nscene: {lead_in_s: 1, hold_s: 86400, "
            "rest_s: 1}\n");
  ExpectOneLineError("render --plan " + day_plan + " --out " + Path("v.mp4") +
                         " --truth " + Path("t.csv"),
                     {"day.yaml: the video would last 8.64e+04 s"});
  // x264 printed its own complaint about the preset before softbench's.
  ExpectOneLineError("render --plan " + kSamples + "/delta/plan.yaml --out " +
                         Path("v.mp4") + " --truth " + Path("t.csv") +
                         " --preset ludicrous",
                     {"preset 'ludicrous' is not one of ultrafast"});
  // Ceres logged "WARNING: Logging before InitGoogleLogging()" and its
  // minimiser's lines through glog.
  std::string err, out;
  EXPECT_EQ(RunProgram("inverse --pressure-unit psi --target 900,900 --max "
                       "14000",
                       &err, &out),
            2);
  EXPECT_EQ(err.find("InitGoogleLogging"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("lower --max toward the characterised 6 psi"),
            std::string::npos)
      << err;
}

// A rest that runs into the first actuation measured every displacement
// from a point the head never rested at, with exit 0.
TEST_F(NeverSilentTest, ARestThatRunsIntoTheMotionIsRefused) {
  ExpectOneLineError("-q track " + kSamples + "/phone/phone.mp4 --plan " +
                         kSamples + "/phone/plan.yaml --rest-s 100 --out " +
                         Path("t.csv"),
                     {"phone.mp4: head 'head' moves by",
                      "within the first 100 s taken as its rest; give a rest "
                      "(--rest-s) that ends before the first actuation"});
  EXPECT_FALSE(fs::exists(Path("t.csv")));
}

// An MP4 that holds only its index was "an unknown pixel format"; a
// mechanism path that is a device was "no such mechanism".
TEST_F(NeverSilentTest, NamesAnIndexWithoutMediaAndADeviceForAMechanism) {
  // The boxes of the sample up to its media data.
  std::ifstream video(kSamples + "/delta/delta.mp4", std::ios::binary);
  std::string head;
  for (;;) {
    char box[8];
    ASSERT_TRUE(video.read(box, 8));
    const uint32_t size = (uint32_t{static_cast<unsigned char>(box[0])} << 24) |
                          (uint32_t{static_cast<unsigned char>(box[1])} << 16) |
                          (uint32_t{static_cast<unsigned char>(box[2])} << 8) |
                          uint32_t{static_cast<unsigned char>(box[3])};
    if (std::string(box + 4, 4) == "mdat") break;
    ASSERT_GE(size, 8u);
    std::string body(size - 8, '\0');
    ASSERT_TRUE(video.read(body.data(), size - 8));
    head += std::string(box, 8) + body;
  }
  std::ofstream(Path("index.mp4"), std::ios::binary) << head;
  ExpectOneLineError("validate " + Path("index.mp4") + " --plan " + kSamples +
                         "/delta/plan.yaml --out " + Path("r"),
                     {"index.mp4: holds no video data: the container lists "
                      "3420 frames"});
  ExpectOneLineError(
      "predict --mechanism /dev/zero --pressure-unit psi "
      "--pressures 1,1,1",
      {"/dev/zero: is a device, not a regular file; give the "
       "mechanism file's path"});
}

}  // namespace
}  // namespace softbench
