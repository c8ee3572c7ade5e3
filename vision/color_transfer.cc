#include "vision/color_transfer.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <mutex>

namespace softbench {
namespace {

// BT.2100 HLG constants.
constexpr double kHlgA = 0.17883277, kHlgB = 1.0 - 4.0 * kHlgA;
const double kHlgC = 0.5 - kHlgA * std::log(4.0 * kHlgA);
// SMPTE ST 2084 (PQ) constants.
constexpr double kPqM1 = 2610.0 / 16384.0, kPqM2 = 2523.0 / 4096.0 * 128.0;
constexpr double kPqC1 = 3424.0 / 4096.0, kPqC2 = 2413.0 / 4096.0 * 32.0,
                 kPqC3 = 2392.0 / 4096.0 * 32.0;
// BT.2408's reference white: 203 cd/m² of PQ's 10000.
constexpr double kPqReferenceWhite = 203.0 / 10000.0;

// RGB -> XYZ for primaries with these chromaticities and a D65 white.
Eigen::Matrix3d XyzFromRgb(const std::array<double, 6>& xy) {
  Eigen::Matrix3d primaries;
  for (int c = 0; c < 3; ++c) {
    const double x = xy[2 * c], y = xy[2 * c + 1];
    primaries.col(c) << x / y, 1.0, (1.0 - x - y) / y;
  }
  const double wx = 0.3127, wy = 0.3290;
  const Eigen::Vector3d white(wx / wy, 1.0, (1.0 - wx - wy) / wy);
  const Eigen::Vector3d scale = primaries.inverse() * white;
  return primaries * scale.asDiagonal();
}

// The matrix in the B, G, R channel order OpenCV stores.
Eigen::Matrix3f InBgrOrder(const Eigen::Matrix3d& rgb) {
  Eigen::Matrix3f bgr;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      bgr(i, j) = static_cast<float>(rgb(2 - i, 2 - j));
  }
  return bgr;
}

}  // namespace

std::string ColorEncoding::Name() const {
  const char* t = transfer == Transfer::kHlg  ? "HLG"
                  : transfer == Transfer::kPq ? "PQ"
                                              : "SDR";
  return std::string(t) +
         (primaries == Primaries::kBt2020 ? " BT.2020" : " BT.709");
}

double ToLinear(Transfer transfer, double code) {
  code = std::clamp(code, 0.0, 1.0);
  switch (transfer) {
    case Transfer::kHlg:  // BT.2100 Table 5, inverse OETF
      return code <= 0.5 ? code * code / 3.0
                         : (std::exp((code - kHlgC) / kHlgA) + kHlgB) / 12.0;
    case Transfer::kPq: {  // BT.2100 Table 4, EOTF / 10000 cd/m²
      const double p = std::pow(code, 1.0 / kPqM2);
      return std::pow(std::max(p - kPqC1, 0.0) / (kPqC2 - kPqC3 * p),
                      1.0 / kPqM1);
    }
    case Transfer::kSdr:  // BT.709 OETF, inverted
      return code < 0.081 ? code / 4.5
                          : std::pow((code + 0.099) / 1.099, 1.0 / 0.45);
  }
  return code;
}

double FromLinear(Transfer transfer, double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  switch (transfer) {
    case Transfer::kHlg:
      return linear <= 1.0 / 12.0
                 ? std::sqrt(3.0 * linear)
                 : kHlgA * std::log(12.0 * linear - kHlgB) + kHlgC;
    case Transfer::kPq: {
      const double y = std::pow(linear, kPqM1);
      return std::pow((kPqC1 + kPqC2 * y) / (1.0 + kPqC3 * y), kPqM2);
    }
    case Transfer::kSdr:
      return linear < 0.018 ? 4.5 * linear
                            : 1.099 * std::pow(linear, 0.45) - 0.099;
  }
  return linear;
}

