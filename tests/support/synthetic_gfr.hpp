/// \file
/// \brief `.gfr` recordings made record by record as the recorder writes them (issue 32), and the
/// damage trials of docs/RELIABILITY.md: single flipped bits and zeroed regions, each read back
/// and compared dwell by dwell with the undamaged file. Used by tests/rigdata and by
/// bench/gfr_recovery.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/messages.hpp"
#include "gyroflip/rigdata/gfr.hpp"

namespace gyroflip::test {

/// What the synthetic recording holds. Records come in the order host/recorder/recorder.cpp
/// appends them: META, INFO, the ACKs of STOP and CONFIGURE, CONFIGURE, the ACK of START, START,
/// then DWELLs and a STATUS every `status_period_s`; a reset is GAP (reset), the new boot's
/// STATUS, its INFO, CONFIGURE with cfg_home, START; a lost port is GAP (link lost).
struct synthetic_options {
  std::uint32_t tick_hz = 32768;
  double dwell_s = 0.9;          ///< device time from one dwell's start to the next
  std::size_t dwells = 400;      ///< DWELLs the device sends in all
  std::uint32_t first_tick = 0;  ///< the device clock at the first dwell
  std::uint16_t first_seq = 0;   ///< the device's first sequence number
  double status_period_s = 1.0;
  /// Device seconds per host second (an emulator at --speed: the host's clock, which stamps the
  /// records, runs this many times slower than the device's).
  double device_speed = 1.0;
  std::vector<std::size_t> resets_after;  ///< the device restarts after these dwells
  /// Device seconds from a reset to the new boot's first STATUS (its boot, the host's PINGs)
  double restart_s = 0.0;
  /// Device seconds from the START after a reset to its first dwell (homing, turn, settle)
  double homing_s = 2.0;
  std::vector<std::size_t> link_losses_after;  ///< the port is lost after these dwells
  /// Dwells lost on the line, counted by a GAP (missing) record: never in the file.
  std::vector<std::size_t> lost;
  /// Every this many dwells one arrives late (RESEND): stored after the next one (0: none).
  std::size_t late_every = 37;
  /// The last this many dwells before each reset are held (a transmitter held by CTS, or sent
  /// again on RESEND) and arrive only at the reset, together; STATUS frames keep arriving.
  std::size_t held_before_reset = 0;
  /// The first this many dwells after each reset are held and arrive after the next one.
  std::size_t held_after_reset = 0;
  std::uint32_t serial = 4711;
  /// true: written by the library's writer (the current format, with COPY records); false: a
  /// file of format 4 as recorders before it wrote (no COPY records).
  bool copies = true;
  std::uint64_t seed = 1;  ///< the dwells' values
};

/// A dwell the device sent, as the test knows it.
struct synthetic_dwell {
  std::size_t boot = 0;  ///< which device boot (0: the first)
  std::uint16_t seq = 0;
  std::uint32_t cycle = 0;
  std::uint8_t position = 0;
  double angle_deg = 0.0;
  double device_s = 0.0;  ///< its start on the device's clock, from the first dwell, unwrapped
  /// Its start on a clock that runs on through resets (the rig's own time; the device's clock
  /// restarts at a reset), from the start of the recording.
  double through_s = 0.0;
};

struct synthetic_recording {
  std::vector<std::uint8_t> bytes;
  std::vector<synthetic_dwell> dwells;  ///< every dwell in the file, in the order sent
};

/// Makes the recording; `path` is where the library's writer puts it (copies = true), also
/// written for copies = false.
[[nodiscard]] synthetic_recording make_synthetic_recording(const synthetic_options& o,
                                                           const std::string& path);

/// A message's payload as the device encodes it.
template <class M>
[[nodiscard]] std::vector<std::uint8_t> payload_of(const M& m) {
  std::uint8_t b[protocol::max_payload];
  protocol::writer w{b, sizeof b};
  m.put(w);
  return std::vector<std::uint8_t>(b, b + w.n);
}

/// One record as a recorder of format 4 wrote it (length, its complement, kind, time, body,
/// CRC-32), and a file header of `version`.
[[nodiscard]] std::vector<std::uint8_t> encode_record(rigdata::gfr::kind k, std::uint64_t host_us,
                                                      const std::vector<std::uint8_t>& body);
[[nodiscard]] std::vector<std::uint8_t> encode_file_header(std::uint16_t version);

/// Damage trials on one recording: each damaged copy read back (gfr::parse + interpret) and
/// compared with the undamaged one, dwell by dwell. A dwell is *intact* when some FRAME record
/// holding it has no damaged byte; it is *recovered* when the damaged file's reading has it with
/// the same angle, rate and temperature; a dwell the damaged reading has with another angle,
/// rate or temperature, or that the undamaged reading has not, is *mislabelled*.
struct damage_tally {
  std::size_t trials = 0;
  std::size_t unreadable = 0;  ///< trials whose file did not read at all
  std::size_t intact = 0;
  std::size_t recovered = 0;
  std::size_t mislabelled = 0;
  std::size_t repeated = 0;  ///< dwells the damaged reading has more than once
  /// Dwells the damaged reading times outside the undamaged reading's span (first to last dwell)
  std::size_t beyond_span = 0;
  /// Dwells the damaged reading counts as lost on the line beyond the undamaged reading's count
  /// and the dwells whose records the damage touched (a claim "never arrived" that is false)
  std::size_t false_lost = 0;
  double max_time_shift_s = 0.0;   ///< largest |time_s| change of a recovered dwell
  std::string max_time_shift_at;   ///< the trial that had it
  std::vector<std::string> notes;  ///< what went wrong in which trial (first few)
};

/// `flips` trials of one flipped bit each, at positions drawn from `seed`.
void flip_trials(const std::vector<std::uint8_t>& file, std::size_t flips, std::uint64_t seed,
                 damage_tally& t);
/// `regions` trials of one zeroed region each, 1 to `max_bytes` long, at offsets from `seed`.
void zero_trials(const std::vector<std::uint8_t>& file, std::size_t regions, std::size_t max_bytes,
                 std::uint64_t seed, damage_tally& t);
/// `trials` trials of one block of 1 to `max_bytes` bytes written twice (repeated right after
/// itself, as bench/gfr_recovery --dups): a dwell is intact unless its record holds the whole
/// block and more on both sides (bytes repeated inside it).
void repeat_trials(const std::vector<std::uint8_t>& file, std::size_t trials, std::size_t max_bytes,
                   std::uint64_t seed, damage_tally& t);
/// `trials` trials of two blocks of equal length (512 to `max_bytes` bytes) exchanged: a dwell
/// is intact when its record lies wholly inside or wholly outside each block.
void swap_trials(const std::vector<std::uint8_t>& file, std::size_t trials, std::size_t max_bytes,
                 std::uint64_t seed, damage_tally& t);

/// `trials` trials of a block of `other` - another recording: another run, boot or board, its
/// numbers and times alike - of 1 to `max_bytes` bytes (never its file header) put into `file`:
/// inserted, or with `overwrite` written over file's bytes there (fifth review of issue 32, F3).
/// Even trials cut the block from `other` and put it into `file` at record boundaries, odd ones
/// at any byte. A dwell of `file` is intact unless the block cuts its record (inserted inside it)
/// or covers a byte of it; a dwell of `other` the reading uses is mislabelled (the undamaged
/// reading has no such dwell).
void splice_trials(const std::vector<std::uint8_t>& file, const std::vector<std::uint8_t>& other,
                   std::size_t trials, std::size_t max_bytes, std::uint64_t seed, bool overwrite,
                   damage_tally& t);

}  // namespace gyroflip::test
