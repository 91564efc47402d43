// The MSP430F149 code on an MSP430 instruction simulator (issue 20): mspdebug's `sim` driver
// (Debian's mspdebug 0.22: a CPU, 64 KB of RAM and simulated I/O devices).
//  - The self-test image (firmware/ports/msp430f149/selftest.cpp: the shipped image's compiler,
//    flags, start-up and runtime helpers) computes the runtime helpers and the firmware's own
//    arithmetic on thousands of vectors; each result must equal, bit for bit, the same source
//    (selftest::compute) run on the host with the firmware core built for the host.
//  - The shipped image, flashed as a user would (the Intel HEX, and the ELF), must read back
//    byte for byte and boot from reset into its main loop with the watchdog never expiring.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "firmware/ports/msp430f149/selftest.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace gyroflip;
namespace st = fw::selftest;
using st::op;

const std::string image_dir = GYROFLIP_F149_DIR;
const std::string shipped_elf = image_dir + "/gyroflip_f149.elf";
const std::string shipped_hex = image_dir + "/gyroflip_f149.hex";
const std::string selftest_elf = image_dir + "/gyroflip_f149_selftest.elf";

// ---- the simulator -----------------------------------------------------------------------

// Runs mspdebug's simulator on `commands` (each one mspdebug command), with a time limit; the
// whole output.
std::string mspdebug(const std::vector<std::string>& commands) {
  std::vector<std::string> argv{"timeout", "120", "mspdebug", "-q", "sim"};
  argv.insert(argv.end(), commands.begin(), commands.end());
  const auto r = test::run_program(argv);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  return r.out + r.err;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// ---- ELF (32-bit little-endian, what ld.lld writes for msp430) -----------------------------

struct segment {
  std::uint32_t paddr = 0;
  std::vector<std::uint8_t> bytes;
};
struct section {
  std::string name;
  std::uint32_t type = 0, flags = 0, addr = 0, size = 0;
};
struct elf_image {
  std::vector<segment> loads;  // PT_LOAD with file bytes, at their load (physical) address
  std::vector<section> sections;
  std::map<std::string, std::uint32_t> symbols;
};

std::uint32_t le(const std::vector<std::uint8_t>& b, std::size_t at, int n) {
  std::uint32_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | b.at(at + static_cast<std::size_t>(i));
  return v;
}

elf_image read_elf(const std::string& path) {
  const auto b = read_bytes(path);
  elf_image e;
  if (b.size() < 52 || std::memcmp(b.data(),
                                   "\x7f"
                                   "ELF",
                                   4) != 0)
    return e;
  const std::uint32_t phoff = le(b, 28, 4), shoff = le(b, 32, 4);
  const std::uint32_t phnum = le(b, 44, 2), shnum = le(b, 48, 2), shstrndx = le(b, 50, 2);
  for (std::uint32_t i = 0; i < phnum; ++i) {
    const std::size_t p = phoff + 32 * i;
    const std::uint32_t off = le(b, p + 4, 4), paddr = le(b, p + 12, 4), filesz = le(b, p + 16, 4);
    if (le(b, p, 4) == 1 && filesz != 0)
      e.loads.push_back({paddr, {b.begin() + off, b.begin() + off + filesz}});
  }
  const auto sh = [&](std::uint32_t i, std::uint32_t field) {
    return le(b, shoff + 40 * i + field, 4);
  };
  const std::uint32_t strtab = sh(shstrndx, 16);
  std::uint32_t symtab = 0, symstr = 0, symsize = 0;
  for (std::uint32_t i = 0; i < shnum; ++i) {
    section s;
    s.name = reinterpret_cast<const char*>(b.data() + strtab + sh(i, 0));
    s.type = sh(i, 4);
    s.flags = sh(i, 8);
    s.addr = sh(i, 12);
    s.size = sh(i, 20);
    e.sections.push_back(s);
    if (s.type == 2) {  // SHT_SYMTAB
      symtab = sh(i, 16);
      symsize = s.size;
      symstr = sh(sh(i, 24), 16);
    }
  }
  for (std::uint32_t at = symtab; at + 16 <= symtab + symsize; at += 16)
    e.symbols[reinterpret_cast<const char*>(b.data() + symstr + le(b, at, 4))] = le(b, at + 4, 4);
  return e;
}

// ---- the self-test mailbox -------------------------------------------------------------

struct vec {
  op o;
  std::uint64_t a = 0, b = 0;
};
using out = st::results;

// Runs `v` on the simulated MSP430 in batches; one result per vector.
std::vector<out> run_on_msp430(const std::vector<vec>& v) {
  std::vector<out> res;
  test::temp_dir tmp;
  for (std::size_t first = 0, n = 0; first < v.size(); first += n) {
    // A batch is one run of the image: it must hold each calibration (cal_begin .. cal_result)
    // whole, as the calibrator's state lives in that run only.
    n = std::min<std::size_t>(st::max_records, v.size() - first);
    if (first + n < v.size()) {
      std::size_t cut = first + n;
      while (cut > first && v[cut - 1].o != op::cal_result && v[cut].o != op::cal_begin &&
             (v[cut].o == op::cal_add || v[cut].o == op::cal_result))
        --cut;
      if (cut > first) n = cut - first;
    }
    std::vector<std::uint8_t> in{static_cast<std::uint8_t>(n), static_cast<std::uint8_t>(n >> 8)};
    for (std::size_t i = first; i < first + n; ++i) {
      in.push_back(static_cast<std::uint8_t>(v[i].o));
      in.push_back(0);
      for (int k = 0; k < 8; ++k) in.push_back(static_cast<std::uint8_t>(v[i].a >> (8 * k)));
      for (int k = 0; k < 8; ++k) in.push_back(static_cast<std::uint8_t>(v[i].b >> (8 * k)));
    }
    std::ofstream(tmp.file("in.bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(in.data()), static_cast<std::streamsize>(in.size()));
    const auto log =
        mspdebug({"prog " + selftest_elf,
                  "load_raw " + tmp.file("in.bin") + " " + std::to_string(st::in_addr),
                  "setbreak selftest_done", "run",
                  "save_raw " + std::to_string(st::out_addr) + " " +
                      std::to_string(n * st::out_record_bytes) + " " + tmp.file("out.bin")});
    const auto o = read_bytes(tmp.file("out.bin"));
    if (o.size() != n * st::out_record_bytes) {
      ADD_FAILURE() << "no results from the simulator:\n" << log;
      return res;
    }
    for (std::size_t i = 0; i < n; ++i) {
      out r;
      for (std::size_t k = 8; k > 0; --k) r.r0 = (r.r0 << 8) | o[16 * i + k - 1];
      for (std::size_t k = 8; k > 0; --k) r.r1 = (r.r1 << 8) | o[16 * i + 8 + k - 1];
      res.push_back(r);
    }
  }
  return res;
}

// ---- vectors ----------------------------------------------------------------------------

// Operand values that break carries, signs and loops: 0, 1, the extremes of each width and
// their neighbours, single bits, and alternating patterns.
std::vector<std::uint64_t> edges() {
  std::vector<std::uint64_t> e{
      0, 1, 2, 3, 7, 10, 255, 256, 0x5555555555555555u, 0xAAAAAAAAAAAAAAAAu, 0x0123456789ABCDEFu};
  for (int w : {8, 15, 16, 31, 32, 47, 48, 63, 64}) {
    const std::uint64_t top = w == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << w) - 1;
    for (std::uint64_t d : {std::uint64_t{0}, std::uint64_t{1}}) {
      e.push_back(top - d);
      e.push_back(~(top - d));  // the negative extremes, sign-extended
    }
  }
  for (int k = 0; k < 64; k += 5) e.push_back(std::uint64_t{1} << k);
  return e;
}

// Random operands of every magnitude (a random width, then a random value of that width).
std::uint64_t random_operand(std::mt19937_64& g) {
  const int bits = static_cast<int>(g() % 65);
  if (bits == 0) return 0;
  const std::uint64_t v = g();
  return bits == 64 ? v : v & ((std::uint64_t{1} << bits) - 1);
}

int width_of(op o) {
  switch (o) {
    case op::mul16:
    case op::divu16:
    case op::remu16:
    case op::divi16:
    case op::remi16:
      return 16;
    case op::mul32:
    case op::divu32:
    case op::remu32:
    case op::divi32:
    case op::remi32:
    case op::shl32:
    case op::shr32:
    case op::sar32:
      return 32;
    default:
      return 64;
  }
}

bool is_signed_division(op o) {
  return o == op::divi16 || o == op::remi16 || o == op::divi32 || o == op::remi32 ||
         o == op::divi64 || o == op::remi64;
}
bool is_division(op o) {
  return is_signed_division(o) || o == op::divu16 || o == op::remu16 || o == op::divu32 ||
         o == op::remu32 || o == op::divu64 || o == op::remu64;
}
bool is_shift(op o) {
  return o >= op::shl32 && o <= op::sar64;
}

// Whether C++ defines the operation for these operands (the firmware never relies on the
// rest: no division by 0 or of the most negative value by -1, no shift by the width or more).
bool defined(op o, std::uint64_t a, std::uint64_t b) {
  const int w = width_of(o);
  const std::uint64_t mask = w == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << w) - 1;
  if (is_shift(o)) return (b & 0xFFFF) < static_cast<std::uint64_t>(w);
  if (!is_division(o)) return true;
  if ((b & mask) == 0) return false;
  const std::uint64_t most_negative = std::uint64_t{1} << (w - 1);
  return !(is_signed_division(o) && (a & mask) == most_negative && (b & mask) == mask);
}

std::vector<vec> helper_vectors() {
  std::vector<vec> v;
  std::mt19937_64 g(20);
  const auto e = edges();
  for (int o = static_cast<int>(op::mul16); o <= static_cast<int>(op::sar64); ++o) {
    const auto which = static_cast<op>(o);
    const auto add = [&](std::uint64_t a, std::uint64_t b) {
      if (is_shift(which)) b %= static_cast<std::uint64_t>(width_of(which) + 3);  // 0..width+2
      if (defined(which, a, b)) v.push_back({which, a, b});
    };
    for (const auto a : e)
      for (const auto b : e) add(a, b);
    for (int k = 0; k < 300; ++k) add(random_operand(g), random_operand(g));
  }
  return v;
}

std::vector<vec> firmware_vectors() {
  std::vector<vec> v;
  std::mt19937_64 g(21);
  // Dwell means: any n up to 65535 and codes within +-2^23 (|sum| <= 2^23 n).
  for (int k = 0; k < 400; ++k) {
    const auto n =
        static_cast<std::uint32_t>(k < 4 ? std::uint64_t{1} << (4 * k) : 1 + g() % 65535);
    const std::int64_t limit = (std::int64_t{1} << 23) * n;
    std::int64_t sum =
        static_cast<std::int64_t>(g() % (2 * static_cast<std::uint64_t>(limit) + 1)) - limit;
    if (k % 7 == 0) sum = (k % 2 == 0 ? limit : -limit);
    v.push_back({op::mean_q8, static_cast<std::uint64_t>(sum), n});
    v.push_back({op::div_round, static_cast<std::uint64_t>(sum * 256), n});
  }
  // Cycles and compensation over the whole int32 range of q8 means and dN.
  const std::int32_t q8_edges[] = {0, 1, -1, 2147483647, -2147483647 - 1, 1 << 30, -(1 << 30)};
  for (const auto a : q8_edges)
    for (const auto b : q8_edges) {
      v.push_back({op::make_cycle, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)});
      v.push_back({op::compensate, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)});
    }
  for (int k = 0; k < 300; ++k) {
    const auto a = static_cast<std::uint32_t>(g()), b = static_cast<std::uint32_t>(g());
    v.push_back({op::make_cycle, a, b});
    v.push_back({op::compensate, a, b});
  }
  for (const auto a : edges()) v.push_back({op::isqrt, a, 0});
  for (int k = 0; k < 200; ++k) v.push_back({op::isqrt, random_operand(g), 0});
  // Calibrations: steady rates with noise, a ramp, a spread too large for the sums (saturated),
  // K from 2 to 300.
  for (int c = 0; c < 12; ++c) {
    const std::uint16_t cycles = c == 0 ? 2 : static_cast<std::uint16_t>(2 + g() % 299);
    v.push_back({op::cal_begin, cycles, 0});
    const std::int32_t base = static_cast<std::int32_t>(g() % 2000000) - 1000000;
    for (int i = 0; i < cycles; ++i) {
      std::int32_t r = base + static_cast<std::int32_t>(g() % 5001) - 2500;
      if (c == 5) r = base + 1000 * i;                           // a drift
      if (c == 7 && i == 3) r = base + (std::int32_t{1} << 25);  // beyond 2^24 q8: saturated
      v.push_back({op::cal_add, static_cast<std::uint32_t>(r), static_cast<std::uint64_t>(c & 3)});
    }
    v.push_back({op::cal_result, 0, 0});
  }
  // The device's timing arithmetic: ramps, ms and conversion times to ticks.
  for (int k = 0; k < 200; ++k) {
    const std::uint16_t top = static_cast<std::uint16_t>(1 + g() % 5000);
    const std::uint16_t start = static_cast<std::uint16_t>(1 + g() % top);
    const std::uint16_t accel = static_cast<std::uint16_t>(1 + g() % 65535);
    const auto n = static_cast<std::uint32_t>(1 + g() % 400);
    const auto step = static_cast<std::uint32_t>(g() % n);
    v.push_back({op::step_interval,
                 start | (std::uint64_t{top} << 16) | (std::uint64_t{accel} << 32),
                 step | (std::uint64_t{n} << 32)});
    v.push_back({op::ms_to_ticks, g() % 65536, k % 2 == 0 ? 32768u : 1000000u});
    v.push_back({op::mclk_to_ticks,
                 ad7739::conversion_mclk(k % 2 == 0, static_cast<std::uint8_t>(2 + g() % 126)) |
                     (std::uint64_t{6144000 + g() % 1000} << 32),
                 k % 2 == 0 ? 32768u : 1000000u});
  }
  // The CONFIGURE check and the link budget it applies.
  for (int k = 0; k < 200; ++k) {
    const std::uint64_t n_avg = 1 + g() % 65535, n_temp = g() % 70, fw_word = g() % 130;
    const std::uint64_t flags = g() % 32, settle = g() % 2000;
    const std::uint64_t rate = g() % 6000, pos_b = g() % 250, status = g() % 70000;
    v.push_back({op::link_budget,
                 n_avg | (n_temp << 16) | (fw_word << 24) | (flags << 32) | (settle << 40),
                 rate | (pos_b << 16) | ((status & 0xFFFF) << 32)});
  }
  return v;
}

