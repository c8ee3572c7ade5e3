#include "vision/image_codec.h"

#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "tests/support/scratch_directory.h"

namespace softbench {
namespace {

// A picture with structure in every direction, so that a transposition or
// a flip shows: random blocks of colour (fixed seed) and a corner mark.
cv::Mat TestPicture(int rows, int cols) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> level(0, 255);
  cv::Mat bgr(rows, cols, CV_8UC3);
  for (int y = 0; y < rows; y += 8) {
    for (int x = 0; x < cols; x += 8) {
      bgr(cv::Rect(x, y, std::min(8, cols - x), std::min(8, rows - y)))
          .setTo(cv::Scalar(level(random), level(random), level(random)));
    }
  }
  bgr(cv::Rect(0, 0, 16, 8)).setTo(cv::Scalar(0, 0, 255));
  return bgr;
}

std::string Write(const std::string& name, const std::vector<uint8_t>& bytes) {
  std::string path = (TestScratch().dir() / name).string();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

double MeanAbsoluteDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  return cv::mean(diff.reshape(1))[0];
}

// `jpeg` with an EXIF block giving `orientation` after its start-of-image
// marker.
std::vector<uint8_t> WithOrientation(const std::vector<uint8_t>& jpeg,
                                     int orientation) {
  std::vector<uint8_t> out(jpeg.begin(), jpeg.begin() + 2);
  const auto put = [&](std::initializer_list<int> bytes) {
    for (const int b : bytes) out.push_back(static_cast<uint8_t>(b));
  };
  put({0xFF, 0xE1, 0, 34});                 // APP1, 32 bytes after the length
  put({'E', 'x', 'i', 'f', 0, 0});          // EXIF's signature
  put({'I', 'I', 42, 0, 8, 0, 0, 0});       // little-endian TIFF, IFD at 8
  put({1, 0});                              // one entry:
  put({0x12, 0x01, 3, 0, 1, 0, 0, 0});      // Orientation, one SHORT,
  put({orientation, 0, 0, 0, 0, 0, 0, 0});  // its value; no next IFD
  out.insert(out.end(), jpeg.begin() + 2, jpeg.end());
  return out;
}

TEST(ImageCodec, PngRoundTripsExactly) {
  const cv::Mat bgr = TestPicture(45, 71);  // odd sizes: no row padding
  const ImageRead read =
      ReadImageFile(Write("codec_bgr.png", EncodePng(bgr)), ImageColor::kBgr);
  ASSERT_FALSE(read.image.empty()) << read.why_not;
  EXPECT_EQ(cv::norm(read.image, bgr, cv::NORM_INF), 0.0);

  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  const std::string gray_path = Write("codec_gray.png", EncodePng(gray));
  const ImageRead gray_read = ReadImageFile(gray_path, ImageColor::kGray);
  ASSERT_EQ(gray_read.image.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(gray_read.image, gray, cv::NORM_INF), 0.0);
  // A gray file asked for in colour: its levels as they are, not stretched
  // as video range.
  const ImageRead as_bgr = ReadImageFile(gray_path, ImageColor::kBgr);
  cv::Mat expected;
  cv::cvtColor(gray, expected, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(cv::norm(as_bgr.image, expected, cv::NORM_INF), 0.0);
}

TEST(ImageCodec, ReadsWhatOpenCvWritesAsOpenCvReadsIt) {
  const cv::Mat bgr = TestPicture(48, 64);
  const std::string png = (TestScratch().dir() / "codec_cv.png").string();
  cv::imwrite(png, bgr);
  EXPECT_EQ(
      cv::norm(ReadImageFile(png, ImageColor::kBgr).image, bgr, cv::NORM_INF),
      0.0);
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  // libpng's own weighting of colour to gray rounds a code apart at most.
  EXPECT_LE(cv::norm(ReadImageFile(png, ImageColor::kGray).image,
                     cv::imread(png, cv::IMREAD_GRAYSCALE), cv::NORM_INF),
            1.0);
  // JPEG: another decoder's chroma upsampling, as near the picture as
  // libjpeg's.
  const std::string jpg = (TestScratch().dir() / "codec_cv.jpg").string();
  cv::imwrite(jpg, bgr, {cv::IMWRITE_JPEG_QUALITY, 95});
  for (const ImageColor color : {ImageColor::kBgr, ImageColor::kGray}) {
    const cv::Mat ours = ReadImageFile(jpg, color).image;
    const cv::Mat opencv =
        cv::imread(jpg, color == ImageColor::kBgr ? cv::IMREAD_COLOR
                                                  : cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(ours.size(), opencv.size());
    ASSERT_EQ(ours.type(), opencv.type());
    cv::Mat original = bgr;
    if (color == ImageColor::kGray) {
      cv::cvtColor(bgr, original, cv::COLOR_BGR2GRAY);
    }
    EXPECT_LT(MeanAbsoluteDifference(ours, original),
              1.1 * MeanAbsoluteDifference(opencv, original) + 0.1);
    EXPECT_LT(MeanAbsoluteDifference(ours, opencv), 4.0);
  }
}

TEST(ImageCodec, JpegKeepsThePictureAsLibjpegDoes) {
  const cv::Mat bgr = TestPicture(64, 96);
  const std::vector<uint8_t> jpeg = EncodeJpeg(bgr, 1);
  const ImageRead read =
      ReadImageFile(Write("codec.jpg", jpeg), ImageColor::kBgr);
  ASSERT_EQ(read.image.size(), bgr.size());
  // Blocks of random colour: 4:2:0 chroma blurs their edges, no more than
  // libjpeg's quality 92 (the report's crops' former setting) does.
  std::vector<uint8_t> libjpeg;
  cv::imencode(".jpg", bgr, libjpeg, {cv::IMWRITE_JPEG_QUALITY, 92});
  EXPECT_LT(
      MeanAbsoluteDifference(read.image, bgr),
      MeanAbsoluteDifference(cv::imdecode(libjpeg, cv::IMREAD_COLOR), bgr));
  // A coarser quantiser writes fewer bytes.
  EXPECT_LT(EncodeJpeg(bgr, 20).size(), jpeg.size());
}

TEST(ImageCodec, AppliesEveryExifOrientationAsOpenCvDoes) {
  const cv::Mat bgr = TestPicture(40, 64);
  const std::vector<uint8_t> jpeg = EncodeJpeg(bgr, 1);
  const cv::Mat stored =
      ReadImageFile(Write("codec_o1.jpg", jpeg), ImageColor::kBgr).image;
  for (int orientation = 1; orientation <= 8; ++orientation) {
    const std::string path =
        Write("codec_o" + std::to_string(orientation) + ".jpg",
              WithOrientation(jpeg, orientation));
    const cv::Mat ours = ReadImageFile(path, ImageColor::kBgr).image;
    const cv::Mat opencv = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_EQ(ours.size(), opencv.size()) << "orientation " << orientation;
    EXPECT_LT(MeanAbsoluteDifference(ours, opencv), 4.0)
        << "orientation " << orientation;
    // The same pixels as the unrotated file's, moved.
    EXPECT_EQ(ours.total(), stored.total());
    EXPECT_EQ(orientation >= 5, ours.rows == stored.cols)
        << "orientation " << orientation;
  }
  // Orientation 6: the top row becomes the right column, read downward.
  const cv::Mat six =
      ReadImageFile((TestScratch().dir() / "codec_o6.jpg").string(),
                    ImageColor::kBgr)
          .image;
  cv::Mat rotated;
  cv::rotate(stored, rotated, cv::ROTATE_90_CLOCKWISE);
  EXPECT_EQ(cv::norm(six, rotated, cv::NORM_INF), 0.0);
}

TEST(ImageCodec, SaysWhyItCannotRead) {
  const std::string text = Write("codec_text.png", {'n', 'o', 't', '\n'});
  const ImageRead text_read = ReadImageFile(text, ImageColor::kBgr);
  EXPECT_TRUE(text_read.image.empty());
  EXPECT_EQ(text_read.why_not, "not a PNG or JPEG image");

  std::vector<uint8_t> png = EncodePng(TestPicture(64, 64));
  png.resize(png.size() / 2);
  const ImageRead cut =
      ReadImageFile(Write("codec_cut.png", png), ImageColor::kBgr);
  EXPECT_TRUE(cut.image.empty());
  EXPECT_FALSE(cut.why_not.empty());

  const ImageRead missing = ReadImageFile(
      (TestScratch().dir() / "codec_missing.png").string(), ImageColor::kBgr);
  EXPECT_TRUE(missing.image.empty());
  EXPECT_FALSE(missing.why_not.empty());
}

}  // namespace
}  // namespace softbench
