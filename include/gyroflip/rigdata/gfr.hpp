/// \file
/// \brief The `.gfr` recording (docs/FORMATS.md, "Rig recording"): a 16-byte file header, then
/// append-only records, each length-prefixed and CRC-32 checked, written as they happen so that
/// whatever reached the file before a crash reads back. The writer appends and syncs, and writes
/// a second copy of each record the reading of the others depends on (META, INFO, CONFIGURE,
/// START, a reset or link GAP) 16 KiB further on (format 5). The reader checks every byte,
/// repairs a record with one flipped bit (CRC-32 locates it), ignores a torn last record (a
/// writer killed mid-write) and zeros at the end (a power loss), reads every intact record around
/// a damaged region, with a warning for each region it skips, and puts back a damaged record
/// from its copy.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::rigdata::gfr {

/// PNG-style magic: a non-ASCII first byte, then CR LF, ^Z and LF catch text-mode transfers.
inline constexpr std::array<std::uint8_t, 8> magic = {0x89, 'G', 'F', 'R', '\r', '\n', 0x1A, '\n'};
/// 6: every record's CRC-32 starts from the file's own id (record_crc_seed; the header's u16 at
/// offset 10, drawn at random when the file is made): a record of another recording (a block of
/// another .gfr spliced or written into this one) fails its CRC here and is read as damage, never
/// as this file's (fifth review of issue 32, F3). 5: COPY records (a second copy of the records
/// the others depend on). 4: INFO bodies carry
/// the device's `board` (a real board or an emulator; 3 and older: INFO of
/// protocol 2's first layout, 80 bytes, without it). 3: START records carry the CRC of the
/// configuration started (2: the device frame that acknowledged them only; 1: empty START
/// bodies; all read too).
inline constexpr std::uint16_t format_version = 6;
/// magic, u16 version, u16 file id (format 6; reserved, 0, before), u32 CRC-32 of the 12 bytes
/// before it.
inline constexpr std::size_t file_header_bytes = 16;
/// u32 length L (of kind, time and body), u32 L XOR 0xFFFFFFFF (a damaged length is told from a
/// record cut short: a cut removes bytes, it never changes them), u8 kind, u64 host time (us),
/// body, u32 CRC-32 of all that precedes it in the record (format 6: continued from the file's
/// record_crc_seed).
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
  copy = 8,       ///< u64 the file offset of the record it copies, u8 its kind, u64 its host
                  ///< time, its body (format 5; the reader puts a damaged original back from it)
};

/// A COPY record's body before the copied body: offset, kind, host time.
inline constexpr std::size_t copy_header_bytes = 8 + 1 + 8;
/// How far (bytes of the file) after its original the writer puts a copy: a damaged region
/// shorter than this (a 4 KiB page, a few sectors) never takes a record and its copy.
inline constexpr std::uint64_t copy_distance = 16 * 1024;

/// Whether the writer keeps a copy of a record of kind `k` with `body`: META, INFO, CONFIGURE,
/// START, and GAP records of a device reset or a lost port (what the reading of the others
/// depends on; docs/FORMATS.md).
[[nodiscard]] bool is_copied(kind k, std::span<const std::uint8_t> body) noexcept;

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
  /// The file could not take more (a full disk, a file size limit, a failing write): what the
  /// device sent after the last record is not in the file and is counted in the GAP (missing)
  /// before this record (issue 32; readers before it refuse this reason as unknown).
  disk_full = 6,
};

/// A record as read back.
struct record {
  kind type = kind::meta;
  std::uint64_t host_time_us = 0;  ///< microseconds since the recording started (host clock)
  std::vector<std::uint8_t> body;
  std::uint64_t offset = 0;  ///< where it starts in the file
  std::size_t number = 0;    ///< its number in the file (1: META); a restored one: its copy's
  bool repaired = false;     ///< one flipped bit was put right (its CRC-32 located it)
  bool restored = false;     ///< read from its COPY record (the original is damaged)
};

/// Bytes of the file between two records that are no record (damage the reader skipped).
struct damaged_region {
  std::uint64_t offset = 0;
  std::uint64_t bytes = 0;
  std::size_t before = 0;  ///< index in file::records of the first record after it
  /// The same region again: records were read in another order than the file's (records out of
  /// place), and what it held may belong both after the record before it and before the record
  /// after it; counted once.
  bool again = false;
};

/// Every record of a file plus what the reader noticed.
struct file {
  std::vector<record> records;          ///< in the order they were written (their host times)
  std::vector<std::string> warnings;    ///< `FILE: record N: ...`, e.g. a torn last record
  std::vector<damaged_region> damaged;  ///< in reading order, after repairs and restores
  std::size_t repaired = 0;             ///< records with one flipped bit put right
  std::size_t restored = 0;             ///< damaged records put back from their copies
  std::size_t repeats = 0;    ///< records dropped as exact repeats of one read before them
  std::size_t misplaced = 0;  ///< records out of place (their host time goes back), reordered
  std::uint16_t version = 0;  ///< the header's format version (0: header damaged)
  /// The file's id (format 6; 0 before): its records' CRC-32 start from record_crc_seed(file_id).
  /// With the header damaged beyond repair, the id its first intact record was found with.
  std::uint16_t file_id = 0;
};

