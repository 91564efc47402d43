/// \file
/// \brief Rows -> dwells: streaming (`dwell_builder`) and batch (`extract_dwells`) forms.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// The sign (+1 at 0 deg, -1 at 180 deg) of a validated angle.
[[nodiscard]] constexpr int sign_of_angle(double angle_deg) noexcept {
  return angle_deg < 90.0 ? 1 : -1;
}

/// Accumulates rows into dwells. A row whose angle is NaN (table turning) is skipped and
/// does not end the dwell; a change of orientation does. Rows must be validated already
/// (angle 0 or 180, finite values, n_avg >= 1).
class dwell_builder {
 public:
  /// Adds a row; returns the dwell that this row completed, if any. Inline: this runs once
  /// per recorded conversion, and the common case is a plain accumulation.
  [[nodiscard]] std::optional<dwell> push(const row& r) {
    if (r.angle_deg != r.angle_deg) return std::nullopt;  // NaN: table turning, row skipped
    const int s = sign_of_angle(r.angle_deg);
    if (s != sign_) return start(r, s);
    add(r);
    return std::nullopt;
  }
  /// Returns the last, open dwell (end of data), if any.
  [[nodiscard]] std::optional<dwell> flush();

 private:
  [[nodiscard]] dwell close() const;
  [[nodiscard]] std::optional<dwell> start(const row& r, int s);
  void add(const row& r) {
    const double w = static_cast<double>(r.n_avg);
    sum_w_ += w;
    sum_t_ += w * r.time_s;
    sum_y_ += w * r.rate_dps;
    if (r.temp_c == r.temp_c) {  // not NaN
      sum_temp_ += w * r.temp_c;
      sum_w_temp_ += w;
    }
  }
  int sign_ = 0;  // 0: no open dwell
  double sum_w_ = 0.0;
  double sum_t_ = 0.0;
  double sum_y_ = 0.0;
  double sum_temp_ = 0.0;
  double sum_w_temp_ = 0.0;
};

/// Batch form of dwell_builder: all dwells of `rows`, in order.
[[nodiscard]] std::vector<dwell> extract_dwells(std::span<const row> rows);

}  // namespace gyroflip::method
