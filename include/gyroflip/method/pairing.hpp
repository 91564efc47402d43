/// \file
/// \brief Dwells -> cycles with the `simple` (paper eqn 7) or `abba` pairing, in streaming
/// (`cycle_builder`) and batch (`pair_cycles`) forms that give bit-identical results.
///
/// Cycle j is formed from dwells 2j and 2j+1 (the first dwell may be at either position of the
/// pair). s_k is dwell k's sign: +1 at the pair's `plus` position (0 deg), -1 at `minus` (180
/// deg) (method/flip_pair.hpp).
/// - simple: r = s_a (y_a - y_b)/2, c = (y_a + y_b)/2 for the cycle's dwells a, b.
/// - abba: for every dwell k with neighbours on both sides, the opposite orientation is
///   linearly interpolated to t_k from dwells k-1 and k+1: yhat = y_{k-1} + (y_{k+1} -
///   y_{k-1}) (t_k - t_{k-1})/(t_{k+1} - t_{k-1}); then r_k = s_k (y_k - yhat)/2 and
///   c_k = (y_k + yhat)/2. A cycle's r and c are the mean of r_k, c_k over its dwells that
///   have both neighbours (the first dwell of the record and the last have not; such an
///   edge cycle is stamped with the time and temperature of its one usable dwell). Any bias
///   linear in time cancels exactly, whatever the dwell spacing (METHOD-NOTES.md).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

namespace detail {
/// A cycle value before it gets its time stamp: r and c.
struct estimate {
  double rate_dps = 0.0;
  double bias_dps = 0.0;
};
}  // namespace detail

class cycle_builder {
 public:
  /// Pairs dwells at the positions of `pair` (which the dwells must alternate between).
  explicit cycle_builder(pairing p, flip_pair pair = {}) noexcept : pairing_(p), pair_(pair) {}
  /// Adds the next dwell; returns a cycle once it is final.
  [[nodiscard]] std::optional<cycle> push(const dwell& d);
  /// End of data: returns the last cycle that still needed its right neighbour (abba).
  [[nodiscard]] std::optional<cycle> flush();

 private:
  pairing pairing_;
  flip_pair pair_;
  std::array<dwell, 3> last_{};  // last_[2] is the newest dwell
  std::size_t count_ = 0;        // dwells seen
  detail::estimate pending_{};   // abba: estimate at the first dwell of the open cycle
};

/// Batch form: the cycles of a dwell sequence. Dwells must alternate between the positions of
/// `pair`.
[[nodiscard]] std::vector<cycle> pair_cycles(std::span<const dwell> dwells, pairing p,
                                             flip_pair pair = {});

}  // namespace gyroflip::method
