// The report module: golden gnuplot scripts (text, not pixels), rendering through gnuplot into
// all three formats with nothing left behind, and the figures' content from known inputs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/report/figures.hpp"
#include "gyroflip/report/page.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace gyroflip;

const std::string golden_dir = std::string(GYROFLIP_SOURCE_DIR) + "/tests/report/golden/";

std::string read(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Compares with the golden file; GYROFLIP_UPDATE_GOLDEN=1 rewrites it (review the diff).
void expect_golden(const std::string& text, const std::string& name) {
  const auto path = golden_dir + name;
  if (std::getenv("GYROFLIP_UPDATE_GOLDEN") != nullptr)
    std::ofstream(path, std::ios::binary) << text;
  EXPECT_EQ(text, read(path)) << "golden " << path << " (GYROFLIP_UPDATE_GOLDEN=1 rewrites it)";
}

// A white-noise OADEV curve with N = 0.01 deg/s/sqrt(Hz) and bounds, and its fitted terms.
report::allan_curve white_curve() {
  report::allan_curve c;
  c.name = "compensated";
  for (double tau = 1.0; tau <= 1024.0; tau *= 2.0) {
    analysis::deviation_point p;
    p.tau_s = tau;
    p.dev = 0.01 / std::sqrt(tau);
    p.ci_lo = 0.9 * p.dev;
    p.ci_hi = 1.1 * p.dev;
    c.points.push_back(p);
  }
  analysis::noise_terms t;
  t.arw = {true, 0.01, 0.009, 0.011};
  t.bias_instability = {false, 0.0, 0.0, 0.0004};
  t.rrw = {false, 0.0, 0.0, 0.00002};
  t.fit_min_tau_s = 1024.0;
  t.bias_floor_tau_s = 1024.0;
  t.bias_floor_dev = 0.01 / 32.0;
  c.terms = t;
  return c;
}

TEST(ReportFigure, AllanScriptIsGolden) {
  const std::vector<report::allan_curve> curves{white_curve()};
  const auto f = report::allan_figure(curves, "°/s", "Allan deviation");
  const std::vector formats{report::image_format::png, report::image_format::svg,
                            report::image_format::pdf};
  expect_golden(report::script(f, "allan", formats), "allan.gp");
  // The fitted ARW line passes through N at tau = 1 s, and that point is marked.
  ASSERT_EQ(f.data.size(), 2u);
  EXPECT_NEAR(f.data[1].y.front() * std::sqrt(f.data[1].x.front()), 0.01, 1e-12);
  ASSERT_FALSE(f.notes.empty());
  EXPECT_EQ(f.notes[0].x, 1.0);
  EXPECT_EQ(f.notes[0].y, 0.01);
}

TEST(ReportFigure, PaperFiguresAreGolden) {
  std::vector<method::dwell> dwells;
  std::vector<method::cycle> cycles;
  std::vector<method::compensated_cycle> comp;
  for (int k = 0; k < 6; ++k) {
    dwells.push_back(
        {k % 2 == 0 ? 0 : 1, 0.9 * k, (k % 2 == 0 ? 0.5 : -0.3) + 0.01 * k, 20.0, 256});
    cycles.push_back({1.8 * k, 0.4, 0.1 + 0.001 * k, 20.0});
    comp.push_back({1.8 * k, 0.001 * (k - 2.5), 0.1, 20.0, 0.4});
  }
  method::compensation_summary s;
  s.cycles = 6;
  s.mean_dps = 0.0;
  s.std_dps = 0.00187;
  const std::vector formats{report::image_format::svg};
  expect_golden(
      report::script(report::dwell_figure(dwells, "Output at 0° and 180°"), "dwells", formats),
      "dwells.gp");
  expect_golden(
      report::script(report::compensated_figure(comp, s, "Compensated output"), "comp", formats),
      "compensated.gp");
  expect_golden(report::script(report::bias_figure(cycles, "Bias"), "bias", formats), "bias.gp");
  std::vector<io::calibration_entry> runs;
  for (int k = 0; k < 3; ++k) {
    method::calibration c;
    c.delta_n_dps = 0.39 + 0.01 * k;
    c.stderr_correlated_dps = 0.002;
    c.temp_c = 20.0 + 0.5 * k;
    runs.push_back({"run" + std::to_string(k), c, std::nullopt});
  }
  const auto ft = report::delta_n_runs_figure(runs, "ΔN per run");
  expect_golden(report::script(ft, "runs", formats), "delta_n_runs.gp");
  EXPECT_NE(ft.caption.find("mean 0.4000 °/s, std 0.01 °/s"), std::string::npos) << ft.caption;
  // Review R16: runs at 4, 12 and 20 degC got one pooled "mean +- std" band, a number in no
  // table; over a temperature span of 2 degC or more the runs are drawn without it.
  for (int k = 0; k < 3; ++k) runs[static_cast<std::size_t>(k)].cal.temp_c = 4.0 + 8.0 * k;
  const auto spread = report::delta_n_runs_figure(runs, "ΔN per run");
  EXPECT_EQ(report::script(spread, "runs", formats).find("filledcurves"), std::string::npos);
  EXPECT_EQ(spread.data.size(), 1u);
  EXPECT_NE(spread.caption.find("over 4.0–20.0 °C"), std::string::npos) << spread.caption;
  EXPECT_NE(spread.caption.find("no pooled mean ± std"), std::string::npos) << spread.caption;
}

TEST(ReportFigure, RendersPngSvgPdfAndLeavesNothingElse) {
  const test::temp_dir dir;
  const std::vector<report::allan_curve> curves{white_curve()};
  const std::vector formats{report::image_format::png, report::image_format::svg,
                            report::image_format::pdf};
  const auto s =
      report::render(report::allan_figure(curves, "°/s", "Allan"), dir.path(), "a", formats);
  if (!s && s.err().message.find("install gnuplot") != std::string::npos)
    GTEST_SKIP() << "gnuplot not installed";
  ASSERT_TRUE(s) << s.err().message;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names,
            (std::vector<std::string>{"a.gp", "a.pdf", "a.png", "a.svg", "a_1.dat", "a_2.dat"}));
  EXPECT_EQ(read(dir.path() + "/a.png").substr(1, 3), "PNG");
  EXPECT_EQ(read(dir.path() + "/a.pdf").substr(0, 5), "%PDF-");
  EXPECT_NE(read(dir.path() + "/a.svg").find("<svg"), std::string::npos);
  // A figure with nothing to plot is an error, and leaves nothing.
  report::figure empty;
  empty.title = "empty";
  EXPECT_FALSE(report::render(empty, dir.path(), "e", formats));
  EXPECT_FALSE(fs::exists(dir.path() + "/e.gp"));
}

