#include "vision/image_data_uri.h"

extern "C" {
#include <libavutil/base64.h>
}

#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "util/check.h"

namespace softbench {

std::string JpegDataUri(const cv::Mat& bgr, int quality) {
  SOFTBENCH_CHECK(bgr.depth() == CV_8U && quality >= 0 && quality <= 100)
      << "JpegDataUri takes an 8-bit image and a quality of 0-100";
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
  std::string encoded(AV_BASE64_SIZE(jpeg.size()), '\0');
  av_base64_encode(encoded.data(), static_cast<int>(encoded.size()),
                   jpeg.data(), static_cast<int>(jpeg.size()));
  encoded.resize(encoded.find('\0'));
  return "data:image/jpeg;base64," + encoded;
}

}  // namespace softbench
