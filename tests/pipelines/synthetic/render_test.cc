// The renderer's exactness and truth (issue: synthetic bench footage).
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "model/equilibrium.h"
#include "model/units.h"
#include "pipelines/commands/render_command.h"
#include "pipelines/measurement/camera_processing.h"
#include "pipelines/synthetic/render_timeline.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "tests/support/rendered_truth.h"
#include "tests/support/scratch_directory.h"
#include "vision/color_transfer.h"
#include "vision/dot_centre.h"
#include "vision/tag_detector.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

constexpr char kPlan[] = R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 7, size_mm: 25}
tests:
  - {id: a, pressures: [6, 6, 0], actuate_s: 0.5, release_s: 2.5}
  - {id: b, pressures: [4, 6, 1], actuate_s: 3.0, release_s: 5.0}
scene: {settle_time_constant_s: 0.1, rest_s: 1.0}
)";

RenderOptions Clean(double tilt_deg) {
  RenderOptions options;
  options.noise_sigma_dn = options.shot_noise_dn = 0.0;
  options.lighting_gradient = options.vignetting = 0.0;
  options.tilt_x_deg = tilt_deg;
  options.tilt_y_deg = -0.6 * tilt_deg;
  return options;
}

// Linear light (8-bit levels) of a BT.709 code (8-bit levels).
double Light(double code) { return 255 * ToLinear(Transfer::kSdr, code / 255); }

// Centre of the dot near `pixel` from the green channel's contrast between
// head and dot in light (a recorded frame's codes linearised): the weight is
// exactly the dot's coverage of each pixel.
// `gain`: the light's gain at the dot (a phone's local tone mapping).
Eigen::Vector2d CoverageCentroid(const cv::Mat& image,
                                 const Eigen::Vector2d& pixel,
                                 double gain = 1.0) {
  // kHeadColor / red's green codes.
  const double head = gain * Light(217.0), dot = gain * Light(40.0);
  double sum = 0, su = 0, sv = 0;
  for (int v = static_cast<int>(pixel.y()) - 16; v <= pixel.y() + 16; ++v) {
    for (int u = static_cast<int>(pixel.x()) - 16; u <= pixel.x() + 16; ++u) {
      const double value = image.depth() == CV_32F
                               ? image.at<cv::Vec3f>(v, u)[1]
                               : Light(image.at<cv::Vec3b>(v, u)[1]);
      const double w = (head - value) / (head - dot);
      sum += w, su += w * u, sv += w * v;
    }
  }
  return {su / sum, sv / sum};
}

// Centre of the image ellipse of a dot under a homography (no distortion):
// the conic of the circle mapped to the image, C = H^-T Q H^-1, has its
// centre at -A^-1 b.
Eigen::Vector2d EllipseCentre(const Camera& camera, double height,
                              const Eigen::Vector2d& centre, double radius) {
  Eigen::Matrix3d k;
  const CameraIntrinsics& in = camera.intrinsics();
  k << in.fx_px, 0, in.cx_px, 0, in.fy_px, in.cy_px, 0, 0, 1;
  const Eigen::Matrix3d h = k * camera.NormalizedFromPlane(height);
  Eigen::Matrix3d q;
  q << 1, 0, -centre.x(), 0, 1, -centre.y(), -centre.x(), -centre.y(),
      centre.squaredNorm() - radius * radius;
  const Eigen::Matrix3d hi = h.inverse();
  const Eigen::Matrix3d c = hi.transpose() * q * hi;
  return -c.topLeftCorner<2, 2>().inverse() * c.topRightCorner<2, 1>();
}

TEST(SceneRenderer, DotCentresAreExactWithoutTilt) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const SceneRenderer renderer(plan, Clean(0.0));
  // Sub-pixel positions: a displacement that is no round number of pixels.
  const Eigen::Vector2d x(-0.8137, 0.4519);
  const cv::Mat linear = renderer.RenderLinear({x});
  const cv::Mat recorded = renderer.Render({x}, 0);
  for (const DotTruth& dot : renderer.Dots(x)) {
    EXPECT_LT((CoverageCentroid(linear, dot.pixel) - dot.pixel).norm(), 0.01);
    EXPECT_LT((CoverageCentroid(recorded, dot.pixel) - dot.pixel).norm(), 0.01);
  }
}

