/// \file
/// \brief Reading and appending `.gfr` recordings (gfr.hpp, docs/FORMATS.md).
#include "gyroflip/rigdata/gfr.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>
#include <unordered_map>
#include <utility>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::rigdata::gfr {

namespace {

constexpr std::size_t npos_index = static_cast<std::size_t>(-1);

void put_u16(std::vector<std::uint8_t>& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}
void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& b, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// The little-endian unsigned integer of `bytes` (1..8) bytes at `p`.
std::uint64_t load_le(const std::uint8_t* p, int bytes) noexcept {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

std::vector<std::uint8_t> file_header(std::uint16_t file_id) {
  std::vector<std::uint8_t> h(magic.begin(), magic.end());
  put_u16(h, format_version);
  put_u16(h, file_id);
  put_u32(h, crc32(h));
  return h;
}

bool known_kind(std::uint8_t k) {
  return k >= static_cast<std::uint8_t>(kind::meta) && k <= static_cast<std::uint8_t>(kind::copy);
}

error at_record(const std::string& name, std::size_t n, const std::string& what) {
  return input_error({name}, fmt::format("record {}: {}", n, what));
}

// A failed write or sync of the recording: a full disk (or a failing one) is a condition of the
// run (exit 1), not of what the user asked for.
error write_error(const std::string& path, const std::string& what, int err) {
  const std::string m = what + std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EIO || err == EFBIG)
    return runtime_error(path + ": " + m);
  return io_error(path, m);
}

}  // namespace

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t seed) noexcept {
  uLong c = seed;
  // zlib takes uInt lengths: feed in pieces below 4 GiB.
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min<std::size_t>(bytes.size() - done, std::size_t{1} << 30);
    c = ::crc32(c, bytes.data() + done, static_cast<uInt>(n));
    done += n;
  }
  return static_cast<std::uint32_t>(c);
}

std::uint32_t record_crc_seed(std::uint16_t file_id) noexcept {
  const std::array<std::uint8_t, 2> id = {static_cast<std::uint8_t>(file_id),
                                          static_cast<std::uint8_t>(file_id >> 8)};
  return crc32(id);
}

