/// \file
/// \brief The report a person would send (issue 10): one self-contained HTML page (figures
/// embedded as data: URIs, no network, a print style sheet), built from sections of tables,
/// figures and paragraphs; the SHA-256 of the inputs for its provenance; and its PDF, printed by
/// headless Chromium when present, else the figures' PDFs merged by poppler's pdfunite.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::report {

struct table {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
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
  std::vector<table> tables;
  std::vector<figure_ref> figures;
};

struct page {
  std::string title;
  std::vector<section> sections;
  std::string command;                                      ///< the exact command that made it
  std::string version;                                      ///< gyroflip's version
  std::vector<std::pair<std::string, std::string>> inputs;  ///< (file, SHA-256 hex)
};

/// The HTML text of `p`; images read from `dir` (the report folder) and embedded. Errors: an
/// image that cannot be read.
[[nodiscard]] result<std::string> html(const page& p, const std::string& dir);

/// The SHA-256 of a file's bytes, lowercase hex (FIPS 180-4, by OpenSSL's libcrypto).
[[nodiscard]] result<std::string> sha256_file(const std::string& path);

/// DIR/report.pdf from DIR/index.html by headless Chromium (`chromium` on PATH), else the
/// figures' PDFs merged by `pdfunite`. Errors: neither program works.
[[nodiscard]] status print_pdf(const page& p, const std::string& dir);

}  // namespace gyroflip::report
