// The printed sheets measured as a printer would put them on paper: each PDF
// is rasterised by poppler (as a print driver does) and the tag, squares and
// dots measured in the raster against the asked sizes.
#include "pipelines/targets/printable_targets.h"

#include <gtest/gtest.h>
#include <poppler/cpp/poppler-document.h>
#include <poppler/cpp/poppler-page-renderer.h>
#include <poppler/cpp/poppler-page.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "vision/tag_detector.h"

namespace softbench {
namespace {

constexpr double kDpi = 600.0;
constexpr double kMmPerPx = 25.4 / kDpi;

// The PDF's one page, rasterised with anti-aliasing (8-bit grey, or BGR).
cv::Mat Rasterise(const std::string& pdf, bool colour = false) {
  std::unique_ptr<poppler::document> document(
      poppler::document::load_from_raw_data(pdf.data(),
                                            static_cast<int>(pdf.size())));
  EXPECT_NE(document, nullptr);
  EXPECT_EQ(document->pages(), 1);
  std::unique_ptr<poppler::page> page(document->create_page(0));
  poppler::page_renderer renderer;
  renderer.set_render_hint(poppler::page_renderer::antialiasing, true);
  renderer.set_image_format(poppler::image::format_bgr24);
  const poppler::image image = renderer.render_page(page.get(), kDpi, kDpi);
  const cv::Mat bgr(image.height(), image.width(), CV_8UC3,
                    const_cast<char*>(image.const_data()),
                    image.bytes_per_row());
  cv::Mat out;
  if (colour) {
    out = bgr.clone();
  } else {
    cv::cvtColor(bgr, out, cv::COLOR_BGR2GRAY);
  }
  return out;
}

// Ink along a row or column segment, in pixels of full coverage: with
// anti-aliasing an edge's pixel holds its covered fraction, so the sum is
// the inked length to a small fraction of a pixel.
double InkedLength(const cv::Mat& gray, cv::Point from, cv::Point to) {
  double ink = 0.0;
  cv::LineIterator it(gray, from, to);
  for (int i = 0; i < it.count; ++i, ++it) ink += (255 - **it) / 255.0;
  return ink;
}

// The bounding box of the largest dark connected region (the tag's border).
cv::Rect LargestDarkRegion(const cv::Mat& gray) {
  cv::Mat dark = gray < 128, labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids,
                                                 8, CV_32S);
  int best = 1;
  for (int i = 1; i < n; ++i) {
    if (stats.at<int>(i, cv::CC_STAT_AREA) >
        stats.at<int>(best, cv::CC_STAT_AREA)) {
      best = i;
    }
  }
  return {stats.at<int>(best, cv::CC_STAT_LEFT),
          stats.at<int>(best, cv::CC_STAT_TOP),
          stats.at<int>(best, cv::CC_STAT_WIDTH),
          stats.at<int>(best, cv::CC_STAT_HEIGHT)};
}

TEST(PrintableTargets, TagPrintsAtItsSizeAndDecodesToItsId) {
  for (const auto& [id, size_mm] :
       {std::pair{0, 25.0}, {7, 50.0}, {586, 120.0}}) {
    TagSheetOptions options;
    options.id = id;
    options.size_mm = size_mm;
    ASSERT_FALSE(options.Problem()) << *options.Problem();
    const cv::Mat page = Rasterise(DrawTagSheet(options, SheetFormat::kPdf));
    const cv::Rect box = LargestDarkRegion(page);
    // Across the top and left border cells, half a cell in (a tag36h11
    // border cell is size / 8).
    const int half_cell = static_cast<int>(size_mm / 8.0 / 2.0 / kMmPerPx);
    const double width_mm =
        kMmPerPx * InkedLength(page, {box.x - 5, box.y + half_cell},
                               {box.x + box.width + 5, box.y + half_cell});
    const double height_mm =
        kMmPerPx * InkedLength(page, {box.x + half_cell, box.y - 5},
                               {box.x + half_cell, box.y + box.height + 5});
    EXPECT_NEAR(width_mm, size_mm, 0.1) << "id " << id;
    EXPECT_NEAR(height_mm, size_mm, 0.1) << "id " << id;
    TagDetector detector;
    const std::vector<TagDetection> tags = detector.Detect(page);
    ASSERT_EQ(tags.size(), 1u) << "id " << id;
    EXPECT_EQ(tags[0].id, id);
    EXPECT_EQ(tags[0].hamming, 0);
  }
}

TEST(PrintableTargets, CheckBarIsAsLongAsItSays) {
  TagSheetOptions options;
  options.check_bar_mm = 100.0;
  const cv::Mat page = Rasterise(DrawTagSheet(options, SheetFormat::kPdf));
  // The horizontal bar is the widest dark region that is 1.5 mm tall.
  cv::Mat dark = page < 128, labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids,
                                                 8, CV_32S);
  double bar_mm = 0.0;
  for (int i = 1; i < n; ++i) {
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH);
    const int h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    if (std::abs(h * kMmPerPx - 1.5) > 0.2 || w * kMmPerPx < 10.0) continue;
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT);
    const int mid = stats.at<int>(i, cv::CC_STAT_TOP) + h / 2;
    bar_mm = kMmPerPx * InkedLength(page, {x - 5, mid}, {x + w + 5, mid});
  }
  EXPECT_NEAR(bar_mm, 100.0, 0.1);
}