std::string describe(const vec& v) {
  return "op " + std::to_string(static_cast<int>(v.o)) + " a=" + std::to_string(v.a) +
         " b=" + std::to_string(v.b);
}

void expect_same(const std::vector<vec>& v) {
  const auto got = run_on_msp430(v);
  ASSERT_EQ(got.size(), v.size());
  fw::calibrator cal;
  int wrong = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const out want = st::compute(v[i].o, v[i].a, v[i].b, cal);
    if (!(got[i] == want) && ++wrong <= 20)
      ADD_FAILURE() << describe(v[i]) << ": MSP430 " << got[i].r0 << "," << got[i].r1 << "  host "
                    << want.r0 << "," << want.r1;
  }
  EXPECT_EQ(wrong, 0) << "of " << v.size() << " vectors";
}

// ---- tests ----------------------------------------------------------------------------------

TEST(Msp430Sim, SelfTestImageLeavesTheMailboxFree) {
  const auto e = read_elf(selftest_elf);
  ASSERT_FALSE(e.loads.empty()) << selftest_elf;
  for (const auto& s : e.loads) {
    if (s.paddr >= 0x1000 && s.paddr < 0xFFE0) {
      EXPECT_LE(s.paddr + s.bytes.size(), st::in_addr) << "the image's code reaches the mailbox";
    }
  }
}