TEST(ReportPage, Sha256OfKnownText) {
  const test::temp_dir dir;
  std::ofstream(dir.path() + "/abc") << "abc";
  // FIPS 180-4 example: SHA-256("abc").
  EXPECT_EQ(*report::sha256_file(dir.path() + "/abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_FALSE(report::sha256_file(dir.path() + "/none"));
}

// Issue 21: from the installed package, `report` failed with "neither chromium nor pdfunite
// (poppler-utils) ran: " and nothing after it. With no renderer on PATH the error says what each
// did and what to install; without gnuplot, to install gnuplot-nox.
TEST(ReportPage, WithoutARendererTheErrorSaysWhatToInstall) {
  const test::temp_dir dir, empty_path;
  report::page p;
  p.title = "t";
  report::section s;
  s.figures.push_back({"f", "figures/f.png", "figures/f.pdf", ""});
  p.sections.push_back(s);
  const std::string path = std::getenv("PATH") != nullptr ? std::getenv("PATH") : "";
  ::setenv("PATH", empty_path.path().c_str(), 1);
  const auto pdf = report::print_pdf(p, dir.path());
  p.sections.clear();
  const auto no_figure = report::print_pdf(p, dir.path());
  const std::vector<report::allan_curve> curves{white_curve()};
  const auto figure = report::render(report::allan_figure(curves, "°/s", "Allan"), dir.path(), "a",
                                     std::array{report::image_format::png});
  ::setenv("PATH", path.c_str(), 1);
  ASSERT_FALSE(pdf);
  EXPECT_EQ(pdf.err().message,
            "cannot make report.pdf: no Chromium (chromium, chromium-browser, google-chrome); no "
            "pdfunite. Install poppler-utils (pdfunite merges the figures' PDFs) or chromium "
            "(prints the whole page)");
  ASSERT_FALSE(no_figure);
  EXPECT_NE(no_figure.err().message.find("no figure for pdfunite to merge. Install poppler-utils"),
            std::string::npos)
      << no_figure.err().message;
  ASSERT_FALSE(figure);
  EXPECT_NE(figure.err().message.find("install gnuplot-nox"), std::string::npos)
      << figure.err().message;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ReportCli, AdevPlotWritesImageScriptAndData) {
  const test::temp_dir dir;
  std::ofstream csv(dir.path() + "/y.csv");
  csv << "rate_dps\n";
  for (int k = 0; k < 4000; ++k)
    csv << std::sin(k * 0.37) * 0.01 + 0.001 * ((k * 7919) % 13) << "\n";
  csv.close();
  const auto r = test::run_cli({"adev", dir.path() + "/y.csv", "--rate", "100", "--plot",
                                dir.path() + "/fig.svg", "-o", dir.path() + "/y_adev.csv"});
  if (r.exit_code == 1 && r.err.find("install gnuplot") != std::string::npos)
    GTEST_SKIP() << "gnuplot not installed";
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read(dir.path() + "/fig.svg").find("<svg"), std::string::npos);
  EXPECT_NE(read(dir.path() + "/fig.gp").find("set output 'fig.svg'"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir.path() + "/fig_1.dat"));
  const auto bad = test::run_cli(
      {"adev", dir.path() + "/y.csv", "--rate", "100", "--plot", dir.path() + "/fig.jpg"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--plot must name a .png, .svg or .pdf file"), std::string::npos);
}

}  // namespace
