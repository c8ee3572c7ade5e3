// Measurement accuracy on rendered frames with exact truth (issue: vision).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "calibration/camera_calibration.h"
#include "model/units.h"
#include "pipelines/measurement/distortion_check.h"
#include "pipelines/measurement/plan_camera.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "tests/support/rendered_truth.h"
#include "tests/vision/board_images.h"
#include "vision/frame_source.h"
#include "vision/head_tracker.h"
#include "vision/plate_pose.h"
#include "vision/tag_detector.h"

namespace softbench {
namespace {

// The thesis's delta with three 4 mm red dots and a 25 mm tag, beside the
// ring by default or at `tag_center` (e.g. far out in the field, where a
// lens's distortion changes the scale by ~0.8 % from the centre's).
TestPlan DeltaPlan(const std::string& tag_center = "") {
  const std::string center =
      tag_center.empty() ? "" : ", center_mm: " + tag_center;
  return ParseTestPlan(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 0, size_mm: 25)" +
                           center + R"(}
  plane_offset_mm: 16
markers:
  - {head: head, color: red, dots: 3, dot_diameter_mm: 4}
tests:
  - {id: a, pressures: [6, 6, 0]}
)",
                       "plan.yaml");
}

constexpr char kFarTag[] = "[-110, -55]";

// The dot-plane mapping from the tag in one rendered frame, for a camera
// with the given intrinsics.
PlaneMapping TagMapping(const TestPlan& plan,
                        const CameraIntrinsics& intrinsics,
                        const cv::Mat& frame) {
  cv::Mat gray;
  cv::cvtColor(frame, gray, cv::COLOR_BGR2GRAY);
  const std::vector<TagDetection> tags = TagDetector().Detect(gray);
  EXPECT_EQ(tags.size(), 1u);
  return PlaneMapping::FromTag(intrinsics, tags.at(0).corners,
                               plan.calibration.tag->size_mm,
                               plan.calibration.plane_offset_mm);
}

struct Measured {
  std::vector<HeadObservation> heads;
  std::vector<DotTruth> truth;
};

// Renders the plan's heads at `x` (no motion) and measures the frame.
Measured RenderAndMeasure(const SceneRenderer& renderer, HeadTracker* tracker,
                          const Eigen::VectorXd& x, int64_t frame_index) {
  const cv::Mat frame = renderer.Render({x}, frame_index);
  return {tracker->Measure(ImageFrameSource(frame)), renderer.Dots(x)};
}

TEST(Measurement, DotCentresWithinFiveHundredthsOfAPixelUncompressed) {
  const TestPlan plan = DeltaPlan();
  const SceneRenderer renderer(plan, RenderOptions{});
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(2);
  const PlaneMapping mapping = TagMapping(plan, renderer.camera().intrinsics(),
                                          renderer.Render({rest}, 0));
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  double sum_sq = 0.0, binary_sum_sq = 0.0;
  int n = 0;
  for (int k = 0; k < 8; ++k) {
    Eigen::VectorXd x(2);
    x << -1.1 + 0.29 * k, 1.2 - 0.33 * k;
    const Measured m = RenderAndMeasure(renderer, &tracker, x, k);
    ASSERT_TRUE(m.heads[0].complete) << m.heads[0].note;
    for (int i = 0; i < 3; ++i) {
      const DotObservation& d = m.heads[0].dots[i];
      // Identity follows the layout: truth dot i is plan layout dot i.
      sum_sq += (d.pixel - m.truth[i].pixel).squaredNorm() / 2;
      binary_sum_sq += (d.binary_pixel - m.truth[i].pixel).squaredNorm() / 2;
      ++n;
    }
  }
  const double rms = std::sqrt(sum_sq / n),
               binary = std::sqrt(binary_sum_sq / n);
  std::cout << "dot centre RMS: luma " << rms << " px, binary mask " << binary
            << " px\n";
  EXPECT_LT(rms, 0.05);
  EXPECT_GT(binary, 2 * rms);  // the thesis's centroid, shown beside ours
}

// Amplitude of the first harmonic of `error` over the sub-pixel `phase`:
// what pixel locking looks like.
double PhaseHarmonic(const std::vector<double>& phase,
                     const std::vector<double>& error) {
  std::complex<double> sum = 0.0;
  for (size_t i = 0; i < phase.size(); ++i) {
    sum += error[i] * std::polar(1.0, 2.0 * std::numbers::pi * phase[i]);
  }
  return 2.0 * std::abs(sum) / phase.size();
}

