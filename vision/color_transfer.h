#ifndef SOFTBENCH_VISION_COLOR_TRANSFER_H_
#define SOFTBENCH_VISION_COLOR_TRANSFER_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace softbench {

// How a video's R'G'B' code values encode light: the transfer function and
// the primaries (ITU-R BT.709, BT.2020, BT.2100).
enum class Transfer {
  kSdr,  // BT.709 / BT.601 / BT.2020 SDR: the BT.709 camera curve
  kHlg,  // BT.2100 hybrid log-gamma (ARIB STD-B67): phones' HDR default
  kPq,   // BT.2100 perceptual quantiser (SMPTE ST 2084)
};
enum class Primaries { kBt709, kBt2020 };

struct ColorEncoding {
  Transfer transfer = Transfer::kSdr;
  Primaries primaries = Primaries::kBt709;

  // SDR with BT.709 primaries: the colours HSV bounds are tuned on.
  bool IsSdrBt709() const {
    return transfer == Transfer::kSdr && primaries == Primaries::kBt709;
  }
  std::string Name() const;  // "HLG BT.2020", "SDR BT.709", ...
};

// Linear light in [0, 1] from a code value in [0, 1], and back. The linear
// units are the transfer's own: scene light for SDR (the BT.709 curve) and
// HLG, display light / 10000 cd/m² for PQ.
double ToLinear(Transfer transfer, double code);
double FromLinear(Transfer transfer, double linear);
// d FromLinear / d linear, for linear in (0, 1) (0 outside, where FromLinear
// clamps): analytic derivatives of models fitted through the curve.
double FromLinearSlope(Transfer transfer, double linear);

// The linear level of SDR's white in each transfer (ITU-R BT.2408: HLG 75 %,
// PQ 203 cd/m²): the level that converts to SDR 1.0.
double ReferenceWhiteLinear(Transfer transfer);

// Linear RGB in BT.709 primaries from linear RGB in BT.2020 primaries (from
// the primaries' chromaticities and D65); its inverse goes the other way.
Eigen::Matrix3d Bt709FromBt2020();

// Converts R'G'B' of any encoding into SDR BT.709 R'G'B' (8 bits), so that
// colour bounds tuned on SDR footage find the same dots on HDR footage: code
// -> linear, scaled so that `white_linear` becomes SDR white, primaries ->
// BT.709, clipped, then the BT.709 curve. Hue is kept; light above the
// white clips, as an SDR camera would.
class SdrConverter {
 public:
  SdrConverter(const ColorEncoding& from, double white_linear);
  // `bgr16`: CV_16UC3, full range (65535 = code 1.0). Returns CV_8UC3.
  cv::Mat Convert(const cv::Mat& bgr16) const;

 private:
  std::vector<float> to_linear_;      // 16-bit code -> SDR-relative linear
  std::vector<uint8_t> from_linear_;  // linear * 65535 -> 8-bit SDR code
  Eigen::Matrix3f bgr_from_bgr_;      // primaries, in B, G, R order
  bool mix_ = false;                  // whether the primaries change
};

// How a luma plane's codes encode light: the transfer, whether black and
// white are at the ends of the codes (full range) or at 16 and 235 in 8-bit
// levels (limited range, the default of video), and how many bits a 16-bit
// plane's codes have.
struct LumaEncoding {
  Transfer transfer = Transfer::kSdr;
  bool full_range = true;  // images (PNG, JPEG) are full range
  // The bits of CV_16UC1 luma's codes (vision/luma.h): 16 where they fill
  // the range (renders, 16-bit images), the video's depth where they are
  // read as decoded (10 for a phone's HDR video: codes 0-1023). 8-bit luma
  // ignores it.
  int deep_bits = 16;
};

// Black's code in 8-bit levels: 0 in full range, 16 in limited range (at
// any depth, scaled with it).
double BlackLevel(const LumaEncoding& encoding);

// Linear light per luma code, in 8-bit levels of SDR white (0 at black, 255
// at BT.2408's reference white, so thresholds mean the same in SDR and HDR;
// HDR highlights go above): one entry per code of CV_8U (256) or CV_16U
// (2^deep_bits) luma (vision/luma.h). A lens blurs light, not codes, so
// sub-pixel edges are located in linear light; for grey (a tag's ink and paper)
// luma is the channels' code, so its linearisation is the grey's light. Built
// once per encoding and depth; thread-safe.
const std::vector<float>& LinearLumaTable(const LumaEncoding& encoding,
                                          int depth);

// FromLinear as 16-bit codes (65535 = 1.0) through a table indexed by the
// square root of the level: fine where the curves are steep, near black, and
// fast enough for every pixel of a rendered frame.
class CodeFromLinearTable {
 public:
  explicit CodeFromLinearTable(Transfer transfer);
  uint16_t operator()(float linear) const;  // linear in [0, 1], clamped

 private:
  static constexpr int kSize = 65536;
  std::vector<uint16_t> codes_;
};

// The reverse, for rendering HDR footage: SDR BT.709 R'G'B' (CV_8UC3, or
// CV_16UC3 with 65535 = 1.0) into `to` (CV_16UC3, full range), SDR white at
// ReferenceWhiteLinear(to.transfer).
cv::Mat ConvertFromSdr(const cv::Mat& bgr, const ColorEncoding& to);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_COLOR_TRANSFER_H_