// A head lifted 0.6 mm toward the camera and tilted 1 deg (issue 27) is
// drawn where its truth says: its dots' coverage centroids on its projected
// dot centres, spread apart by the camera's height over its own.
TEST(SceneRenderer, LiftedAndTiltedHeadsAreDrawnWhereTheTruthSays) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const SceneRenderer renderer(plan, Clean(0.0));
  Eigen::VectorXd flat(5), lifted(5);
  flat << -0.8137, 0.4519, 0, 0, 0;
  lifted << -0.8137, 0.4519, 0.6, DegToRad(0.8), DegToRad(-0.6);
  const cv::Mat linear = renderer.RenderLinear({lifted});
  const std::vector<DotTruth> dots = renderer.Dots(lifted);
  const std::vector<DotTruth> flat_dots = renderer.Dots(flat);
  ASSERT_EQ(dots.size(), 3u);
  for (const DotTruth& dot : dots) {
    EXPECT_LT((CoverageCentroid(linear, dot.pixel) - dot.pixel).norm(), 0.01);
  }
  // 475 mm from the head tops: 0.6 mm up is 0.126 % larger in the image.
  const double ratio = (dots[1].pixel - dots[0].pixel).norm() /
                       (flat_dots[1].pixel - flat_dots[0].pixel).norm();
  EXPECT_NEAR(ratio, 475.0 / 474.4, 2e-4);
  EXPECT_GT(ratio, 1.0008);
}

// A camera that moved (a knock with a roll) sees the dots where the truth
// says, and the tag's corners too: the frame is resampled along the moved
// camera's rays in full precision.
TEST(SceneRenderer, AMovedCameraSeesTheDotsAndTheTagWhereTheTruthSays) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  RenderOptions options = Clean(0.0);
  options.intrinsics.distortion = {-0.05, 0.0, 0.0, 0.0, 0.0};
  const SceneRenderer renderer(plan, options);
  const Eigen::Vector2d x(-0.8137, 0.4519);
  FrameConditions conditions;
  conditions.motion = CameraMotion::FromImageShift(
      options.intrinsics, {2.37, -1.61}, DegToRad(0.08));
  const cv::Mat moved = renderer.Render({x}, 0, conditions);
  const std::vector<DotTruth> still = renderer.Dots(x);
  const std::vector<DotTruth> dots = renderer.Dots(x, conditions.motion);
  for (size_t i = 0; i < dots.size(); ++i) {
    EXPECT_GT((dots[i].pixel - still[i].pixel).norm(), 1.5);
    EXPECT_LT((CoverageCentroid(moved, dots[i].pixel) - dots[i].pixel).norm(),
              0.01);
  }
  cv::Mat gray;
  cv::cvtColor(moved, gray, cv::COLOR_BGR2GRAY);
  const std::vector<TagDetection> tags = TagDetector().Detect(gray);
  ASSERT_EQ(tags.size(), 1u);
  const std::vector<Eigen::Vector2d> corners =
      renderer.TagCorners(conditions.motion);
  for (int c = 0; c < 4; ++c) {
    EXPECT_LT((tags[0].corners[c] - corners[c]).norm(), 0.05) << c;
  }
}

TEST(SceneRenderer, DotCentresAreExactUnderFiveDegreesOfTilt) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const SceneRenderer renderer(plan, Clean(5.0));
  const Eigen::Vector2d x(0.3311, -0.9127);
  const cv::Mat linear = renderer.RenderLinear({x});
  for (const DotTruth& dot : renderer.Dots(x)) {
    const Eigen::Vector2d ellipse = EllipseCentre(
        renderer.camera(), renderer.dot_plane_height_mm(), dot.plane_mm, 2.0);
    EXPECT_LT((CoverageCentroid(linear, dot.pixel) - ellipse).norm(), 0.01);
    // The known bias (docs/rendering.md): the ellipse's centre is not the
    // projected centre, by a few thousandths of a pixel at 5 deg.
    EXPECT_GT((ellipse - dot.pixel).norm(), 1e-4);
    EXPECT_LT((ellipse - dot.pixel).norm(), 0.01);
  }
}

TEST(SceneRenderer, DistortedDotsLandWhereOpenCvProjectsThem) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  RenderOptions options = Clean(0.0);
  options.intrinsics =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1280, 720);
  options.intrinsics.distortion = {-0.1, 0, 0, 0, 0};
  const SceneRenderer renderer(plan, options);
  const Eigen::Vector2d x(0.5, 0.25);
  const cv::Mat linear = renderer.RenderLinear({x});
  for (const DotTruth& dot : renderer.Dots(x)) {
    // Near the centre the distortion is nearly affine over a dot.
    EXPECT_LT((CoverageCentroid(linear, dot.pixel) - dot.pixel).norm(), 0.01);
  }
}