/// Reads and checks a whole `.gfr` file. Errors name the file and the record (`FILE: record N:
/// what`; record 0 is the file header): not a regular file, not a recording (no magic and no
/// intact record), a newer format version, two recordings joined into one file, META damaged
/// with no copy. A record with one flipped bit anywhere (its length words, kind, time, body or
/// CRC) is repaired: CRC-32's single-bit syndromes are distinct for any record length up to
/// 2^32 bits, so the bit is located, never guessed; the record after it must then be intact. A
/// damaged file header is repaired the same way, or read past when intact records follow. Other
/// damage (several bits, zeros) is skipped up to the next intact record, with a warning that
/// names the record number and the bytes skipped, and a record damaged there is put back from
/// its COPY when the file has one. The writer appends in the order of its host clock (a steady
/// clock): a record that repeats one read before it (kind, host time and body: a block of the
/// file written twice) is dropped, and records whose host times go back (blocks of the file moved
/// or swapped) are read in the order of their host times, with a warning naming their offsets.
/// With `strict` any damage is an error instead.
[[nodiscard]] result<file> read(const std::string& path, bool strict = false);
/// The same from bytes in memory (`name` is used in messages): the fuzz target's entry.
[[nodiscard]] result<file> parse(std::span<const std::uint8_t> bytes, const std::string& name,
                                 bool strict = false);

/// Bytes the writer keeps free below a file size limit (RLIMIT_FSIZE, `ulimit -f`) for the records
/// that end a recording whose file is full: a GAP (26 bytes) and a STOP (22).
inline constexpr std::uint64_t end_reserve = 64;

/// Appends records to a new file. Each record goes to the kernel in one write as it is made, so
/// a killed writer loses nothing it appended; `sync` (fdatasync) makes it survive power loss. A
/// write that fails (a full disk, a file size limit) is cut back to the last whole record, so the
/// file never holds a torn record its writer did not die in, and what went before stays whole;
/// the room the torn part took may still hold the small records that end the file
/// (append_last). Under a file size limit the writer stops end_reserve bytes short of it (the
/// write fails with EFBIG, "File too large", as the kernel's would), so that those always fit.
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

  /// Appends one record (not a COPY: the writer makes those itself), then the copies that are
  /// due: each copied record (is_copied) again once copy_distance bytes follow it. Host times
  /// strictly increase: a record not later than the one before it is stamped a microsecond
  /// after it (its COPY records keep its time).
  [[nodiscard]] status append(kind k, std::uint64_t host_time_us,
                              std::span<const std::uint8_t> body);
  /// Appends one of the records that end a file whose writes failed (a GAP, the STOP): it may use
  /// the end_reserve bytes under a file size limit, and no COPY follows it. A failure is cut back
  /// like any other.
  [[nodiscard]] status append_last(kind k, std::uint64_t host_time_us,
                                   std::span<const std::uint8_t> body);
  [[nodiscard]] status sync();
  /// Writes the copies still due, syncs and closes. A copy the file has no room for (it filled up
  /// as it ended) is left out: the records are all in, and the reader needs no copy of an intact
  /// record.
  [[nodiscard]] status close();
  [[nodiscard]] std::uint64_t bytes() const noexcept { return bytes_; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

  /// One of the last records written: its kind and the first byte of its body (a FRAME's
  /// message type; 0 for an empty body).
  struct written_record {
    kind type = kind::meta;
    std::uint8_t first = 0;
  };
  /// The last record in the file, while it is one of the last tail_records written and not yet
  /// taken back; none otherwise.
  [[nodiscard]] std::optional<written_record> last_record() const;
  /// Takes the last record out of the file (cut back to where it began): the room the records
  /// that end a full file need, when the write failed with less free than they take and the
  /// writer did not know the limit (a full disk: ENOSPC; review of issue 32). The caller counts
  /// what it held. Fails when last_record() has none.
  [[nodiscard]] status take_back_last();
  /// Records last_record() can go back over.
  static constexpr std::size_t tail_records = 16;

 private:
  writer(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::string path_;
  // A record whose copy is still to be written (is_copied): its offset, kind, time and body.
  struct pending_copy {
    std::uint64_t offset = 0;
    kind type = kind::meta;
    std::uint64_t host_time_us = 0;
    std::vector<std::uint8_t> body;
  };
  [[nodiscard]] status write_record(kind k, std::uint64_t host_time_us,
                                    std::span<const std::uint8_t> body, bool last = false);
  [[nodiscard]] status write_copies(std::uint64_t host_time_us, bool all);
  std::uint64_t bytes_ = 0;
  std::uint64_t last_host_us_ = 0;
  std::uint64_t size_limit_ = UINT64_MAX;  // RLIMIT_FSIZE when the writer was made
  std::uint32_t crc_seed_ = 0;             // record_crc_seed of the header's file id (format 6)
  std::vector<std::uint8_t> buf_;
  std::vector<pending_copy> pending_;
  // The last records written (at most tail_records): where each began, and what it was.
  struct tail_entry {
    std::uint64_t offset = 0;
    written_record what;
  };
  std::vector<tail_entry> tail_;
};

/// CRC-32 (ISO-HDLC, zlib's) of `bytes`; with `seed`, continued from that CRC (zlib's crc32(seed,
/// ...): the CRC of what gave `seed` followed by `bytes`).
[[nodiscard]] std::uint32_t crc32(std::span<const std::uint8_t> bytes,
                                  std::uint32_t seed = 0) noexcept;
/// What the CRC-32 of each record of a format-6 file with id `file_id` is continued from: the
/// CRC-32 of the id's two bytes (little-endian). Two ids give two seeds (CRC-32 is one-to-one
/// on two-byte messages), and a record checked with another seed fails for any length (the CRC
/// register's step is invertible), so it is read as damage. Never 0 for an id the writer draws.
[[nodiscard]] std::uint32_t record_crc_seed(std::uint16_t file_id) noexcept;

}  // namespace gyroflip::rigdata::gfr
