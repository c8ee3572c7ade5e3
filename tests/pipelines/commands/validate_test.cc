// `softbench validate`: scoring against the renderer's truth on the bundled
// samples, predictions against `softbench predict`, hysteresis flags on a
// rendered slip, and its outputs.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <tuple>

#include "pipelines/commands/predict_command.h"
#include "pipelines/commands/render_command.h"
#include "pipelines/commands/validate_command.h"
#include "pipelines/measurement/snapshots.h"
#include "pipelines/measurement/test_point_detection.h"
#include "tests/support/input_error_matchers.h"
#include "tests/support/rendered_clip.h"
#include "tests/support/rendered_truth.h"
#include "tests/support/report_page.h"
#include "tests/support/scratch_directory.h"
#include "util/csv.h"
#include "util/file_digest.h"
#include "util/input_error.h"
#include "util/version.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

int Count(const std::string& text, const std::string& pattern) {
  int count = 0;
  for (size_t at = 0; (at = text.find(pattern, at)) != std::string::npos;
       at += pattern.size()) {
    ++count;
  }
  return count;
}

// The truth's displacement from window `from` to window `to`, as scoring
// takes it: the difference of the windows' medians.
Eigen::VectorXd TruthDisplacement(const RenderedTruth& truth,
                                  const WindowSummary& from,
                                  const WindowSummary& to) {
  return truth.MedianDisplacementMm(to.start_s, to.end_s) -
         truth.MedianDisplacementMm(from.start_s, from.end_s);
}

// The share of registered frames whose tag was located (not held between
// the tag's strides).
double TagLocatedShare(const VideoMeasurement& m) {
  int registered = 0, located = 0;
  for (const FrameSample& f : m.frames) {
    registered += f.registered;
    located += f.registered && f.tag_corners.has_value();
  }
  return static_cast<double>(located) / std::max(registered, 1);
}

// Measures `video` again with its tag located in every frame (tag_stride 1)
// and returns the largest difference [mm] of `strided` (the same video
// scored with the default stride) from it: of any window's median position
// and any measured displacement. Checks that the second run did locate the
// tag in every frame.
double DifferenceFromTagInEveryFrame(const TestPlan& plan,
                                     const std::string& video,
                                     const ValidationResult& strided) {
  VideoMeasurementOptions measure;
  measure.progress = false;
  measure.registration.tag_stride = 1;
  const VideoMeasurement m = MeasureVideo(plan, video, measure);
  EXPECT_EQ(TagLocatedShare(m), 1.0);
  const ValidationResult every = ScoreTests(plan, m, ValidationOptions());
  EXPECT_EQ(every.tests.size(), strided.tests.size());
  double largest = 0.0;
  for (size_t i = 0; i < every.tests.size() && i < strided.tests.size(); ++i) {
    const TestScore &a = every.tests[i], &b = strided.tests[i];
    for (size_t h = 0; h < a.heads.size(); ++h) {
      largest =
          std::max(largest, (a.heads[h].measured_mm - b.heads[h].measured_mm)
                                .lpNorm<Eigen::Infinity>());
      for (size_t w = 0; w < a.windows.size(); ++w) {
        largest = std::max(
            largest, (a.windows[w].median_mm[h] - b.windows[w].median_mm[h])
                         .lpNorm<Eigen::Infinity>());
      }
    }
  }
  return largest;
}

// Scores a bundled sample and checks every measured displacement against
// the truth in the same windows, and every prediction against predict;
// `windows_only` reads only the windows' frames.
ValidationResult CheckSample(const std::string& name, bool windows_only,
                             bool register_frames = true) {
  const std::string dir =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + name;
  const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
  VideoMeasurementOptions measure;
  measure.progress = false;
  measure.register_frames = register_frames;
  if (windows_only) {
    const VideoInfo info = VideoReader(dir + "/" + name + ".mp4").info();
    for (const auto& windows : PlanWindows(plan, info.LastFrameS())) {
      for (const WindowSummary& w : windows) {
        measure.spans.push_back({w.start_s, w.end_s});
      }
    }
  }
  const VideoMeasurement m =
      MeasureVideo(plan, dir + "/" + name + ".mp4", measure);
  EXPECT_EQ(m.every_frame, !windows_only);
  const ValidationResult result = ScoreTests(plan, m, ValidationOptions());
  const int num_heads = plan.mechanism.NumHeads();
  const RenderedTruth truth = ReadRenderedTruth(dir + "/truth.csv");

  // What predict says for the same pressures (both models).
  std::string pressures = "";
  for (int k = 1; k <= plan.mechanism.NumActuators(); ++k) {
    pressures += fmt::format("{}p{}", k > 1 ? "," : "", k);
  }
  pressures += "\n";
  for (const TestPoint& test : plan.tests) {
    for (int k = 0; k < test.pressures.size(); ++k) {
      pressures += fmt::format("{}{}", k > 0 ? "," : "", test.pressures[k]);
    }
    pressures += "\n";
  }
  const std::string input =
      (TestScratch().dir() /
       ("softbench_validate_" + name + "_" + std::to_string(getpid()) + ".csv"))
          .string();
  std::ofstream(input) << pressures;
  std::array<std::vector<Eigen::VectorXd>, 2> predicted;
  for (int model = 0; model < 2; ++model) {
    PredictOptions predict;
    predict.model.mechanism = plan.mechanism_name;
    predict.model.model = model == 0 ? "axial-shear" : "pressurized-spring";
    predict.model.pressure_unit = plan.pressure_unit;
    predict.input_path = input;
    predict.output_path = input + ".out";
    std::ostringstream out;
    RunPredict(predict, out);
    CsvReader reader(predict.output_path);
    std::vector<std::string_view> fields;
    while (reader.ReadRow(&fields)) {
      Eigen::VectorXd x(2 * num_heads);
      for (int k = 0; k < 2 * num_heads; ++k) {
        x[k] = *ParseDouble(fields[plan.mechanism.NumActuators() + k]);
      }
      predicted[model].push_back(x);
    }
  }

  EXPECT_EQ(result.tests.size(), plan.tests.size());
  double worst = 0.0;
  for (size_t i = 0; i < result.tests.size(); ++i) {
    const TestScore& score = result.tests[i];
    EXPECT_TRUE(score.measured) << score.id << ": " << score.reason;
    EXPECT_NE(score.status, "not measured") << score.id;
    const Eigen::VectorXd true_displacement = TruthDisplacement(
        truth, score.windows[kInitialWindow], score.windows[kActuatedWindow]);
    for (int h = 0; h < num_heads; ++h) {
      const double error =
          (score.heads[h].measured_mm - true_displacement.segment<2>(2 * h))
              .norm();
      worst = std::max(worst, error);
      EXPECT_LT(error, 0.005) << name << " " << score.id << " head " << h;
      // predict prints 6 decimals.
      EXPECT_NEAR(score.heads[h].model_mm.x(), predicted[0][i][2 * h], 1e-6);
      EXPECT_NEAR(score.heads[h].model_mm.y(), predicted[0][i][2 * h + 1],
                  1e-6);
      EXPECT_NEAR(score.heads[h].baseline_mm.x(), predicted[1][i][2 * h], 1e-6);
      EXPECT_NEAR(score.heads[h].baseline_mm.y(), predicted[1][i][2 * h + 1],
                  1e-6);
    }
  }
  std::cout << name << (windows_only ? " (windows only)" : "")
            << ": worst displacement error against the truth " << worst
            << " mm in " << m.frames.size() << " frames\n";
  // The samples' holds are 5 s, shorter than the thesis's 20 s.
  EXPECT_FALSE(result.warnings.empty() ||
               result.warnings.front().find("holds as short as") ==
                   std::string::npos);
  return result;
}

