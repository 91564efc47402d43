/// \file
/// \brief The `.gfr` recording (docs/FORMATS.md, "Rig recording"): a 16-byte file header, then
/// append-only records, each length-prefixed and CRC-32 checked, written as they happen so that
/// whatever reached the file before a crash reads back. The writer appends and syncs; the reader
/// checks every byte, ignores a torn last record (a writer killed mid-write) and zeros at the end
/// (a power loss), and reads every intact record around a damaged region, with a warning for
/// each region it skips.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::rigdata::gfr {

/// PNG-style magic: a non-ASCII first byte, then CR LF, ^Z and LF catch text-mode transfers.
inline constexpr std::array<std::uint8_t, 8> magic = {0x89, 'G', 'F', 'R', '\r', '\n', 0x1A, '\n'};
/// 4: INFO bodies carry the device's `board` (a real board or an emulator; 3 and older: INFO of
/// protocol 2's first layout, 80 bytes, without it). 3: START records carry the CRC of the
/// configuration started (2: the device frame that acknowledged them only; 1: empty START
/// bodies; all read too).
inline constexpr std::uint16_t format_version = 4;
/// magic, u16 version, u16 reserved (0), u32 CRC-32 of the 12 bytes before it.
inline constexpr std::size_t file_header_bytes = 16;
/// u32 length L (of kind, time and body), u32 L XOR 0xFFFFFFFF (a damaged length is told from a
/// record cut short: a cut removes bytes, it never changes them), u8 kind, u64 host time (us),
/// body, u32 CRC-32 of all that precedes it in the record.
inline constexpr std::size_t record_overhead = 4 + 4 + 1 + 8 + 4;
/// The largest body a record may have (a META of a long command line fits many times).
inline constexpr std::size_t max_body = std::size_t{1} << 20;

/// What a record holds (docs/FORMATS.md has each body byte by byte).
enum class kind : std::uint8_t {
  meta = 1,       ///< JSON: host metadata and the conversion of device units (first record)
  info = 2,       ///< the device's INFO payload as received
  configure = 3,  ///< a CONFIGURE payload the device acknowledged
  start = 4,      ///< a START the device acknowledged: u16 the sequence number of its ACK frame
                  ///< (the run's frames follow it), u16 the CRC of its configuration
                  ///< (protocol::configure_crc; format 2: no CRC; format 1: empty body)
  frame = 5,      ///< u8 type, u16 seq, payload: a valid device frame as received
  gap = 6,        ///< u8 gap_reason, u32 count: what was lost or happened between frames
  stop = 7,       ///< u8 stop_reason: the recorder ended the run (the file is complete)
};

enum class gap_reason : std::uint8_t {
  corrupt = 1,       ///< frames dropped by the decoder (COBS, length, CRC, version, type)
  missing = 2,       ///< frames given up: the device no longer holds them (count), or owed
                     ///< when it restarted
  device_reset = 3,  ///< the device restarted (an INFO unasked, or STATUS: another boot count,
                     ///< its uptime back, idle mid-run); count = 0
  link_lost = 4,     ///< the port failed (an unplugged adapter); count = ms until it came back
};

enum class stop_reason : std::uint8_t {
  duration = 1,        ///< the requested duration was recorded
  signal = 2,          ///< SIGINT or SIGTERM
  link_lost = 3,       ///< the port did not come back in time
  device_changed = 4,  ///< another device (another serial) answered after a reconnect
  device_failed = 5,   ///< the device could not be started again after a reset (format 3)
};

/// A record as read back.
struct record {
  kind type = kind::meta;
  std::uint64_t host_time_us = 0;  ///< microseconds since the recording started (host clock)
  std::vector<std::uint8_t> body;
};

/// Every record of a file plus what the reader noticed.
struct file {
  std::vector<record> records;
  std::vector<std::string> warnings;  ///< `FILE: record N: ...`, e.g. a torn last record
};

/// Reads and checks a whole `.gfr` file. Errors name the file and the record (`FILE: record N:
/// what`; record 0 is the file header): not a regular file, wrong magic, a newer format
/// version, two recordings joined into one file. A damaged region (a flipped bit, a damaged
/// length, an unknown kind) is skipped up to the next intact record, with a warning that names
/// the record number and the bytes skipped; with `strict` it is an error instead.
[[nodiscard]] result<file> read(const std::string& path, bool strict = false);
/// The same from bytes in memory (`name` is used in messages): the fuzz target's entry.
[[nodiscard]] result<file> parse(std::span<const std::uint8_t> bytes, const std::string& name,
                                 bool strict = false);

/// Appends records to a new file. Each record goes to the kernel in one write as it is made, so
/// a killed writer loses nothing it appended; `sync` (fdatasync) makes it survive power loss.
class writer {
 public:
  /// Creates `path` (never replacing an existing file: a recording is never overwritten) and
  /// writes the file header.
  [[nodiscard]] static result<writer> create(const std::string& path);
  writer(writer&& o) noexcept;
  writer& operator=(writer&& o) noexcept;
  writer(const writer&) = delete;
  writer& operator=(const writer&) = delete;
  ~writer();

  [[nodiscard]] status append(kind k, std::uint64_t host_time_us,
                              std::span<const std::uint8_t> body);
  [[nodiscard]] status sync();
  [[nodiscard]] status close();
  [[nodiscard]] std::uint64_t bytes() const noexcept { return bytes_; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

 private:
  writer(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::string path_;
  std::uint64_t bytes_ = 0;
  std::vector<std::uint8_t> buf_;
};

/// CRC-32 (ISO-HDLC, zlib's) of `bytes`.
[[nodiscard]] std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept;

}  // namespace gyroflip::rigdata::gfr
