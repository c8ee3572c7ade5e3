#include "vision/image_data_uri.h"

extern "C" {
#include <libavutil/base64.h>
}

#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "util/check.h"

namespace softbench {

namespace {

std::string DataUri(const std::string& mime,
                    const std::vector<uint8_t>& bytes) {
  std::string encoded(AV_BASE64_SIZE(bytes.size()), '\0');
  av_base64_encode(encoded.data(), static_cast<int>(encoded.size()),
                   bytes.data(), static_cast<int>(bytes.size()));
  encoded.resize(encoded.find('\0'));
  return "data:" + mime + ";base64," + encoded;
}

}  // namespace

std::string JpegDataUri(const cv::Mat& bgr, int quality) {
  SOFTBENCH_CHECK(bgr.depth() == CV_8U && quality >= 0 && quality <= 100)
      << "JpegDataUri takes an 8-bit image and a quality of 0-100";
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
  return DataUri("image/jpeg", jpeg);
}

std::string PngDataUri(const cv::Mat& bgr) {
  SOFTBENCH_CHECK(bgr.depth() == CV_8U) << "PngDataUri takes an 8-bit image";
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  return DataUri("image/png", png);
}

}  // namespace softbench
