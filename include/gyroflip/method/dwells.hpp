/// \file
/// \brief Rows -> dwells: streaming (`dwell_builder`) and batch (`extract_dwells`) forms.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// Accumulates rows into dwells. A row at table_moving (the table turning) is skipped and does
/// not end the dwell; a change of position does. Rows must be validated already (a position of
/// their table, finite values, n_avg >= 1).
class dwell_builder {
 public:
  /// Adds a row; returns the dwell that this row completed, if any. Inline: this runs once
  /// per recorded conversion, and the common case is a plain accumulation.
  [[nodiscard]] std::optional<dwell> push(const row& r) {
    if (r.position < 0) return std::nullopt;  // table turning: row skipped
    if (r.position != position_) return start(r, r.position);
    add(r);
    return std::nullopt;
  }
  /// Returns the last, open dwell (end of data), if any.
  [[nodiscard]] std::optional<dwell> flush();

 private:
  [[nodiscard]] dwell close() const;
  [[nodiscard]] std::optional<dwell> start(const row& r, int position);
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
  int position_ = table_moving;  // table_moving: no open dwell
  double sum_w_ = 0.0;
  double sum_t_ = 0.0;
  double sum_y_ = 0.0;
  double sum_temp_ = 0.0;
  double sum_w_temp_ = 0.0;
};

/// Batch form of dwell_builder: all dwells of `rows`, in order.
[[nodiscard]] std::vector<dwell> extract_dwells(std::span<const row> rows);
/// The dwells the 0/180 demodulators see: those of the rows at `pair`'s positions (rows at other
/// positions are passed over as rows taken while the table turns; flip_stream does the same).
[[nodiscard]] std::vector<dwell> extract_dwells(std::span<const row> rows, const flip_pair& pair);

}  // namespace gyroflip::method