TEST(SceneRenderer, AprilTagIsDetectedWithItsIdAndCorners) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  for (double tilt : {0.0, 5.0}) {
    RenderOptions options;  // default noise and lighting
    options.tilt_x_deg = tilt;
    options.tilt_y_deg = -0.6 * tilt;
    const SceneRenderer renderer(plan, options);
    cv::Mat gray;
    cv::cvtColor(renderer.Render({Eigen::Vector2d::Zero()}, 0), gray,
                 cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = TagDetector().Detect(gray);
    ASSERT_EQ(tags.size(), 1u);
    EXPECT_EQ(tags[0].id, 7);
    EXPECT_EQ(tags[0].hamming, 0);
    const std::vector<Eigen::Vector2d> truth = renderer.TagCorners();
    for (int i = 0; i < 4; ++i) {
      EXPECT_LT((tags[0].corners[i] - truth[i]).norm(), 0.1)
          << "corner " << i << " detected " << tags[0].corners[i].transpose()
          << " truth " << truth[i].transpose();
      // libapriltag alone gets the corner to within a pixel.
      EXPECT_LT((tags[0].coarse_corners[i] - truth[i]).norm(), 1.0);
    }
    EXPECT_TRUE(tags[0].refined);
  }
}

TEST(HeadTimeline, SettlesOnTheModelsEquilibriumAndComesBack) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const HeadTimeline timeline(plan);
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  ASSERT_TRUE(
      solver.Solve(Eigen::Vector3d(6, 6, 0) * kMpaPerPsi, &x).converged());
  EXPECT_LT((timeline.DisplacementAt(2.49) - x).norm(), 1e-6);
  // Released at 2.5 s: first-order return with tau = 0.1 s.
  EXPECT_NEAR(timeline.DisplacementAt(2.99).norm(), x.norm() * std::exp(-4.9),
              1e-9);
  EXPECT_LT(timeline.DisplacementAt(0.49).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(timeline.duration_s(), 6.0);
}

// A plan without times lasts the times AssignTimes gives it. render's
// length check read the unset times of such a plan (the delta sample's) and
// refused it as lasting 7e218 s in some runs (found under clang's ASan).
TEST(RenderedDuration, GivesAPlanWithoutTimesTheTimesItWillBeRenderedWith) {
  EXPECT_DOUBLE_EQ(RenderedDurationS(ParseTestPlan(kPlan, "plan.yaml")), 6.0);
  const TestPlan timeless = ParseTestPlan(
      "mechanism: delta\npressure_unit: psi\ntests:\n"
      "  - {id: a, pressures: [6, 6, 0]}\n"
      "  - {id: b, pressures: [4, 6, 1]}\n"
      "scene: {lead_in_s: 1.5, hold_s: 2.0, rest_s: 3.0}\n",
      "timeless.yaml");
  ASSERT_FALSE(timeless.HasTimes());
  EXPECT_DOUBLE_EQ(RenderedDurationS(timeless), 1.5 + 2 * (2.0 + 3.0));
  TestPlan timed = timeless;
  AssignTimes(&timed);
  EXPECT_DOUBLE_EQ(HeadTimeline(timed).duration_s(), 11.5);
}

// Lifted and tilted heads (issue 27): within the scene's bounds while
// actuated, the same for every timeline of the plan, flat again at rest.
TEST(HeadTimeline, LiftsAndTiltsWithinTheScenesBoundsAndSettlesFlat) {
  std::string yaml = kPlan;
  yaml.replace(yaml.find("rest_s: 1.0}"), 12,
               "rest_s: 1.0, head_lift_mm: 0.6, head_tilt_deg: 1}");
  const TestPlan plan = ParseTestPlan(yaml, "plan.yaml");
  const HeadTimeline timeline(plan), again(plan);
  ASSERT_EQ(timeline.out_of_plane().size(), 2u);
  for (double t : {2.49, 4.99}) {
    const Eigen::VectorXd state = timeline.StateAt(t);
    ASSERT_EQ(state.size(), 5);
    EXPECT_GE(state[2], 0.0);
    EXPECT_LE(state[2], 0.6);
    EXPECT_LE(state.tail<2>().norm(), DegToRad(1.0));
    EXPECT_EQ(state, again.StateAt(t));
  }
  // The two tests lift differently, and each head settles on its target.
  EXPECT_NE(timeline.out_of_plane()[0], timeline.out_of_plane()[1]);
  EXPECT_LT(
      (timeline.StateAt(2.49).tail<3>() - timeline.out_of_plane()[0]).norm(),
      1e-6);
  EXPECT_LT(timeline.StateAt(5.99).tail<3>().norm(), 1e-3);
  EXPECT_EQ(timeline.DisplacementAt(2.49), timeline.StateAt(2.49).head<2>());
}

