#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_BAYER_SENSOR_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_BAYER_SENSOR_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace softbench {

// How the two colours a Bayer pixel does not see are filled in.
enum class Demosaic {
  kNone,       // no colour filter: every pixel sees all three (the default)
  kBilinear,   // each missing colour the mean of its nearest neighbours
  kEdgeAware,  // interpolated along edges rather than across them
};

// A phone's sensor behind an RGGB colour filter array (issue 28): each
// pixel records one channel of the light, with shot and read noise, and the
// camera's processing interpolates the other two.
struct BayerSensorOptions {
  Demosaic demosaic = Demosaic::kNone;
  // Electrons at white (full scale): shot noise, Poisson in the electrons
  // counted, as a Gaussian of variance equal to the count; 0 is none. A
  // phone's small pixels hold a few thousand.
  double full_well_e = 0.0;
  double read_noise_e = 0.0;  // Gaussian, per pixel [electrons]

  std::optional<std::string> Problem() const;
};

// Parses "bilinear" or "edge-aware" (the render command's --bayer).
std::optional<Demosaic> ParseDemosaic(const std::string& name);

// `light` (CV_32FC3 BGR, linear, 1 = the sensor's full scale) as the sensor
// records it and demosaicing restores it: the RGGB mosaic (red at even rows
// and columns, blue at odd ones), clipped at full scale, noised (seeded by
// `seed`), quantised to 16 bits and demosaiced by OpenCV. Returns CV_32FC3 in
// the same units.
cv::Mat ThroughBayerSensor(const cv::Mat& light,
                           const BayerSensorOptions& options, uint64_t seed);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_BAYER_SENSOR_H_
