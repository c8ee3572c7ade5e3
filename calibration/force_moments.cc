#include "calibration/force_moments.h"

namespace softbench {

void ForceMoments::Merge(const ForceMoments& other) {
  if (other.count == 0) return;
  if (count == 0) {
    *this = other;
    return;
  }
  const double n_a = static_cast<double>(count);
  const double n_b = static_cast<double>(other.count);
  const double n = n_a + n_b;
  const Eigen::Vector3d delta = other.mean - mean;
  comoment += other.comoment + (n_a * n_b / n) * delta * delta.transpose();
  mean += (n_b / n) * delta;
  count += other.count;
}

ForceMoments ForceMomentAccumulator::Moments() const {
  ForceMoments moments;
  if (count_ == 0) return moments;
  const double n = static_cast<double>(count_);
  const Eigen::Vector3d shift(shift_[0], shift_[1], shift_[2]);
  const Eigen::Vector3d sum(sum_[0], sum_[1], sum_[2]);
  Eigen::Matrix3d products;
  products << products_[0], products_[1], products_[2],  //
      products_[1], products_[3], products_[4],          //
      products_[2], products_[4], products_[5];
  moments.count = count_;
  moments.mean = shift + sum / n;
  moments.comoment = products - sum * sum.transpose() / n;
  return moments;
}

}  // namespace softbench