namespace {

// CRC-32's table (reflected polynomial 0xEDB88320, zlib's): the register's step over one byte.
constexpr std::array<std::uint32_t, 256> crc_table = [] {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}();

// The bit of `n` message bytes (byte index x 8 + bit, LSB first) whose flip changes the CRC-32 by
// `syndrome`, if one does. CRC-32 is linear: crc(m ^ e) ^ crc(m) is the register run over `e`
// from 0 without the final inversion, which for one set bit is the table entry of its byte
// followed by a zero byte per byte after it. The polynomial's order is 2^32 - 1, so no two bits
// of a message shorter than 2^32 bits share a syndrome (a record is at most 1 MiB).
std::optional<std::size_t> flipped_bit(std::size_t n, std::uint32_t syndrome) {
  std::array<std::uint32_t, 8> r{};
  for (std::size_t b = 0; b < 8; ++b) r[b] = crc_table[std::size_t{1} << b];
  for (std::size_t j = n; j-- > 0;) {
    for (std::size_t b = 0; b < 8; ++b)
      if (r[b] == syndrome) return j * 8 + b;
    for (auto& x : r) x = crc_table[x & 0xFFU] ^ (x >> 8);
  }
  return std::nullopt;
}

// The one bit of a checked block (`n` message bytes, then its stored little-endian CRC-32) whose
// flip explains a CRC mismatch `syndrome` (computed ^ stored), if one does: a bit of the stored
// CRC itself (a syndrome of one bit), else one of the message.
std::optional<std::size_t> bit_to_repair(std::size_t n, std::uint32_t syndrome) {
  if (std::popcount(syndrome) == 1)
    return n * 8 + static_cast<std::size_t>(std::countr_zero(syndrome));
  return flipped_bit(n, syndrome);
}

// A record found at an offset: its whole length (length words, kind, time, body, CRC), and the
// bit (from its start) that was flipped, when it was repaired.
struct found {
  std::size_t whole = 0;
  std::optional<std::size_t> bit;
};

// The record at `at`: intact, or with `repair` one whose single flipped bit its CRC locates (a
// bit of a length word too: the other word gives the length). Else whole = 0.
found record_at(std::span<const std::uint8_t> b, std::size_t at, bool repair, std::uint32_t seed) {
  const std::size_t left = b.size() - at;
  if (left < record_overhead) return {};
  const auto l0 = static_cast<std::uint32_t>(load_le(b.data() + at, 4));
  const auto l1 = static_cast<std::uint32_t>(load_le(b.data() + at + 4, 4) ^ 0xFFFFFFFFU);
  const bool agree = l0 == l1;
  if (!agree && (!repair || std::popcount(l0 ^ l1) != 1)) return {};
  for (const std::uint32_t len : {l0, l1}) {
    if (len < 9 || len - 9 > max_body) continue;
    const std::size_t whole = static_cast<std::size_t>(len) + 12;
    if (whole > left) continue;
    const auto rec = b.subspan(at, whole);
    const auto stored = static_cast<std::uint32_t>(load_le(rec.data() + whole - 4, 4));
    const std::uint32_t syndrome = crc32(rec.first(whole - 4), seed) ^ stored;
    if (syndrome == 0) {
      if (agree && known_kind(rec[8])) return {whole, std::nullopt};
      continue;
    }
    if (!repair) continue;
    const auto bit = bit_to_repair(whole - 4, syndrome);
    if (!bit) continue;
    // The bit must explain everything found: the disagreeing length words (it lies in one of
    // them), or nothing there when they agree; and the record it gives must be of a known kind.
    const bool in_length = *bit < 64;
    if (in_length == agree) continue;
    std::uint8_t kind_byte = rec[8];
    if (*bit / 8 == 8) kind_byte = static_cast<std::uint8_t>(kind_byte ^ (1U << (*bit % 8)));
    if (!known_kind(kind_byte)) continue;
    return {whole, bit};
  }
  return {};
}

bool all_zero(std::span<const std::uint8_t> b) {
  return std::all_of(b.begin(), b.end(), [](std::uint8_t v) { return v == 0; });
}

// Whether what follows a repaired record is what follows a record: the end, zeros to the end,
// or another record (intact or itself repairable).
bool followed_well(std::span<const std::uint8_t> b, std::size_t at, std::uint32_t seed) {
  if (at >= b.size() || all_zero(b.subspan(at))) return true;
  return record_at(b, at, true, seed).whole != 0;
}

// The seed of the first intact record after a file header damaged beyond repair: 0 (formats
// 1-5) or a format-6 file's record_crc_seed(id), the id found by trying each (a record's CRC-32
// continued from a seed is the seed's CRC run over its bytes combined with its own: zlib's
// crc32_combine). `id` 0 for a file of no id. None when no intact record follows. The ids are
// tried on the first few places that look like a record (agreeing length words, a known kind):
// every place would cost 2^16 tries each (a file of such places took seconds to refuse); beyond
// them only records of no id (seed 0) are looked for.
std::optional<std::pair<std::uint32_t, std::uint16_t>> seed_after_lost_header(
    std::span<const std::uint8_t> b) {
  constexpr int places_tried = 4;
  int tried = 0;
  for (std::size_t at = file_header_bytes; at + record_overhead <= b.size(); ++at) {
    const auto l0 = static_cast<std::uint32_t>(load_le(b.data() + at, 4));
    const auto l1 = static_cast<std::uint32_t>(load_le(b.data() + at + 4, 4) ^ 0xFFFFFFFFU);
    if (l0 != l1 || l0 < 9 || l0 - 9 > max_body || l0 + std::size_t{12} > b.size() - at ||
        !known_kind(b[at + 8]))
      continue;
    const auto rec = b.subspan(at, std::size_t{l0} + 8);
    const auto stored = static_cast<std::uint32_t>(load_le(rec.data() + rec.size(), 4));
    const std::uint32_t plain = crc32(rec);
    if (plain == stored) return std::pair{std::uint32_t{0}, std::uint16_t{0}};
    if (tried++ >= places_tried) continue;
    const uLong op = ::crc32_combine_gen(static_cast<z_off_t>(rec.size()));
    for (std::uint32_t id = 1; id <= 0xFFFFU; ++id) {
      const std::uint32_t seed = record_crc_seed(static_cast<std::uint16_t>(id));
      if (::crc32_combine_op(seed, plain, op) == stored)
        return std::pair{seed, static_cast<std::uint16_t>(id)};
    }
  }
  return std::nullopt;
}

// Where this file's records go on after the header of another recording at `at`: an intact
// file header of format 6 with another id than this file's (format 6) starts a block of another
// recording inside this one when this file's own records follow it (review of issue 32, fifth
// pass, F3). 0: none (two files joined, `cat a.gfr b.gfr`, or this file's own header again).
std::size_t other_files_block_end(std::span<const std::uint8_t> b, std::size_t at, const file& out,
                                  std::uint32_t seed) {
  if (out.version < 6 || b.size() - at < file_header_bytes) return 0;
  const auto h = b.subspan(at, file_header_bytes);
  if (crc32(h.first(12)) != static_cast<std::uint32_t>(load_le(h.data() + 12, 4)) ||
      load_le(h.data() + 8, 2) < 6 || load_le(h.data() + 10, 2) == out.file_id)
    return 0;
  for (std::size_t next = at + file_header_bytes; next < b.size(); ++next)
    if (record_at(b, next, false, seed).whole != 0) return next;
  return 0;
}

// The file header: checked, or repaired (one flipped bit), or - when it is beyond repair but
// intact records follow - read past. `version` 0 when it cannot be trusted.
status read_file_header(std::span<const std::uint8_t> b, const std::string& name, file& out,
                        std::uint32_t& seed) {
  const bool magic_ok =
      b.size() >= magic.size() && std::memcmp(b.data(), magic.data(), magic.size()) == 0;
  if (magic_ok && b.size() < file_header_bytes)
    return at_record(
        name, 0,
        fmt::format("the file header is cut short ({} of {} bytes)", b.size(), file_header_bytes));
  std::array<std::uint8_t, file_header_bytes> h{};
  if (b.size() >= file_header_bytes) {
    std::copy_n(b.begin(), file_header_bytes, h.begin());
    const std::uint32_t syndrome =
        crc32(std::span(h).first(12)) ^ static_cast<std::uint32_t>(load_le(h.data() + 12, 4));
    if (syndrome != 0) {
      if (const auto bit = bit_to_repair(12, syndrome)) {
        h[*bit / 8] = static_cast<std::uint8_t>(h[*bit / 8] ^ (1U << (*bit % 8)));
        if (std::memcmp(h.data(), magic.data(), magic.size()) == 0) {
          out.warnings.push_back(
              fmt::format("{}: record 0: one flipped bit of the file header (offset {}) repaired",
                          name, *bit / 8));
          ++out.repaired;
          out.version = static_cast<std::uint16_t>(load_le(h.data() + 8, 2));
          out.file_id = static_cast<std::uint16_t>(load_le(h.data() + 10, 2));
        }
      }
    } else if (magic_ok) {
      out.version = static_cast<std::uint16_t>(load_le(h.data() + 8, 2));
      out.file_id = static_cast<std::uint16_t>(load_le(h.data() + 10, 2));
    }
  }
  if (out.version != 0) {
    if (out.version > format_version)
      return at_record(name, 0,
                       fmt::format("format version {} is newer than this gyroflip reads "
                                   "({}): update gyroflip",
                                   out.version, format_version));
    // Before format 6 the id's bytes were reserved (0): records checked from 0.
    if (out.version < 6) out.file_id = 0;
    seed = out.version >= 6 ? record_crc_seed(out.file_id) : 0;
    return ok();
  }
  // Beyond repair: a recording whose first bytes are damaged still has its records (some
  // intact one: the chance that other bytes pass a record's length check and CRC-32 is 2^-64;
  // with 2^16 ids tried, 2^-48), and the first one tells the file's id.
  const auto found_seed = seed_after_lost_header(b);
  if (found_seed) {
    seed = found_seed->first;
    out.file_id = found_seed->second;
  }
  if (!found_seed) {
    if (!magic_ok)
      return at_record(name, 0,
                       "not a gyroflip rig recording (the file does not start with the "
                       ".gfr magic bytes)");
    if (b.size() >= file_header_bytes && load_le(b.data() + 8, 2) == 0)
      return at_record(name, 0, "format version 0 does not exist");
    return at_record(name, 0, "file header checksum mismatch (the file is damaged)");
  }
  out.warnings.push_back(fmt::format(
      "{}: record 0: the file header is damaged beyond repair; its records are read (the format "
      "version is told by them)",
      name));
  return ok();
}

// A COPY record's original, when its body holds one.
std::optional<record> original_of(const record& c) {
  if (c.body.size() < copy_header_bytes) return std::nullopt;
  const std::uint8_t k = c.body[8];
  if (!known_kind(k) || static_cast<kind>(k) == kind::copy) return std::nullopt;
  record r;
  r.offset = load_le(c.body.data(), 8);
  r.type = static_cast<kind>(k);
  r.host_time_us = load_le(c.body.data() + 9, 8);
  r.body.assign(c.body.begin() + copy_header_bytes, c.body.end());
  r.number = c.number;
  r.restored = true;
  return r;
}

// Puts back, from their COPY records, the records of damaged regions; checks the copies of
// intact ones; drops the COPY records; and finds the damaged regions left (bytes no record
// covers).
void merge_copies(file& out, const std::string& name, std::size_t end) {
  std::vector<record> copies;
  std::vector<record> recs;
  for (auto& r : out.records) (r.type == kind::copy ? copies : recs).push_back(std::move(r));
  // The bytes each record read covers, the copies' own included.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> spans;
  for (const auto& r : recs)
    spans.emplace_back(r.offset, r.offset + record_overhead + r.body.size());
  for (const auto& c : copies)
    spans.emplace_back(c.offset, c.offset + record_overhead + c.body.size());
  std::sort(spans.begin(), spans.end());
  const auto covered_by_record = [&](std::uint64_t o) {
    return std::any_of(recs.begin(), recs.end(), [&](const record& r) { return r.offset == o; });
  };
  std::vector<record> put_back;
  for (const auto& c : copies) {
    auto o = original_of(c);
    if (!o) {
      out.warnings.push_back(fmt::format(
          "{}: record {}: a COPY record that holds no record; ignored", name, c.number));
      continue;
    }
    const auto same = std::find_if(recs.begin(), recs.end(),
                                   [&](const record& r) { return r.offset == o->offset; });
    // A record of another kind where the original stood: bytes before it were cut out and the
    // records after the cut moved up (review of issue 32, fifth pass, finding 2). The original
    // is displaced, not disagreeing: put back below when it is not read elsewhere.
    const bool moved_up = same != recs.end() && same->type != o->type;
    if (same != recs.end() && !moved_up) {
      if (same->host_time_us != o->host_time_us || same->body != o->body)
        out.warnings.push_back(
            fmt::format("{}: record {}: the COPY of record {} differs from it; the record is read",
                        name, c.number, same->number));
      continue;
    }
    // The original lies in bytes no record read covers (a damaged region), or where other
    // records were read (a block of the file moved there), and is not read intact elsewhere (a
    // block moved, or bytes repeated before it: its offset changed).
    const std::uint64_t o_end = o->offset + record_overhead + o->body.size();
    const bool in_file = o->offset >= file_header_bytes && o_end <= end;
    const bool inside_damage =
        in_file && std::none_of(spans.begin(), spans.end(), [&](const auto& s) {
          return s.first < o_end && o->offset < s.second;
        });
    const bool read_elsewhere = std::any_of(recs.begin(), recs.end(), [&](const record& r) {
      return r.host_time_us == o->host_time_us && r.type == o->type && r.body == o->body;
    });
    if (!in_file || read_elsewhere || (covered_by_record(o->offset) && !moved_up) ||
        std::any_of(put_back.begin(), put_back.end(),
                    [&](const record& r) { return r.offset == o->offset; })) {
      if (!in_file && !read_elsewhere)
        out.warnings.push_back(fmt::format(
            "{}: record {}: a COPY of a record at offset {}, outside the records read; ignored",
            name, c.number, o->offset));
      continue;
    }
    out.warnings.push_back(
        fmt::format("{}: record {}: the {} record at offset {} ({}) is put back from its copy",
                    name, c.number, inside_damage ? "damaged" : "displaced", o->offset,
                    o->type == kind::meta ? "META" : "a record the others depend on"));
    put_back.push_back(std::move(*o));
  }
  out.restored = put_back.size();
  for (auto& r : put_back) {
    spans.emplace_back(r.offset, r.offset + record_overhead + r.body.size());
    recs.push_back(std::move(r));
  }
  // A record put back where another now stands came before it (that one moved up from later).
  std::sort(recs.begin(), recs.end(), [](const record& a, const record& b) {
    return a.offset != b.offset ? a.offset < b.offset : a.restored && !b.restored;
  });
  std::sort(spans.begin(), spans.end());
  // Damaged regions: bytes between the header and `end` that no record covers.
  out.damaged.clear();
  std::uint64_t at = file_header_bytes;
  for (const auto& [lo, hi] : spans) {
    if (lo > at) {
      const auto next =
          std::lower_bound(recs.begin(), recs.end(), lo,
                           [](const record& r, std::uint64_t o) { return r.offset < o; });
      out.damaged.push_back({at, lo - at, static_cast<std::size_t>(next - recs.begin())});
    }
    at = std::max(at, hi);
  }
  out.records = std::move(recs);
}

// Records in the order the writer appended them. The writer's host clock is a steady clock, so
// host times never go back in a file as written: a record that repeats one read before it (the
// same kind, host time and body) is a block written twice, and is read once; records whose host
// times go back are out of place (blocks moved or swapped), and are read in the order of their
// host times. A damaged region among records out of place may have held records of both of its
// neighbours' places: it stands after the one before it and before the one after it.
void put_in_order(file& out, const std::string& name) {
  auto& recs = out.records;
  const auto body_hash = [](const record& r) {
    return (std::uint64_t{crc32(r.body)} << 32) ^ r.host_time_us ^
           (std::uint64_t{static_cast<std::uint8_t>(r.type)} << 56);
  };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> seen;
  std::vector<std::size_t> kept_before(recs.size() + 1, 0);  // records kept before each index
  std::vector<record> kept;
  kept.reserve(recs.size());
  std::optional<std::uint64_t> first_repeat;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    kept_before[i] = kept.size();
    auto& same = seen[body_hash(recs[i])];
    const bool repeat = std::any_of(same.begin(), same.end(), [&](std::size_t k) {
      return kept[k].type == recs[i].type && kept[k].host_time_us == recs[i].host_time_us &&
             kept[k].body == recs[i].body;
    });
    if (repeat) {
      ++out.repeats;
      if (!first_repeat) first_repeat = recs[i].offset;
      continue;
    }
    same.push_back(kept.size());
    kept.push_back(std::move(recs[i]));
  }
  kept_before[recs.size()] = kept.size();
  for (auto& d : out.damaged) d.before = kept_before[d.before];
  recs = std::move(kept);
  if (out.repeats != 0)
    out.warnings.push_back(fmt::format(
        "{}: {} records repeat records read before them (the same kind, host time and body; the "
        "first at offset {}: a block of the file written twice); each is read once",
        name, out.repeats, *first_repeat));
  const bool in_order = std::is_sorted(recs.begin(), recs.end(), [](const auto& a, const auto& b) {
    return a.host_time_us < b.host_time_us;
  });
  if (in_order) return;
  // The records in place: the longest run in file order whose host times never go back
  // (patience sorting); the others are out of place.
  const std::size_t n = recs.size();
  std::vector<std::size_t> tails, prev(n, npos_index);
  for (std::size_t i = 0; i < n; ++i) {
    const auto it =
        std::upper_bound(tails.begin(), tails.end(), recs[i].host_time_us,
                         [&](std::uint64_t t, std::size_t k) { return t < recs[k].host_time_us; });
    if (it != tails.begin()) prev[i] = *(it - 1);
    if (it == tails.end()) {
      tails.push_back(i);
    } else {
      *it = i;
    }
  }
  std::vector<bool> in_place(n, false);
  for (std::size_t k = tails.empty() ? npos_index : tails.back(); k != npos_index; k = prev[k])
    in_place[k] = true;
  for (std::size_t i = 0; i < n;) {
    if (in_place[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && !in_place[j]) ++j;
    out.misplaced += j - i;
    out.warnings.push_back(fmt::format(
        "{}: record {}: {} records at offsets {}..{} are out of place (their host times go back: "
        "a block of the file was moved); they are read in the order of their host times",
        name, recs[i].number, j - i, recs[i].offset,
        recs[j - 1].offset + record_overhead + recs[j - 1].body.size() - 1));
    i = j;
  }
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return recs[a].host_time_us < recs[b].host_time_us;
  });
  std::vector<std::size_t> pos(n);
  for (std::size_t k = 0; k < n; ++k) pos[order[k]] = k;
  std::vector<damaged_region> damaged;
  for (const auto& d : out.damaged) {
    const std::size_t after_prev = d.before == 0 ? 0 : pos[d.before - 1] + 1;
    const std::size_t before_next = d.before >= n ? n : pos[d.before];
    damaged_region a = d;
    a.before = after_prev;
    damaged.push_back(a);
    if (before_next != after_prev) {
      a.before = before_next;
      a.again = true;
      damaged.push_back(a);
    }
  }
  std::stable_sort(damaged.begin(), damaged.end(),
                   [](const auto& a, const auto& b) { return a.before < b.before; });
  out.damaged = std::move(damaged);
  std::vector<record> sorted;
  sorted.reserve(n);
  for (const std::size_t k : order) sorted.push_back(std::move(recs[k]));
  recs = std::move(sorted);
}

}  // namespace