// Largest gap between the empirical distribution of `values` in [0, 1) and
// the uniform one (Kolmogorov-Smirnov statistic).
double UniformityGap(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  double gap = 0.0;
  for (size_t i = 0; i < values.size(); ++i) {
    gap = std::max({gap, std::abs(values[i] - double(i) / values.size()),
                    std::abs(values[i] - double(i + 1) / values.size())});
  }
  return gap;
}

TEST(Measurement, NoPixelLocking) {
  const TestPlan plan = DeltaPlan();
  const SceneRenderer renderer(plan, RenderOptions{});
  const PlaneMapping mapping =
      TagMapping(plan, renderer.camera().intrinsics(),
                 renderer.Render({Eigen::VectorXd::Zero(2)}, 0));
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  // 24 shifts across one pixel in u and, in another order, in v: each
  // dot's true phases are evenly spread over the pixel on both axes.
  const double mm_per_px = mapping.MmPerPixelAt({959.5, 539.5});
  std::vector<double> phase, error, binary_error, fraction;
  for (int k = 0; k < 24; ++k) {
    Eigen::VectorXd x(2);
    x << 0.3 + mm_per_px * k / 24.0, -0.2 + mm_per_px * (5 * k % 24) / 24.0;
    const Measured m = RenderAndMeasure(renderer, &tracker, x, k);
    ASSERT_TRUE(m.heads[0].complete) << m.heads[0].note;
    for (int i = 0; i < 3; ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        const double truth = m.truth[i].pixel[axis];
        const double measured = m.heads[0].dots[i].pixel[axis];
        phase.push_back(truth - std::floor(truth));
        error.push_back(measured - truth);
        binary_error.push_back(m.heads[0].dots[i].binary_pixel[axis] - truth);
        fraction.push_back(measured - std::floor(measured));
      }
    }
  }
  const double locking = PhaseHarmonic(phase, error);
  std::cout << "phase harmonic: luma " << locking << " px, binary mask "
            << PhaseHarmonic(phase, binary_error) << " px; uniformity gap "
            << UniformityGap(fraction) << " (truth " << UniformityGap(phase)
            << ")\n";
  EXPECT_LT(locking, 0.005);
  EXPECT_LT(UniformityGap(fraction), 0.08);
}

// Displacements measured on stills against their truth, for one camera.
double WorstDisplacementError(const TestPlan& plan, const RenderOptions& render,
                              const CameraIntrinsics& measure_with,
                              double* binary_worst = nullptr) {
  const SceneRenderer renderer(plan, render);
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(2);
  const cv::Mat first = renderer.Render({rest}, 0);
  HeadTracker tracker(TagMapping(plan, measure_with, first),
                      PlanHeadMarkers(plan));
  const HeadObservation at_rest = tracker.Measure(ImageFrameSource(first))[0];
  // Table 4.1's extremes and a point in between.
  const double points[][2] = {{-1.1254, 0.6497},
                              {0.0, 1.2874},
                              {1.1254, 0.6497},
                              {-0.5640, -0.9},
                              {0.7, -1.2}};
  double worst = 0.0, worst_binary = 0.0;
  int index = 1;
  for (const auto& p : points) {
    Eigen::VectorXd x(2);
    x << p[0], p[1];
    const HeadObservation o =
        tracker.Measure(ImageFrameSource(renderer.Render({x}, index++)))[0];
    EXPECT_TRUE(o.complete) << o.note;
    worst = std::max(worst, (o.position_mm - at_rest.position_mm -
                             Eigen::Vector2d(x[0], x[1]))
                                .lpNorm<Eigen::Infinity>());
    worst_binary = std::max(worst_binary,
                            (o.binary_position_mm - at_rest.binary_position_mm -
                             Eigen::Vector2d(x[0], x[1]))
                                .lpNorm<Eigen::Infinity>());
  }
  if (binary_worst != nullptr) *binary_worst = worst_binary;
  return worst;
}

TEST(Measurement, TagCorrectsFiveDegreeTilt) {
  const TestPlan plan = DeltaPlan();
  RenderOptions render;
  render.tilt_x_deg = 5.0;
  render.tilt_y_deg = -3.0;
  double binary = 0.0;
  const double worst =
      WorstDisplacementError(plan, render, render.intrinsics, &binary);
  std::cout << "5 deg tilt: worst displacement error " << worst
            << " mm (binary mask " << binary << " mm)\n";
  EXPECT_LT(worst, 0.005);
}