// Every 16-, 32- and 64-bit multiply, divide, remainder and variable shift the compiler calls a
// helper for (TI SLAA534 §6.3), on edges and random operands, as the host computes them. The
// 64-bit multiply and divide use the EABI's special register convention: a helper written as an
// ordinary C++ function returns garbage there (mpyll(32768, 1000) gave 0).
TEST(Msp430Sim, RuntimeHelpersMatchTheHostBitForBit) {
  const auto v = helper_vectors();
  ASSERT_GT(v.size(), 4000u);
  expect_same(v);
}

// The image calls every helper runtime.cpp defines (so none is left untested above).
TEST(Msp430Sim, SelfTestCallsEveryRuntimeHelper) {
  const auto e = read_elf(selftest_elf);
  for (const char* h : {"__mspabi_mpyi",   "__mspabi_mpyl",   "__mspabi_mpyll",  "__mspabi_divu",
                        "__mspabi_remu",   "__mspabi_divi",   "__mspabi_remi",   "__mspabi_divul",
                        "__mspabi_remul",  "__mspabi_divli",  "__mspabi_remli",  "__mspabi_divull",
                        "__mspabi_remull", "__mspabi_divlli", "__mspabi_remlli", "__mspabi_slll",
                        "__mspabi_srll",   "__mspabi_sral",   "__ashldi3",       "__lshrdi3",
                        "__ashrdi3"})
    EXPECT_TRUE(e.symbols.count(h)) << h << " is not linked into the self-test image";
}

