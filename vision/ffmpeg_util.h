#ifndef SOFTBENCH_VISION_FFMPEG_UTIL_H_
#define SOFTBENCH_VISION_FFMPEG_UTIL_H_

#include <string>

extern "C" {
#include <libavutil/pixfmt.h>
}

struct SwsContext;

namespace softbench {

// FFmpeg's text for an error code.
std::string FfmpegError(int error);

// Set the YUV -> RGB (reader) or RGB -> YUV (writer) coefficients and the
// YUV side's range of a swscale context from a stream's colour metadata
// (BT.601, BT.709, BT.2020; BT.709 when unspecified, as for HD video), so
// the reader and writer convert with the same matrix.
void SetYuvToRgb(SwsContext* sws, AVColorSpace colorspace, AVColorRange range);
void SetRgbToYuv(SwsContext* sws, AVColorSpace colorspace, AVColorRange range);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_FFMPEG_UTIL_H_
