/// \file
/// \brief Rows -> dwells: streaming (`dwell_builder`) and batch (`extract_dwells`) forms.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// Accumulates rows into dwells. A row whose angle is NaN (table turning) is skipped and
/// does not end the dwell; a change of orientation does. Rows must be validated already
/// (angle 0 or 180, finite values, n_avg >= 1).
class dwell_builder {
 public:
  /// Adds a row; returns the dwell that this row completed, if any.
  [[nodiscard]] std::optional<dwell> push(const row& r);
  /// Returns the last, open dwell (end of data), if any.
  [[nodiscard]] std::optional<dwell> flush();

 private:
  [[nodiscard]] dwell close() const;
  int sign_ = 0;  // 0: no open dwell
  double sum_w_ = 0.0;
  double sum_t_ = 0.0;
  double sum_y_ = 0.0;
  double sum_temp_ = 0.0;
  double sum_w_temp_ = 0.0;
};

/// The sign (+1 at 0 deg, -1 at 180 deg) of a validated angle.
[[nodiscard]] constexpr int sign_of_angle(double angle_deg) noexcept {
  return angle_deg < 90.0 ? 1 : -1;
}

/// Batch form of dwell_builder: all dwells of `rows`, in order.
[[nodiscard]] std::vector<dwell> extract_dwells(std::span<const row> rows);

}  // namespace gyroflip::method
