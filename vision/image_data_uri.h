#ifndef SOFTBENCH_VISION_IMAGE_DATA_URI_H_
#define SOFTBENCH_VISION_IMAGE_DATA_URI_H_

#include <opencv2/core.hpp>
#include <string>

namespace softbench {

// An 8-bit image as a JPEG data: URI (quality 0-100), for pictures inside a
// self-contained HTML page. Lives in vision/ because its base64 is FFmpeg's,
// and FFmpeg stays behind vision/'s walls.
std::string JpegDataUri(const cv::Mat& bgr, int quality);
// The same, lossless (PNG): for a page that reads the pixels' colours back.
std::string PngDataUri(const cv::Mat& bgr);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_IMAGE_DATA_URI_H_