TEST(RenderCommand, TruthEqualsTheEquilibriumOnceSettled) {
  const fs::path dir = TestScratch().dir() / "softbench_render_cmd";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "plan.yaml") << kPlan;
  RenderCommandOptions options;
  options.plan_path = (dir / "plan.yaml").string();
  options.output_path = (dir / "v.mp4").string();
  options.truth_path = (dir / "t.csv").string();
  options.resolution = "640x360";
  options.quiet = true;
  std::ostringstream out;
  ASSERT_EQ(RunRender(options, out), 0);

  const TestPlan plan = LoadTestPlan(options.plan_path);
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  std::vector<Eigen::VectorXd> equilibria;
  for (const TestPoint& test : plan.tests) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
    ASSERT_TRUE(solver.Solve(test.pressures * kMpaPerPsi, &x).converged());
    equilibria.push_back(x);
  }
  const RenderedTruth truth = ReadRenderedTruth(options.truth_path);
  int settled = 0;
  const int rows = static_cast<int>(truth.time_s.size());
  for (int k = 0; k < rows; ++k) {
    const double t = truth.time_s[k];
    const Eigen::Vector2d y = truth.displacement_mm[k][0];
    for (size_t i = 0; i < plan.tests.size(); ++i) {
      // Settled: 15 time constants after actuation, until release.
      if (t > *plan.tests[i].actuate_s + 1.5 && t < *plan.tests[i].release_s) {
        EXPECT_LT((y - equilibria[i]).norm(), 2e-6) << "t = " << t;
        ++settled;
      }
    }
  }
  EXPECT_EQ(rows, 180);
  EXPECT_GT(settled, 20);
  VideoReader video(options.output_path);
  EXPECT_EQ(video.info().frame_count, 180);
  EXPECT_TRUE(fs::exists(dir / "v.plan.yaml"));
  EXPECT_FALSE(fs::exists(dir / ".v.mp4.partial.mp4"));
}

TEST(RenderCommand, RendersAreReproducibleFromTheSeed) {
  const fs::path dir = TestScratch().dir() / "softbench_render_seed";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "plan.yaml") << kPlan;
  std::string bytes[2];
  for (int run = 0; run < 2; ++run) {
    RenderCommandOptions options;
    options.plan_path = (dir / "plan.yaml").string();
    options.output_path = (dir / ("v" + std::to_string(run) + ".mp4")).string();
    options.truth_path = (dir / "t.csv").string();
    options.resolution = "320x180";
    options.quiet = true;
    options.render.seed = 42;
    std::ostringstream out;
    ASSERT_EQ(RunRender(options, out), 0);
    std::ifstream stream(options.output_path, std::ios::binary);
    bytes[run].assign(std::istreambuf_iterator<char>(stream), {});
  }
  EXPECT_GT(bytes[0].size(), 1000u);
  EXPECT_EQ(bytes[0], bytes[1]);
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

// Mean distance of the corners from their centroid: the tag's size.
double TagSize(const std::vector<Eigen::Vector2d>& corners) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& c : corners) centre += c / corners.size();
  double size = 0.0;
  for (const Eigen::Vector2d& c : corners) {
    size += (c - centre).norm() / corners.size();
  }
  return size;
}

// Luma of a grey-on-grey frame (any channel: the tag is grey) in `encoding`,
// as a 16-bit video of that encoding decodes it (CV_16UC1 filling 16 bits,
// LumaEncoding's default deep_bits).
cv::Mat LumaIn(const cv::Mat& bgr_sdr, const LumaEncoding& encoding) {
  const cv::Mat coded = ConvertFromSdr(
      bgr_sdr, ColorEncoding{encoding.transfer, Primaries::kBt709});
  cv::Mat luma;
  cv::extractChannel(coded, luma, 1);
  if (!encoding.full_range) {
    luma.convertTo(luma, CV_16U, 219.0 / 255.0, 16.0 * 256.0);
  }
  return luma;
}

