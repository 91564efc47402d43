/// \file
/// \brief The paper's "basic processing" on the device, in fixed point (codes x 256, "q8"):
/// dwell means, the cycle's rate and bias (paper eqn 7), compensation (eqn 12) and the
/// calibration of dN over K cycles (eqns 8-11) with its spread. Integer only; each result is
/// the host library's double result (gyroflip::method) rounded to q8, within 1 q8 (tested in
/// tests/firmware/test_core.cpp).
#pragma once

#include <stdint.h>

#include "firmware/protocol/messages.hpp"

namespace gyroflip::fw {

/// Mean of `n` codes summing to `sum`, x 256, rounded (n > 0). |sum| <= 2^23 n, so sum x 256
/// stays below 2^63 for any n up to 2^32.
[[nodiscard]] int32_t mean_q8(int64_t sum, uint32_t n);

/// One cycle: r = (y_A - y_B) / 2 and c = (y_A + y_B) / 2 (paper eqn 7), x 256, rounded.
struct cycle_q8 {
  int32_t rate_q8 = 0;
  int32_t bias_q8 = 0;
};
[[nodiscard]] cycle_q8 make_cycle(int32_t mean_a_q8, int32_t mean_b_q8);

/// dN = mean of r over K cycles and the sample standard deviation of r, from shifted sums
/// (d = r - r_1, so the sums stay small for a steady sensor): sum d < 2^40 and sum d^2 < 2^64
/// for K <= 65535 and |d| < 2^24 q8 (65 536 codes, ~1.5 deg/s for an ADXRS150). A larger spread
/// sets `saturated` and reports the spread as 0xFFFFFFFF.
class calibrator {
 public:
  void begin(uint16_t cycles);
  /// Adds one cycle's r; true when the K-th cycle arrived.
  bool add(int32_t rate_q8, uint8_t flags);
  [[nodiscard]] bool active() const { return target_ != 0 && n_ < target_; }
  [[nodiscard]] protocol::cal_result_msg result() const;
  void cancel() { target_ = 0; }

 private:
  uint16_t target_ = 0;
  uint16_t n_ = 0;
  int32_t first_ = 0;
  int64_t s1_ = 0;
  uint64_t s2_ = 0;
  bool saturated_ = false;
  uint8_t flags_ = 0;
};

}  // namespace gyroflip::fw
