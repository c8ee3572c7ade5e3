// SceneRenderer's frames: the scene drawn in linear light, moved by the
// camera, then exposed, noised and encoded as the camera's codes.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "pipelines/synthetic/pixel_grid.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "util/check.h"
#include "vision/color_transfer.h"

namespace softbench {

cv::Mat SceneRenderer::RenderLinear(
    const std::vector<Eigen::VectorXd>& displacement_samples,
    bool tag_visible) const {
  const cv::Mat& background =
      tag_visible ? background_ : background_without_tag_;
  if (displacement_samples.size() == 1) {
    cv::Mat image = background.clone();
    DrawMoving(displacement_samples[0], &image);
    return image;
  }
  cv::Mat sum = cv::Mat::zeros(background_.size(), CV_32FC3), image;
  for (const Eigen::VectorXd& sample : displacement_samples) {
    background.copyTo(image);
    DrawMoving(sample, &image);
    sum += image;
  }
  return sum / static_cast<double>(displacement_samples.size());
}

cv::Mat SceneRenderer::Moved(const cv::Mat& linear,
                             const FrameConditions& conditions) const {
  // Each pixel of the moved camera looks along a ray that the still camera
  // saw at (distorted) pixel Distort(H^-1 n): sample the still frame there.
  // Bilinear in float, not cv::remap, whose coordinates are fixed-point
  // (1/32 px) and would quantise sub-pixel motion. H is the motion when the
  // pixel's line was read.
  const auto inverse = [](const std::vector<CameraMotion>& motions) {
    std::vector<Eigen::Matrix3d> h;
    for (const CameraMotion& m : motions) {
      h.emplace_back(m.CurrentFromReference().inverse());
    }
    return h;
  };
  const std::vector<Eigen::Matrix3d> by_row = inverse(conditions.row_motion);
  const std::vector<Eigen::Matrix3d> by_column =
      inverse(conditions.column_motion);
  const Eigen::Matrix3d whole =
      conditions.motion.CurrentFromReference().inverse();
  // Lines are the video's: a sensor finer than the video reads each video
  // line's sensor lines together.
  const int scale = options_.sensor_scale;
  SOFTBENCH_CHECK((by_row.empty() ||
                   static_cast<int>(by_row.size()) * scale == linear.rows) &&
                  (by_column.empty() ||
                   static_cast<int>(by_column.size()) * scale == linear.cols))
      << "a rolling shutter's motion per line must cover every line";
  const PixelGrid& grid = *pixels_;
  cv::Mat moved(linear.size(), CV_32FC3);
  cv::parallel_for_(cv::Range(0, linear.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      auto* out = moved.ptr<cv::Vec3f>(v);
      for (int u = 0; u < linear.cols; ++u) {
        const Eigen::Matrix3d& reference_from_current =
            !by_row.empty()      ? by_row[v / scale]
            : !by_column.empty() ? by_column[u / scale]
                                 : whole;
        const Eigen::Vector3d n =
            reference_from_current * grid.At(u, v).homogeneous();
        const Eigen::Vector2d src = sensor_camera_.Distort(n.head<2>() / n.z());
        const double x = std::clamp(src.x(), 0.0, linear.cols - 1.0);
        const double y = std::clamp(src.y(), 0.0, linear.rows - 1.0);
        const int x0 = std::min(static_cast<int>(x), linear.cols - 2);
        const int y0 = std::min(static_cast<int>(y), linear.rows - 2);
        const float a = static_cast<float>(x - x0),
                    b = static_cast<float>(y - y0);
        const auto* r0 = linear.ptr<cv::Vec3f>(y0) + x0;
        const auto* r1 = linear.ptr<cv::Vec3f>(y0 + 1) + x0;
        out[u] = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) +
                 b * ((1 - a) * r1[0] + a * r1[1]);
      }
    }
  });
  return moved;
}

namespace {

// Local tone mapping (RenderOptions::local_tone) on the light, BGR, 1 = white.
void ApplyLocalTone(double strength, cv::Mat* light) {
  // The luma's log on a coarse grid: the phone's tone map is computed small
  // and applied through interpolation, so it varies smoothly and follows
  // the scene's content frame by frame.
  constexpr int kCellsDown = 32;
  const int cell = std::max(1, light->rows / kCellsDown);
  cv::Mat luma;
  cv::transform(*light, luma, cv::Matx13f(0.0722f, 0.7152f, 0.2126f));
  cv::Mat coarse;
  cv::resize(luma, coarse,
             cv::Size(std::max(1, light->cols / cell),
                      std::max(1, light->rows / cell)),
             0, 0, cv::INTER_AREA);
  cv::max(coarse, 1e-4, coarse);
  cv::log(coarse, coarse);
  cv::GaussianBlur(coarse, coarse, cv::Size(), 1.5, 1.5, cv::BORDER_REPLICATE);
  // log gain = -s (log luma - log 0.18), within log(1/4)..log(4).
  const double log_grey = std::log(0.18), limit = std::log(4.0);
  cv::Mat log_gain = (coarse - log_grey) * -strength;
  cv::min(cv::max(log_gain, -limit), limit, log_gain);
  cv::Mat gain;
  cv::resize(log_gain, gain, light->size(), 0, 0, cv::INTER_LINEAR);
  cv::exp(gain, gain);
  light->forEach<cv::Vec3f>(
      [&](cv::Vec3f& l, const int* at) { l *= gain.at<float>(at[0], at[1]); });
}

}  // namespace