TEST(Measurement, KnownDistortionCorrected) {
  const TestPlan plan = DeltaPlan();
  RenderOptions render;
  render.intrinsics.distortion[0] = -0.1;
  EXPECT_LT(WorstDisplacementError(plan, render, render.intrinsics), 0.005);
}

TEST(Measurement, CalibratedDistortionCorrected) {
  const TestPlan plan = DeltaPlan(kFarTag);
  RenderOptions render;
  render.intrinsics.distortion[0] = -0.1;
  // Calibrate the very lens from rendered checkerboards.
  const BoardOptions board{9, 6, 20.0};
  const BoardRenderer boards(render.intrinsics, 9, 6, 20.0);
  std::vector<std::vector<cv::Point2f>> corners;
  int seed = 1;
  for (const Camera& view : BoardViews(render.intrinsics, 600.0)) {
    corners.push_back(
        FindBoardCorners(boards.Render(view, 0.6, seed++), board));
  }
  const CameraCalibrationSummary summary = CalibrateCamera(
      corners, {render.intrinsics.width_px, render.intrinsics.height_px},
      {board, 5, false});
  ASSERT_TRUE(summary.converged) << summary.why_not;
  CameraIntrinsics calibrated = render.intrinsics;
  const cv::Matx33d& k = summary.calibration.camera_matrix;
  calibrated.fx_px = k(0, 0);
  calibrated.fy_px = k(1, 1);
  calibrated.cx_px = k(0, 2);
  calibrated.cy_px = k(1, 2);
  calibrated.distortion = summary.calibration.distortion;
  const double worst = WorstDisplacementError(plan, render, calibrated);
  // Ignoring the distortion is what the check below must catch.
  CameraIntrinsics ignored = render.intrinsics;
  ignored.distortion = {};
  const double uncorrected = WorstDisplacementError(plan, render, ignored);
  std::cout << "k1 = -0.1: worst error " << worst
            << " mm with calibrated intrinsics (k1 = "
            << calibrated.distortion[0] << "), " << uncorrected
            << " mm ignoring distortion\n";
  EXPECT_LT(worst, 0.005);
  EXPECT_GT(uncorrected, 0.005);  // so the correction is what passes
}

TEST(Measurement, DistortionCheckWarnsWithoutIntrinsics) {
  const TestPlan plan = DeltaPlan(kFarTag);
  RenderOptions render;
  render.intrinsics.distortion[0] = -0.1;
  const SceneRenderer renderer(plan, render);
  const cv::Mat frame = renderer.Render({Eigen::VectorXd::Zero(2)}, 0);
  const auto check = [&](const CameraIntrinsics& intrinsics) {
    HeadTracker tracker(TagMapping(plan, intrinsics, frame),
                        PlanHeadMarkers(plan));
    FrameSample sample;
    for (HeadObservation& o : tracker.Measure(ImageFrameSource(frame))) {
      sample.heads.push_back({o, {}, {}});
    }
    return CheckDistortion(plan, {sample}, "tag 0", 0.0, {});
  };
  CameraIntrinsics ignored = render.intrinsics;
  ignored.distortion = {};
  const DistortionCheck without = check(ignored);
  const DistortionCheck with = check(render.intrinsics);
  std::cout << without.message << "\n" << with.message << "\n";
  EXPECT_TRUE(without.performed);
  EXPECT_TRUE(without.warn);
  EXPECT_FALSE(with.warn);
}

