#include "vision/tag_finder.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <vector>

#include "vision/color_transfer.h"
#include "vision/tag_bitmap.h"

namespace softbench {
namespace {

const cv::Size k4K(3840, 2160);

// Paints tag36h11 `id` upright onto `image` (8-bit SDR luma, a dark table),
// its black border's outer corners `side_px` apart from `top_left`, each
// pixel the light of 4x4 samples averaged (a camera's area sampling), then
// encoded. Edges on multiples of 1/4 px fall midway between samples, so the
// painted edge is exactly there. Returns the border's
// outer corners (OpenCV's convention: pixel centres at integers).
std::array<Eigen::Vector2d, 4> PaintTag(int id, const Eigen::Vector2d& top_left,
                                        double side_px, cv::Mat* image) {
  const TagBitmap tag = Tag36h11Bitmap(id);
  const double cell = side_px / tag.width_at_border;
  const double quiet = 0.5 * (tag.total_width - tag.width_at_border);
  const Eigen::Vector2d grid =
      top_left - Eigen::Vector2d::Constant(quiet * cell);
  const double extent = tag.total_width * cell;
  for (int v = static_cast<int>(grid.y()) - 1; v <= grid.y() + extent + 1;
       ++v) {
    for (int u = static_cast<int>(grid.x()) - 1; u <= grid.x() + extent + 1;
         ++u) {
      double sum = 0.0;
      for (int i = 0; i < 16; ++i) {
        const int sample_u = i % 4, sample_v = i / 4;
        const double x = u - 0.5 + (sample_u + 0.5) / 4.0 - grid.x();
        const double y = v - 0.5 + (sample_v + 0.5) / 4.0 - grid.y();
        const int col = static_cast<int>(std::floor(x / cell));
        const int row = static_cast<int>(std::floor(y / cell));
        const bool inside = col >= 0 && row >= 0 && col < tag.total_width &&
                            row < tag.total_width;
        sum += !inside ? 0.05 : tag.IsWhite(row, col) ? 0.8 : 0.02;
      }
      image->at<uint8_t>(v, u) = static_cast<uint8_t>(
          std::lround(255.0 * FromLinear(Transfer::kSdr, sum / 16.0)));
    }
  }
  const Eigen::Vector2d& a = top_left;
  return {a, a + Eigen::Vector2d(side_px, 0),
          a + Eigen::Vector2d::Constant(side_px),
          a + Eigen::Vector2d(0, side_px)};
}

// The largest distance from a corner in `truth` to the nearest in `found`.
double WorstCornerError(const std::array<Eigen::Vector2d, 4>& truth,
                        const std::array<Eigen::Vector2d, 4>& found) {
  double worst = 0.0;
  for (const Eigen::Vector2d& t : truth) {
    double nearest = 1e9;
    for (const Eigen::Vector2d& f : found)
      nearest = std::min(nearest, (t - f).norm());
    worst = std::max(worst, nearest);
  }
  return worst;
}

TEST(TagFinder, FindsABigTagCoarselyAndReadsItAsTheDetectorDoes) {
  cv::Mat frame(k4K, CV_8UC1, cv::Scalar(40));
  const auto truth = PaintTag(0, {2100.25, 900.75}, 270.0, &frame);
  TagFinder finder(0, {});
  const std::optional<TagDetection> tag = finder.Find(frame);
  ASSERT_TRUE(tag.has_value());
  EXPECT_TRUE(tag->refined);
  EXPECT_LT(WorstCornerError(truth, tag->corners), 0.05);
  // The same fit as a whole-frame detection at the detector's decimation.
  const std::vector<TagDetection> whole = TagDetector().Detect(frame);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_LT(WorstCornerError(whole[0].corners, tag->corners), 0.01);
}

TEST(TagFinder, FindsATagTooSmallForTheCoarseSearch) {
  cv::Mat frame(k4K, CV_8UC1, cv::Scalar(40));
  const auto truth = PaintTag(3, {600.5, 1500.25}, 40.0, &frame);
  // The coarse search alone (a 4K frame decimated to 640 px) misses it...
  EXPECT_TRUE(TagDetector({.quad_decimate = 6.0f}).Detect(frame).empty());
  // ...and the finder looks again at the detector's own decimation.
  TagFinder finder(3, {});
  const std::optional<TagDetection> tag = finder.Find(frame);
  ASSERT_TRUE(tag.has_value());
  EXPECT_LT(WorstCornerError(truth, tag->corners), 0.05);
}

TEST(TagFinder, ReadsLaterFramesAroundTheTagAndNamesOtherTags) {
  cv::Mat first(k4K, CV_8UC1, cv::Scalar(40));
  PaintTag(5, {1000.0, 1000.0}, 200.0, &first);
  TagFinder finder(5, {});
  ASSERT_TRUE(finder.Find(first).has_value());

  // A knock of 30 px stays in the region (half the tag's side around it).
  cv::Mat knocked(k4K, CV_8UC1, cv::Scalar(40));
  const auto truth = PaintTag(5, {1030.25, 985.75}, 200.0, &knocked);
  const std::optional<TagDetection> tag = finder.Find(knocked);
  ASSERT_TRUE(tag.has_value());
  EXPECT_LT(WorstCornerError(truth, tag->corners), 0.05);

  // Only the region is read once the tag has been: a tag elsewhere is not.
  cv::Mat moved(k4K, CV_8UC1, cv::Scalar(40));
  PaintTag(5, {2500.0, 1500.0}, 200.0, &moved);
  EXPECT_FALSE(finder.Find(moved).has_value());
}

TEST(TagFinder, NamesTheOtherTagsItReadsWhenItsOwnIsAbsent) {
  cv::Mat frame(k4K, CV_8UC1, cv::Scalar(40));
  PaintTag(7, {3000.0, 300.0}, 200.0, &frame);
  PaintTag(9, {200.0, 1700.0}, 200.0, &frame);
  TagFinder finder(5, {});
  EXPECT_FALSE(finder.Find(frame).has_value());
  EXPECT_EQ(finder.other_ids(), (std::set<int>{7, 9}));
}

TEST(TagFinderOptions, ProblemNamesTheBadField) {
  EXPECT_FALSE(TagFinderOptions{}.Problem().has_value());
  EXPECT_NE(
      TagFinderOptions{.search_side_px = 10}.Problem()->find("search_side_px"),
      std::string::npos);
  EXPECT_NE(
      TagFinderOptions{.region_margin = 0.0}.Problem()->find("region_margin"),
      std::string::npos);
}

}  // namespace
}  // namespace softbench