double FromLinearSlope(Transfer transfer, double linear) {
  if (!(linear > 0.0 && linear < 1.0)) return 0.0;
  switch (transfer) {
    case Transfer::kHlg:
      return linear <= 1.0 / 12.0 ? 1.5 / std::sqrt(3.0 * linear)
                                  : 12.0 * kHlgA / (12.0 * linear - kHlgB);
    case Transfer::kPq: {
      const double y = std::pow(linear, kPqM1);
      const double ratio = (kPqC1 + kPqC2 * y) / (1.0 + kPqC3 * y);
      const double d_ratio =
          (kPqC2 - kPqC1 * kPqC3) / ((1.0 + kPqC3 * y) * (1.0 + kPqC3 * y));
      return kPqM2 * std::pow(ratio, kPqM2 - 1.0) * d_ratio * kPqM1 * y /
             linear;
    }
    case Transfer::kSdr:
      return linear < 0.018 ? 4.5 : 1.099 * 0.45 * std::pow(linear, -0.55);
  }
  return 1.0;
}

double ReferenceWhiteLinear(Transfer transfer) {
  switch (transfer) {
    case Transfer::kHlg:
      return ToLinear(Transfer::kHlg, 0.75);
    case Transfer::kPq:
      return kPqReferenceWhite;
    case Transfer::kSdr:
      return 1.0;
  }
  return 1.0;
}

Eigen::Matrix3d Bt709FromBt2020() {
  static const Eigen::Matrix3d kMatrix =
      XyzFromRgb({0.640, 0.330, 0.300, 0.600, 0.150, 0.060}).inverse() *
      XyzFromRgb({0.708, 0.292, 0.170, 0.797, 0.131, 0.046});
  return kMatrix;
}

double BlackLevel(const LumaEncoding& encoding) {
  return encoding.full_range ? 0.0 : 16.0;
}

const std::vector<float>& LinearLumaTable(const LumaEncoding& encoding,
                                          int depth) {
  CV_Assert(depth == CV_8U || depth == CV_16U);
  // 16-bit luma has 9 to 16 bits: 8 would share the 8-bit table's key.
  const int bits = depth == CV_8U ? 8 : encoding.deep_bits;
  CV_Assert(depth == CV_8U || (bits > 8 && bits <= 16));
  constexpr int kTransfers = 3, kBitCounts = 9;  // 8 to 16 bits
  static std::array<std::once_flag, kTransfers * 2 * kBitCounts> built;
  static std::array<std::vector<float>, kTransfers * 2 * kBitCounts> tables;
  const int key = (static_cast<int>(encoding.transfer) * 2 +
                   (encoding.full_range ? 1 : 0)) *
                      kBitCounts +
                  bits - 8;
  std::call_once(built[key], [&] {
    const int codes = 1 << bits;
    // Limited range: black at 16, white at 235 in 8-bit levels, whatever
    // the depth (BT.2100: scaled by 2^(bits - 8)).
    const double per_level = codes / 256.0;
    const double black = BlackLevel(encoding) * per_level;
    const double white = encoding.full_range ? codes - 1.0 : 235.0 * per_level;
    const double sdr_white = ReferenceWhiteLinear(encoding.transfer);
    // Every 16-bit value has an entry, so a table indexed by a sample is
    // never read past its end (above 2^bits the curve runs on).
    std::vector<float>& table = tables[key];
    table.resize(depth == CV_8U ? 256 : 65536);
    for (int i = 0; i < static_cast<int>(table.size()); ++i) {
      table[i] = static_cast<float>(
          255.0 * ToLinear(encoding.transfer, (i - black) / (white - black)) /
          sdr_white);
    }
  });
  return tables[key];
}

CodeFromLinearTable::CodeFromLinearTable(Transfer transfer) : codes_(kSize) {
  for (int i = 0; i < kSize; ++i) {
    const double s = static_cast<double>(i) / (kSize - 1);
    codes_[i] = static_cast<uint16_t>(
        std::lround(65535.0 * FromLinear(transfer, s * s)));
  }
}