bool is_copied(kind k, std::span<const std::uint8_t> body) noexcept {
  switch (k) {
    case kind::meta:
    case kind::info:
    case kind::configure:
    case kind::start:
      return true;
    case kind::gap:
      return !body.empty() && (body[0] == static_cast<std::uint8_t>(gap_reason::device_reset) ||
                               body[0] == static_cast<std::uint8_t>(gap_reason::link_lost));
    default:
      return false;
  }
}

result<file> parse(std::span<const std::uint8_t> b, const std::string& name, bool strict) {
  file out;
  std::uint32_t seed = 0;  // the records' CRC-32 seed (format 6: the file's id)
  if (auto s = read_file_header(b, name, out, seed); !s) return s.err();
  if (strict && out.version == 0) return at_record(name, 0, "the file header is damaged");
  if (strict && out.repaired != 0) return at_record(name, 0, "the file header has a flipped bit");
  std::size_t at = file_header_bytes;
  std::size_t end = b.size();  // where the records end (a torn or zero tail after)
  for (std::size_t n = 1; at < b.size(); ++n) {
    if (const found f = record_at(b, at, true, seed);
        f.whole != 0 && (!f.bit || followed_well(b, at + f.whole, seed))) {
      std::vector<std::uint8_t> rec(b.begin() + static_cast<std::ptrdiff_t>(at),
                                    b.begin() + static_cast<std::ptrdiff_t>(at + f.whole));
      if (f.bit) {
        if (strict)
          return at_record(name, n, fmt::format("one flipped bit at offset {}", at + *f.bit / 8));
        rec[*f.bit / 8] = static_cast<std::uint8_t>(rec[*f.bit / 8] ^ (1U << (*f.bit % 8)));
        out.warnings.push_back(fmt::format(
            "{}: record {}: one flipped bit at offset {} repaired (its CRC-32 locates it)", name, n,
            at + *f.bit / 8));
        ++out.repaired;
      }
      record r;
      r.type = static_cast<kind>(rec[8]);
      r.host_time_us = load_le(rec.data() + 9, 8);
      r.body.assign(rec.begin() + 17, rec.end() - 4);
      r.offset = at;
      r.number = n;
      r.repaired = f.bit.has_value();
      out.records.push_back(std::move(r));
      at += f.whole;
      continue;
    }
    const std::size_t left = b.size() - at;
    // Another recording's header here: two files were joined (`cat a.gfr b.gfr`); or, when this
    // file's own records follow, a block of another recording inside this one, which is damage.
    if (left >= magic.size() && std::memcmp(b.data() + at, magic.data(), magic.size()) == 0) {
      const std::size_t next = other_files_block_end(b, at, out, seed);
      if (next == 0)
        return at_record(name, n,
                         fmt::format("offset {}: the header of another recording: two .gfr files "
                                     "were joined into one; split them there",
                                     at));
      if (strict)
        return at_record(name, n, fmt::format("offset {}: a block of another recording", at));
      out.warnings.push_back(fmt::format(
          "{}: record {}: the header of another recording (file id {}) and what follows it at "
          "offsets {}..{} skipped: a block of another .gfr inside this one (none of its records "
          "passes this file's CRC-32); reading goes on at this file's next record",
          name, n, load_le(b.data() + at + 10, 2), at, next - 1));
      at = next;
      continue;
    }
    // Zeros to the end: what a power loss leaves after the last write (the file's size was
    // extended, its data never written).
    if (all_zero(b.subspan(at))) {
      out.warnings.push_back(fmt::format(
          "{}: record {}: the last {} bytes are zeros (a power loss during writing); ignored", name,
          n, left));
      end = at;
      break;
    }
    std::size_t next = at + 1;
    while (next < b.size() && record_at(b, next, true, seed).whole == 0) ++next;
    if (next >= b.size()) {
      // Nothing intact after it: a record cut off while it was written (a hard stop).
      out.warnings.push_back(fmt::format(
          "{}: record {}: the last {} bytes are a record cut off while it was written (the "
          "recorder was stopped hard); ignored",
          name, n, left));
      end = at;
      break;
    }
    if (strict)
      return at_record(
          name, n,
          fmt::format("damaged: {} bytes from offset {} are no intact record", next - at, at));
    out.warnings.push_back(fmt::format(
        "{}: record {}: {} damaged bytes at offsets {}..{} skipped; reading goes on at the next "
        "intact record (every record is checked by its CRC-32)",
        name, n, next - at, at, next - 1));
    at = next;
  }
  merge_copies(out, name, end);
  put_in_order(out, name);
  if (strict && (out.repeats != 0 || out.misplaced != 0))
    return at_record(name, 0, "records repeated or out of place (a block of the file moved)");
  if (out.records.empty() && out.damaged.empty())
    return at_record(name, 1, "no META record: the recorder stopped before it wrote anything");
  if (out.records.empty() || out.records.front().type != kind::meta) {
    // META holds the conversion to physical units: without it nothing reads.
    if (!out.damaged.empty() && out.damaged.front().offset == file_header_bytes)
      return at_record(name, 1,
                       "the META record is damaged (its checksum does not match) and the file "
                       "holds no intact copy of it");
    return at_record(name, out.records.front().number, "the first record is not META");
  }
  return out;
}

