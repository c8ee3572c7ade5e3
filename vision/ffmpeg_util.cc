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

namespace {

const int* Coefficients(AVColorSpace colorspace) {
  int sws_space = SWS_CS_ITU709;
  if (colorspace == AVCOL_SPC_BT470BG || colorspace == AVCOL_SPC_SMPTE170M) {
    sws_space = SWS_CS_ITU601;
  } else if (colorspace == AVCOL_SPC_BT2020_NCL ||
             colorspace == AVCOL_SPC_BT2020_CL) {
    sws_space = SWS_CS_BT2020;
  } else if (colorspace == AVCOL_SPC_SMPTE240M) {
    sws_space = SWS_CS_SMPTE240M;
  } else if (colorspace == AVCOL_SPC_FCC) {
    sws_space = SWS_CS_FCC;
  }
  return sws_getCoefficients(sws_space);
}

}  // namespace

void SetYuvToRgb(SwsContext* sws, AVColorSpace colorspace, AVColorRange range) {
  const int* coefficients = Coefficients(colorspace);
  // The YUV side's range; RGB is always full range.
  sws_setColorspaceDetails(sws, coefficients, range == AVCOL_RANGE_JPEG ? 1 : 0,
                           coefficients, 1, 0, 1 << 16, 1 << 16);
}

void SetRgbToYuv(SwsContext* sws, AVColorSpace colorspace, AVColorRange range) {
  const int* coefficients = Coefficients(colorspace);
  sws_setColorspaceDetails(sws, coefficients, 1, coefficients,
                           range == AVCOL_RANGE_JPEG ? 1 : 0, 0, 1 << 16,
                           1 << 16);
}

}  // namespace softbench
