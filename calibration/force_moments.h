#ifndef SOFTBENCH_CALIBRATION_FORCE_MOMENTS_H_
#define SOFTBENCH_CALIBRATION_FORCE_MOMENTS_H_

#include <Eigen/Core>
#include <cstdint>

namespace softbench {

// Centred first and second moments of force-log samples x = (P [MPa],
// F_axial [N], F_shear [N]): everything a linear least-squares fit needs from
// a group of rows whose actuator configuration is the same, since within one
// configuration every model is an affine function of P (model.md, "Fitting
// the constants"). Merging follows Chan et al.'s pairwise update, so sums of
// millions of rows never subtract two large numbers.
struct ForceMoments {
  int64_t count = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  // Sum over rows of (x - mean)(x - mean)^T.
  Eigen::Matrix3d comoment = Eigen::Matrix3d::Zero();

  void Merge(const ForceMoments& other);
};

// Streams rows into ForceMoments: sums are kept relative to the group's first
// row (the shifted-data algorithm), which is as careful as Welford's update
// for data of this kind and needs no division per row.
class ForceMomentAccumulator {
 public:
  void Add(double pressure_mpa, double axial_n, double shear_n) {
    if (count_ == 0) {
      shift_[0] = pressure_mpa;
      shift_[1] = axial_n;
      shift_[2] = shear_n;
    }
    const double d0 = pressure_mpa - shift_[0];
    const double d1 = axial_n - shift_[1];
    const double d2 = shear_n - shift_[2];
    ++count_;
    sum_[0] += d0;
    sum_[1] += d1;
    sum_[2] += d2;
    products_[0] += d0 * d0;
    products_[1] += d0 * d1;
    products_[2] += d0 * d2;
    products_[3] += d1 * d1;
    products_[4] += d1 * d2;
    products_[5] += d2 * d2;
  }
  int64_t count() const { return count_; }
  ForceMoments Moments() const;

 private:
  int64_t count_ = 0;
  double shift_[3] = {0.0, 0.0, 0.0};
  double sum_[3] = {0.0, 0.0, 0.0};
  double products_[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
};

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_FORCE_MOMENTS_H_