result<file> read(const std::string& path, bool strict) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return io_error(path, "is a directory, not a .gfr recording");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return io_error(path, std::string("cannot open: ") + std::strerror(errno));
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + got);
  const bool failed = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (failed) return io_error(path, std::string("read failed: ") + std::strerror(err));
  return parse(bytes, path, strict);
}

namespace {

// The file cut back to its first `at` bytes, the next write going there; false (errno says why)
// when it could not be.
bool cut_back(int fd, std::uint64_t at) {
  return ::ftruncate(fd, static_cast<off_t>(at)) == 0 &&
         ::lseek(fd, static_cast<off_t>(at), SEEK_SET) >= 0;
}

}  // namespace

result<writer> writer::create(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST)
      return io_error(path, "exists; a recording is never overwritten (choose another name)");
    return io_error(path, std::string("cannot create: ") + std::strerror(errno));
  }
  writer w(fd, path);
  // A file size limit (ulimit -f) is where this file is full: the writer keeps end_reserve bytes
  // below it for the records that end the file.
  if (rlimit lim{}; ::getrlimit(RLIMIT_FSIZE, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY)
    w.size_limit_ = static_cast<std::uint64_t>(lim.rlim_cur);
  // A file this call made and could not start is removed: no empty recording is left behind
  // (a full disk).
  const auto fail = [&](const std::string& what) {
    const int err = errno;
    (void)::close(std::exchange(w.fd_, -1));
    (void)::unlink(path.c_str());
    return write_error(path, what, err);
  };
  // The file's id: its records' CRC-32 start from it, so that no record of another recording
  // passes as one of this file's (format 6).
  std::random_device rd;
  std::uint16_t file_id = 0;
  do {
    file_id = static_cast<std::uint16_t>(rd());
  } while (file_id == 0 || record_crc_seed(file_id) == 0);
  w.crc_seed_ = record_crc_seed(file_id);
  const auto h = file_header(file_id);
  if (::write(fd, h.data(), h.size()) != static_cast<ssize_t>(h.size())) return fail("write: ");
  w.bytes_ = h.size();
  if (::fdatasync(fd) != 0) return fail("fsync: ");
  // The new name must survive a power loss too: sync the folder that holds it.
  const std::string dir = std::filesystem::path(path).parent_path().empty()
                              ? std::string(".")
                              : std::filesystem::path(path).parent_path().string();
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0 || ::fsync(dfd) != 0) {
    if (dfd >= 0) ::close(dfd);
    return fail("fsync of its folder: ");
  }
  ::close(dfd);
  return w;
}