// Both ways to read the video: every frame, and only the windows (seeking
// between them), which must measure the same displacements: each window's
// first frame is detected afresh instead of tracked, so its centres may
// differ within LocateDotCentre's tolerance (1e-4 px, 2e-5 mm). Compared
// with the camera taken to be still: a registered video's tag pose is averaged
// over the frames read, which differ between the two ways.
TEST(ValidateSamples,
     DeltaDisplacementsMatchTheTruthReadingEveryFrameOrOnlyTheWindows) {
  const ValidationResult all = CheckSample("delta", false, false);
  const ValidationResult windows = CheckSample("delta", true, false);
  EXPECT_TRUE(all.hysteresis_flagged.empty());
  ASSERT_EQ(all.tests.size(), windows.tests.size());
  double largest = 0.0;
  for (size_t i = 0; i < all.tests.size(); ++i) {
    EXPECT_EQ(all.tests[i].windows[kActuatedWindow].frames,
              windows.tests[i].windows[kActuatedWindow].frames);
    const double difference = (all.tests[i].heads[0].measured_mm -
                               windows.tests[i].heads[0].measured_mm)
                                  .norm();
    largest = std::max(largest, difference);
    EXPECT_LT(difference, 1e-4) << all.tests[i].id;
  }
  std::cout << "delta: every frame vs windows only: largest difference "
            << largest << " mm\n";
}

// Registered (the default), both ways of reading meet the bar on their own.
TEST(ValidateSamples, DeltaRegisteredMeetsTheBarEveryFrameAndWindowsOnly) {
  for (const bool windows_only : {false, true}) {
    const ValidationResult result = CheckSample("delta", windows_only);
    EXPECT_TRUE(result.hysteresis_flagged.empty());
    EXPECT_TRUE(result.camera_moved_windows.empty());
  }
}

TEST(ValidateSamples,
     FloatingDisplacementsMatchTheTruthAndPredictionsMatchPredict) {
  const ValidationResult result = CheckSample("floating", false);
  EXPECT_TRUE(result.hysteresis_flagged.empty());
}

// The phone sample: 1080p at 10 Mb/s from a camera that drifts, trembles
// and is knocked three times (inside test a's hold, inside test b's
// actuated window, between test c's actuated and final windows), with
// auto-exposure and white balance wandering; test b slips 0.1 mm. Every
// displacement within 0.005 mm of the truth (CheckSample), hysteresis on b
// alone, and the camera named as moving in b's actuated window alone.
TEST(ValidateSamples, PhoneFootageMeetsTheBarWhileTheCameraMoves) {
  const ValidationResult result = CheckSample("phone", false);
  EXPECT_EQ(result.hysteresis_flagged, std::vector<std::string>{"b"});
  EXPECT_EQ(result.camera_moved_windows,
            std::vector<std::string>{"b actuated"});
  for (const TestScore& test : result.tests) {
    for (const WindowSummary& w : test.windows) {
      EXPECT_EQ(w.unregistered_frames, 0) << test.id;
    }
  }
}

// Each frame of the phone sample measured through its own registration: the
// camera's tremor (0.08 px RMS, frame to frame) is followed, not left to the
// windows' medians. Every frame's head, less the median error over the
// video, within 0.005 mm RMS of the truth (measured 0.003 mm; a camera path
// smoothed over seconds gives 0.013 mm).
TEST(ValidateSamples, PhoneFramesFollowTheTremor) {
  const std::string dir = std::string(SOFTBENCH_SOURCE_DIR) + "/samples/phone";
  const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
  VideoMeasurementOptions measure;
  measure.progress = false;
  const VideoMeasurement m = MeasureVideo(plan, dir + "/phone.mp4", measure);
  const RenderedTruth truth = ReadRenderedTruth(dir + "/truth.csv");
  std::vector<Eigen::Vector2d> errors;
  for (const FrameSample& f : m.frames) {
    const Eigen::Vector2d d = f.heads[0].displacement_mm;
    if (!f.registered || !d.allFinite()) continue;
    ASSERT_LT(f.frame, static_cast<int64_t>(truth.time_s.size()));
    errors.push_back(d - truth.displacement_mm[f.frame][0]);
  }
  ASSERT_GT(errors.size(), 400u);
  Eigen::Vector2d median;
  for (int c = 0; c < 2; ++c) {
    std::vector<double> v;
    for (const Eigen::Vector2d& e : errors) v.push_back(e[c]);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    median[c] = v[v.size() / 2];
  }
  double squares = 0.0;
  for (const Eigen::Vector2d& e : errors) squares += (e - median).squaredNorm();
  const double rms = std::sqrt(squares / errors.size());
  std::cout << "phone: per-frame RMS error " << rms << " mm\n";
  EXPECT_LT(rms, 0.005);
}

// A still camera's tag is located on one frame in four, its corners held
// between (BenchRegistrationOptions::tag_stride): on the still delta sample
// every window and displacement agrees with the tag located in every frame
// to 0.0002 mm (issue 29), and the phone sample's trembling, knocked camera
// is registered in full on every frame.
TEST(ValidateSamples, TagAtAStrideAgreesWithTheTagInEveryFrame) {
  for (const std::string name : {"delta", "phone"}) {
    const std::string dir =
        std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + name;
    const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
    VideoMeasurementOptions measure;
    measure.progress = false;
    const VideoMeasurement m =
        MeasureVideo(plan, dir + "/" + name + ".mp4", measure);
    const double share = TagLocatedShare(m);
    const double difference =
        DifferenceFromTagInEveryFrame(plan, dir + "/" + name + ".mp4",
                                      ScoreTests(plan, m, ValidationOptions()));
    std::cout << name << ": tag located in " << share
              << " of the frames; largest difference from the tag in every "
                 "frame "
              << difference << " mm\n";
    EXPECT_LT(difference, 2e-4) << name;
    if (name == "delta") {
      EXPECT_LT(share, 0.4);
    } else {
      EXPECT_EQ(share, 1.0);
    }
  }
}

// The same footage taken as from a still camera (the thesis's method) is
// off by tenths of a millimetre: the registration is what makes it right.
TEST(ValidateSamples, PhoneFootageIsWrongWithoutRegistration) {
  const std::string dir = std::string(SOFTBENCH_SOURCE_DIR) + "/samples/phone";
  const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
  VideoMeasurementOptions measure;
  measure.progress = false;
  measure.register_frames = false;
  const ValidationResult result =
      ScoreTests(plan, MeasureVideo(plan, dir + "/phone.mp4", measure),
                 ValidationOptions());
  const RenderedTruth truth = ReadRenderedTruth(dir + "/truth.csv");
  double worst = 0.0;
  for (const TestScore& score : result.tests) {
    const Eigen::VectorXd d =
        TruthDisplacement(truth, score.windows[0], score.windows[1]);
    worst = std::max(worst, (score.heads[0].measured_mm - d.head<2>()).norm());
  }
  EXPECT_GT(worst, 0.1);
  EXPECT_GT(result.hysteresis_flagged.size(), 1u);
}

