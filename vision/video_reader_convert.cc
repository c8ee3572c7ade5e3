// VideoReader's conversions: luma upright at its full depth, colour through
// SDR, and regions converted from the planes without the whole frame.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "util/check.h"
#include "util/input_error.h"
#include "util/input_file.h"
#include "vision/ffmpeg_util.h"
#include "vision/luma.h"
#include "vision/video_reader_state.h"

namespace softbench {
namespace {

// 16-bit luma turned a quarter turn (clockwise for 90, counter-clockwise
// for 270), in 8 x 8 blocks transposed in SIMD registers: one pass instead
// of cv::rotate's transpose and flip (every frame of a portrait 10-bit phone
// video).
void QuarterTurn16(const cv::Mat& in, int rotation_deg, cv::Mat* out) {
  const int h = in.rows, w = in.cols;
  out->create(w, h, CV_16UC1);
  const bool clockwise = rotation_deg == 90;
  // Output (i, j) shows input (h - 1 - j, i) clockwise, (j, w - 1 - i)
  // counter-clockwise.
  const auto at = [&](int i, int j) -> uint16_t {
    return clockwise ? in.ptr<uint16_t>(h - 1 - j)[i]
                     : in.ptr<uint16_t>(j)[w - 1 - i];
  };
  int i0 = 0;
  for (; i0 + 8 <= w; i0 += 8) {
    int j0 = 0;
    for (; j0 + 8 <= h; j0 += 8) {
      // Rows of the input whose transpose is the output block.
      cv::v_uint16x8 r[8];
      for (int k = 0; k < 8; ++k) {
        const uint16_t* src = clockwise ? in.ptr<uint16_t>(h - 1 - j0 - k) + i0
                                        : in.ptr<uint16_t>(j0 + k) + w - 8 - i0;
        r[k] = cv::v_load(src);
      }
      cv::v_uint16x8 a[8];
      for (int k = 0; k < 8; k += 2) cv::v_zip(r[k], r[k + 1], a[k], a[k + 1]);
      cv::v_uint32x4 b[8];
      for (int k = 0; k < 2; ++k) {
        cv::v_zip(cv::v_reinterpret_as_u32(a[k]),
                  cv::v_reinterpret_as_u32(a[k + 2]), b[2 * k], b[2 * k + 1]);
        cv::v_zip(cv::v_reinterpret_as_u32(a[k + 4]),
                  cv::v_reinterpret_as_u32(a[k + 6]), b[2 * k + 4],
                  b[2 * k + 5]);
      }
      cv::v_float64x2 c[8];  // 64-bit lanes: OpenCV zips them as doubles
      for (int k = 0; k < 4; ++k) {
        cv::v_zip(cv::v_reinterpret_as_f64(b[k]),
                  cv::v_reinterpret_as_f64(b[k + 4]), c[2 * k], c[2 * k + 1]);
      }
      for (int m = 0; m < 8; ++m) {
        cv::v_store(out->ptr<uint16_t>(i0 + m) + j0,
                    cv::v_reinterpret_as_u16(c[clockwise ? m : 7 - m]));
      }
    }
    for (; j0 < h; ++j0) {
      for (int m = 0; m < 8; ++m) {
        out->ptr<uint16_t>(i0 + m)[j0] = at(i0 + m, j0);
      }
    }
  }
  for (; i0 < w; ++i0) {
    for (int j = 0; j < h; ++j) {
      out->ptr<uint16_t>(i0)[j] = at(i0, j);
    }
  }
}

}  // namespace

cv::Mat VideoReader::State::Luma() {
  const int w = frame->width, h = frame->height;
  const bool deep = desc->comp[0].step == 2;
  cv::Mat plane(h, w, deep ? CV_16UC1 : CV_8UC1, frame->data[0],
                frame->linesize[0]);
  // Deeper codes stay as decoded (LumaEncoding::deep_bits says how many
  // bits): shifting every pixel of every frame to fill 16 bits was a pass
  // over the whole plane, 5 % of validate's CPU on 10-bit 1080p, where
  // measurement reads a few regions.
  if (info.rotation_deg == 0) return plane;
  if (deep && (info.rotation_deg == 90 || info.rotation_deg == 270)) {
    QuarterTurn16(plane, info.rotation_deg, &luma_upright);
  } else {
    Rotate(plane, &luma_upright);
  }
  return luma_upright;
}

double VideoReader::State::HdrWhiteOf(const cv::Mat& first_luma) const {
  const double reference = ReferenceWhiteLinear(info.encoding.transfer);
  // 1024 bins of 64 levels of the codes scaled to 16 bits, counted in
  // place: a scaled copy of the frame first made it 18 ms instead of 2 ms
  // at 10-bit 1080p, on the thread that measures, before the first frame.
  // A code above its depth (raw video's words are not clipped to it) falls
  // in the top bin, as the copy's saturation put it.
  const int to_16_bits =
      first_luma.depth() == CV_8U ? 8 : 16 - info.luma_encoding().deep_bits;
  std::vector<int> histogram(1024, 0);
  WithLumaType(first_luma, [&](auto type) {
    using T = decltype(type);
    for (int v = 0; v < first_luma.rows; ++v) {
      const T* row = first_luma.ptr<T>(v);
      for (int u = 0; u < first_luma.cols; ++u) {
        ++histogram[std::min((row[u] << to_16_bits) >> 6, 1023)];
      }
    }
  });
  int64_t above = 0, bin = 1023;
  const int64_t wanted = first_luma.total() / 100;
  for (; bin > 0 && above + histogram[bin] <= wanted; --bin) {
    above += histogram[bin];
  }
  const double code16 = bin * 64.0;  // the bin's bottom: never above it
  const double black = BlackLevel(info.luma_encoding()) * 256.0;
  const double white = info.full_range ? 65535.0 : 235.0 * 256.0;
  const double bright =
      ToLinear(info.encoding.transfer, (code16 - black) / (white - black));
  return bright > 1.5 * reference ? bright : reference;
}

double VideoReader::State::HdrWhite() {
  if (hdr_white) return *hdr_white;
  VideoReaderOptions luma_only;
  luma_only.want_bgr = false;
  luma_only.threads = 1;
  VideoReader first(path, luma_only);
  VideoFrame frame;
  hdr_white = first.Read(&frame) ? HdrWhiteOf(frame.luma)
                                 : ReferenceWhiteLinear(info.encoding.transfer);
  return *hdr_white;
}

void VideoReader::State::Convert(VideoFrame* out) {
  out->time_s = last_good_time;
  out->index = last_good_index;
  const int w = frame->width, h = frame->height;
  if (last_good_index == 0 && !hdr_white && !info.encoding.IsSdrBt709()) {
    hdr_white = HdrWhiteOf(Luma());
  }
  if (options.want_luma) {
    out->luma = Luma();  // a view or the reused buffer: no allocation
  } else {
    out->luma.release();
  }
  if (options.want_bgr) {
    Rotate(ConvertBgr(frame->data, frame->linesize, w, h), &out->bgr);
  } else {
    out->bgr.release();
  }
}

SwsContext* VideoReader::State::SwsFor(const SwsKey& key) {
  const auto it =
      std::find_if(sws_contexts.begin(), sws_contexts.end(),
                   [&](const auto& entry) { return entry.first == key; });
  if (it != sws_contexts.end()) {
    std::rotate(sws_contexts.begin(), it, it + 1);
    return sws_contexts.front().second;
  }
  SwsContext* context = sws_getContext(
      key.w, key.h, static_cast<AVPixelFormat>(key.format), key.dst_w,
      key.dst_h, static_cast<AVPixelFormat>(key.dst_format), key.flags, nullptr,
      nullptr, nullptr);
  SOFTBENCH_CHECK(context != nullptr) << "swscale refused " << key.w << "x"
                                      << key.h << " format " << key.format;
  SetYuvToRgb(context, static_cast<AVColorSpace>(key.colorspace),
              static_cast<AVColorRange>(key.range));
  if (sws_contexts.size() == kMaxSwsContexts) {
    sws_freeContext(sws_contexts.back().second);
    sws_contexts.pop_back();
  }
  sws_contexts.insert(sws_contexts.begin(), {key, context});
  return context;
}

cv::Mat VideoReader::State::ConvertBgr(const uint8_t* const* data,
                                       const int* linesize, int w, int h,
                                       cv::Size dst_size) {
  if (dst_size.empty()) dst_size = {w, h};
  const bool reduce = dst_size != cv::Size(w, h);
  if (!info.encoding.IsSdrBt709() && !to_sdr) {
    to_sdr.emplace(info.encoding, HdrWhite());
  }
  // SDR BT.709 straight to 8 bits; anything else through 16 bits to SDR.
  SwsContext* context =
      SwsFor({.w = w,
              .h = h,
              .format = frame->format,
              .dst_w = dst_size.width,
              .dst_h = dst_size.height,
              .dst_format = to_sdr ? AV_PIX_FMT_BGR48LE : AV_PIX_FMT_BGR24,
              .flags = reduce ? SWS_AREA : SWS_BILINEAR,
              .colorspace = frame->colorspace,
              .range = frame->color_range});
  // swscale's vector code writes whole 16-pixel blocks: rows padded to
  // them (and aligned), then cut to the width.
  cv::Mat padded(dst_size.height, (dst_size.width + 15) / 16 * 16,
                 to_sdr ? CV_16UC3 : CV_8UC3);
  uint8_t* dst[] = {padded.data};
  const int dst_stride[] = {static_cast<int>(padded.step)};
  sws_scale(context, data, linesize, 0, h, dst, dst_stride);
  if (to_sdr) return to_sdr->Convert(padded.colRange(0, dst_size.width));
  return padded.colRange(0, dst_size.width);  // owned: not a view
}

void VideoReader::State::Rotate(const cv::Mat& in, cv::Mat* out) const {
  switch (info.rotation_deg) {
    case 90:
      cv::rotate(in, *out, cv::ROTATE_90_CLOCKWISE);
      break;
    case 180:
      cv::rotate(in, *out, cv::ROTATE_180);
      break;
    case 270:
      cv::rotate(in, *out, cv::ROTATE_90_COUNTERCLOCKWISE);
      break;
    default:
      *out = in;
  }
}

namespace {

// The planar formats whose regions convert by pointing at their planes.
const AVPixFmtDescriptor* PlanarYuv(const AVFrame& frame) {
  const AVPixFmtDescriptor* desc =
      av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  const bool planar =
      desc != nullptr && (desc->flags & AV_PIX_FMT_FLAG_PLANAR) != 0 &&
      (desc->flags & (AV_PIX_FMT_FLAG_HWACCEL | AV_PIX_FMT_FLAG_RGB)) == 0;
  return planar ? desc : nullptr;
}

// The smallest rectangle of whole chroma samples holding `r`.
cv::Rect ChromaAligned(const cv::Rect& r, const AVPixFmtDescriptor& desc,
                       const cv::Size& frame_size) {
  const int align_x = 1 << desc.log2_chroma_w,
            align_y = 1 << desc.log2_chroma_h;
  const int x0 = r.x / align_x * align_x, y0 = r.y / align_y * align_y;
  const int x1 = std::min(frame_size.width,
                          (r.br().x + align_x - 1) / align_x * align_x),
            y1 = std::min(frame_size.height,
                          (r.br().y + align_y - 1) / align_y * align_y);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

cv::Mat VideoReader::ConvertRegion(const cv::Rect& aligned,
                                   const cv::Size& dst_size) {
  State& s = *state_;
  const AVPixFmtDescriptor& desc = *PlanarYuv(*s.frame);
  // Point each plane at the region's corner.
  const uint8_t* data[4] = {};
  for (int c = 0; c < desc.nb_components; ++c) {
    const AVComponentDescriptor& comp = desc.comp[c];
    const bool chroma = c == 1 || c == 2;
    const int px = chroma ? aligned.x >> desc.log2_chroma_w : aligned.x;
    const int py = chroma ? aligned.y >> desc.log2_chroma_h : aligned.y;
    data[comp.plane] =
        s.frame->data[comp.plane] +
        static_cast<ptrdiff_t>(py) * s.frame->linesize[comp.plane] +
        static_cast<ptrdiff_t>(px) * comp.step;
  }
  return s.ConvertBgr(data, s.frame->linesize, aligned.width, aligned.height,
                      dst_size);
}

bool VideoReader::RegionsConvertInPlace() const {
  return PlanarYuv(*state_->frame) != nullptr;
}

cv::Rect VideoReader::StoredRect(const cv::Rect& display) const {
  // The decoded frame is turned clockwise by the rotation for display.
  const int w = state_->frame->width, h = state_->frame->height;
  const int x0 = display.x, y0 = display.y, x1 = display.br().x,
            y1 = display.br().y;
  switch (state_->info.rotation_deg) {
    case 90:
      return {y0, h - x1, y1 - y0, x1 - x0};
    case 180:
      return {w - x1, h - y1, x1 - x0, y1 - y0};
    case 270:
      return {w - y1, x0, y1 - y0, x1 - x0};
    default:
      return display;
  }
}

cv::Mat VideoReader::BgrRegion(const cv::Rect& region) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || s.last_good_index < 0) return {};
  if (!RegionsConvertInPlace()) {
    // Rare path (formats without planes to point into): convert it all.
    cv::Mat full;
    s.Rotate(s.ConvertBgr(s.frame->data, s.frame->linesize, s.frame->width,
                          s.frame->height),
             &full);
    return full(clipped).clone();
  }
  // The region as decoded (before the display rotation), grown to whole
  // chroma samples, converted, cut to the request and turned upright.
  const cv::Rect stored = StoredRect(clipped);
  const cv::Rect aligned = ChromaAligned(stored, *PlanarYuv(*s.frame),
                                         {s.frame->width, s.frame->height});
  cv::Mat upright;
  s.Rotate(ConvertRegion(aligned, {})(stored - aligned.tl()), &upright);
  return upright.clone();
}

cv::Mat VideoReader::BgrRegionReduced(const cv::Rect& region,
                                      const cv::Size& size) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || size.empty() || s.last_good_index < 0) return {};
  if (RegionsConvertInPlace()) {
    const cv::Rect stored = StoredRect(clipped);
    if (ChromaAligned(stored, *PlanarYuv(*s.frame),
                      {s.frame->width, s.frame->height}) == stored) {
      // Straight from the planes, reduced, then turned upright.
      const bool quarter_turn =
          s.info.rotation_deg == 90 || s.info.rotation_deg == 270;
      cv::Mat upright;
      s.Rotate(
          ConvertRegion(
              stored, quarter_turn ? cv::Size(size.height, size.width) : size),
          &upright);
      return upright;
    }
  }
  cv::Mat reduced;
  cv::resize(BgrRegion(clipped), reduced, size, 0, 0, cv::INTER_AREA);
  return reduced;
}

}  // namespace softbench