writer::writer(writer&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)),
      path_(std::move(o.path_)),
      bytes_(o.bytes_),
      last_host_us_(o.last_host_us_),
      size_limit_(o.size_limit_),
      crc_seed_(o.crc_seed_),
      buf_(std::move(o.buf_)),
      pending_(std::move(o.pending_)),
      tail_(std::move(o.tail_)) {}

writer& writer::operator=(writer&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
    bytes_ = o.bytes_;
    last_host_us_ = o.last_host_us_;
    size_limit_ = o.size_limit_;
    crc_seed_ = o.crc_seed_;
    buf_ = std::move(o.buf_);
    pending_ = std::move(o.pending_);
    tail_ = std::move(o.tail_);
  }
  return *this;
}

writer::~writer() {
  if (fd_ >= 0) ::close(fd_);
}

status writer::append(kind k, std::uint64_t host_time_us, std::span<const std::uint8_t> body) {
  if (k == kind::copy) return runtime_error("COPY records are the .gfr writer's own");
  // Host times strictly increase from record to record (one in the same microsecond as the one
  // before it is stamped a microsecond later): the reader puts records moved in a damaged file
  // back in their order by them, which a tie would leave open.
  if (bytes_ > file_header_bytes && host_time_us <= last_host_us_) host_time_us = last_host_us_ + 1;
  const std::uint64_t offset = bytes_;
  if (auto s = write_record(k, host_time_us, body); !s) return s;
  if (is_copied(k, body)) pending_.push_back({offset, k, host_time_us, {body.begin(), body.end()}});
  // The record is in: a copy that does not fit (a full disk) stays due, tried again after the
  // next record and at close(). An error here would have its caller take the record for lost.
  static_cast<void>(write_copies(host_time_us, false));
  return ok();
}

