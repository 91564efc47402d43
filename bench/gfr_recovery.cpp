/// \file
/// \brief The `.gfr` reader against damage (issue 32, docs/RELIABILITY.md "Damaged recordings"):
/// random single-bit flips, zeroed regions, blocks written twice and blocks swapped, and blocks
/// of another recording inserted or written over (--splices: fifth review of issue 32, F3), each
/// applied
/// to a fresh copy of one recording, which is read back and compared dwell by dwell with the
/// undamaged reading. Prints the share of intact dwells recovered and the dwells mislabelled (the
/// goal: >= 99.9 %, none), read more than once, timed outside the recording's span, or counted lost
/// although intact (none).
///
///   gfr_recovery [--file RUN.gfr] [--format 4|5] [--flips N] [--zeros N] [--max-zero-bytes B]
///                [--dups N] [--swaps N] [--max-block-bytes B] [--splices N] [--other B.gfr]
///                [--seed S] [--write FILE]
///
/// Without --file: a synthetic recording as the recorder writes it (tests/support/synthetic_gfr:
/// 1 500 dwells, 4 device resets, 3 lost ports, 4 dwells lost on the line, RESENDs), in this
/// format (6: COPY records, each record's CRC from the file's id; --format 5 is the same) or, with
/// --format 4, as recorders before issue 32 wrote it; --write keeps it in FILE. The other
/// recording of --splices: --other, else the synthetic one again with other values (the same
/// board, boots, numbers and times: the hardest to tell).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "support/run_cli.hpp"
#include "support/synthetic_gfr.hpp"
#include "support/temp_dir.hpp"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: gfr_recovery [--file RUN.gfr] [--format 4|5] [--flips N] [--zeros N] "
               "[--max-zero-bytes B] [--dups N] [--swaps N] [--max-block-bytes B] [--splices N] "
               "[--other B.gfr] [--seed S] [--write SYNTHETIC.gfr]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string file, write, other_file;
  std::size_t splices = 0;
  int format = 5;
  std::size_t flips = 1000, zeros = 100, max_zero = 4096, dups = 100, swaps = 100, max_block = 4096;
  std::uint64_t seed = 20261128;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage();
      return 0;
    }
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    char* end = nullptr;
    const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
    const bool number = end != v.c_str() && *end == '\0';
    if (a == "--file") {
      file = v;
    } else if (a == "--format" && number && (n >= 4 && n <= 6)) {
      format = static_cast<int>(n);
    } else if (a == "--flips" && number) {
      flips = n;
    } else if (a == "--zeros" && number) {
      zeros = n;
    } else if (a == "--max-zero-bytes" && number && n > 0) {
      max_zero = n;
    } else if (a == "--write") {
      write = v;
    } else if (a == "--dups" && number) {
      dups = n;
    } else if (a == "--swaps" && number) {
      swaps = n;
    } else if (a == "--max-block-bytes" && number && n > 0) {
      max_block = n;
    } else if (a == "--splices" && number) {
      splices = n;
    } else if (a == "--other") {
      other_file = v;
    } else if (a == "--seed" && number) {
      seed = n;
    } else {
      return usage();
    }
  }
  std::vector<std::uint8_t> bytes, other;
  gyroflip::test::temp_dir dir;
  if (!other_file.empty()) {
    const std::string t = gyroflip::test::read_text(other_file);
    other.assign(t.begin(), t.end());
  }
  if (!file.empty()) {
    const std::string t = gyroflip::test::read_text(file);
    bytes.assign(t.begin(), t.end());
    if (bytes.empty()) {
      std::fprintf(stderr, "gfr_recovery: %s: empty or missing\n", file.c_str());
      return 2;
    }
  } else {
    gyroflip::test::synthetic_options o;
    o.dwells = 1500;
    o.resets_after = {200, 520, 521, 900, 1240};
    o.link_losses_after = {350, 700, 1100};
    o.lost = {60, 610, 611, 1400};
    o.copies = format != 4;
    bytes = gyroflip::test::make_synthetic_recording(o, dir.file("synthetic.gfr")).bytes;
    if (other_file.empty() && splices != 0) {
      o.seed = 2;
      other = gyroflip::test::make_synthetic_recording(o, dir.file("other.gfr")).bytes;
    }
    file = format != 4 ? "synthetic (format 6)" : "synthetic (format 4)";
    if (!write.empty()) gyroflip::test::write_text(write, std::string(bytes.begin(), bytes.end()));
  }
  std::printf("%s: %zu bytes; seed %llu\n", file.c_str(), bytes.size(),
              static_cast<unsigned long long>(seed));
  const auto show = [](const char* what, const gyroflip::test::damage_tally& t) {
    std::printf(
        "%-34s trials %5zu  intact dwells %9zu  recovered %9zu (%.4f %%)  mislabelled %zu  "
        "unreadable files %zu  largest time shift %.3g s\n"
        "%-34s read twice %zu  timed outside the span %zu  counted lost although intact %zu\n",
        what, t.trials, t.intact, t.recovered,
        t.intact == 0 ? 100.0
                      : 100.0 * static_cast<double>(t.recovered) / static_cast<double>(t.intact),
        t.mislabelled, t.unreadable, t.max_time_shift_s, "", t.repeated, t.beyond_span,
        t.false_lost);
    if (t.max_time_shift_s > 0.0)
      std::printf("  largest time shift in: %s\n", t.max_time_shift_at.c_str());
    for (const auto& n : t.notes) std::printf("  %s\n", n.c_str());
  };
  if (splices != 0 && other.size() <= 16) {
    std::fprintf(stderr, "gfr_recovery: --splices needs --other B.gfr with --file\n");
    return 2;
  }
  gyroflip::test::damage_tally f, z, r, s, si, so;
  if (flips != 0) {
    gyroflip::test::flip_trials(bytes, flips, seed, f);
    show("single-bit flips", f);
  }
  if (zeros != 0) {
    gyroflip::test::zero_trials(bytes, zeros, max_zero, seed + 1, z);
    const std::string zname = "zeroed regions of 1.." + std::to_string(max_zero) + " B";
    show(zname.c_str(), z);
  }
  if (dups != 0) {
    gyroflip::test::repeat_trials(bytes, dups, max_block, seed + 2, r);
    const std::string name = "blocks of 1.." + std::to_string(max_block) + " B twice";
    show(name.c_str(), r);
  }
  if (swaps != 0) {
    gyroflip::test::swap_trials(bytes, swaps, max_block, seed + 3, s);
    const std::string name = "blocks of 512.." + std::to_string(max_block) + " B swapped";
    show(name.c_str(), s);
  }
  if (splices != 0) {
    gyroflip::test::splice_trials(bytes, other, splices, max_block, seed + 4, false, si);
    const std::string name = "another's 1.." + std::to_string(max_block) + " B inserted";
    show(name.c_str(), si);
    gyroflip::test::splice_trials(bytes, other, splices, max_block, seed + 5, true, so);
    const std::string over = "another's 1.." + std::to_string(max_block) + " B over";
    show(over.c_str(), so);
  }
  std::size_t wrong = 0;
  for (const auto* t : {&f, &z, &r, &s, &si, &so})
    wrong += t->mislabelled + t->repeated + t->beyond_span + t->false_lost;
  return wrong == 0 ? 0 : 1;
}
