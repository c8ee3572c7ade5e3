#include "vision/color_transfer.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <vector>

#include "vision/luma.h"

namespace softbench {
namespace {

constexpr Transfer kTransfers[] = {Transfer::kSdr, Transfer::kHlg,
                                   Transfer::kPq};

// Within 1e-6 of the code range (a thousandth of a 10-bit code): PQ's code
// 0 is 7e-7 above linear 0, and HLG's published constants put code 1 a
// hair above linear 1.
TEST(ColorTransfer, LinearRoundTripsEveryTransfer) {
  for (const Transfer t : kTransfers) {
    for (double code = 0.0; code <= 1.0; code += 1.0 / 512) {
      EXPECT_NEAR(FromLinear(t, ToLinear(t, code)), code, 1e-6)
          << static_cast<int>(t) << " at " << code;
    }
  }
}

TEST(ColorTransfer, CurvesIncreaseEverywhere) {
  for (const Transfer t : kTransfers) {
    double last = -1.0;
    for (double code = 0.0; code <= 1.0; code += 1.0 / 1024) {
      const double linear = ToLinear(t, code);
      EXPECT_GT(linear, last) << static_cast<int>(t) << " at " << code;
      last = linear;
    }
  }
}

// The slope against central differences of the curve, on both sides of
// each curve's joint (SDR's linear toe at 0.018, HLG's square root below
// 1/12), and zero outside (0, 1) where the curve clamps.
TEST(ColorTransfer, SlopeIsTheCurvesDerivative) {
  for (const Transfer t : kTransfers) {
    for (const double linear :
         {1e-3, 0.01, 0.017, 0.019, 0.05, 0.08, 0.09, 0.2, 0.5, 0.9, 0.99}) {
      const double h = 1e-7 * linear;
      const double numeric =
          (FromLinear(t, linear + h) - FromLinear(t, linear - h)) / (2 * h);
      EXPECT_NEAR(FromLinearSlope(t, linear), numeric, 1e-6 * numeric)
          << static_cast<int>(t) << " at " << linear;
    }
    EXPECT_EQ(FromLinearSlope(t, 0.0), 0.0);
    EXPECT_EQ(FromLinearSlope(t, 1.2), 0.0);
  }
}

// Reference points of BT.2100 and BT.2408.
TEST(ColorTransfer, MatchesTheStandardsReferencePoints) {
  // HLG: the square-root segment ends at 1/12 -> 0.5; peak 1 -> 1.
  EXPECT_NEAR(FromLinear(Transfer::kHlg, 1.0 / 12.0), 0.5, 1e-12);
  EXPECT_NEAR(FromLinear(Transfer::kHlg, 1.0), 1.0, 1e-7);
  // SDR white is 75 % HLG and 203 cd/m² PQ (58 % code).
  EXPECT_NEAR(FromLinear(Transfer::kHlg, ReferenceWhiteLinear(Transfer::kHlg)),
              0.75, 1e-12);
  EXPECT_NEAR(FromLinear(Transfer::kPq, ReferenceWhiteLinear(Transfer::kPq)),
              0.58, 0.005);
  // PQ: 100 cd/m² -> 0.508, 10000 -> 1.
  EXPECT_NEAR(FromLinear(Transfer::kPq, 0.01), 0.508, 0.001);
  EXPECT_NEAR(FromLinear(Transfer::kPq, 1.0), 1.0, 1e-9);
  // BT.709: the linear segment's slope and the knee.
  EXPECT_NEAR(FromLinear(Transfer::kSdr, 0.01), 0.045, 1e-12);
  EXPECT_NEAR(FromLinear(Transfer::kSdr, 1.0), 1.0, 1e-12);
}

// BT.2087's matrix, and white stays white.
TEST(ColorTransfer, PrimariesMatrixMatchesBt2087AndKeepsWhite) {
  const Eigen::Matrix3d m = Bt709FromBt2020();
  Eigen::Matrix3d bt2087;
  bt2087 << 1.6605, -0.5876, -0.0728, -0.1246, 1.1329, -0.0083, -0.0182,
      -0.1006, 1.1187;
  EXPECT_LT((m - bt2087).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((m * Eigen::Vector3d::Ones() - Eigen::Vector3d::Ones()).norm(),
            1e-12);
}

// SDR colours written as HDR and read back as SDR come back within a
// level: HSV bounds tuned on SDR footage hold on HDR footage.
TEST(ColorTransfer, SdrThroughHdrAndBackKeepsEveryColour) {
  cv::Mat bgr(32, 32, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
  for (const ColorEncoding encoding :
       {ColorEncoding{Transfer::kHlg, Primaries::kBt2020},
        ColorEncoding{Transfer::kPq, Primaries::kBt2020},
        ColorEncoding{Transfer::kSdr, Primaries::kBt2020}}) {
    const cv::Mat hdr = ConvertFromSdr(bgr, encoding);
    ASSERT_EQ(hdr.type(), CV_16UC3);
    const cv::Mat back =
        SdrConverter(encoding, ReferenceWhiteLinear(encoding.transfer))
            .Convert(hdr);
    cv::Mat difference;
    cv::absdiff(back, bgr, difference);
    double worst = 0.0;
    cv::minMaxLoc(difference.reshape(1), nullptr, &worst);
    EXPECT_LE(worst, 1.0) << encoding.Name();
  }
}

// Footage graded brighter (its white at a higher level) reads as SDR with
// that level as white: the same colours, scaled.
TEST(ColorTransfer, WhiteLevelScalesTheLight) {
  const ColorEncoding hlg{Transfer::kHlg, Primaries::kBt709};
  const double white = ToLinear(Transfer::kHlg, 0.9);
  cv::Mat grey(1, 1, CV_16UC3, cv::Scalar::all(0.9 * 65535));
  EXPECT_NEAR(SdrConverter(hlg, white).Convert(grey).at<cv::Vec3b>(0)[1], 255,
              1);
  // With the white four times brighter, the grey is a quarter of white.
  EXPECT_NEAR(SdrConverter(hlg, 4 * white).Convert(grey).at<cv::Vec3b>(0)[1],
              255 * FromLinear(Transfer::kSdr, 0.25), 1);
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

// Deeper video's luma is read as decoded (LumaEncoding::deep_bits): its
// light and its levels must be those of the same codes scaled to fill 16
// bits, exactly, in limited range (BT.2100 scales black and white by 2^(bits
// - 8)); in full range white is the top code at every depth. Every 16-bit
// value has an entry, so no sample reads past the table.
TEST(LinearLumaTable, ReadsDecodedCodesAsTheirSixteenBitScaling) {
  for (const Transfer t : kTransfers) {
    const std::vector<float>& filled = LinearLumaTable({t, false, 16}, CV_16U);
    for (const int bits : {10, 12}) {
      const LumaEncoding decoded{t, false, bits};
      const std::vector<float>& table = LinearLumaTable(decoded, CV_16U);
      ASSERT_EQ(table.size(), 65536u);
      const int shift = 16 - bits;
      for (int code = 0; code < (1 << bits); ++code) {
        ASSERT_EQ(table[code], filled[code << shift])
            << static_cast<int>(t) << " " << bits << " bits, code " << code;
        ASSERT_EQ(LevelsPerCode(CV_16U, decoded) * code,
                  LevelsPerCode(CV_16U, {t, false, 16}) * (code << shift));
      }
      const float white =
          LinearLumaTable({t, true, bits}, CV_16U)[(1 << bits) - 1];
      EXPECT_FLOAT_EQ(white, LinearLumaTable({t, true, 16}, CV_16U)[65535]);
      EXPECT_FLOAT_EQ(white, LinearLumaTable({t, true}, CV_8U)[255]);
    }
  }
}

}  // namespace
}  // namespace softbench