TEST(PrintableTargets, CheckerboardSquaresPrintAtTheirSize) {
  for (const double square_mm : {15.0, 22.0}) {
    CheckerboardSheetOptions options;
    options.board = {9, 6, square_mm};
    ASSERT_FALSE(options.Problem()) << *options.Problem();
    const cv::Mat page =
        Rasterise(DrawCheckerboardSheet(options, SheetFormat::kPdf));
    cv::Mat small;
    cv::resize(page, small, page.size() / 4, 0, 0, cv::INTER_AREA);
    std::vector<cv::Point2f> corners;
    ASSERT_TRUE(cv::findChessboardCorners(small, cv::Size(9, 6), corners));
    for (cv::Point2f& c : corners)
      c = (c + cv::Point2f(0.5f, 0.5f)) * 4.0f - cv::Point2f(0.5f, 0.5f);
    cv::cornerSubPix(page, corners, cv::Size(9, 9), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS, 0, 1e-3));
    // Every row's span of 8 squares, and every column's of 5.
    for (int row = 0; row < 6; ++row) {
      const double span = cv::norm(corners[row * 9 + 8] - corners[row * 9]);
      EXPECT_NEAR(span * kMmPerPx / 8.0, square_mm, 0.1 / 8.0) << row;
    }
    for (int col = 0; col < 9; ++col) {
      const double span = cv::norm(corners[5 * 9 + col] - corners[col]);
      EXPECT_NEAR(span * kMmPerPx / 5.0, square_mm, 0.1 / 5.0) << col;
    }
  }
}

TEST(PrintableTargets, DotsPrintAtTheirDiameterInTheirInk) {
  DotSheetOptions options;
  options.groups = {{"head 0 (red)", {40, 40, 200}, 4.0, 3},
                    {"head 1 (green)", {60, 170, 40}, 6.0, 5}};
  options.sets = 2;
  ASSERT_FALSE(options.Problem()) << *options.Problem();
  const cv::Mat page =
      Rasterise(DrawDotSheet(options, SheetFormat::kPdf), /*colour=*/true);
  for (const DotGroup& g : options.groups) {
    // Ink within 30 codes of the group's, channel by channel.
    cv::Mat ink;
    const cv::Scalar bgr(g.ink_bgr[0], g.ink_bgr[1], g.ink_bgr[2]);
    cv::inRange(page, bgr - cv::Scalar::all(30), bgr + cv::Scalar::all(30),
                ink);
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(ink, labels, stats,
                                                   centroids, 8, CV_32S);
    ASSERT_EQ(n - 1, g.dots_per_head * options.sets) << g.label;
    for (int i = 1; i < n; ++i) {
      const double diameter_mm =
          kMmPerPx * std::sqrt(4.0 * stats.at<int>(i, cv::CC_STAT_AREA) /
                               std::numbers::pi);
      EXPECT_NEAR(diameter_mm, g.diameter_mm, 0.1) << g.label;
    }
  }
}

TEST(PrintableTargets, SvgDeclaresThePaperInMillimetres) {
  TagSheetOptions options;
  options.sheet.paper = *FindPaper("letter");
  const std::string svg = DrawTagSheet(options, SheetFormat::kSvg);
  EXPECT_NE(svg.find("width=\"215.9mm\" height=\"279.4mm\""), std::string::npos)
      << svg.substr(0, 300);
  CheckerboardSheetOptions board;
  const std::string landscape = DrawCheckerboardSheet(board, SheetFormat::kSvg);
  EXPECT_NE(landscape.find("width=\"297mm\" height=\"210mm\""),
            std::string::npos)
      << landscape.substr(0, 300);
}

TEST(PrintableTargets, RefusesWhatDoesNotFitAndSaysWhatWould) {
  TagSheetOptions tag;
  tag.size_mm = 400.0;
  ASSERT_TRUE(tag.Problem());
  EXPECT_NE(tag.Problem()->find("does not fit on a4"), std::string::npos)
      << *tag.Problem();
  EXPECT_NE(tag.Problem()->find("tags up to 1"), std::string::npos)
      << *tag.Problem();
  CheckerboardSheetOptions board;
  board.board = {9, 6, 40.0};
  ASSERT_TRUE(board.Problem());
  EXPECT_NE(board.Problem()->find("squares up to 22.5 mm fit"),
            std::string::npos)
      << *board.Problem();
  DotSheetOptions dots;
  EXPECT_EQ(*dots.Problem(), "no dots to print");
}

}  // namespace
}  // namespace softbench