TEST(SceneRenderer, TagIsMeasuredInLightWhateverTheTransferCurve) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  // Square to the camera the tag's edges run along the pixels, where 16
  // subsamples a side leave each edge off by up to 1/32 px; 64 make the
  // rendered truth good to 0.008 px.
  RenderOptions options = Clean(0.0);
  options.supersampling = 64;
  const SceneRenderer renderer(plan, options);
  const cv::Mat bgr = renderer.Render({Eigen::Vector2d::Zero()}, 0);
  const double truth = TagSize(renderer.TagCorners());
  for (Transfer transfer : {Transfer::kSdr, Transfer::kHlg, Transfer::kPq}) {
    for (bool full_range : {true, false}) {
      const LumaEncoding encoding{transfer, full_range};
      const cv::Mat luma = LumaIn(bgr, encoding);
      const auto size = [&](const LumaEncoding& assumed) {
        const std::vector<TagDetection> tags =
            TagDetector({.luma_encoding = assumed}).Detect(luma);
        EXPECT_EQ(tags.size(), 1u);
        return tags.empty()
                   ? 0.0
                   : TagSize({tags[0].corners.begin(), tags[0].corners.end()});
      };
      // Exact to 1e-4 (0.007 px on this 140 px tag).
      EXPECT_NEAR(size(encoding) / truth, 1.0, 1e-4)
          << encoding.full_range << static_cast<int>(transfer);
      // Linearised with another curve each edge moves by a tenth of a pixel
      // or more, but the border's two edges move alike and its midline
      // stays: the size holds to 3e-4 even so.
      const LumaEncoding wrong{
          transfer == Transfer::kPq ? Transfer::kSdr : Transfer::kPq,
          full_range};
      EXPECT_NEAR(size(wrong) / truth, 1.0, 3e-4)
          << encoding.full_range << static_cast<int>(transfer);
    }
  }
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

// A phone's processing after its curve, on the 8-bit codes, which the
// stream's metadata (BT.709) does not describe.
cv::Mat InCodes(const cv::Mat& bgr8, const std::function<cv::Mat(cv::Mat)>& f) {
  cv::Mat codes;
  bgr8.convertTo(codes, CV_32F, 1.0 / 255.0);
  cv::Mat out;
  f(codes).convertTo(out, CV_8U, 255.0);
  return out;
}

TEST(SceneRenderer, TagScaleIgnoresWhatThePhoneDoesToItsCodes) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const SceneRenderer renderer(plan, Clean(2.0));
  const cv::Mat bgr = renderer.Render({Eigen::Vector2d::Zero()}, 0);
  const double truth = TagSize(renderer.TagCorners());
  const auto s_curve = [](double amount) {
    return [amount](cv::Mat x) {
      // (1 - k) x + k smoothstep(x): darker shadows, brighter highlights.
      cv::Mat x2 = x.mul(x);
      cv::Mat smooth = 3 * x2 - 2 * x2.mul(x);
      return cv::Mat((1 - amount) * x + amount * smooth);
    };
  };
  const auto blur = [](double sigma) {
    return [sigma](cv::Mat x) {
      cv::GaussianBlur(x, x, cv::Size(), sigma);
      return x;
    };
  };
  const auto sharpen = [](double radius, double amount) {
    return [radius, amount](cv::Mat x) {
      cv::Mat soft;
      cv::GaussianBlur(x, soft, cv::Size(), radius);
      return cv::Mat(x + amount * (x - soft));
    };
  };
  struct Case {
    std::string name;
    std::function<cv::Mat(cv::Mat)> apply;
    double bound;  // on |size / truth - 1|
  };
  // 0.05 % (issue 28; 0.05 px at this 140 px tag's corners) for each alone.
  // The strongest sharpening measured 0.057 % and, after the S-curve,
  // 0.071 %: the border's two edges are not mirror images there (a white
  // data cell has black cells beside it, the quiet zone does not), and
  // issue 28 stays open on it.
  const std::vector<Case> cases = {
      {"none", [](cv::Mat x) { return x; }, 5e-4},
      {"s-curve 0.5", s_curve(0.5), 5e-4},
      {"s-curve 1.0", s_curve(1.0), 5e-4},
      {"gamma 1.3",
       [](cv::Mat x) {
         cv::pow(x, 1.3, x);
         return x;
       },
       5e-4},
      {"blur in codes 1.2 px", blur(1.2), 5e-4},
      {"sharpen 1 px x1.0", sharpen(1.0, 1.0), 5e-4},
      {"sharpen 2 px x0.5", sharpen(2.0, 0.5), 5e-4},
      {"sharpen 1.5 px x1.0", sharpen(1.5, 1.0), 8e-4},
      {"s 0.6 then sharpen 1.5 px x1.0",
       [&](cv::Mat x) { return sharpen(1.5, 1.0)(s_curve(0.6)(x)); }, 8e-4}};
  for (const Case& c : cases) {
    cv::Mat luma;
    cv::cvtColor(InCodes(bgr, c.apply), luma, cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = TagDetector().Detect(luma);
    ASSERT_EQ(tags.size(), 1u) << c.name;
    const double size =
        TagSize({tags[0].corners.begin(), tags[0].corners.end()});
    EXPECT_NEAR(size / truth, 1.0, c.bound) << c.name;
  }
}