status writer::append_last(kind k, std::uint64_t host_time_us, std::span<const std::uint8_t> body) {
  if (k == kind::copy) return runtime_error("COPY records are the .gfr writer's own");
  if (bytes_ > file_header_bytes && host_time_us <= last_host_us_) host_time_us = last_host_us_ + 1;
  return write_record(k, host_time_us, body, true);
}

// The copies due: those whose original lies copy_distance bytes back (all: at close).
status writer::write_copies(std::uint64_t host_time_us, bool all) {
  while (!pending_.empty() && (all || bytes_ - pending_.front().offset >= copy_distance)) {
    const pending_copy& p = pending_.front();
    std::vector<std::uint8_t> body;
    body.reserve(copy_header_bytes + p.body.size());
    put_u64(body, p.offset);
    body.push_back(static_cast<std::uint8_t>(p.type));
    put_u64(body, p.host_time_us);
    body.insert(body.end(), p.body.begin(), p.body.end());
    if (auto s = write_record(kind::copy, host_time_us, body); !s) return s;
    pending_.erase(pending_.begin());
  }
  return ok();
}

status writer::write_record(kind k, std::uint64_t host_time_us, std::span<const std::uint8_t> body,
                            bool last) {
  if (body.size() > max_body) return runtime_error("a .gfr record body over 1 MiB");
  buf_.clear();
  const auto len = static_cast<std::uint32_t>(body.size() + 9);
  put_u32(buf_, len);
  put_u32(buf_, len ^ 0xFFFFFFFFU);
  buf_.push_back(static_cast<std::uint8_t>(k));
  put_u64(buf_, host_time_us);
  buf_.insert(buf_.end(), body.begin(), body.end());
  put_u32(buf_, crc32(buf_, crc_seed_));
  // Under a file size limit the records that end a full file keep their room (end_reserve).
  const std::uint64_t room = last ? size_limit_ : size_limit_ - std::min(size_limit_, end_reserve);
  if (bytes_ + buf_.size() > room) return write_error(path_, "write: ", EFBIG);
  // One write per record: a kill between records leaves whole ones only, and one inside the
  // write leaves a torn tail the reader skips.
  std::size_t done = 0;
  while (done < buf_.size()) {
    const ssize_t n = ::write(fd_, buf_.data() + done, buf_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // A write that failed part way (a full disk) is cut back to the last whole record: the file
      // holds no torn record (a kill's mark to its reader), and the room the torn part took may
      // hold the records that end the file (review of issue 32).
      const int err = n < 0 ? errno : ENOSPC;
      if (done != 0 && !cut_back(fd_, bytes_))
        return write_error(path_,
                           fmt::format("write: {}; and the record it cut short could not be "
                                       "removed: ",
                                       std::strerror(err)),
                           errno);
      return write_error(path_, "write: ", err);
    }
    done += static_cast<std::size_t>(n);
  }
  if (tail_.size() == tail_records) tail_.erase(tail_.begin());
  tail_.push_back({bytes_, {k, body.empty() ? std::uint8_t{0} : body[0]}});
  bytes_ += buf_.size();
  last_host_us_ = host_time_us;
  return ok();
}

