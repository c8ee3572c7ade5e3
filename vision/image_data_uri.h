#ifndef SOFTBENCH_VISION_IMAGE_DATA_URI_H_
#define SOFTBENCH_VISION_IMAGE_DATA_URI_H_

#include <opencv2/core.hpp>
#include <string>

namespace softbench {

// An 8-bit BGR image as a JPEG data: URI (EncodeJpeg's qscale, 1-31), for
// pictures inside a self-contained HTML page. Lives in vision/ because its
// base64 is FFmpeg's, and FFmpeg stays behind vision/'s walls.
std::string JpegDataUri(const cv::Mat& bgr, int qscale);
// An 8-bit BGR or gray image, lossless (PNG): for a page that reads the
// pixels' colours back.
std::string PngDataUri(const cv::Mat& bgr);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_IMAGE_DATA_URI_H_
