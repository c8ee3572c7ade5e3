#include "vision/image_data_uri.h"

extern "C" {
#include <libavutil/base64.h>
}

#include <vector>

#include "vision/image_codec.h"

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

std::string JpegDataUri(const cv::Mat& bgr, int qscale) {
  return DataUri("image/jpeg", EncodeJpeg(bgr, qscale));
}

std::string PngDataUri(const cv::Mat& bgr) {
  return DataUri("image/png", EncodePng(bgr));
}

}  // namespace softbench
