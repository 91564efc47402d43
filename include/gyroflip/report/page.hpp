/// \file
/// \brief The report a person would send (issues 10, 22): one self-contained HTML page (figures
/// embedded as data: URIs, no network, real tables, a print style sheet that keeps every table on
/// the page), built from sections of paragraphs, warnings, tables and figures; its provenance
/// (the command, date, version and commit, every input's size, SHA-256 and origin); and its PDF,
/// printed by headless Chromium when present, else the figures' PDFs merged by poppler's
/// pdfunite.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::report {

struct table {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string note;  ///< a line under the table (what its marks mean); may be empty
};

/// A figure already rendered: DIR-relative file names of its PNG (embedded) and of its PDF.
struct figure_ref {
  std::string title;
  std::string png;  ///< relative to the report folder
  std::string pdf;  ///< relative to the report folder (for the merged PDF); may be empty
  std::string caption;
};

struct section {
  std::string heading;
  std::vector<std::string> paragraphs;  ///< plain text (escaped when written)
  std::vector<std::string> warnings;    ///< shown as a highlighted list before the tables
  std::vector<table> tables;
  std::vector<figure_ref> figures;
};

/// One input of the run: what it is, to the byte.
struct input_file {
  std::string file;
  std::uint64_t size_bytes = 0;
  std::string sha256;  ///< lowercase hex
  std::string origin;  ///< where the data came from ("simulated: gyroflip simulate, seed 2", ...)
};

/// Where a page came from: enough to make it again and to know what it was made of.
struct provenance {
  std::string command;   ///< the exact command (or call) that made it
  std::string made_utc;  ///< date and time, ISO 8601 UTC
  std::string version;   ///< gyroflip's version
  std::string commit;    ///< the git commit gyroflip was built from
  std::vector<input_file> inputs;
};

struct page {
  std::string title;
  /// Lines shown in a box under the title, before anything else ("Simulated data: ...").
  std::vector<std::string> banners;
  std::vector<section> sections;
  provenance made;
};

/// The size and SHA-256 of a file (input_file without its origin). Errors: it cannot be read.
[[nodiscard]] result<input_file> identify_file(const std::string& path);

/// The current date and time, ISO 8601 UTC to the second ("2026-11-24T09:15:02Z").
[[nodiscard]] std::string utc_now();

/// A warning for a build from a tree with uncommitted changes (`commit` ends in "+modified",
/// cmake/build_commit.cmake): its commit does not identify the code. Empty otherwise. Pages show
/// it as a banner.
[[nodiscard]] std::string modified_build_note(std::string_view commit);

/// `t` as plain text: the caption, then the columns padded to their widest cell (by UTF-8 code
/// points), then the note. What the command line prints of a table the page shows.
[[nodiscard]] std::string text(const table& t);

/// The HTML text of `p`; images read from `dir` (the report folder) and embedded. Errors: an
/// image that cannot be read.
[[nodiscard]] result<std::string> html(const page& p, const std::string& dir);

/// The SHA-256 of a file's bytes, lowercase hex (FIPS 180-4, by OpenSSL's libcrypto).
[[nodiscard]] result<std::string> sha256_file(const std::string& path);

/// The SHA-256 of `bytes`, lowercase hex (as sha256_file).
[[nodiscard]] result<std::string> sha256_text(std::string_view bytes);

/// DIR/report.pdf from DIR/index.html by headless Chromium (`chromium` on PATH), else the
/// figures' PDFs merged by `pdfunite`. Errors: neither program works.
[[nodiscard]] status print_pdf(const page& p, const std::string& dir);

}  // namespace gyroflip::report