// The report's pictures for the detected times: every window's middle has
// a crop kept on the way within a stride of it, the same pixels as the
// crop a seek to its frame cuts, so the video is not decoded again.
void CheckWindowFrames(const std::string& video_path, TestPlan plan,
                       const TestPointDetection& d, VideoMeasurement m) {
  std::set<int64_t> kept_frames;
  for (const FrameSnapshot& s : m.window_frames) kept_frames.insert(s.frame);
  const size_t kept = m.window_frames.size();
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    plan.tests[i].actuate_s = d.points[i].actuate_s;
    plan.tests[i].release_s = d.points[i].release_s;
  }
  const std::vector<double> middles =
      WindowMiddles(PlanWindows(plan, m.last_frame_s));
  EXPECT_LE(kept, 6 * middles.size());
  std::cout << kept << " crops kept for " << middles.size()
            << " windows' middles\n";
  VideoReader reader(video_path);
  CaptureSnapshots(plan, middles, 0.1, &reader, &m);
  ASSERT_EQ(m.snapshots.size(), middles.size());
  EXPECT_TRUE(m.window_frames.empty());
  for (const FrameSnapshot& s : m.snapshots) {
    EXPECT_TRUE(kept_frames.count(s.frame)) << "frame " << s.frame;
    EXPECT_NEAR(s.time_s, s.requested_s, 0.1);
  }
  for (size_t i = 0; i < middles.size(); i += 7) {
    const FrameSnapshot& kept_crop = m.snapshots[i];
    const VideoFrame frame = reader.SeekTo(kept_crop.time_s);
    const FrameSnapshot sought = SnapshotHeads(
        VideoFrameSource(&reader, &frame), *FindFrame(m, kept_crop.time_s),
        plan, m.mm_per_px, middles[i]);
    for (size_t h = 0; h < sought.heads.size(); ++h) {
      EXPECT_EQ(
          cv::norm(sought.heads[h].bgr, kept_crop.heads[h].bgr, cv::NORM_INF),
          0.0)
          << "window middle " << middles[i] << " s, head " << h;
    }
  }
}

// Test points found from the motion for the plans without times match the
// times the renderer used.
void CheckDetectedTimes(const std::string& name) {
  const std::string dir =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + name;
  const TestPlan plan = LoadTestPlan(dir + "/plan.yaml");
  const TestPlan rendered = LoadTestPlan(dir + "/rendered.plan.yaml");
  ASSERT_FALSE(plan.HasTimes());
  VideoMeasurementOptions measure;
  measure.progress = false;
  measure.window_frames =
      WindowFrameKeeperOptions{.window_s = plan.window_s, .stride_s = 0.1};
  const std::string video_path = dir + "/" + name + ".mp4";
  VideoMeasurement m = MeasureVideo(plan, video_path, measure);
  const TestPointDetection d = DetectTestPoints(
      m, static_cast<int>(plan.tests.size()), TestPointDetectionOptions());
  ASSERT_TRUE(d.found) << d.why_not;
  double worst = 0.0;
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    worst = std::max(
        {worst, std::abs(d.points[i].actuate_s - *rendered.tests[i].actuate_s),
         std::abs(d.points[i].release_s - *rendered.tests[i].release_s)});
  }
  EXPECT_LT(worst, 0.2);
  std::cout << name << ": worst detected time error " << worst << " s\n";
  CheckWindowFrames(video_path, plan, d, std::move(m));
}

TEST(ValidateSamples, FindsTheDeltaTestPointsFromTheMotion) {
  CheckDetectedTimes("delta");
}

TEST(ValidateSamples, FindsTheFloatingTestPointsFromTheMotion) {
  CheckDetectedTimes("floating");
}

constexpr char kSlipPlan[] = R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
scene: {settle_time_constant_s: 0.1, lead_in_s: 1.5, hold_s: 1.5, rest_s: 2.5}
tests:
  - {id: a, pressures: [6, 0, 0]}
  - {id: b, pressures: [0, 6, 0], residual_offset_mm: [0.1, 0]}
  - {id: c, pressures: [0, 0, 6]}
)";

// What ValidateCommandTest::CheckPhoneFormat measured beside the
// displacements.
struct PhoneCheck {
  double layout_ratio = 1.0;         // DistortionCheck::median_ratio
  std::vector<std::string> effects;  // CameraProcessing's, by name
  double tag_cell_px = 0.0;          // CameraProcessing's
  bool tag_scale_at_risk = false;    // CameraProcessing's
};

class ValidateCommandTest : public ScratchDirectoryTest {
 protected:
  // The options that render `plan_yaml` as a quick 720p clip (clip.mp4,
  // truth.csv, rendered.plan.yaml here).
  RenderCommandOptions QuickRender(const char* plan_yaml) const {
    return QuickRenderOptions(scratch(), plan_yaml);
  }
  // `compare_tag_stride`: also check that locating the tag on one frame in
  // four (tag_stride) agrees with locating it in every frame to 0.0002 mm.
  PhoneCheck CheckPhoneFormat(
      const std::function<void(RenderCommandOptions*)>& set,
      bool compare_tag_stride = false);
  // A phone's own processing, stage by stage, for CheckPhonePipeline.
  struct PhonePipeline {
    double lens_blur_px = 0.0;
    double tone_curve = 0.0;
    std::string sharpen;
    std::string bayer;  // "" for a sensor without a colour filter
    double temporal_denoise = 0.0;
  };
  // CheckPhoneFormat at 1080p through `phone`.
  PhoneCheck CheckPhonePipeline(const PhonePipeline& phone);
  ValidateCommandOptions CheckClockOffset(const std::string& sample,
                                          const std::string& log, int windows);
  // Validate's options for the delta sample's video against `plan` (YAML
  // text, written to plan.yaml), reporting to report/.
  ValidateCommandOptions DeltaWithPlan(const std::string& plan,
                                       bool windows_only) const {
    ValidateCommandOptions options;
    options.video_paths = {std::string(SOFTBENCH_SOURCE_DIR) +
                           "/samples/delta/delta.mp4"};
    options.plan_path = Write("plan.yaml", plan);
    options.output_directory = Path("report");
    options.windows_only = windows_only;
    options.quiet = true;
    return options;
  }
  // Validate's options for the rendered clip, reporting to `directory`.
  ValidateCommandOptions ValidateClip(const RenderCommandOptions& render,
                                      const std::string& directory) {
    ValidateCommandOptions options;
    options.video_paths = {render.output_path};
    options.plan_path = render.plan_out_path;
    options.output_directory = Path(directory);
    options.quiet = true;
    return options;
  }
  // The delta sample's rendered plan with `from` replaced by `to`.
  std::string EditedRenderedDeltaPlan(std::string_view from,
                                      std::string_view to) {
    std::string plan = Read(std::string(SOFTBENCH_SOURCE_DIR) +
                            "/samples/delta/rendered.plan.yaml");
    EXPECT_NE(plan.find(from), std::string::npos) << from;
    if (plan.find(from) != std::string::npos) {
      plan.replace(plan.find(from), from.size(), to);
    }
    return plan;
  }
  // Validates the delta sample's video against its plan with `from`
  // replaced by `to`; returns the InputError's message ("" when it was
  // accepted) and checks that nothing was written.
  std::string ErrorWithEditedDeltaPlan(std::string_view from,
                                       std::string_view to) {
    std::string plan =
        Read(std::string(SOFTBENCH_SOURCE_DIR) + "/samples/delta/plan.yaml");
    EXPECT_NE(plan.find(from), std::string::npos) << from;
    if (plan.find(from) != std::string::npos) {
      plan.replace(plan.find(from), from.size(), to);
    }
    const ValidateCommandOptions options =
        DeltaWithPlan(plan, /*windows_only=*/false);
    std::ostringstream out;
    const std::string message =
        InputErrorOf([&] { RunValidate(options, out); });
    EXPECT_FALSE(fs::exists(Path("report")));
    return message;
  }
};

