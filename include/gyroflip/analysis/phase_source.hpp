/// \file
/// \brief The phase (angle) series x_0..x_{N-1} of a sample source, rebuilt on demand in blocks,
/// so that no deviation needs the whole phase in memory (`gyroflip adev` on 1e9 samples).
///
/// Rate samples y_i (deg/s) give x_k = tau0 sum_{i<k} (y_i - ybar), k = 0..M (NIST SP1065 eqn 1
/// with the mean removed, which no deviation depends on, so that x stays small): N = M + 1
/// points for M samples. The phase is cut into blocks of `block_samples` points; within block b
/// the sum runs in double from 0, on top of the block's long-double carry
/// c_b = sum_{i<b L} (y_i - ybar) split into two doubles base + base_err:
/// x_{bL+j} = (base + (part_j + base_err)) tau0. `make` reads the samples once (per block the sum,
/// and the running sums about a provisional mean, corrected exactly afterwards) and keeps per block
/// the carry and the block's phase sum (for MDEV's exact restarts): 32 bytes per 1024 samples (31
/// MB at 1e9). A `phase_reader` then rebuilds any range of x from the carries and the samples,
/// bit-identically wherever it starts. Angle samples are the phase itself (x_k = sample k, N = M):
/// only the block sums are kept.
///
/// Does not compute deviations (allan.hpp) and does not read files (io::series::samples()).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::analysis {

class phase_reader;

class phase_source {
 public:
  /// Phase points per carry block.
  static constexpr std::size_t block_points = 1024;
  /// Input range: samples of magnitude up to this, sample intervals within [min_tau0_s,
  /// max_tau0_s]. Within it no sum, square or EDF of any deviation overflows (a phase point is at
  /// most 1e100 x 1e9 s x 1e12 samples, its square 1e242), so every result is finite; beyond it
  /// `make` refuses the series rather than compute inf (docs/FORMATS.md, "Series").
  static constexpr double max_sample_magnitude = max_input_magnitude;
  static constexpr double min_tau0_s = 1e-9;
  static constexpr double max_tau0_s = 1e9;

  /// Prepares the phase of `samples` (which must outlive the source and every reader). Reads
  /// all samples once, on all cores. Errors: tau0 not
  /// positive and finite; a non-finite sample ("sample K (0-based) is not finite"); rate
  /// samples whose block sums overflow.
  [[nodiscard]] static result<phase_source> make(const sample_source& samples, input_kind in,
                                                 double tau0_s,
                                                 const progress_fn& on_progress = {});

  /// Number of phase points N.
  [[nodiscard]] std::size_t size() const noexcept { return n_phase_; }
  [[nodiscard]] double tau0_s() const noexcept { return tau0_s_; }
  [[nodiscard]] input_kind kind() const noexcept { return kind_; }
  [[nodiscard]] const sample_source& samples() const noexcept { return *samples_; }
  /// Rate input: the mean ybar of the samples, which the phase has removed (0 for angle input).
  [[nodiscard]] double rate_mean() const noexcept { return mean_; }
  /// Bytes held by the per-block tables (the memory bound besides the readers' buffers).
  [[nodiscard]] std::size_t table_bytes() const noexcept;

  /// sum_{k=begin}^{end-1} (x_k - x_0) in long double: whole blocks from the stored block sums,
  /// the partial blocks at either end through `reader`. Used for MDEV's exact restarts, where the
  /// x_0 terms cancel; subtracting x_0 keeps an angle series with a large offset accurate.
  [[nodiscard]] long double offset_sum(std::size_t begin, std::size_t end,
                                       phase_reader& reader) const;

  /// Rate input: writes the whole phase x[0, N) to `out` (size() doubles) in one pass over the
  /// samples, on all cores (each thread first-touches the pages it writes); the same bits as a
  /// phase_reader reads. Angle input: copies the samples.
  void build(std::span<double> out) const;
  /// The phase `x` that build() wrote (x.size() == size()) as angle input with this source's
  /// block sums, without a pass over x: what make(x, angle, tau0) gives, but for the rounding of
  /// the block sums (those of the rate samples here, so MDEV's restarts are the rate source's).
  [[nodiscard]] phase_source built(const sample_source& x) const;

 private:
  friend class phase_reader;
  phase_source(const sample_source& samples, input_kind in, double tau0_s) noexcept;
  status prepare_rate(const progress_fn& on_progress);
  status prepare_angle(const progress_fn& on_progress);
  [[nodiscard]] std::size_t blocks() const noexcept;
  /// Writes x over block b's first `count` points to out (rate input).
  void rebuild(std::size_t b, std::size_t count, double* out) const noexcept;
  /// Writes four whole blocks b..b+3 to out (rate input), their running sums side by side.
  void rebuild4(std::size_t b, double* out) const noexcept;

  const sample_source* samples_;
  input_kind kind_;
  double tau0_s_;
  std::size_t n_phase_ = 0;
  double mean_ = 0.0;             ///< ybar (rate)
  std::vector<double> base_;      ///< per block: the carry rounded to double (rate)
  std::vector<double> err_;       ///< per block: carry - base (rate)
  std::vector<long double> sum_;  ///< per block: sum of (x_k - x_0) over the block
  double x0_ = 0.0;               ///< x_0
};

/// Reads ranges of a phase source into its own buffer (rate input) or as a view of the samples
/// (angle input). Use one reader per thread and stream: a read that continues the last one or
/// overlaps it moving forward rebuilds only the new blocks, four at a time so that their running
/// sums overlap in the CPU; a read elsewhere restarts at its block (at most block_points - 1
/// extra points). Consumed samples are handed back to the sample source (`release`) every
/// `release_step()` samples, so a mapped file stays mostly non-resident, unless `hand_back` is
/// false: then whoever drives several readers over the same samples releases them once all have
/// passed (a released page that another reader maps again costs a page fault). The buffer holds
/// at most 2 (len + 2 block_points) doubles for reads of at most len points.
class phase_reader {
 public:
  explicit phase_reader(const phase_source& source, bool hand_back = true) noexcept
      : src_(&source), hand_back_(hand_back) {}
  phase_reader(const phase_reader&) = delete;
  phase_reader& operator=(const phase_reader&) = delete;
  phase_reader(phase_reader&& other) noexcept;
  phase_reader& operator=(phase_reader&&) = delete;
  ~phase_reader();

  /// x[begin, begin + len) (begin + len <= size()); valid until the next call on this reader.
  [[nodiscard]] std::span<const double> read(std::size_t begin, std::size_t len);
  /// Doubles held in the buffer (0 for angle input).
  [[nodiscard]] std::size_t capacity() const noexcept { return buf_.size(); }

 private:
  void make_room(std::size_t begin, std::size_t need);
  void generate(std::size_t need);
  void consumed(std::size_t begin, std::size_t end) noexcept;
  void flush() noexcept;

  const phase_source* src_;
  bool hand_back_;
  std::vector<double> buf_;
  std::size_t base_ = 0;           ///< phase index of buf_[0]
  std::size_t end_ = 0;            ///< x[base_, end_) is in buf_ (end_ at a block boundary or N)
  std::size_t pending_begin_ = 0;  ///< consumed samples not yet released
  std::size_t pending_end_ = 0;
};

/// The phase of rate samples as one array (N = M + 1 points, deg): every x_k of a phase source
/// on a span. NaN everywhere for non-finite samples or tau0. Used by the tests and the
/// calibration's correlated standard error.
[[nodiscard]] std::vector<double> phase_from_rate(std::span<const double> rate, double tau0_s);

}  // namespace gyroflip::analysis
