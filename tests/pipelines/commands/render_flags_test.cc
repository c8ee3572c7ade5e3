#include "pipelines/commands/render_flags.h"

#include <gtest/gtest.h>

#include "util/input_error.h"

namespace softbench {
namespace {

TEST(RenderFlags, ParsesCameraBumps) {
  const CameraBump bump = ParseCameraBump("2.5:2,0.5,0.05");
  EXPECT_EQ(bump.time_s, 2.5);
  EXPECT_EQ(bump.shift_px, Eigen::Vector2d(2.0, 0.5));
  EXPECT_EQ(bump.roll_deg, 0.05);
  EXPECT_EQ(ParseCameraBump("4:1,-1").roll_deg, 0.0);
  for (const char* bad : {"4", "4:1", "x:1,2", "4:1,2,3,4"}) {
    EXPECT_THROW(ParseCameraBump(bad), InputError) << bad;
  }
}

TEST(RenderFlags, ParsesResolutions) {
  EXPECT_EQ(ParseResolution("4k"), cv::Size(3840, 2160));
  EXPECT_EQ(ParseResolution("1080x1920"), cv::Size(1080, 1920));
  for (const char* bad : {"", "1080", "1081x720", "8x8", "hd"}) {
    EXPECT_THROW(ParseResolution(bad), InputError) << bad;
  }
}

// --isp sets every stage of a phone's processing; a stage's own flag wins,
// including one that turns the stage off.
TEST(RenderFlags, IspPresetsEveryStageAndEachFlagWins) {
  RenderOptions none, isp, mixed;
  ApplyPhoneProcessing(PhoneProcessingFlags(), &none);
  EXPECT_EQ(none.lens_blur_px, 0.0);
  EXPECT_EQ(none.tone_curve, 0.0);
  EXPECT_EQ(none.local_tone, 0.0);
  EXPECT_EQ(TemporalDenoiseFromFlags(PhoneProcessingFlags()).strength, 0.0);
  EXPECT_EQ(none.sharpen_amount, 0.0);
  EXPECT_EQ(none.sensor.demosaic, Demosaic::kNone);
  EXPECT_FALSE(none.Problem());

  PhoneProcessingFlags flags;
  flags.isp = true;
  ApplyPhoneProcessing(flags, &isp);
  EXPECT_EQ(isp.lens_blur_px, 0.6);
  EXPECT_EQ(isp.tone_curve, 0.6);
  EXPECT_EQ(isp.local_tone, 0.3);
  EXPECT_EQ(TemporalDenoiseFromFlags(flags).strength, 0.5);
  EXPECT_EQ(isp.sharpen_radius_px, 1.0);
  EXPECT_EQ(isp.sharpen_amount, 0.8);
  EXPECT_EQ(isp.sensor.demosaic, Demosaic::kEdgeAware);
  EXPECT_EQ(isp.sensor.full_well_e, 6000.0);
  EXPECT_EQ(isp.sensor.read_noise_e, 2.0);
  EXPECT_FALSE(isp.Problem());

  flags.lens_blur_px = 0.0;
  flags.bayer = "bilinear";
  flags.sensor_full_well_e = 0.0;
  flags.sharpen = "2,0.3";
  flags.local_tone = 0.0;
  flags.temporal_denoise = 0.8;
  ApplyPhoneProcessing(flags, &mixed);
  EXPECT_EQ(mixed.lens_blur_px, 0.0);
  EXPECT_EQ(mixed.tone_curve, 0.6);
  EXPECT_EQ(mixed.sharpen_radius_px, 2.0);
  EXPECT_EQ(mixed.sharpen_amount, 0.3);
  EXPECT_EQ(mixed.sensor.demosaic, Demosaic::kBilinear);
  EXPECT_EQ(mixed.sensor.full_well_e, 0.0);
  EXPECT_EQ(mixed.sensor.read_noise_e, 0.0);
  EXPECT_EQ(mixed.local_tone, 0.0);
  EXPECT_EQ(TemporalDenoiseFromFlags(flags).strength, 0.8);
  EXPECT_FALSE(mixed.Problem());
}

TEST(RenderFlags, RefusesAPhoneStageItCannotRender) {
  RenderOptions scene;
  PhoneProcessingFlags flags;
  flags.bayer = "vng";
  EXPECT_THROW(ApplyPhoneProcessing(flags, &scene), InputError);
  flags.bayer.clear();
  flags.sharpen = "1";
  EXPECT_THROW(ApplyPhoneProcessing(flags, &scene), InputError);
  flags.sharpen.clear();
  flags.temporal_denoise = 1.0;  // the previous frame only: a frozen video
  EXPECT_THROW(TemporalDenoiseFromFlags(flags), InputError);
  flags.sensor_full_well_e = 5000.0;  // noise without a colour filter
  ApplyPhoneProcessing(flags, &scene);
  EXPECT_EQ(scene.Problem(),
            "the sensor's noise needs a colour filter (--bayer)");
}

}  // namespace
}  // namespace softbench
