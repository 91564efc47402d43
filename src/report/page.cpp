/// \file
/// \brief The report page: HTML, the inputs' SHA-256, the PDF (page.hpp).
#include "gyroflip/report/page.hpp"

#include <openssl/evp.h>

#include <array>
#include <cerrno>
#include <cstring>
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

std::string escaped(std::string_view text) {
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

constexpr std::string_view css =
    R"(body{font-family:"DejaVu Sans",Arial,sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.6em;border-bottom:2px solid #0072B2;padding-bottom:.2em}
h2{font-size:1.25em;margin-top:2em;color:#0072B2}
table{border-collapse:collapse;margin:.8em 0 1.2em;font-size:.9em}
caption{text-align:left;font-weight:bold;padding:.3em 0}
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right}
th{background:#f2f2f2}td:first-child,th:first-child{text-align:left}
figure{margin:1em 0 2em}figure img{width:100%;height:auto;border:1px solid #eee}
figcaption{font-size:.9em;color:#444}
.prov{font-size:.85em;color:#444;word-break:break-all}code{font-size:.95em}
@media print{body{margin:0;max-width:none}h2{break-after:avoid}figure,table{break-inside:avoid}}
)";

void put_table(std::string& out, const table& t) {
  out += fmt::format("<table>\n<caption>{}</caption>\n<tr>", escaped(t.caption));
  for (const auto& h : t.header) out += fmt::format("<th>{}</th>", escaped(h));
  out += "</tr>\n";
  for (const auto& r : t.rows) {
    out += "<tr>";
    for (const auto& c : r) out += fmt::format("<td>{}</td>", escaped(c));
    out += "</tr>\n";
  }
  out += "</table>\n";
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
      escaped(p.title), css, escaped(p.title));
  for (const auto& s : p.sections) {
    out += fmt::format("<h2>{}</h2>\n", escaped(s.heading));
    for (const auto& para : s.paragraphs) out += fmt::format("<p>{}</p>\n", escaped(para));
    for (const auto& t : s.tables) put_table(out, t);
    for (const auto& f : s.figures) {
      const auto img = io::mapped_file::open(dir + "/" + f.png);
      if (!img) return img.err();
      out += fmt::format(
          "<figure>\n<img alt=\"{}\" src=\"data:image/png;base64,{}\">\n"
          "<figcaption>{}{}</figcaption>\n</figure>\n",
          escaped(f.title), base64(img->data()), escaped(f.title),
          f.caption.empty() ? "" : ": " + escaped(f.caption));
    }
  }
  out += "<h2>Provenance</h2>\n<div class=\"prov\">\n";
  out += fmt::format("<p>Made by gyroflip {} with:</p>\n<p><code>{}</code></p>\n",
                     escaped(p.version), escaped(p.command));
  table inputs{"Inputs (SHA-256)", {"file", "sha256"}, {}};
  for (const auto& [file, sum] : p.inputs) inputs.rows.push_back({file, sum});
  put_table(out, inputs);
  out += "</div>\n</body>\n</html>\n";
  return out;
}

result<std::string> sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return io_error(path, std::strerror(errno));
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  if (ctx == nullptr || EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(ctx);
    return runtime_error("SHA-256 is not available (libcrypto)");
  }
  std::array<char, 1 << 16> buf{};
  while (in) {
    in.read(buf.data(), buf.size());
    EVP_DigestUpdate(ctx, buf.data(), static_cast<std::size_t>(in.gcount()));
  }
  const bool read_all = in.eof();
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int len = 0;
  EVP_DigestFinal_ex(ctx, md.data(), &len);
  EVP_MD_CTX_free(ctx);
  if (!read_all) return io_error(path, "read error");
  std::string hex;
  for (unsigned i = 0; i < len; ++i) fmt::format_to(std::back_inserter(hex), "{:02x}", md[i]);
  return hex;
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
