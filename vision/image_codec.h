#ifndef SOFTBENCH_VISION_IMAGE_CODEC_H_
#define SOFTBENCH_VISION_IMAGE_CODEC_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace softbench {

// Still images (PNG, JPEG) through FFmpeg's codecs, which the video path
// links anyway. OpenCV's imgcodecs brought 77 more shared libraries (GDAL,
// GDCM, OpenEXR and theirs), and loading them took 0.13 s of every
// command's start, 1.4 % of decoding the delta sample (issue 29).

enum class ImageColor { kBgr, kGray };

// What ReadImageFile found: an 8-bit image, or why there is none.
struct ImageRead {
  cv::Mat image;        // CV_8UC3 (BGR) or CV_8UC1; empty when not read
  std::string why_not;  // set when `image` is empty
};

// The PNG or JPEG image in `path` as 8-bit BGR or gray, upright: a JPEG's
// EXIF orientation applied as OpenCV's imread applies it (the eight
// orientations, mirrored ones too). Deeper PNGs are reduced to 8 bits, and
// alpha is dropped. Any other content, or a damaged file, is a why_not.
ImageRead ReadImageFile(const std::string& path, ImageColor color);

// An 8-bit BGR or gray image as PNG bytes: lossless.
std::vector<uint8_t> EncodePng(const cv::Mat& image);

// An 8-bit BGR image as JPEG bytes (4:2:0, full-range BT.601, as JPEG
// files are) at FFmpeg's quantiser scale `qscale` (1-31: 1 is its finest).
std::vector<uint8_t> EncodeJpeg(const cv::Mat& bgr, int qscale);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_IMAGE_CODEC_H_
