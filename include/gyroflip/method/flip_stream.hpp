/// \file
/// \brief Streaming rows -> estimates: feed rows one at a time, get each estimate (cycle) as soon
/// as it is final, from any demodulator (method/demodulator.hpp). For the 0/180 schemes it gives
/// the same numbers as `extract_dwells` + `pair_cycles` (tested bit for bit). The live recorder
/// and the firmware use this form. Rows at table positions the demodulator does not use are
/// passed over as rows taken while the table turns.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/dwells.hpp"
#include "gyroflip/method/pairing.hpp"

namespace gyroflip::method {

class flip_stream {
 public:
  /// A 0/180 scheme (`simple`, `abba`) on the two positions of `pair`.
  explicit flip_stream(pairing p, flip_pair pair = {})
      : flip_stream(make_flip_demodulator(p, pair)) {}
  /// Any demodulator (make_demodulator).
  explicit flip_stream(std::unique_ptr<demodulator> d) noexcept
      : demod_(std::move(d)), uses_(demod_->uses()), per_row_(demod_->dwell_per_row()) {}

  /// Adds a validated row; calls `sink(const cycle&)` for each estimate it completes.
  template <class Sink>
  void push(const row& r, Sink&& sink) {
    // Turning, or at a position the demodulator does not use (positions are < 32: the table
    // holds at most position_table::max_positions).
    if (r.position < 0 || ((uses_ >> static_cast<unsigned>(r.position)) & 1u) == 0) {
      if (r.position != table_moving && r.position != last_off_) {
        ++off_pair_;
        last_off_ = r.position;
      }
      if (per_row_ && r.position == table_moving)
        if (auto d = dwells_.flush()) take(*d, sink);
      return;
    }
    last_off_ = table_moving;
    if (per_row_ && r.n_avg > 1) {  // a dwell row (demodulator::dwell_per_row)
      if (auto d = dwells_.flush()) take(*d, sink);
      take(dwell{r.position, r.time_s, r.rate_dps, r.temp_c, r.n_avg}, sink);
      return;
    }
    if (auto d = dwells_.push(r)) take(*d, sink);
  }

  /// End of data: emits the estimates still held back.
  template <class Sink>
  void flush(Sink&& sink) {
    if (auto d = dwells_.flush()) take(*d, sink);
    while (auto c = demod_->flush()) sink(*c);
  }

  /// Dwells seen at table position `position` so far (0 for positions not used).
  [[nodiscard]] std::size_t dwells_at(int position) const noexcept {
    return position >= 0 && static_cast<std::size_t>(position) < counts_.size()
               ? counts_[static_cast<std::size_t>(position)]
               : 0;
  }
  /// Dwells the demodulator took so far.
  [[nodiscard]] std::size_t dwells() const noexcept { return dwells_total_; }
  /// Stays at positions the demodulator does not use so far (runs of rows at one such position).
  [[nodiscard]] std::size_t dwells_off_pair() const noexcept { return off_pair_; }
  [[nodiscard]] const demodulator& demod() const noexcept { return *demod_; }
  /// Also append each dwell's rate, in order, to `out` (the dwells the demodulator pairs: a
  /// run's content print, method/cycle_print.hpp); nullptr: not kept.
  void keep_dwell_rates(std::vector<double>* out) noexcept { dwell_rates_ = out; }

 private:
  template <class Sink>
  void take(const dwell& d, Sink& sink) {
    ++counts_[static_cast<std::size_t>(d.position)];
    ++dwells_total_;
    if (dwell_rates_ != nullptr && ((uses_ >> static_cast<unsigned>(d.position)) & 1U) != 0U)
      dwell_rates_->push_back(d.rate_dps);
    if (auto c = demod_->push(d)) sink(*c);
  }
  std::unique_ptr<demodulator> demod_;
  std::uint32_t uses_ = 0;
  bool per_row_ = false;
  int last_off_ = table_moving;
  std::size_t off_pair_ = 0;
  dwell_builder dwells_;
  std::array<std::size_t, position_table::max_positions> counts_{};
  std::size_t dwells_total_ = 0;
  std::vector<double>* dwell_rates_ = nullptr;
};

}  // namespace gyroflip::method
