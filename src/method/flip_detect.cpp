/// \file
/// \brief Flip-modulation test (see flip_detect.hpp).
#include "gyroflip/method/flip_detect.hpp"

#include <cassert>
#include <cmath>

namespace gyroflip::method {

flip_modulation detect_flip_modulation(std::span<const double> values,
                                       std::span<const double> angle_deg) {
  assert(values.size() == angle_deg.size());
  // Two passes per position: mean, then the variance around it (no cancellation).
  double sum[2] = {0.0, 0.0};
  std::size_t n[2] = {0, 0};
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (angle_deg[i] == 0.0 || angle_deg[i] == 180.0) {
      const int k = angle_deg[i] == 0.0 ? 0 : 1;
      sum[k] += values[i];
      ++n[k];
    }
  }
  flip_modulation out;
  out.n_0 = n[0];
  out.n_180 = n[1];
  if (n[0] < 2 || n[1] < 2) return out;
  const double mean[2] = {sum[0] / static_cast<double>(n[0]), sum[1] / static_cast<double>(n[1])};
  double ss[2] = {0.0, 0.0};
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (angle_deg[i] == 0.0 || angle_deg[i] == 180.0) {
      const int k = angle_deg[i] == 0.0 ? 0 : 1;
      ss[k] += (values[i] - mean[k]) * (values[i] - mean[k]);
    }
  }
  const double v0 = ss[0] / static_cast<double>(n[0] - 1);
  const double v1 = ss[1] / static_cast<double>(n[1] - 1);
  const double within = (ss[0] + ss[1]) / static_cast<double>(n[0] + n[1] - 2);
  const double diff = mean[0] - mean[1];
  const double se = std::sqrt(v0 / static_cast<double>(n[0]) + v1 / static_cast<double>(n[1]));
  out.mean_0 = mean[0];
  out.mean_180 = mean[1];
  out.modulated = std::abs(diff) > 10.0 * se && 0.25 * diff * diff > 0.01 * within;
  return out;
}

}  // namespace gyroflip::method