TEST_F(ValidateCommandTest, FlagsOnlyTheTestWithASlipAndWritesTheReport) {
  const RenderCommandOptions render = QuickRender(kSlipPlan);
  std::ostringstream out;
  RenderClip(render);

  ValidateCommandOptions options = ValidateClip(render, "report");
  ASSERT_EQ(RunValidate(options, out), 0);
  CsvReader results(Path("report/results.csv"));
  std::vector<std::string_view> fields;
  const int status = results.ColumnIndex("status");
  const int flag = results.ColumnIndex("hysteresis_ok");
  std::vector<std::string> statuses;
  while (results.ReadRow(&fields)) {
    statuses.emplace_back(fields[status]);
    EXPECT_EQ(fields[flag], fields[0] == "b" ? "0" : "1") << fields[0];
  }
  EXPECT_EQ(statuses, (std::vector<std::string>{"ok", "hysteresis", "ok"}));
  // Every row carries its provenance: version, unit, each input's SHA-256.
  CsvReader again(Path("report/results.csv"));
  const std::string video_sha256 = *Sha256OfFile(options.video_paths[0]);
  ASSERT_TRUE(again.ReadRow(&fields));
  EXPECT_EQ(fields[again.ColumnIndex("softbench_version")], SoftbenchVersion());
  EXPECT_EQ(fields[again.ColumnIndex("pressure_unit")], "psi");
  EXPECT_EQ(fields[again.ColumnIndex("video_file")],
            fs::path(options.video_paths[0]).filename().string());
  EXPECT_EQ(fields[again.ColumnIndex("video_sha256")], video_sha256);
  EXPECT_EQ(fields[again.ColumnIndex("plan_sha256")],
            Sha256OfFile(options.plan_path));
  EXPECT_EQ(fields[again.ColumnIndex("intrinsics_sha256")], "");
  const std::string summary = Read(Path("report/summary.json"));
  EXPECT_NE(summary.find(fmt::format("\"softbench_version\": \"{}\"",
                                     SoftbenchVersion())),
            std::string::npos);
  EXPECT_NE(summary.find(fmt::format("\"sha256\": \"{}\"", video_sha256)),
            std::string::npos);
  for (const char* file : {"report.html", "summary.json", "trajectory.csv"}) {
    EXPECT_TRUE(fs::exists(Path("report/") + file)) << file;
  }
  const std::string check = std::string(SOFTBENCH_SOURCE_DIR) +
                            "/report/check_in_chromium.sh " +
                            Path("report/report.html") + " >&2";
  EXPECT_EQ(std::system(check.c_str()), 0);
  EXPECT_NE(Read(Path("report/summary.json"))
                .find("\"flagged\": [\n      \"b\"\n    ]"),
            std::string::npos);
  // Each test's pressures with their unit, its uncertainty and frames; the
  // files beside the page linked; the inputs with their SHA-256.
  const std::string html = Read(Path("report/report.html"));
  for (const std::string& text :
       {std::string("<th>pressures [psi]</th>"),
        std::string("<th>U = 2u [mm]</th>"),
        std::string("<h2>Uncertainty budget</h2>"),
        std::string("<th>frames initial / actuated / final</th>"),
        std::string("<a href=\"results.csv\">"),
        std::string("<a href=\"summary.json\">"),
        std::string("<a href=\"trajectory.csv\">"),
        "<td>" + video_sha256 + "</td>"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
  // Equal axes where positions are drawn: a square plot whose y and z
  // domains span the same millimetres.
  const nlohmann::json positions =
      ChartTitled(html, "Measured and predicted displacements");
  ASSERT_TRUE(positions.is_object());
  const nlohmann::json& spec = positions["spec"];
  EXPECT_EQ(spec["width"], spec["height"]);
  const nlohmann::json& encoding = spec["layer"][1]["encoding"];
  const auto span = [&](const char* axis) {
    const nlohmann::json& d = encoding[axis]["scale"]["domain"];
    return d[1].get<double>() - d[0].get<double>();
  };
  EXPECT_GT(span("x"), 0.0);
  EXPECT_NEAR(span("x"), span("y"), 1e-9);
  // Annotated crops: three windows of three tests.
  EXPECT_EQ(Count(Read(Path("report/report.html")), "<figure><svg"), 9);

  // Only the windows' frames: the same displacements from fewer frames. A
  // window's first frame after a seek is found afresh rather than tracked, so
  // its centres may differ within the centre's iteration tolerance. Compared
  // with the camera taken to be still (a registered video's tag pose is
  // averaged over the frames read).
  options.no_registration = true;
  options.output_directory = Path("still");
  ASSERT_EQ(RunValidate(options, out), 0);
  options.windows_only = true;
  options.output_directory = Path("windows");
  ASSERT_EQ(RunValidate(options, out), 0);
  CsvReader all(Path("still/results.csv")),
      windows(Path("windows/results.csv"));
  std::vector<std::string_view> a, w;
  while (all.ReadRow(&a)) {
    ASSERT_TRUE(windows.ReadRow(&w));
    for (size_t k = 0; k < a.size(); ++k) {
      const std::optional<double> x = ParseDouble(a[k]), y = ParseDouble(w[k]);
      const std::string& column = all.header()[k];
      if (x && y && column.rfind("frames_", 0) == 0) {
        // A window's first frame after a seek may fall one frame later.
        EXPECT_NEAR(*x, *y, 1.0) << column;
      } else if (column.rfind("u_", 0) == 0 || column == "hysteresis_u_mm" ||
                 column == "model_error_significant" ||
                 column == "hysteresis_verdict" ||
                 column.find("lift_") != std::string::npos) {
        // The codec's term rests on the I pictures each run reads (all of
        // them, or those near the windows; docs/uncertainty.md): both runs
        // give a budget, not the same one. A lift is measured against the
        // dots at rest in the frames read, and is known to ~0.1 mm
        // (docs/measurement.md): both runs give one.
        EXPECT_EQ(a[k].empty(), w[k].empty()) << column;
      } else if (x && y) {
        EXPECT_NEAR(*x, *y, 2e-4) << column;
      } else {
        EXPECT_EQ(a[k], w[k]);
      }
    }
  }
  EXPECT_LT(Count(Read(Path("windows/trajectory.csv")), "\n"),
            Count(Read(Path("still/trajectory.csv")), "\n"));
  EXPECT_EQ(Count(Read(Path("windows/report.html")), "<figure><svg"), 9);
}

// Renders the slip plan changed by `set` (one thing a phone's video is,
// with the camera still) and checks every displacement within 0.005 mm of
// the truth and hysteresis on the test that slips and no other. Returns the
// dots' spacing through the tag's scale over the plan's layout (the
// distortion check's median ratio).
PhoneCheck ValidateCommandTest::CheckPhoneFormat(
    const std::function<void(RenderCommandOptions*)>& set,
    bool compare_tag_stride) {
  RenderCommandOptions render = QuickRender(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
scene: {settle_time_constant_s: 0.1, lead_in_s: 1.5, hold_s: 1.2, rest_s: 2}
tests:
  - {id: a, pressures: [6, 0, 0]}
  - {id: b, pressures: [0, 6, 0], residual_offset_mm: [0.1, 0]}
)");
  // Little codec loss (x264 at CRF 10), so 720p meets the bar of the 1080p
  // samples. HDR is filmed as a phone does, 1080p HEVC at 10 Mb/s: its SDR
  // range spans about half the codes, so at 720p the codec's loss alone
  // costs more than the bar (12-bit PQ at CRF 6: 0.007 mm; at CRF 0: 0.003).
  render.crf = 10;
  render.preset = "medium";
  set(&render);
  if (render.codec == "hevc") {
    render.resolution = "1080p";
    render.bitrate_mbps = 10.0;
    render.preset = "fast";
  }
  std::ostringstream out;
  RenderClip(render);
  const TestPlan plan = LoadTestPlan(render.plan_out_path);
  VideoMeasurementOptions measure;
  measure.progress = false;
  const VideoMeasurement m = MeasureVideo(plan, render.output_path, measure);
  const ValidationResult result = ScoreTests(plan, m, ValidationOptions());
  const RenderedTruth truth = ReadRenderedTruth(render.truth_path);
  double worst = 0.0;
  for (const TestScore& score : result.tests) {
    EXPECT_TRUE(score.measured) << score.reason;
    if (!score.measured) continue;
    const Eigen::VectorXd d = TruthDisplacement(
        truth, score.windows[kInitialWindow], score.windows[kActuatedWindow]);
    worst = std::max(worst, (score.heads[0].measured_mm - d).norm());
  }
  std::cout << m.video_format << ": worst displacement error " << worst
            << " mm\n";
  EXPECT_LT(worst, 0.005);
  EXPECT_EQ(result.hysteresis_flagged, std::vector<std::string>{"b"});
  EXPECT_TRUE(result.camera_moved_windows.empty());
  if (compare_tag_stride) {
    const double difference =
        DifferenceFromTagInEveryFrame(plan, render.output_path, result);
    std::cout << "tag located in " << TagLocatedShare(m)
              << " of the frames; largest difference from the tag in every "
                 "frame "
              << difference << " mm\n";
    EXPECT_LT(TagLocatedShare(m), 0.5);
    EXPECT_LT(difference, 2e-4);
  }
  PhoneCheck check;
  check.layout_ratio = m.distortion.median_ratio;
  EXPECT_TRUE(m.camera_processing.measured) << m.camera_processing.why_not;
  for (const ProcessingEffect& e : m.camera_processing.effects) {
    check.effects.push_back(e.name);
  }
  check.tag_cell_px = m.camera_processing.tag_cell_px;
  check.tag_scale_at_risk = m.camera_processing.tag_scale_at_risk;
  std::cout << "camera's processing: " << m.camera_processing.Summary() << "\n";
  return check;
}

// Whether `check` named the effect whose name starts with `prefix`.
bool Named(const PhoneCheck& check, const std::string& prefix) {
  return std::any_of(
      check.effects.begin(), check.effects.end(),
      [&](const std::string& name) { return name.starts_with(prefix); });
}

// An iPhone's default: HEVC Main 10 with HLG and BT.2020.
// Its tag is located on one frame in four and agrees with every frame's.
// Its images are the light its transfer names: no processing is named.
TEST_F(ValidateCommandTest, HlgTenBitHevcMeetsTheBar) {
  const PhoneCheck check = CheckPhoneFormat(
      [](RenderCommandOptions* r) {
        r->codec = "hevc";
        r->bit_depth = 10;
        r->hdr = "hlg";
      },
      true);
  EXPECT_TRUE(check.effects.empty()) << check.effects.front();
}

// PQ in 12 bits, 4:4:4 and full range.
TEST_F(ValidateCommandTest, PqTwelveBitFullRangeMeetsTheBar) {
  CheckPhoneFormat([](RenderCommandOptions* r) {
    r->codec = "hevc";
    r->bit_depth = 12;
    r->chroma = "4:4:4";
    r->full_range = true;
    r->hdr = "pq";
  });
}

// A portrait video stored sideways with its display rotation, in 4:2:2.
TEST_F(ValidateCommandTest, PortraitRotatedVideoMeetsTheBar) {
  CheckPhoneFormat([](RenderCommandOptions* r) {
    r->chroma = "4:2:2";
    r->resolution = "720x1280";
    r->rotation_deg = 90;
  });
}

// A phone's own processing on the codes of a stream that says BT.709
// (issue 28), at 1080p where the tag's cells are 17 px: each moves a tag
// edge by tenths of a pixel, up to 0.6 % of the tag's size, which the
// border's midlines leave out, so the dots' spacing measured through the
// tag's scale is the plan's to 0.05 %. (On 720p's 11 px cells the
// midlines still follow the processing; there the tag is fitted whole:
// PhoneCurveAndSharpeningOnSmallCellsMeetTheBar.)
TEST_F(ValidateCommandTest, PhoneToneCurveMeetsTheBar) {
  const PhoneCheck check = CheckPhoneFormat([](RenderCommandOptions* r) {
    r->resolution = "1080p";
    r->processing.tone_curve = 0.6;
  });
  EXPECT_NEAR(check.layout_ratio, 1.0, 5e-4);
}

// The report names the sharpening (CameraProcessing).
TEST_F(ValidateCommandTest, PhoneSharpeningMeetsTheBar) {
  const PhoneCheck check = CheckPhoneFormat([](RenderCommandOptions* r) {
    r->resolution = "1080p";
    r->processing.sharpen = "1.5,1.0";
  });
  EXPECT_NEAR(check.layout_ratio, 1.0, 5e-4);
  EXPECT_TRUE(Named(check, "sharpening halos"));
  EXPECT_TRUE(Named(check, "a tone curve or filtering"));
  // 1080p draws the 25 mm tag's cells 16.8 px wide: over the 15 px below
  // which the processing could move its scale.
  EXPECT_NEAR(check.tag_cell_px, 16.8, 0.3);
  EXPECT_FALSE(check.tag_scale_at_risk);
}

// The S-curve, then sharpening, on 720p's 11.2 px cells, where the border's
// midlines follow them (0.5 % of the scale, and 0.0074 mm of displacement
// error on the four-point delta at CRF 17): the tag is fitted whole, and
// its scale holds as at 1080p.
TEST_F(ValidateCommandTest, PhoneCurveAndSharpeningOnSmallCellsMeetTheBar) {
  const PhoneCheck check = CheckPhoneFormat([](RenderCommandOptions* r) {
    r->processing.tone_curve = 0.6;
    r->processing.sharpen = "1.5,1.0";
  });
  EXPECT_TRUE(Named(check, "sharpening halos"));
  EXPECT_NEAR(check.tag_cell_px, 11.2, 0.3);
  EXPECT_FALSE(check.tag_scale_at_risk);
  std::cout << "dots' spacing over the layout: " << check.layout_ratio << "\n";
  EXPECT_NEAR(check.layout_ratio, 1.0, 1e-3);
}

// The lens's blur in light (none, sharper than any camera, in the first
// test), then the phone's S-curve and its sharpening on the codes, at two
// strengths (separate tests, so ctest runs them side by side). Each
// sharpens: the halos are named and the tag's scale holds to 0.05 %.
PhoneCheck ValidateCommandTest::CheckPhonePipeline(const PhonePipeline& phone) {
  const PhoneCheck check = CheckPhoneFormat([&](RenderCommandOptions* r) {
    r->resolution = "1080p";
    r->processing.lens_blur_px = phone.lens_blur_px;
    r->processing.tone_curve = phone.tone_curve;
    r->processing.sharpen = phone.sharpen;
    r->processing.bayer = phone.bayer;
    r->processing.temporal_denoise = phone.temporal_denoise;
    if (!phone.bayer.empty()) r->processing.sensor_full_well_e = 6000.0;
  });
  EXPECT_NEAR(check.layout_ratio, 1.0, 5e-4);
  EXPECT_TRUE(Named(check, "sharpening halos"));
  return check;
}

// Pixel-sharp edges, curved and sharpened: the light the codes name
// overshoots and undershoots about each dot's edge unevenly with the pixel
// grid, which cost the dots weighed in light 0.0068 mm; weighed in codes,
// as the halos have them (docs/measurement.md), 0.0042 mm.
TEST_F(ValidateCommandTest,
       PhoneCurveAndSharpeningOnPixelSharpEdgesMeetTheBar) {
  // No lens blur, S-curve 0.6, sharpening 1.5 px x 1.0, no colour filter,
  // no noise reduction.
  CheckPhonePipeline({0.0, 0.6, "1.5,1.0", "", 0.0});
}

// The milder strength, with the phone's temporal noise reduction (each
// frame blended with the last where little moves).
TEST_F(ValidateCommandTest,
       PhoneBlurCurveSharpeningAndNoiseReductionMeetTheBar) {
  CheckPhonePipeline({.lens_blur_px = 0.6,
                      .tone_curve = 0.6,
                      .sharpen = "1.5,1.0",
                      .bayer = "",
                      .temporal_denoise = 0.5});
}

// The stronger one through an RGGB Bayer sensor with raw shot and read
// noise and bilinear demosaicing (its zipper at every edge depends on where
// the edge falls on the colour filter).
TEST_F(ValidateCommandTest, PhoneBayerBlurCurveAndSharpeningMeetTheBar) {
  const PhoneCheck check = CheckPhonePipeline({.lens_blur_px = 1.0,
                                               .tone_curve = 1.0,
                                               .sharpen = "1.0,1.5",
                                               .bayer = "bilinear",
                                               .temporal_denoise = 0.0});
  EXPECT_TRUE(Named(check, "a tone curve or filtering"));
}

// A variable frame rate: frame times jitter by up to 0.4 of a frame. Its
// tag is located on one frame in four and agrees with every frame's.
TEST_F(ValidateCommandTest, VariableFrameRateMeetsTheBar) {
  const PhoneCheck check = CheckPhoneFormat(
      [](RenderCommandOptions* r) { r->vfr_jitter = 0.8; }, true);
  EXPECT_TRUE(check.effects.empty()) << check.effects.front();
  // 720p's 11 px cells, but no processing: the scale is not at risk.
  EXPECT_NEAR(check.tag_cell_px, 11.2, 0.3);
  EXPECT_FALSE(check.tag_scale_at_risk);
}

// A tag taken away after the first second on a plain table (nothing else
// static): the frames after it cannot be registered, and validate says
// which instead of measuring them against a stale registration.
TEST_F(ValidateCommandTest, NamesTheFramesItCannotRegister) {
  RenderCommandOptions render = QuickRender(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
scene: {settle_time_constant_s: 0.1, lead_in_s: 1.5, hold_s: 1.5, rest_s: 2}
tests:
  - {id: a, pressures: [6, 0, 0]}
)");
  render.no_ring = true;
  render.conditions.tag_gone_after_s = 1.0;
  std::ostringstream out;
  RenderClip(render);
  ValidateCommandOptions options = ValidateClip(render, "report");
  const std::string message = InputErrorOf([&] { RunValidate(options, out); });
  EXPECT_NE(message.find("could not be registered to the bench (frames 30-"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("tag"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(Path("report")));
  // Without registration the camera is taken to be still, as asked.
  options.no_registration = true;
  EXPECT_EQ(RunValidate(options, out), 0);
}

// A tag the camera never sees: one line naming the plan's tag and what to
// do, and no report.
TEST_F(ValidateCommandTest, SaysWhenTheTagIsNeverVisible) {
  RenderCommandOptions render = QuickRender(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
scene: {settle_time_constant_s: 0.1, lead_in_s: 1, hold_s: 1, rest_s: 1}
tests:
  - {id: a, pressures: [6, 0, 0]}
)");
  render.conditions.tag_gone_after_s = 0.0;
  std::ostringstream out;
  RenderClip(render);
  const std::string message =
      InputErrorOf([&] { RunValidate(ValidateClip(render, "report"), out); });
  EXPECT_NE(message.find("found no tag36h11 tag in the first"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("is id 3; put the tag in view"), std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(Path("report")));
}

// A dot plane at or behind the camera (a height in the wrong unit, say) is
// refused once the tag shows where the camera is, before any measurement.
TEST_F(ValidateCommandTest, RefusesADotPlaneBehindTheCamera) {
  const std::string message =
      ErrorWithEditedDeltaPlan("plane_offset_mm: 16", "plane_offset_mm: 16000");
  EXPECT_NE(message.find("plan.yaml: calibration.plane_offset_mm: 16000 mm "
                         "puts the dots' plane farther from the tag than the "
                         "camera"),
            std::string::npos)
      << message;
  // Far below the tag is as impossible, and was blamed on the first frame's
  // dots (issue 30).
  const std::string below =
      ErrorWithEditedDeltaPlan("plane_offset_mm: 16", "plane_offset_mm: -1e6");
  EXPECT_NE(below.find("calibration.plane_offset_mm: -1000000 mm puts the "
                       "dots' plane farther from the tag than the camera"),
            std::string::npos)
      << below;
}

// A focal length no camera has is named under its own key, not blamed on
// plane_offset_mm or the first frame (issue 30).
TEST_F(ValidateCommandTest, NamesAnImpossibleFocalLengthUnderItsKey) {
  const std::string message = ErrorWithEditedDeltaPlan(
      "plane_offset_mm: 16", "plane_offset_mm: 16\n  focal_length_35mm: 1");
  EXPECT_NE(message.find("focal_length_35mm: 1 mm is no camera's 35 "
                         "mm-equivalent focal length"),
            std::string::npos)
      << message;
}

TEST_F(ValidateCommandTest, WindowsOnlyNeedsThePlansTimes) {
  ValidateCommandOptions options;
  options.video_paths = {std::string(SOFTBENCH_SOURCE_DIR) +
                         "/samples/delta/delta.mp4"};
  options.plan_path =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/delta/plan.yaml";
  options.output_directory = Path("report");
  options.windows_only = true;
  options.quiet = true;
  std::ostringstream out;
  const std::string message = InputErrorOf([&] { RunValidate(options, out); });
  EXPECT_NE(message.find("needs the test times"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(Path("report")));
}

// The regulator's log of a sample on a clock `offset_s` behind the video's:
// a row at every change and every 0.2 s between.
std::string PressureLog(const std::string& sample, double offset_s) {
  const TestPlan rendered =
      LoadTestPlan(std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + sample +
                   "/rendered.plan.yaml");
  std::string log = "time_s,p1,p2,p3\n-2,0,0,0\n";
  for (const TestPoint& test : rendered.tests) {
    const double actuate = *test.actuate_s - offset_s;
    const double release = *test.release_s - offset_s;
    for (double t = actuate; t < release; t += 0.2) {
      log += fmt::format("{:.3f},{},{},{}\n", t, test.pressures[0],
                         test.pressures[1], test.pressures[2]);
    }
    log += fmt::format("{:.3f},0,0,0\n", release);
  }
  return log;
}

// Validates `sample` with a log on a clock 2.5 s behind the video's and
// checks the offset found and the crops of every window.
ValidateCommandOptions ValidateCommandTest::CheckClockOffset(
    const std::string& sample, const std::string& log, int windows) {
  const std::string dir =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + sample + "/";
  ValidateCommandOptions options;
  options.video_paths = {dir + sample + ".mp4"};
  options.plan_path = dir + "plan.yaml";
  options.pressure_log_path = Write("pressures.csv", log);
  options.output_directory = Path("report");
  options.quiet = true;
  std::ostringstream out;
  EXPECT_EQ(RunValidate(options, out), 0);
  const std::string summary = Read(Path("report/summary.json"));
  const size_t at = summary.find("its clock +");
  EXPECT_NE(at, std::string::npos) << summary.substr(0, 600);
  if (at != std::string::npos) {
    EXPECT_NEAR(std::stod(summary.substr(at + 11, 6)), 2.5, 1.0 / 30.0)
        << "within one frame";
  }
  // Crops of every window, decoded again once the times were known.
  EXPECT_EQ(Count(Read(Path("report/report.html")), "<figure><svg"), windows);
  return options;
}

TEST_F(ValidateCommandTest, AlignsAPressureLogWithAClockOffset) {
  const std::string log = PressureLog("delta", 2.5);
  ValidateCommandOptions options = CheckClockOffset("delta", log, 42);
  std::ostringstream out;
  // The log's pressures that disagree with the plan are refused by name.
  std::string wrong = log;
  for (size_t at = 0; (at = wrong.find(",6,6,0", at)) != std::string::npos;) {
    wrong.replace(at, 6, ",6,5,0");
  }
  options.pressure_log_path = Write("wrong.csv", wrong);
  const std::string message = InputErrorOf([&] { RunValidate(options, out); });
  EXPECT_NE(message.find("plan test 't1a'"), std::string::npos) << message;
}

// The same on the phone sample: variable frame rate, portrait, HDR, a
// camera that moves. The clock comes from the frames' timestamps.
TEST_F(ValidateCommandTest, AlignsAPressureLogOnAVariableFrameRateVideo) {
  CheckClockOffset("phone", PressureLog("phone", 2.5), 9);
}

TEST_F(ValidateCommandTest, SeveralVideosGetOneReportEachAndAnIndex) {
  const std::string samples = std::string(SOFTBENCH_SOURCE_DIR) + "/samples/";
  ValidateCommandOptions options;
  options.video_paths = {samples + "delta/delta.mp4",
                         samples + "delta/delta.mp4"};
  options.plan_path = samples + "delta/plan.yaml";
  options.output_directory = Path("reports");
  options.jobs = 2;
  options.quiet = true;
  std::ostringstream out;
  ASSERT_EQ(RunValidate(options, out), 0);
  for (const char* name : {"delta", "delta_2"}) {
    for (const char* file :
         {"report.html", "results.csv", "summary.json", "trajectory.csv"}) {
      EXPECT_TRUE(fs::exists(Path("reports/") + name + "/" + file))
          << name << "/" << file;
    }
  }
  // Both measurements are of the same file: identical results.
  EXPECT_EQ(Read(Path("reports/delta/results.csv")),
            Read(Path("reports/delta_2/results.csv")));
  const std::string index = Read(Path("reports/index.csv"));
  EXPECT_EQ(std::count(index.begin(), index.end(), '\n'), 3) << index;
  EXPECT_NE(
      Read(Path("reports/index.html")).find("href=\"delta_2/report.html\""),
      std::string::npos);
  EXPECT_NE(out.str().find("report: " + Path("reports") + "/index.html"),
            std::string::npos)
      << out.str();
}

TEST_F(ValidateCommandTest, RefusesAPlanWithSomeTimesAndWritesNothing) {
  const std::string message =
      ErrorWithEditedDeltaPlan("pressures: [6, 6, 0]}",
                               "pressures: [6, 6, 0], actuate_s: 2, "
                               "release_s: 7}");
  EXPECT_NE(message.find("some tests have times and some do not"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

// The bench ran t2a and t3a in each other's place (the plan lists them the
// other way round): both are named and not scored, the statistics over the
// rest stay right, the exit status says so, and nothing is flagged as
// hysteresis; a test the plan marks skipped is reported as such.
TEST_F(ValidateCommandTest, NamesTestsThatDoNotMoveAsTheirPlanEntries) {
  const std::string sample = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  std::string plan = Read(sample + "/delta/rendered.plan.yaml");
  const auto swap = [&](const std::string& a, const std::string& b) {
    const size_t i = plan.find(a), j = plan.find(b);
    ASSERT_NE(i, std::string::npos);
    ASSERT_NE(j, std::string::npos);
    plan.replace(j, b.size(), a);
    plan.replace(i, a.size(), b);
  };
  swap("pressures: [6, 3, 0]", "pressures: [6, 0, 0]");  // t2a <-> t3a
  plan += "  - {id: extra, pressures: [1, 1, 1], skipped: true}\n";
  ValidateCommandOptions options = DeltaWithPlan(plan, /*windows_only=*/true);
  std::ostringstream out;
  EXPECT_EQ(RunValidate(options, out), kExitSomeTestsNotScored);
  EXPECT_NE(out.str().find("not scored, their motion does not fit their plan "
                           "entries: t2a, t3a"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("skipped on the bench (as the plan says): extra"),
            std::string::npos)
      << out.str();
  CsvReader results(Path("report/results.csv"));
  const int id = results.ColumnIndex("test_id");
  const int status = results.ColumnIndex("status");
  std::vector<std::string_view> fields;
  std::map<std::string, std::string> statuses;
  while (results.ReadRow(&fields)) {
    statuses[std::string(fields[id])] = std::string(fields[status]);
  }
  EXPECT_EQ(statuses["t2a"], "mismatch");
  EXPECT_EQ(statuses["t3a"], "mismatch");
  EXPECT_EQ(statuses["extra"], "skipped");
  EXPECT_EQ(statuses["t2b"], "ok");
  const std::string summary = Read(Path("report/summary.json"));
  EXPECT_NE(summary.find("\"skipped_tests\""), std::string::npos);
  EXPECT_NE(out.str().find("model error mean 0.00"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("hysteresis above 0.05 mm: none"), std::string::npos)
      << out.str();
}

// The delta sample's dots are 16 mm above its tag; a plan that says 19 mm
// maps them through a plane 3 mm too near the camera, and their spacing
// comes out 0.6 % short of the layout, alike over the video. The check
// names the height they measure at, keeps the tag's scale and carries the
// difference in the uncertainty.
TEST_F(ValidateCommandTest, NamesTheDotsHeightAPlanMisstates) {
  ValidateCommandOptions options = DeltaWithPlan(
      EditedRenderedDeltaPlan("plane_offset_mm: 16", "plane_offset_mm: 19"),
      /*windows_only=*/true);
  std::ostringstream out;
  RunValidate(options, out);
  const nlohmann::json calibration =
      nlohmann::json::parse(Read(Path("report/summary.json")))["calibration"];
  const nlohmann::json& layout = calibration["layout_check"];
  std::cout << calibration["distortion_check"] << "\n";
  EXPECT_TRUE(calibration["distortion_warning"].get<bool>());
  EXPECT_NEAR(layout["implied_plane_offset_mm"].get<double>(), 16.0, 0.5);
  EXPECT_LT(layout["spacing_over_layout_percent"].get<double>(), -0.4);
  EXPECT_LT(layout["shape_misfit_percent"].get<double>(), 0.1);
  EXPECT_EQ(layout["shape_head"], "head");
  const std::string message = calibration["distortion_check"];
  for (const char* named :
       {"plane_offset_mm says 19", "tag 0", "scale is kept"}) {
    EXPECT_NE(message.find(named), std::string::npos) << named;
  }
}

// The plan's times are 3 s late against the video: every window lands on
// another phase of the motion. Some tests then look plausible by chance (a
// small motion read backwards); none may be scored, and no hysteresis may be
// flagged.
TEST_F(ValidateCommandTest, ScoresNothingWhenThePlansTimesAreShifted) {
  const std::string sample = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  std::string plan = Read(sample + "/delta/rendered.plan.yaml");
  std::string shifted;
  std::istringstream lines(plan);
  for (std::string line; std::getline(lines, line);) {
    double actuate = 0.0, release = 0.0;
    const size_t at = line.find("actuate_s: ");
    if (at != std::string::npos &&
        std::sscanf(line.c_str() + at, "actuate_s: %lf, release_s: %lf",
                    &actuate, &release) == 2) {
      line = line.substr(0, at) + "actuate_s: " + std::to_string(actuate + 3) +
             ", release_s: " + std::to_string(release + 3) + "}";
    }
    shifted += line + "\n";
  }
  ASSERT_NE(shifted.find("actuate_s: 5.0"), std::string::npos) << shifted;
  ValidateCommandOptions options =
      DeltaWithPlan(shifted, /*windows_only=*/true);
  std::ostringstream out;
  EXPECT_EQ(RunValidate(options, out), kExitSomeTestsNotScored);
  CsvReader results(Path("report/results.csv"));
  const int status = results.ColumnIndex("status");
  std::vector<std::string_view> fields;
  int rows = 0;
  while (results.ReadRow(&fields)) {
    ++rows;
    EXPECT_EQ(fields[status], "mismatch") << fields[0];
  }
  EXPECT_EQ(rows, 14);
  EXPECT_NE(out.str().find("hysteresis above 0.05 mm: none"), std::string::npos)
      << out.str();
}

// Bit flips in the middle of the stream: the windows that lost frames are
// named with the reason, their tests are not measured, the rest are scored
// as before, and the exit status says the report is not whole.
TEST_F(ValidateCommandTest, NamesTestsLostToDamagedVideoData) {
  const std::string sample = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  std::string video = Read(sample + "/delta/delta.mp4");
  std::mt19937 random(3);
  std::uniform_int_distribution<size_t> where(video.size() / 3,
                                              2 * video.size() / 3);
  for (int i = 0; i < 40; ++i) video[where(random)] ^= 0x10;
  ValidateCommandOptions options;
  options.video_paths = {Write("flipped.mp4", video)};
  options.plan_path = sample + "/delta/rendered.plan.yaml";
  options.output_directory = Path("report");
  options.quiet = true;
  std::ostringstream out;
  EXPECT_EQ(RunValidate(options, out), kExitSomeTestsNotScored);
  EXPECT_NE(out.str().find("frames lost to damaged video data)\n"),
            std::string::npos)
      << out.str();
  CsvReader results(Path("report/results.csv"));
  const int status = results.ColumnIndex("status");
  const int reason = results.ColumnIndex("reason");
  const int error = results.ColumnIndex("model_error_mm");
  ASSERT_GE(reason, 0);
  std::vector<std::string_view> fields;
  int lost = 0, ok = 0;
  while (results.ReadRow(&fields)) {
    if (fields[status] == "not measured") {
      ++lost;
      EXPECT_NE(fields[reason].find("lost to damaged video data"),
                std::string_view::npos)
          << fields[reason];
      EXPECT_EQ(fields[error], "");
    } else if (fields[status] == "ok") {
      ++ok;
      EXPECT_LT(std::stod(std::string(fields[error])), 0.005) << fields[0];
    }
  }
  EXPECT_GT(lost, 0);
  EXPECT_GT(ok, 0);
}

// A video that stops before the plan does (a phone's storage ran out): the
// tests beyond its end are named with the reason, the others are scored,
// and the exit status says the report is not whole. No settling warning is
// made up for them.
TEST_F(ValidateCommandTest, NamesTestsBeyondTheVideosEnd) {
  ValidateCommandOptions options =
      DeltaWithPlan(EditedRenderedDeltaPlan("actuate_s: 106, release_s: 111",
                                            "actuate_s: 206, release_s: 211"),
                    /*windows_only=*/true);
  std::ostringstream out;
  EXPECT_EQ(RunValidate(options, out), kExitSomeTestsNotScored);
  EXPECT_NE(out.str().find("not measured: t7b (initial window 205.00-206.00 "
                           "s: beyond the video's end"),
            std::string::npos)
      << out.str();
  // t6b rests until the video ends: measured.
  EXPECT_EQ(out.str().find("not measured: t6b"), std::string::npos)
      << out.str();
  const std::string summary = Read(Path("report/summary.json"));
  EXPECT_EQ(summary.find("may not have settled"), std::string::npos);
}

}  // namespace
}  // namespace softbench
