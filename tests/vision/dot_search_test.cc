#include "vision/dot_search.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace softbench {
namespace {

// The built-in red (formats/dot_colors.cc), which wraps through hue 0.
const HsvRange kRedRange{170, 10, 100, 255, 50, 255};

const cv::Scalar kHead(214, 217, 220);
const cv::Scalar kRed(40, 40, 200);

SegmentationOptions Options(double radius_px) {
  SegmentationOptions options;
  options.dot_radius_px = radius_px;
  return options;
}

// Both searches find the same blobs, to the last bit (same order is not
// promised: sorted by position).
void ExpectSameBlobs(std::vector<Blob> a, std::vector<Blob> b) {
  const auto by_position = [](const Blob& p, const Blob& q) {
    return p.centroid.y() < q.centroid.y() ||
           (p.centroid.y() == q.centroid.y() &&
            p.centroid.x() < q.centroid.x());
  };
  std::sort(a.begin(), a.end(), by_position);
  std::sort(b.begin(), b.end(), by_position);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].centroid, b[i].centroid) << i;
    EXPECT_EQ(a[i].area_px, b[i].area_px) << i;
    EXPECT_EQ(a[i].box, b[i].box) << i;
  }
}

TEST(DotSearch, ReductionKeepsDotsAFewPixelsWide) {
  const DotSearchOptions options;
  EXPECT_EQ(DotSearchReduction(5.0, options), 1);   // full resolution
  EXPECT_EQ(DotSearchReduction(11.1, options), 3);  // thesis dots at 1080p
  EXPECT_EQ(DotSearchReduction(22.3, options), 4);  // at 4K: the cap
  EXPECT_FALSE(options.Problem());
  DotSearchOptions bad;
  bad.min_coarse_radius_px = 1.0;
  EXPECT_TRUE(bad.Problem());
}

TEST(DotSearch, FindsWhatTheFullResolutionPassFinds) {
  // Dots of several sizes (some next to each other and on the image's
  // edge), a tube, a bar and specks, at a fixed seed.
  cv::Mat image(480, 640, CV_8UC3, kHead);
  cv::RNG rng(11);
  for (int i = 0; i < 24; ++i) {
    const cv::Point2f centre(rng.uniform(0.0f, 640.0f),
                             rng.uniform(0.0f, 480.0f));
    const int radius = rng.uniform(9, 15);
    cv::circle(image, centre, radius, kRed, cv::FILLED, cv::LINE_AA);
  }
  cv::circle(image, {300, 200}, 12, kRed, cv::FILLED, cv::LINE_AA);
  cv::circle(image, {326, 200}, 12, kRed, cv::FILLED, cv::LINE_AA);
  cv::line(image, {20, 430}, {600, 460}, kRed, 9);               // a tube
  cv::rectangle(image, {400, 80}, {470, 89}, kRed, cv::FILLED);  // a bar
  for (int i = 0; i < 30; ++i) {
    cv::circle(image, {rng.uniform(0, 640), rng.uniform(0, 480)}, 1, kRed,
               cv::FILLED);
  }
  const ImageFrameSource frame(image);
  const HsvRange red = kRedRange;
  const SegmentationOptions options = Options(12.0);
  ASSERT_EQ(DotSearchReduction(12.0, {}), 3);
  const BlobSummary full = SegmentDots(image, red, options, {0, 0});
  const BlobSummary coarse =
      SearchDots(frame, cv::Rect(0, 0, 640, 480), red, options);
  ASSERT_GE(full.accepted.size(), 10u);
  ExpectSameBlobs(full.accepted, coarse.accepted);
  EXPECT_GE(coarse.TotalRejected(), 2);  // at least the tube and the bar
}

TEST(DotSearch, SearchesOnlyItsRegion) {
  cv::Mat image(300, 400, CV_8UC3, kHead);
  for (int x = 40; x < 400; x += 60) {
    cv::circle(image, {x, 150}, 12, kRed, cv::FILLED, cv::LINE_AA);
  }
  const ImageFrameSource frame(image);
  const HsvRange red = kRedRange;
  // An odd corner and size; dots cut by the region's edges at x = 101 and
  // x = 280.
  const cv::Rect region(101, 97, 179, 121);
  const BlobSummary coarse = SearchDots(frame, region, red, Options(12.0));
  const BlobSummary full =
      SegmentDots(image(region), red, Options(12.0), region.tl());
  ExpectSameBlobs(full.accepted, coarse.accepted);
  EXPECT_GE(coarse.accepted.size(), 3u);  // whole at x = 160 and 220
  for (const Blob& blob : coarse.accepted) {
    EXPECT_TRUE(region.contains(blob.box.tl()) &&
                region.contains(blob.box.br() - cv::Point(1, 1)));
  }
}

TEST(DotSearch, SmallDotsAreSearchedAtFullResolution) {
  cv::Mat image(120, 160, CV_8UC3, kHead);
  cv::circle(image, {50, 60}, 5, kRed, cv::FILLED, cv::LINE_AA);
  cv::circle(image, {110, 60}, 5, kRed, cv::FILLED, cv::LINE_AA);
  const BlobSummary blobs =
      SearchDots(ImageFrameSource(image), cv::Rect(0, 0, 160, 120), kRedRange,
                 Options(5.0));
  EXPECT_EQ(blobs.accepted.size(), 2u);
}

}  // namespace
}  // namespace softbench