// The dwell mean, cycle, compensation, calibration (dN and its spread), the ramp and tick
// arithmetic and the CONFIGURE check, against the firmware core built for the host.
TEST(Msp430Sim, FirmwareArithmeticMatchesTheHostPortBitForBit) {
  const auto v = firmware_vectors();
  ASSERT_GT(v.size(), 3000u);
  expect_same(v);
}

// The shipped image has only sections a flasher programs: no .init_array (a flasher that writes
// PROGBITS only left it erased, and the start-up called 0xFFFF), every allocated section with
// contents is PROGBITS.
TEST(Msp430Sim, ShippedImageHasOnlyProgbitsToFlash) {
  const auto e = read_elf(shipped_elf);
  ASSERT_FALSE(e.sections.empty()) << shipped_elf;
  for (const auto& s : e.sections) {
    constexpr std::uint32_t alloc = 2;
    if ((s.flags & alloc) == 0 || s.size == 0 || s.type == 8 /* NOBITS */) continue;
    EXPECT_EQ(s.type, 1u) << s.name << " is allocated but not PROGBITS";
  }
  for (const auto& s : e.sections) {
    EXPECT_NE(s.name, ".init_array") << "a static constructor";
  }
}

// Flashed as docs/HARDWARE.md says (the HEX, and the ELF), the simulator's memory holds every
// loadable byte at its load address (.data's initial values in flash included).
TEST(Msp430Sim, FlashedImageReadsBackByteForByte) {
  auto e = read_elf(shipped_elf);
  // Only flash is programmed: 0x1000 (information memory) up. ld.lld maps the ELF header into
  // a segment at address 0, which no flasher writes.
  std::erase_if(e.loads, [](const segment& s) { return s.paddr < 0x1000; });
  ASSERT_FALSE(e.loads.empty());
  test::temp_dir tmp;
  for (const auto& image : {shipped_hex, shipped_elf}) {
    std::vector<std::string> cmd{"prog " + image};
    for (std::size_t i = 0; i < e.loads.size(); ++i)
      cmd.push_back("save_raw " + std::to_string(e.loads[i].paddr) + " " +
                    std::to_string(e.loads[i].bytes.size()) + " " +
                    tmp.file("seg" + std::to_string(i)));
    mspdebug(cmd);
    for (std::size_t i = 0; i < e.loads.size(); ++i)
      EXPECT_EQ(read_bytes(tmp.file("seg" + std::to_string(i))), e.loads[i].bytes)
          << image << ": the segment at " << e.loads[i].paddr << " reads back differently";
  }
}

