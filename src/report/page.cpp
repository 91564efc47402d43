/// \file
/// \brief The report page: HTML, the inputs' SHA-256, the PDF (page.hpp).
#include "gyroflip/report/page.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/mapped_file.hpp"
#include "run_program.hpp"

namespace gyroflip::report {

namespace {

// HTML text of a value that may come from a recording (a name, a header field): markup escaped,
// the direction controls made visible (visible_controls: they would reorder the page's text).
std::string escaped(std::string_view raw) {
  const std::string text = visible_controls(raw);
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// A word that must stay with the one before it: a unit or a mark written after a number
// ("18 s", "2 σ", "40 %", "20 °C", "0.05 °/s/√Hz"), trailing punctuation aside.
bool is_suffix(std::string_view word) {
  while (!word.empty() && std::string_view(",;:.)]}").find(word.back()) != std::string_view::npos)
    word.remove_suffix(1);
  static constexpr std::string_view units[] = {"s",  "h", "min", "ms", "Hz", "ppm", "g",
                                               "dB", "V", "mV",  "µV", "σ",  "%",   "‰"};
  return word.starts_with("°") || word.starts_with("%") || word.starts_with("σ") ||
         std::find(std::begin(units), std::end(units), word) != std::end(units);
}

// A word that must stay with the one after it: a sign or a relation written before a number
// ("± 0.002", "≤ 2 σ", "< 1.45", "= 0.05").
bool is_prefix(std::string_view word) {
  static constexpr std::string_view marks[] = {"±", "<", ">", "≤", "≥", "≈", "~",
                                               "×", "=", "−", "→", "+", "-"};
  // A word that ends in a relation too ("P(≥ 2)").
  for (const std::string_view end : {"≤", "≥", "<", ">", "="})
    if (word.size() > end.size() && word.ends_with(end)) return true;
  return std::find(std::begin(marks), std::end(marks), word) != std::end(marks);
}

// A relation between a name and a value ("P < 0.01", "N = 0.05").
bool is_relation(std::string_view word) {
  for (const std::string_view mark : {"<", ">", "≤", "≥", "=", "≈"})
    if (word == mark) return true;
  return false;
}

// A character after which a browser may break a line inside a word (a hyphen, a dash, a slash).
bool has_break_inside(std::string_view word) {
  for (const std::string_view mark : {"-", "–", "—", "/", "‐", "?", "!"})
    if (word.find(mark) != std::string_view::npos) return true;
  return false;
}

// A token longer than any column can hold (a path, a hash, a command): the only words that may
// break anywhere (class "brk").
constexpr std::size_t longest_unbroken = 40;
// The longest interval in brackets kept on one line.
constexpr std::size_t short_interval = 24;

// HTML text of `raw` that breaks lines between words only, never inside one: "compensat ed",
// "18 00 s" and "inconclusiv e" were words broken to fit a column (review of issue 31). Words
// are kept whole, with their units and signs ("18 s", "± 0.002", "≤ 2 σ"), by no-break spans
// around the groups that need one; a browser breaks between the groups. A word longer than
// `longest_unbroken` (a path, a hash) may still break anywhere, as the page's CSS says.
std::string wrapped(std::string_view raw) {
  std::vector<std::string_view> words;
  for (std::size_t at = 0; at <= raw.size();) {
    const auto end = std::min(raw.find(' ', at), raw.size());
    if (end > at) words.push_back(raw.substr(at, end - at));
    at = end + 1;
  }
  std::string out;
  for (std::size_t k = 0; k < words.size();) {
    std::size_t last = k;  // the group is words[k..last]
    // An interval stays whole ("[0.488, 0.551]", at most `short_interval` bytes).
    if (words[k].starts_with('[') && words[k].find(']') == std::string_view::npos) {
      std::size_t end = k, bytes = words[k].size();
      while (end + 1 < words.size() && words[end].find(']') == std::string_view::npos)
        bytes += 1 + words[++end].size();
      if (words[end].find(']') != std::string_view::npos && bytes <= short_interval) last = end;
    }
    // A relation also stays with a short name before it ("P < 0.01", "N = 0.05").
    while (last + 1 < words.size() &&
           (is_prefix(words[last]) || is_suffix(words[last + 1]) ||
            (is_relation(words[last + 1]) && words[last].size() <= 3)) &&
           words[last + 1].size() <= longest_unbroken)
      ++last;
    std::string group;
    bool whole = last > k;
    for (std::size_t j = k; j <= last; ++j) {
      if (j > k) group += ' ';
      group += escaped(words[j]);
      whole = whole || has_break_inside(words[j]);
    }
    if (!out.empty()) out += ' ';
    const bool long_word = last == k && words[k].size() > longest_unbroken;
    if (long_word || whole) {
      out += long_word ? "<span class=\"brk\">" : "<span class=\"nw\">";
      out += group;
      out += "</span>";
    } else {
      out += group;
    }
    k = last + 1;
  }
  return out;
}

// RFC 4648 base64, for the data: URIs of the embedded images.
std::string base64(std::string_view bytes) {
  constexpr std::string_view abc =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const auto v = (static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16U) |
                   (static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8U) |
                   static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 2]));
    for (const unsigned shift : {18U, 12U, 6U, 0U}) out += abc[(v >> shift) & 63U];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const auto v =
        (static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16U) |
        (two ? static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8U : 0U);
    out += abc[(v >> 18U) & 63U];
    out += abc[(v >> 12U) & 63U];
    out += two ? abc[(v >> 6U) & 63U] : '=';
    out += '=';
  }
  return out;
}