// The floating mechanism's heads sit off the camera's axis: lifted 0.6 and
// 0.35 mm and tilted up to 1 deg (issue 27), their dots show the lift, and
// the plate's pose puts them back where they are on the plane, which the
// dots' plain centre misses by the parallax.
TEST(Measurement, LiftedHeadsPoseRemovesTheParallax) {
  const TestPlan plan = ParseTestPlan(R"(mechanism: floating
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 1, size_mm: 25}
  plane_offset_mm: 16
markers:
  - {head: left, color: red, dots: 3, dot_diameter_mm: 3.5}
  - {head: right, color: green, dots: 3, dot_diameter_mm: 3.5}
tests:
  - {id: a, pressures: [1, 1, 1, 1, 1]}
)",
                                      "plan.yaml");
  const SceneRenderer renderer(plan, RenderOptions{});
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(10), moved(10);
  moved << 0.41, -0.23, -0.35, 0.18,        // displacements [mm]
      0.6, DegToRad(0.7), DegToRad(-0.7),   // left: lift, tilt
      0.35, DegToRad(-0.5), DegToRad(0.2);  // right
  const PlaneMapping mapping = TagMapping(plan, renderer.camera().intrinsics(),
                                          renderer.Render({rest}, 0));
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  // Each head's dots' plane positions, the mean of ten frames (their
  // noise: a dot's 0.01 px is about 0.05 mm of lift in one frame).
  constexpr int kFrames = 10;
  const auto dots = [&](const Eigen::VectorXd& state, int first) {
    std::vector<std::vector<Eigen::Vector2d>> mean(
        2, std::vector<Eigen::Vector2d>(3, Eigen::Vector2d::Zero()));
    for (int k = 0; k < kFrames; ++k) {
      const Measured m = RenderAndMeasure(renderer, &tracker, state, first + k);
      for (int head = 0; head < 2; ++head) {
        EXPECT_TRUE(m.heads[head].complete) << m.heads[head].note;
        for (int d = 0; d < 3; ++d) {
          mean[head][d] += m.heads[head].dots[d].plane_mm / kFrames;
        }
      }
    }
    return mean;
  };
  const auto centre = [](const std::vector<Eigen::Vector2d>& points) {
    return Eigen::Vector2d((points[0] + points[1] + points[2]) / 3);
  };
  const auto at_rest = dots(rest, 0);
  const auto now = dots(moved, kFrames);
  // The dots weighed as `validate` weighs them (MeasurePlatePoses).
  const double dot_sigma_mm = VideoMeasurementOptions{}.plate_dot_sigma_px *
                              mapping.MmPerPixelAt(Eigen::Vector2d(
                                  renderer.camera().intrinsics().cx_px,
                                  renderer.camera().intrinsics().cy_px));
  for (int head = 0; head < 2; ++head) {
    const PlatePose pose = FitPlatePose(at_rest[head], now[head],
                                        mapping.CameraAbove(), dot_sigma_mm);
    ASSERT_TRUE(pose.found) << pose.why_not;
    const Eigen::Vector2d truth = moved.segment<2>(2 * head);
    const double corrected =
        (pose.centre_mm - centre(at_rest[head]) - truth).norm();
    const double plain =
        (centre(now[head]) - centre(at_rest[head]) - truth).norm();
    EXPECT_NEAR(pose.lift_mm, moved[4 + 3 * head], 0.05) << head;
    // The issue's target for the in-plane displacement.
    EXPECT_LT(corrected, 0.005) << head;
    EXPECT_GT(plain, 3 * corrected) << head;
    EXPECT_GT(plain, 0.008) << head;
  }
}

TEST(Measurement, RedTubeAndGlintRejected) {
  const TestPlan plan = DeltaPlan();
  RenderOptions render;
  render.red_tube = true;
  render.glint = true;
  const SceneRenderer renderer(plan, render);
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(2);
  const PlaneMapping mapping = TagMapping(plan, renderer.camera().intrinsics(),
                                          renderer.Render({rest}, 0));
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  Eigen::VectorXd x(2);
  x << 0.4, -0.7;
  const Measured m = RenderAndMeasure(renderer, &tracker, x, 1);
  ASSERT_TRUE(m.heads[0].complete) << m.heads[0].note;
  EXPECT_TRUE(m.heads[0].full_frame);
  EXPECT_GE(m.heads[0].rejected_blobs, 1);  // the tube
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((m.heads[0].dots[i].pixel - m.truth[i].pixel).norm(), 0.05);
  }
}

TEST(Measurement, MissingColourSaysWhatWasSeen) {
  TestPlan plan = DeltaPlan();
  const SceneRenderer renderer(plan, RenderOptions{});
  const cv::Mat frame = renderer.Render({Eigen::VectorXd::Zero(2)}, 0);
  plan.markers[0].color = "blue";
  HeadTracker tracker(TagMapping(plan, renderer.camera().intrinsics(), frame),
                      PlanHeadMarkers(plan));
  const HeadObservation o = tracker.Measure(ImageFrameSource(frame))[0];
  EXPECT_EQ(o.dots_found, 0);
  EXPECT_NE(o.note.find("head 'head': found 0 blue dot-like blobs"),
            std::string::npos)
      << o.note;
  EXPECT_NE(o.note.find("the plan says 3 dots"), std::string::npos) << o.note;
}