// From reset to the main loop (the first device::poll) on the simulated MSP430 with its
// watchdog: the reset handler's first instruction holds the watchdog, it never expires, and
// no interval between two writes of WDTCTL (or the last one and the main loop) comes near the
// watchdog's interval at the board's clock ratio. The simulator has no USART, so the AD7739
// does not answer: the boot reports it and goes on, as on a board without the ADC.
TEST(Msp430Sim, ShippedImageBootsIntoItsMainLoopWithinTheWatchdog) {
  const auto e = read_elf(shipped_elf);
  const std::string poll = "_ZN8gyroflip2fw6device4pollEv";
  ASSERT_TRUE(e.symbols.count(poll));
  const auto log =
      mspdebug({"simio add tracer tr 65536", "simio add wdt wd", "simio add timer ta 3",
                "simio config ta irq0 6", "simio config ta irq1 5", "prog " + shipped_hex,
                "sym import " + shipped_elf, "reset", "simio config tr clear", "setbreak " + poll,
                "run", "regs", "simio info wd", "simio info tr"});
  // (No std::regex: GCC 12's <regex> warns maybe-uninitialized under the sanitizers' -O1.)
  const std::size_t pc_at = log.find("( PC: ");
  ASSERT_NE(pc_at, std::string::npos) << log;
  EXPECT_EQ(std::stoul(log.substr(pc_at + 6), nullptr, 16), e.symbols.at(poll))
      << "did not reach the main loop";
  EXPECT_NE(log.find("Reset:               not triggered"), std::string::npos) << log;
  const std::size_t mclk_at = log.find("MCLK:");
  ASSERT_NE(mclk_at, std::string::npos) << log;
  const double cycles_to_main = std::stod(log.substr(mclk_at + 5));
  // WDTCTL writes with their MCLK cycle ("CYCLE: write.w => 0x0120 0xVALUE" in the tracer's
  // log): the first holds it (WDTPW | WDTHOLD), at once.
  std::vector<std::pair<double, unsigned>> writes;
  const std::string wdt = ": write.w => 0x0120 0x";
  for (std::size_t at = log.find(wdt); at != std::string::npos; at = log.find(wdt, at + 1)) {
    std::size_t begin = at;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(log[begin - 1])) != 0) --begin;
    if (begin == at) continue;
    writes.emplace_back(std::stod(log.substr(begin, at - begin)),
                        std::stoul(log.substr(at + wdt.size()), nullptr, 16));
  }
  ASSERT_FALSE(writes.empty());
  EXPECT_EQ(writes.front().second, 0x5A80u);
  EXPECT_LE(writes.front().first, 8.0) << "the watchdog is not stopped by the reset handler";
  // The image runs the watchdog from ACLK (32 768 Hz), 32 768 ticks, while MCLK runs from the
  // 5.5296 MHz crystal (XT2; docs/HARDWARE.md, Clocks): 5 529 600 MCLK cycles per interval (the
  // simulator's own ACLK ratio, 1:256, is slower; the board's ratio is the one that counts).
  constexpr double interval_mclk = 32768.0 * 5529600.0 / 32768.0;
  double gap = 0;
  for (std::size_t i = 1; i < writes.size(); ++i)
    gap = std::max(gap, writes[i].first - writes[i - 1].first);
  gap = std::max(gap, cycles_to_main - writes.back().first);
  EXPECT_LT(gap, 0.25 * interval_mclk) << "a boot step runs too long between watchdog kicks";
  RecordProperty("cycles_to_main_loop", std::to_string(static_cast<long>(cycles_to_main)));
  RecordProperty("longest_watchdog_gap_cycles", std::to_string(static_cast<long>(gap)));
  std::printf(
      "msp430f149 boot: %.0f MCLK cycles to the main loop (%.2f ms at 5.5296 MHz); "
      "longest watchdog gap %.0f cycles (%.1f %% of its interval)\n",
      cycles_to_main, cycles_to_main / 5529.6, gap, 100 * gap / interval_mclk);
}

}  // namespace