cv::Mat SceneRenderer::Render(
    const std::vector<Eigen::VectorXd>& displacement_samples,
    int64_t frame_index, const FrameConditions& conditions) const {
  cv::Mat linear = RenderLinear(displacement_samples, conditions.tag_visible);
  if (conditions.motion.rotation_rad != Eigen::Vector3d::Zero() ||
      conditions.motion.scale != 1.0 || !conditions.row_motion.empty() ||
      !conditions.column_motion.empty()) {
    linear = Moved(linear, conditions);
  }
  if (options_.lens_blur_px > 0.0) {
    cv::GaussianBlur(linear, linear, cv::Size(),
                     options_.lens_blur_px * options_.sensor_scale);
  }
  const cv::Vec3f exposure =
      conditions.channel_gain * static_cast<float>(conditions.brightness);
  // The light on the sensor, 1 = its full scale (white).
  cv::Mat light(linear.size(), CV_32FC3);
  light.forEach<cv::Vec3f>([&](cv::Vec3f& out, const int* at) {
    const float g = gain_.at<float>(at[0], at[1]);
    const cv::Vec3f& in = linear.at<cv::Vec3f>(at[0], at[1]);
    for (int c = 0; c < 3; ++c) out[c] = in[c] * g * exposure[c] / 255.0f;
  });
  if (options_.sensor.demosaic != Demosaic::kNone) {
    light = ThroughBayerSensor(
        light, options_.sensor,
        options_.seed * 0x9E3779B97F4A7C15ULL + 2 * frame_index + 1);
  }
  if (options_.sensor_scale > 1) {
    // The phone's scaler: each video pixel the mean of its sensor pixels.
    const CameraIntrinsics& k = camera_.intrinsics();
    cv::resize(light, light, cv::Size(k.width_px, k.height_px), 0, 0,
               cv::INTER_AREA);
  }
  if (options_.local_tone > 0.0) ApplyLocalTone(options_.local_tone, &light);
  static const CodeFromLinearTable kBt709Table(Transfer::kSdr);
  // The camera's codes (8-bit levels) before noise: the BT.709 curve, then
  // the phone's own tone curve.
  cv::Mat codes(light.size(), CV_32FC3);
  const float k = static_cast<float>(options_.tone_curve);
  codes.forEach<cv::Vec3f>([&](cv::Vec3f& code, const int* at) {
    const cv::Vec3f& l = light.at<cv::Vec3f>(at[0], at[1]);
    for (int c = 0; c < 3; ++c) {
      // Scaled in one step without a tone curve, so the bundled samples
      // re-render to the same bytes (scripts/make_samples.sh --check).
      const float bt709 = kBt709Table(l[c]);
      if (k == 0.0f) {
        code[c] = bt709 * (255.0f / 65535.0f);
      } else {
        const float x = bt709 / 65535.0f;
        code[c] = 255.0f * ((1 - k) * x + k * x * x * (3 - 2 * x));
      }
    }
  });
  if (options_.sharpen_amount > 0.0) {
    cv::Mat soft;
    cv::GaussianBlur(codes, soft, cv::Size(), options_.sharpen_radius_px);
    cv::addWeighted(codes, 1.0 + options_.sharpen_amount, soft,
                    -options_.sharpen_amount, 0.0, codes);
  }
  cv::Mat out(light.size(), options_.sixteen_bit ? CV_16UC3 : CV_8UC3);
  // Fixed stripes, each with its own seeded generator: the same frame for any
  // number of threads.
  constexpr int kStripes = 32;
  cv::parallel_for_(cv::Range(0, kStripes), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const int begin = light.rows * s / kStripes;
      const int end = light.rows * (s + 1) / kStripes;
      cv::RNG rng(options_.seed * 0x9E3779B97F4A7C15ULL +
                  static_cast<uint64_t>(frame_index) * kStripes + s + 1);
      cv::Mat noise(end - begin, light.cols, CV_32FC3);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
      for (int v = begin; v < end; ++v) {
        const auto* in = codes.ptr<cv::Vec3f>(v);
        const auto* n = noise.ptr<cv::Vec3f>(v - begin);
        auto* o8 = out.ptr<cv::Vec3b>(v);
        auto* o16 = out.ptr<cv::Vec3w>(v);
        for (int u = 0; u < light.cols; ++u) {
          for (int c = 0; c < 3; ++c) {
            // Noise in codes, after the phone's processing.
            const float signal = in[u][c];
            const float sigma =
                std::sqrt(static_cast<float>(options_.noise_sigma_dn *
                                             options_.noise_sigma_dn) +
                          static_cast<float>(options_.shot_noise_dn) *
                              std::max(signal, 0.0f));
            const float level = signal + sigma * n[u][c];
            if (options_.sixteen_bit) {
              o16[u][c] = cv::saturate_cast<uint16_t>(level * 257.0f);
            } else {
              o8[u][c] = cv::saturate_cast<uint8_t>(level);
            }
          }
        }
      }
    }
  });
  return out;
}

}  // namespace softbench
