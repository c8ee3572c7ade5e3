#include "vision/ffmpeg_util.h"

extern "C" {
#include <libavutil/error.h>
#include <libswscale/swscale.h>
}

namespace softbench {

std::string FfmpegError(int error) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(error, text, sizeof(text));
  return text;
}

void SetColorspace(SwsContext* sws, AVColorSpace colorspace,
                   AVColorRange range) {
  const int sws_space =
      colorspace == AVCOL_SPC_BT470BG || colorspace == AVCOL_SPC_SMPTE170M
          ? SWS_CS_ITU601
          : SWS_CS_ITU709;
  const int* coefficients = sws_getCoefficients(sws_space);
  const int full_range = range == AVCOL_RANGE_JPEG ? 1 : 0;
  // Source and destination tables; RGB is always full range.
  sws_setColorspaceDetails(sws, coefficients, full_range, coefficients, 1, 0,
                           1 << 16, 1 << 16);
}

}  // namespace softbench