// The lens's blur (render --lens-blur) spreads light symmetrically, before
// the curve: the dots' centres and the tag's size stay where the truth says,
// while the image is visibly softer.
TEST(SceneRenderer, LensBlurSoftensTheImageButMovesNothing) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  RenderOptions options = Clean(2.0);
  const SceneRenderer sharp_renderer(plan, options);
  options.lens_blur_px = 1.0;
  const SceneRenderer renderer(plan, options);
  EXPECT_FALSE(options.Problem().has_value());
  const Eigen::Vector2d x(0.3719, -0.6024);
  const cv::Mat blurred = renderer.Render({x}, 0);
  const cv::Mat sharp = sharp_renderer.Render({x}, 0);
  // The steepest step between neighbours drops by more than a third.
  const auto steepest = [](const cv::Mat& bgr) {
    cv::Mat gray, dx;
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    cv::Sobel(gray, dx, CV_32F, 1, 0);
    double top = 0.0;
    cv::minMaxLoc(cv::abs(dx), nullptr, &top);
    return top;
  };
  EXPECT_LT(steepest(blurred), 0.67 * steepest(sharp));
  for (const DotTruth& dot : renderer.Dots(x)) {
    EXPECT_LT((CoverageCentroid(blurred, dot.pixel) - dot.pixel).norm(), 0.01);
  }
  cv::Mat luma;
  cv::cvtColor(blurred, luma, cv::COLOR_BGR2GRAY);
  const std::vector<TagDetection> tags = TagDetector().Detect(luma);
  ASSERT_EQ(tags.size(), 1u);
  EXPECT_NEAR(TagSize({tags[0].corners.begin(), tags[0].corners.end()}) /
                  TagSize(renderer.TagCorners()),
              1.0, 5e-4);
  options.lens_blur_px = -1.0;
  EXPECT_EQ(options.Problem(), "lens blur must be 0..5 px");
}

// Local tone mapping (render --local-tone) lifts the dark table and dims
// the white tag by a gain that varies smoothly, by under 0.5 % between
// neighbouring pixels. (What it does to the measurement is measured end to
// end by scripts/phone_pipeline_footage.sh: docs/measurement.md.)
TEST(SceneRenderer, LocalToneLiftsShadowsWithASmoothGain) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  RenderOptions options = Clean(2.0);
  options.sixteen_bit = true;  // the gain, not the codes' rounding
  const SceneRenderer plain_renderer(plan, options);
  options.local_tone = 0.5;
  ASSERT_FALSE(options.Problem().has_value());
  const SceneRenderer renderer(plan, options);
  const Eigen::Vector2d x(0.3719, -0.6024);
  // Each frame's light, 8-bit levels.
  const auto light = [&](const SceneRenderer& r) {
    const cv::Mat codes = r.Render({x}, 0);
    cv::Mat out(codes.size(), CV_32FC3);
    out.forEach<cv::Vec3f>([&](cv::Vec3f& l, const int* at) {
      const cv::Vec3w& c = codes.at<cv::Vec3w>(at[0], at[1]);
      for (int i = 0; i < 3; ++i) l[i] = Light(c[i] / 257.0);
    });
    return out;
  };
  const cv::Mat toned = light(renderer), plain = light(plain_renderer);
  // The gain, green channel, where the light is neither black nor clipped.
  cv::Mat gain(toned.size(), CV_64F, cv::Scalar(0.0));
  for (int v = 0; v < toned.rows; ++v) {
    for (int u = 0; u < toned.cols; ++u) {
      const double before = plain.at<cv::Vec3f>(v, u)[1];
      if (before > 5.0 && before < 250.0) {
        gain.at<double>(v, u) = toned.at<cv::Vec3f>(v, u)[1] / before;
      }
    }
  }
  double lowest = 1e9, highest = 0.0, steepest = 0.0;
  for (int v = 0; v < gain.rows; ++v) {
    for (int u = 0; u + 1 < gain.cols; ++u) {
      const double g = gain.at<double>(v, u), next = gain.at<double>(v, u + 1);
      if (g == 0.0) continue;
      lowest = std::min(lowest, g);
      highest = std::max(highest, g);
      if (next != 0.0) steepest = std::max(steepest, std::abs(next / g - 1));
    }
  }
  EXPECT_GT(highest / lowest, 1.3);  // it does lift and dim
  EXPECT_LT(steepest, 0.005);        // smoothly, under 0.5 % per pixel
  options.local_tone = 1.5;
  EXPECT_EQ(options.Problem(), "local tone mapping strength must be 0..1");
}