// The page's style. Tables never leave the page: they take at most its width and wrap their
// cells between words, never inside one (no-break groups, class "nw"); only words longer than
// any column (file names, hashes, in the provenance too: class "brk") break anywhere; they print
// smaller (@media print). Narrower than 60em they print smaller; narrower than 45em (700 px, a
// phone) each row stacks, a cell labelled by its column (data-h), so no caption is cut and no
// column lies off-screen in a scroll box (third review of issue 31, M7). Checked in Chromium at
// 1280, 900, 700 and 500 px (tests/report/check_report_page.py).
constexpr std::string_view css =
    R"(body{font-family:"DejaVu Sans",Arial,sans-serif;max-width:62em;margin:2em auto;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.6em;border-bottom:2px solid #0072B2;padding-bottom:.2em}
h2{font-size:1.25em;margin-top:2em;color:#0072B2}
.banner{border:2px solid #D55E00;background:#fff4ec;padding:.5em .8em;margin:1em 0;font-weight:bold}
.warn{border-left:4px solid #D55E00;background:#fff8f3;padding:.3em .8em;margin:.8em 0}
.warn li{margin:.2em 0}
.tablebox{max-width:100%;overflow-x:auto;margin:.8em 0 1.2em}
table{border-collapse:collapse;font-size:.88em;max-width:100%}
caption{text-align:left;font-weight:bold;padding:.3em 0}
th,td{border:1px solid #ccc;padding:.25em .5em;text-align:right;vertical-align:top}
td.t{text-align:left;min-width:5em}th.t{text-align:left}.nw{white-space:nowrap}.brk{overflow-wrap:anywhere;word-break:break-all}
th{background:#f2f2f2}td:first-child,th:first-child{text-align:left}
.note{font-size:.85em;color:#444;margin:.2em 0 0}
figure{margin:1em 0 2em}figure img{width:100%;height:auto;border:1px solid #eee}
figcaption{font-size:.9em;color:#444}
.prov{font-size:.85em;color:#444}.prov td{overflow-wrap:break-word}code{font-size:.95em;overflow-wrap:anywhere}
@media (max-width:60em){table{font-size:.78em}th,td{padding:.2em .25em}td.t{min-width:0}}
@media (max-width:45em){.tablebox table,.tablebox tbody,.tablebox tr,.tablebox td,.tablebox caption{display:block}.tablebox tr:has(>th){display:none}.tablebox table{font-size:.9em}.tablebox tr{border-top:1px solid #ccc;padding:.3em 0}.tablebox td{border:none;text-align:left;padding:.05em .3em}.tablebox td:first-child{font-weight:bold}.tablebox td[data-h]::before{content:attr(data-h) ": ";color:#555}}
@page{size:A4;margin:14mm}
@media print{body{margin:0;max-width:none;font-size:10pt}h2,caption{break-after:avoid}figure,tr{break-inside:avoid}.tablebox{overflow:visible}table{font-size:8pt}th,td{padding:.15em .3em}}
)";

// A cell that reads as a number (with its interval, unit or mark), kept on one line and
// right-aligned; anything else is text, left-aligned and wrapped.
bool is_number(std::string_view c) {
  std::size_t letters = 0;
  for (const char ch : c)
    if ((ch >= 'a' && ch <= 'z' && ch != 'e') || (ch >= 'A' && ch <= 'Z' && ch != 'E')) ++letters;
  return !c.empty() && letters <= 3 && c.find(": ") == std::string_view::npos;
}

void put_table(std::string& out, const table& t) {
  out +=
      fmt::format("<div class=\"tablebox\">\n<table>\n<caption>{}</caption>\n", wrapped(t.caption));
  if (!t.header.empty()) {  // a table of key-value rows has none
    out += "<tr>";
    for (std::size_t k = 0; k < t.header.size(); ++k) {
      // A column of text has its heading on the left, as its cells.
      bool text = false;
      for (const auto& r : t.rows) text = text || (k < r.size() && !is_number(r[k]));
      out += fmt::format("<th{}>{}</th>", text ? " class=\"t\"" : "", wrapped(t.header[k]));
    }
    out += "</tr>\n";
  }
  // Each cell but a row's first names its column (data-h), which a phone-wide window shows
  // beside the value when the rows stack (the style's max-width:45em rule).
  for (const auto& r : t.rows) {
    out += "<tr>";
    for (std::size_t k = 0; k < r.size(); ++k) {
      const auto& c = r[k];
      const std::string h = k > 0 && k < t.header.size()
                                ? fmt::format(" data-h=\"{}\"", escaped(t.header[k]))
                                : std::string();
      out += fmt::format("<td class=\"{}\"{}>{}</td>", is_number(c) ? "n" : "t", h, wrapped(c));
    }
    out += "</tr>\n";
  }
  out += "</table>\n";
  if (!t.note.empty()) out += fmt::format("<p class=\"note\">{}</p>\n", wrapped(t.note));
  out += "</div>\n";
}

// Code points of UTF-8 text (for the plain-text tables' widths).
std::size_t width(std::string_view s) {
  std::size_t n = 0;
  for (const char c : s)
    if ((static_cast<unsigned char>(c) & 0xC0U) != 0x80U) ++n;
  return n;
}

// "NAME failed (exit N): its first messages" for a helper that ran and failed.
std::string program_failure(const std::string& name, const detail::program_run& r) {
  std::string what =
      r.exit_code < 0 ? std::string("was killed") : fmt::format("failed (exit {})", r.exit_code);
  const std::string text = printable(r.messages, 200);
  return name + " " + what + (text.empty() ? std::string() : ": " + text);
}

}  // namespace

result<std::string> html(const page& p, const std::string& dir) {
  std::string out;
  out += fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
      escaped(p.title), css, wrapped(p.title));
  for (const auto& b : p.banners) out += fmt::format("<p class=\"banner\">{}</p>\n", wrapped(b));
  if (const auto m = modified_build_note(p.made.commit); !m.empty())
    out += fmt::format("<p class=\"banner\">{}</p>\n", wrapped(m));
  for (const auto& s : p.sections) {
    out += fmt::format("<h2>{}</h2>\n", wrapped(s.heading));
    for (const auto& para : s.paragraphs) out += fmt::format("<p>{}</p>\n", wrapped(para));
    if (!s.warnings.empty()) {
      out += "<div class=\"warn\"><ul>\n";
      for (const auto& w : s.warnings) out += fmt::format("<li>{}</li>\n", wrapped(w));
      out += "</ul></div>\n";
    }
    for (const auto& t : s.tables) put_table(out, t);
    for (const auto& f : s.figures) {
      const auto img = io::mapped_file::open(dir + "/" + f.png);
      if (!img) return img.err();
      out += fmt::format(
          "<figure>\n<img alt=\"{}\" src=\"data:image/png;base64,{}\">\n"
          "<figcaption>{}{}</figcaption>\n</figure>\n",
          escaped(f.title), base64(img->data()), wrapped(f.title),
          f.caption.empty() ? "" : ": " + wrapped(f.caption));
    }
  }
  const auto& m = p.made;
  out += "<h2>Provenance</h2>\n<div class=\"prov\">\n";
  table made{"How this page was made",
             {},
             {{"command", m.command},
              {"made (UTC)", m.made_utc},
              {"gyroflip version", m.version},
              {"built from commit", m.commit}},
             ""};
  put_table(out, made);
  table inputs{
      fmt::format("Inputs ({})", m.inputs.size()), {"file", "bytes", "SHA-256", "origin"}, {}, ""};
  for (const auto& f : m.inputs)
    inputs.rows.push_back({f.file, fmt::format("{}", f.size_bytes), f.sha256, f.origin});
  if (m.inputs.empty()) inputs.note = "none: everything on this page was simulated by the command";
  put_table(out, inputs);
  out += "</div>\n</body>\n</html>\n";
  return out;
}

result<input_file> identify_file(const std::string& path) {
  auto sum = sha256_file(path);
  if (!sum) return sum.err();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return io_error(path, ec.message());
  return input_file{path, static_cast<std::uint64_t>(size), *sum, {}};
}

std::string modified_build_note(std::string_view commit) {
  if (!commit.ends_with("+modified")) return {};
  return fmt::format(
      "Built from a modified source tree (commit {}): the commit does not identify "
      "the code that made this.",
      commit);
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z", tm.tm_year + 1900, tm.tm_mon + 1,
                     tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec);
}

std::string text(const table& t) {
  std::vector<std::size_t> w(t.header.size(), 0);
  const auto widen = [&w](const std::vector<std::string>& r) {
    if (w.size() < r.size()) w.resize(r.size(), 0);
    for (std::size_t k = 0; k < r.size(); ++k) w[k] = std::max(w[k], width(r[k]));
  };
  widen(t.header);
  for (const auto& r : t.rows) widen(r);
  std::string out = t.caption + "\n";
  const auto line = [&](const std::vector<std::string>& r) {
    std::string l;
    for (std::size_t k = 0; k < r.size(); ++k) {
      const std::string pad(w[k] - width(r[k]), ' ');
      // The first column left-aligned (names), the others right-aligned (numbers).
      l += (k == 0 ? r[k] + pad : pad + r[k]) + (k + 1 < r.size() ? "  " : "");
    }
    while (!l.empty() && l.back() == ' ') l.pop_back();
    out += "  " + l + "\n";
  };
  if (!t.header.empty()) line(t.header);
  for (const auto& r : t.rows) line(r);
  if (!t.note.empty()) out += "  " + t.note + "\n";
  return out;
}

namespace {

// The SHA-256 (FIPS 180-4, OpenSSL's libcrypto) of the bytes `feed` hands to the function it is
// given, lowercase hex.
template <class Feed>
result<std::string> sha256_of(Feed&& feed) {
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  if (ctx == nullptr || EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(ctx);
    return runtime_error("SHA-256 is not available (libcrypto)");
  }
  feed([ctx](const char* bytes, std::size_t n) { EVP_DigestUpdate(ctx, bytes, n); });
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int len = 0;
  EVP_DigestFinal_ex(ctx, md.data(), &len);
  EVP_MD_CTX_free(ctx);
  std::string hex;
  for (unsigned i = 0; i < len; ++i) fmt::format_to(std::back_inserter(hex), "{:02x}", md[i]);
  return hex;
}

}  // namespace

result<std::string> sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return io_error(path, std::strerror(errno));
  bool read_all = false;
  auto sum = sha256_of([&](const auto& update) {
    std::array<char, 1 << 16> buf{};
    while (in) {
      in.read(buf.data(), buf.size());
      update(buf.data(), static_cast<std::size_t>(in.gcount()));
    }
    read_all = in.eof();
  });
  if (sum && !read_all) return io_error(path, "read error");
  return sum;
}

result<std::string> sha256_text(std::string_view bytes) {
  return sha256_of([bytes](const auto& update) { update(bytes.data(), bytes.size()); });
}

status print_pdf(const page& p, const std::string& dir) {
  // Headless Chromium prints the page itself (STACK.md §8): a fresh profile, no sandbox (root).
  // What each renderer did, for the message when none made the PDF: it must say what to install.
  std::vector<std::string> why;
  const std::string profile = dir + "/.chromium-profile";
  const auto abs = std::filesystem::absolute(dir).string();
  bool browser_found = false;
  for (const char* browser : {"chromium", "chromium-browser", "google-chrome"}) {
    auto r = detail::run_program(
        {browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
         "--no-first-run", "--disable-background-networking", "--user-data-dir=" + profile,
         "--no-pdf-header-footer", "--print-to-pdf=" + abs + "/report.pdf",
         "file://" + abs + "/index.html"},
        dir);
    std::error_code ec;
    std::filesystem::remove_all(profile, ec);
    if (r && r->exit_code == 0 && std::filesystem::exists(dir + "/report.pdf")) return ok();
    if (r && r->exit_code == 127) continue;  // not installed under this name
    browser_found = true;
    why.push_back(!r ? r.err().message : program_failure(browser, *r));
  }
  if (!browser_found) why.emplace_back("no Chromium (chromium, chromium-browser, google-chrome)");
  // Without a browser: the figures' PDFs, merged (the tables are in index.html and summary.json).
  std::vector<std::string> argv{"pdfunite"};
  for (const auto& s : p.sections)
    for (const auto& f : s.figures)
      if (!f.pdf.empty()) argv.push_back(f.pdf);
  argv.emplace_back("report.pdf");
  if (argv.size() < 3) {
    why.emplace_back("no figure for pdfunite to merge");
  } else {
    auto r = detail::run_program(argv, dir);
    if (r && r->exit_code == 0) return ok();
    why.push_back(!r                    ? r.err().message
                  : r->exit_code == 127 ? std::string("no pdfunite")
                                        : program_failure("pdfunite", *r));
  }
  std::string reasons;
  for (const auto& w : why) reasons += (reasons.empty() ? "" : "; ") + w;
  return runtime_error(
      fmt::format("cannot make report.pdf: {}. Install poppler-utils (pdfunite "
                  "merges the figures' PDFs) or chromium (prints the whole page)",
                  reasons));
}

}  // namespace gyroflip::report