// The bundled samples: every test point's window (the last windows.length_s
// before release, ~30 frames) within 0.005 mm of the truth, for every head.
void CheckSample(const std::string& name) {
  const std::string dir =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + name;
  const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
  VideoMeasurementOptions options;
  options.progress = false;
  const VideoMeasurement m =
      MeasureVideo(plan, dir + "/" + name + ".mp4", options);
  const RenderedTruth truth = ReadRenderedTruth(dir + "/truth.csv");
  ASSERT_EQ(truth.time_s.size(), m.frames.size());
  EXPECT_EQ(m.missing_dots, 0);
  double worst = 0.0, worst_binary = 0.0;
  for (const TestPoint& t : plan.tests) {
    for (size_t h = 0; h < plan.markers.size(); ++h) {
      Eigen::Vector2d measured = Eigen::Vector2d::Zero(),
                      binary = Eigen::Vector2d::Zero(),
                      expected = Eigen::Vector2d::Zero();
      int n = 0;
      for (size_t k = 0; k < m.frames.size(); ++k) {
        const double time = m.frames[k].time_s;
        if (time < *t.release_s - plan.window_s || time >= *t.release_s)
          continue;
        measured += m.frames[k].heads[h].displacement_mm;
        binary += m.frames[k].heads[h].binary_displacement_mm;
        expected += truth.displacement_mm[k][h];
        ++n;
      }
      ASSERT_GE(n, 25);
      const double error =
          ((measured - expected) / n).lpNorm<Eigen::Infinity>();
      EXPECT_LT(error, 0.005) << "test " << t.id << ", head " << h;
      worst = std::max(worst, error);
      worst_binary = std::max(
          worst_binary, ((binary - expected) / n).lpNorm<Eigen::Infinity>());
    }
  }
  std::cout << name << ": worst window error " << worst << " mm (binary mask "
            << worst_binary << " mm)\n";
}

// --windows-only's workers take the spans in whatever order they free up,
// each span after a seek: what a span measures must not depend on which
// spans its worker measured before it. The delta sample's windows measured
// all, and again with the three before the last left out: the last one's
// dots and tag corners are the same to the bit. (Not its displacements:
// the tag's mapping is averaged over every measured frame.)
TEST(MeasurementSamples, ASpanMeasuresAlikeWhateverWasMeasuredBeforeIt) {
  const std::string dir = std::string(SOFTBENCH_SOURCE_DIR) + "/samples/delta";
  const TestPlan plan = LoadTestPlan(dir + "/rendered.plan.yaml");
  VideoMeasurementOptions options;
  options.progress = false;
  options.spans = {{1.0, 2.0}, {6.0, 7.0}, {9.0, 10.0}, {13.0, 15.0}};
  const VideoMeasurement all = MeasureVideo(plan, dir + "/delta.mp4", options);
  options.spans = {{1.0, 2.0}, {13.0, 15.0}};
  const VideoMeasurement some = MeasureVideo(plan, dir + "/delta.mp4", options);
  std::vector<const FrameSample*> last;
  for (const FrameSample& f : all.frames) {
    if (f.time_s >= 13.0 || f.time_s < 2.0) last.push_back(&f);
  }
  ASSERT_EQ(some.frames.size(), last.size());
  ASSERT_GE(last.size(), 80u);
  for (size_t k = 0; k < last.size(); ++k) {
    const FrameSample& a = *last[k];
    const FrameSample& b = some.frames[k];
    ASSERT_EQ(a.frame, b.frame);
    ASSERT_TRUE(a.registered && b.registered) << a.time_s;
    // Located on the frames the tag is looked for (tag_stride) alike.
    EXPECT_EQ(a.tag_corners.has_value(), b.tag_corners.has_value());
    if (a.tag_corners && b.tag_corners) {
      for (int c = 0; c < 4; ++c) {
        EXPECT_EQ((*a.tag_corners)[c], (*b.tag_corners)[c]) << a.time_s;
      }
    }
    for (size_t h = 0; h < a.heads.size(); ++h) {
      const HeadObservation& oa = a.heads[h].observation;
      const HeadObservation& ob = b.heads[h].observation;
      ASSERT_TRUE(oa.complete && ob.complete) << a.time_s;
      for (size_t d = 0; d < oa.dots.size(); ++d) {
        EXPECT_EQ(oa.dots[d].pixel, ob.dots[d].pixel) << a.time_s;
        EXPECT_EQ(oa.dots[d].binary_pixel, ob.dots[d].binary_pixel) << a.time_s;
      }
    }
  }
}

TEST(MeasurementSamples, DeltaWindowsWithinFiveMicrons) {
  CheckSample("delta");
}

TEST(MeasurementSamples, FloatingWindowsWithinFiveMicrons) {
  CheckSample("floating");
}

}  // namespace
}  // namespace softbench