// Local tone mapping's gain is lower on the white tag than on the dark table
// around it, so it rises outward across the tag's border and moved every
// edge of it outward: the tag read 0.03-0.11 % large at strengths 0.3-1.0,
// the dots' spacing through it as much short. The border's fit measures
// the gain from the paper's white on either side of the border and takes
// out what it does to the edges; the dots' centres, whose background is a
// plane fitted around each dot, were never moved by more than 0.02 px.
TEST(SceneRenderer, TagScaleIgnoresLocalToneMapping) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const Eigen::Vector2d x(0.3719, -0.6024);
  for (double strength : {0.3, 0.6, 1.0}) {
    RenderOptions options = Clean(2.0);
    options.lighting_gradient = 0.12;  // the defaults', falling off as well
    options.vignetting = 0.2;
    options.local_tone = strength;
    const SceneRenderer renderer(plan, options);
    cv::Mat luma;
    cv::cvtColor(renderer.Render({x}, 0), luma, cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = TagDetector().Detect(luma);
    ASSERT_EQ(tags.size(), 1u) << strength;
    // 0.025 % (measured within 0.018 %; before, +0.034 %, +0.074 % and
    // +0.106 %).
    EXPECT_NEAR(TagSize({tags[0].corners.begin(), tags[0].corners.end()}) /
                    TagSize(renderer.TagCorners()),
                1.0, 2.5e-4)
        << strength;
    constexpr double kDotRadiusMm = 2.0;  // the plan's 4 mm dots
    const double radius_px = renderer.camera().intrinsics().fx_px *
                             kDotRadiusMm / options.distance_mm;
    for (const DotTruth& dot : renderer.Dots(x)) {
      const DotCentre centre = LocateDotCentre(
          luma, dot.pixel + Eigen::Vector2d(0.3, -0.2), radius_px);
      ASSERT_TRUE(centre.found) << centre.why_not;
      EXPECT_LT((centre.centre - dot.pixel).norm(), 0.025) << strength;
    }
  }
}

// The tag's border shows what the camera did to its image (TagEdgeSigns),
// each sign on its own: on plain footage (the default lighting and noise,
// with the lens's blur, or through a Bayer sensor) none is named (halos
// 0.2-0.3 % of the step, edges within 0.01 px); sharpening leaves halos
// (15 % at 1 px x 0.8, 2.1 % at 0.5 px x 0.3, 2.6 % after 1 px of lens blur
// and under a strong S-curve) and moves every edge toward its dark side
// (0.04-0.4 px), a strong tone curve the metadata does not name moves them
// too (0.033 px at 1.0), and local tone mapping lifts the white beyond the
// border over the white inside it (4.6 % at 0.6). One frame each,
// unencoded.
TEST(SceneRenderer, TagBorderShowsTheCamerasProcessing) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const Eigen::Vector2d x(0.3719, -0.6024);
  const auto named = [&](const std::function<void(RenderOptions*)>& change) {
    RenderOptions options;
    options.tilt_x_deg = 2.0, options.tilt_y_deg = -1.2;
    change(&options);
    const SceneRenderer renderer(plan, options);
    cv::Mat luma;
    cv::cvtColor(renderer.Render({x}, 0), luma, cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = TagDetector().Detect(luma);
    std::vector<std::string> names;
    EXPECT_EQ(tags.size(), 1u);
    if (tags.empty() || !tags[0].signs) {
      ADD_FAILURE() << "no signs";
      return names;
    }
    const CameraProcessing p = DescribeCameraProcessing({*tags[0].signs}, {});
    for (const ProcessingEffect& e : p.effects) names.push_back(e.name);
    return names;
  };
  using Names = std::vector<std::string>;
  const std::string halos = "sharpening halos";
  const std::string curve =
      "a tone curve or filtering the video's transfer does not describe";
  const std::string gain =
      "local tone mapping or light falling off across the tag";
  EXPECT_EQ(named([](RenderOptions*) {}), Names{});
  EXPECT_EQ(named([](RenderOptions* o) { o->lens_blur_px = 0.6; }), Names{});
  EXPECT_EQ(named([](RenderOptions* o) {
              o->sensor.demosaic = Demosaic::kBilinear;
              o->lens_blur_px = 0.6;
            }),
            Names{});
  EXPECT_EQ(named([](RenderOptions* o) { o->sharpen_amount = 0.8; }),
            (Names{halos, curve}));
  EXPECT_EQ(named([](RenderOptions* o) {
              o->sharpen_radius_px = 0.5, o->sharpen_amount = 0.3;
            }),
            (Names{halos, curve}));
  // A phone's strongest: its halos are cut by the curve's shoulder at
  // white, and still named.
  EXPECT_EQ(named([](RenderOptions* o) {
              o->lens_blur_px = 1.0;
              o->sensor.demosaic = Demosaic::kBilinear;
              o->sensor.full_well_e = 6000;
              o->tone_curve = 1.0;
              o->sharpen_amount = 1.5;
            }),
            (Names{halos, curve}));
  EXPECT_EQ(named([](RenderOptions* o) { o->tone_curve = 1.0; }), Names{curve});
  EXPECT_EQ(named([](RenderOptions* o) { o->local_tone = 0.6; }), Names{gain});
}