uint16_t CodeFromLinearTable::operator()(float linear) const {
  const float s = std::sqrt(std::clamp(linear, 0.0f, 1.0f));
  // s >= 0: adding a half and truncating rounds, faster than lround per
  // pixel.
  const int index =
      static_cast<int>(s * (kSize - 1) + 0.5f);  // NOLINT(bugprone-*)
  return codes_[index];
}

SdrConverter::SdrConverter(const ColorEncoding& from, double white_linear)
    : to_linear_(65536), from_linear_(65536) {
  for (int i = 0; i < 65536; ++i) {
    to_linear_[i] =
        static_cast<float>(ToLinear(from.transfer, i / 65535.0) / white_linear);
    from_linear_[i] = static_cast<uint8_t>(
        std::lround(255.0 * FromLinear(Transfer::kSdr, i / 65535.0)));
  }
  mix_ = from.primaries == Primaries::kBt2020;
  bgr_from_bgr_ =
      mix_ ? InBgrOrder(Bt709FromBt2020()) : Eigen::Matrix3f::Identity();
}

cv::Mat SdrConverter::Convert(const cv::Mat& bgr16) const {
  CV_Assert(bgr16.type() == CV_16UC3);
  cv::Mat out(bgr16.size(), CV_8UC3);
  const auto code = [&](float linear) {
    // Non-negative: adding a half and truncating rounds (per pixel).
    const float scaled = std::clamp(linear, 0.0f, 1.0f) * 65535.0f;
    const int index = static_cast<int>(scaled + 0.5f);  // NOLINT(bugprone-*)
    return from_linear_[index];
  };
  for (int v = 0; v < bgr16.rows; ++v) {
    const auto* in = bgr16.ptr<cv::Vec3w>(v);
    auto* o = out.ptr<cv::Vec3b>(v);
    for (int u = 0; u < bgr16.cols; ++u) {
      Eigen::Vector3f linear(to_linear_[in[u][0]], to_linear_[in[u][1]],
                             to_linear_[in[u][2]]);
      if (mix_) linear = bgr_from_bgr_ * linear;
      o[u] = {code(linear[0]), code(linear[1]), code(linear[2])};
    }
  }
  return out;
}

cv::Mat ConvertFromSdr(const cv::Mat& bgr, const ColorEncoding& to) {
  CV_Assert(bgr.type() == CV_8UC3 || bgr.type() == CV_16UC3);
  const bool deep = bgr.depth() == CV_16U;
  const int levels = deep ? 65536 : 256;
  const double white = ReferenceWhiteLinear(to.transfer);
  std::vector<float> to_linear(levels);
  for (int i = 0; i < levels; ++i) {
    to_linear[i] = static_cast<float>(
        white *
        ToLinear(Transfer::kSdr, static_cast<double>(i) / (levels - 1)));
  }
  const bool mix = to.primaries == Primaries::kBt2020;
  const Eigen::Matrix3f mixing = mix ? InBgrOrder(Bt709FromBt2020().inverse())
                                     : Eigen::Matrix3f::Identity();
  static const CodeFromLinearTable kSdrTable(Transfer::kSdr),
      kHlgTable(Transfer::kHlg), kPqTable(Transfer::kPq);
  const CodeFromLinearTable& table = to.transfer == Transfer::kHlg  ? kHlgTable
                                     : to.transfer == Transfer::kPq ? kPqTable
                                                                    : kSdrTable;
  cv::Mat out(bgr.size(), CV_16UC3);
  cv::parallel_for_(cv::Range(0, bgr.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      auto* o = out.ptr<cv::Vec3w>(v);
      for (int u = 0; u < bgr.cols; ++u) {
        Eigen::Vector3f linear;
        for (int c = 0; c < 3; ++c) {
          linear[c] = to_linear[deep ? bgr.ptr<cv::Vec3w>(v)[u][c]
                                     : bgr.ptr<cv::Vec3b>(v)[u][c]];
        }
        if (mix) linear = mixing * linear;
        o[u] = {table(linear[0]), table(linear[1]), table(linear[2])};
      }
    }
  });
  return out;
}

}  // namespace softbench