std::optional<writer::written_record> writer::last_record() const {
  if (tail_.empty()) return std::nullopt;
  return tail_.back().what;
}

status writer::take_back_last() {
  if (fd_ < 0 || tail_.empty()) return runtime_error("no record to take back");
  const std::uint64_t at = tail_.back().offset;
  if (!cut_back(fd_, at)) return write_error(path_, "truncate: ", errno);
  tail_.pop_back();
  bytes_ = at;
  // A copy still due of a record taken out is not written.
  std::erase_if(pending_, [&](const pending_copy& p) { return p.offset >= at; });
  return ok();
}

status writer::sync() {
  if (::fdatasync(fd_) != 0) return write_error(path_, "fsync: ", errno);
  return ok();
}

status writer::close() {
  if (fd_ < 0) return ok();
  // The copies still due go in before the end (a killed writer leaves them out: its last
  // records have none).
  // A copy the file has no room for is left out: the records are all in, the copies are their
  // second copies (a file that filled up as it ended).
  static_cast<void>(write_copies(last_host_us_, true));
  auto s = sync();
  const int rc = ::close(std::exchange(fd_, -1));
  if (!s) return s;
  if (rc != 0) return io_error(path_, std::string("close: ") + std::strerror(errno));
  return ok();
}

}  // namespace gyroflip::rigdata::gfr