// A rolling shutter's frame: each row seen after its own camera motion, so
// a shift growing down the frame (-8.5 px at the top, +11.5 px at the
// bottom; the dots' rows differ by about 1 px of it) moves each dot by the
// shift at its own row.
TEST(SceneRenderer, RollingShutterMovesEachRowByItsOwnMotion) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  const RenderOptions options = Clean(0.0);
  const SceneRenderer renderer(plan, options);
  const Eigen::Vector2d x(-0.8137, 0.4519);
  const int rows = options.intrinsics.height_px;
  const auto shift_at = [&](double row) {
    return Eigen::Vector2d(1.5 + 10.0 * (2.0 * row / (rows - 1) - 1.0), 0.0);
  };
  FrameConditions conditions;
  for (int v = 0; v < rows; ++v) {
    conditions.row_motion.push_back(
        CameraMotion::FromImageShift(options.intrinsics, shift_at(v), 0.0));
  }
  const cv::Mat sheared = renderer.Render({x}, 0, conditions);
  const std::vector<DotTruth> still = renderer.Dots(x);
  for (size_t i = 0; i < still.size(); ++i) {
    // Where the camera of the dot's own row sees it.
    const CameraMotion row_motion = CameraMotion::FromImageShift(
        options.intrinsics, shift_at(still[i].pixel.y()), 0.0);
    const Eigen::Vector2d expected = renderer.Dots(x, row_motion)[i].pixel;
    EXPECT_GT((expected - still[i].pixel).norm(), 0.5);
    EXPECT_LT((CoverageCentroid(sheared, still[i].pixel) - expected).norm(),
              0.01);
  }
}

// A sensor with twice the video's pixels per side, drawn there and scaled
// down by area (with and without its Bayer filter): the video's frame
// still has the dots and the tag where the video camera's truth says. (With
// the Bayer filter at the video's own size, the harder case, the end-to-end
// tests measure it:
// ValidateCommandTest.PhoneBayerBlurCurveAndSharpeningMeetTheBar.)
TEST(SceneRenderer, ASensorFinerThanTheVideoSeesTheSameGeometry) {
  const TestPlan plan = ParseTestPlan(kPlan, "plan.yaml");
  for (const Demosaic demosaic : {Demosaic::kNone, Demosaic::kBilinear}) {
    SCOPED_TRACE(static_cast<int>(demosaic));
    RenderOptions options = Clean(2.0);
    options.sensor_scale = 2;
    options.sensor.demosaic = demosaic;
    ASSERT_FALSE(options.Problem().has_value());
    const SceneRenderer renderer(plan, options);
    const Eigen::Vector2d x(0.3719, -0.6024);
    EXPECT_EQ(renderer.RenderLinear({x}).cols, 2 * options.intrinsics.width_px);
    const cv::Mat frame = renderer.Render({x}, 0);
    ASSERT_EQ(frame.cols, options.intrinsics.width_px);
    ASSERT_EQ(frame.rows, options.intrinsics.height_px);
    // Bilinear demosaicing keeps the green of half the sites and averages
    // it at the others: a filter that differs between the colour filter's
    // phases, which moves a centroid by about 0.01 px.
    const double tolerance_px = demosaic == Demosaic::kNone ? 0.01 : 0.02;
    for (const DotTruth& dot : renderer.Dots(x)) {
      EXPECT_LT((CoverageCentroid(frame, dot.pixel) - dot.pixel).norm(),
                tolerance_px);
    }
    cv::Mat luma;
    cv::cvtColor(frame, luma, cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = TagDetector().Detect(luma);
    ASSERT_EQ(tags.size(), 1u);
    EXPECT_NEAR(TagSize({tags[0].corners.begin(), tags[0].corners.end()}) /
                    TagSize(renderer.TagCorners()),
                1.0, 5e-4);
  }
  RenderOptions options;
  options.sensor_scale = 5;
  EXPECT_EQ(options.Problem(),
            "the sensor's scale must be 1..4 sensor pixels per video pixel");
}

}  // namespace
}  // namespace softbench
