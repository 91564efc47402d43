// The report module: golden gnuplot scripts (text, not pixels), rendering through gnuplot into
// all three formats with nothing left behind, and the figures' content from known inputs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/method/runs.hpp"
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
  // Two significant digits, the trailing zero kept (review of issue 31, L2: "std 0.01").
  EXPECT_NE(ft.caption.find("mean 0.4000 °/s, std 0.010 °/s"), std::string::npos) << ft.caption;
  // Review R16: runs at 4, 12 and 20 degC got one pooled "mean +- std" band, a number in no
  // table; over a temperature span of 2 degC or more the runs are drawn without it.
  for (int k = 0; k < 3; ++k) runs[static_cast<std::size_t>(k)].cal.temp_c = 4.0 + 8.0 * k;
  const auto spread = report::delta_n_runs_figure(runs, "ΔN per run");
  EXPECT_EQ(report::script(spread, "runs", formats).find("filledcurves"), std::string::npos);
  EXPECT_EQ(spread.data.size(), 1u);
  EXPECT_NE(spread.caption.find("over 4.0–20.0 °C"), std::string::npos) << spread.caption;
  EXPECT_NE(spread.caption.find("no pooled mean ± std"), std::string::npos) << spread.caption;
}

// The ΔN(T) figure's bands say what they hold (review of issue 31: the line's interval was
// labelled as if it held the runs, and 3 of 5 runs lay outside it). Simulated campaigns of 5
// runs over 10-30 degC with known truth, scattering 5 times their own errors from one power-up
// to the next (fixed seed): a new run at a random temperature lies in the band labelled as a new
// run's at its 68 % (the band read off the figure's own data, interpolated), and the true line
// in the band labelled as the fit's. Tolerance: 800 campaigns give a binomial std of 0.016;
// +-0.05 is 3 of it. The fit's band holds far fewer new runs: that is why the labels matter.
TEST(ReportFigure, DeltaNTemperatureBandsHoldWhatTheirLabelsSay) {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> z;
  std::uniform_real_distribution<double> u01;
  const auto truth = [](double t_c) { return 3.0e-3 - 5.0e-5 * (t_c - 20.0); };
  const double se = 1e-4, tau = 5e-4;
  const std::string fit_label = "ΔN(T) fit, 68 %";
  const std::string run_label = "a new power-up's run, 68 % (prediction)";
  // The band's half-width about its centre at t_c, by linear interpolation of its points.
  const auto inside = [](const report::series& b, double t_c, double v) {
    const auto it = std::lower_bound(b.x.begin(), b.x.end(), t_c);
    const auto j = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(
        it - b.x.begin(), 1, static_cast<std::ptrdiff_t>(b.x.size()) - 1));
    const double w = (t_c - b.x[j - 1]) / (b.x[j] - b.x[j - 1]);
    const double lo = b.y_lo[j - 1] + w * (b.y_lo[j] - b.y_lo[j - 1]);
    const double hi = b.y_hi[j - 1] + w * (b.y_hi[j] - b.y_hi[j - 1]);
    return v >= lo && v <= hi;
  };
  int n = 0, run_in_run_band = 0, run_in_fit_band = 0, line_in_fit_band = 0;
  for (int k = 0; k < 800; ++k) {
    std::vector<io::calibration_entry> runs;
    for (int i = 0; i < 5; ++i) {
      method::calibration c;
      c.temp_c = 10.0 + 5.0 * i;
      c.delta_n_dps = truth(c.temp_c) + tau * z(rng) + se * z(rng);
      c.stderr_correlated_dps = se;
      runs.push_back({"run" + std::to_string(i), c, std::nullopt});
    }
    std::vector<method::calibration> cals;
    for (const auto& r : runs) cals.push_back(r.cal);
    const auto m = method::fit_runs_model(cals);
    ASSERT_TRUE(m && *m);
    const auto f = report::delta_n_temperature_figure(runs, **m, "ΔN against temperature");
    const auto band = [&](const std::string& title) {
      const auto it = std::find_if(f.data.begin(), f.data.end(), [&](const report::series& s) {
        return s.title == title && s.how == report::series::style::band;
      });
      return it == f.data.end() ? nullptr : &*it;
    };
    const auto* fit_band = band(fit_label);
    const auto* run_band = band(run_label);
    ASSERT_NE(fit_band, nullptr) << "no band labelled " << fit_label;
    ASSERT_NE(run_band, nullptr) << "no band labelled " << run_label;
    const double t_c = 10.0 + 20.0 * u01(rng);
    const double fresh = truth(t_c) + tau * z(rng) + se * z(rng);
    ++n;
    run_in_run_band += inside(*run_band, t_c, fresh);
    run_in_fit_band += inside(*fit_band, t_c, fresh);
    line_in_fit_band += inside(*fit_band, t_c, truth(t_c));
    if (k == 0) {
      const std::vector formats{report::image_format::svg};
      const auto gp = report::script(f, "dt", formats);
      EXPECT_NE(gp.find("title '" + fit_label + "'"), std::string::npos) << gp;
      // gnuplot doubles a quote inside a quoted string.
      EXPECT_NE(gp.find("title 'a new power-up''s run, 68 % (prediction)'"), std::string::npos)
          << gp;
      EXPECT_NE(f.caption.find("the prediction band holds 68 % of new runs"), std::string::npos)
          << f.caption;
    }
  }
  EXPECT_NEAR(run_in_run_band / static_cast<double>(n), 0.683, 0.05);
  EXPECT_NEAR(line_in_fit_band / static_cast<double>(n), 0.683, 0.05);
  EXPECT_LT(run_in_fit_band / static_cast<double>(n), 0.45);
}

// The Allan plot's letters cover no data (review of issue 31: the "B" of the raw curve sat on
// its last point and on the line into it). Checked against gnuplot's own geometry, not the
// library's model of it: each figure is rendered, its PNG block run again by gnuplot with the
// frame, character size and axis ranges printed (GPVAL_*), and every letter's box (a full
// character cell wide per character, 0.75 of its height tall, at its point plus its offset)
// must stay clear of every point (3 px), error bar and line of the data. The review's figure
// (Figs 5/6's raw and compensated curves, B read at the raw curve's last point), as the report
// and as `noise --plot` draw it (key inside), and the golden white curve.
std::vector<report::allan_curve> review_curves() {
  const double raw_dph[][4] = {
      {1.7909791666666666, 182.09411207904094, 178.12028896273995, 186.3461713552758},
      {3.581958333333333, 133.71020928563038, 130.22482053631106, 137.49112547779967},
      {7.163916666666666, 102.87397272587083, 99.22016989439605, 106.96333366017807},
      {14.327833333333333, 79.64299825879355, 75.76016252149911, 84.19085277782995},
      {28.655666666666665, 71.2861982112741, 66.51631395024376, 77.25423634108773},
      {57.31133333333333, 57.19341179235918, 51.96908276099018, 64.392132292962},
      {114.62266666666666, 49.702948681948826, 43.55480570107931, 59.49269668034919},
      {229.24533333333332, 62.742761160518526, 53.233559751019754, 80.24513002644214},
      {458.49066666666664, 52.13325826692796, 41.496242437495646, 80.04763227901455}};
  report::allan_curve raw, comp;
  raw.name = "raw: dwell means at 0°";
  comp.name = "compensated (simple cycles)";
  for (const auto& p : raw_dph) {
    analysis::deviation_point r;
    r.tau_s = p[0];
    r.dev = p[1] / 3600.0;
    r.ci_lo = p[2] / 3600.0;
    r.ci_hi = p[3] / 3600.0;
    raw.points.push_back(r);
    const double d = 0.0467 / std::sqrt(p[0]);
    r.dev = d;
    r.ci_lo = 0.9 * d;
    r.ci_hi = 1.15 * d;
    comp.points.push_back(r);
  }
  analysis::noise_terms t;
  t.arw = {true, 3.9 / 60.0, 3.5 / 60.0, 4.3 / 60.0};
  t.bias_instability = {true, 78.5 / 3600.0, 70.0 / 3600.0, 90.0 / 3600.0};
  t.rrw = {false, 0.0, 0.0, 220.0 / 3600.0 / 60.0};
  t.fit_min_tau_s = 458.49066666666664;
  raw.terms = t;
  analysis::noise_terms c = t;
  c.arw = {true, 2.8 / 60.0, 2.6 / 60.0, 3.0 / 60.0};
  c.bias_instability = {false, 0.0, 0.0, 9.22 / 3600.0};
  comp.terms = c;
  return {raw, comp};
}

struct gp_geometry {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, hchar = 0, vchar = 0, xmin = 0, xmax = 0, ymin = 0,
         ymax = 0;
};

void expect_letters_clear_of_data(const report::figure& f, const std::string& what) {
  const test::temp_dir dir;
  const std::vector formats{report::image_format::png};
  const auto st = report::render(f, dir.path(), "a", formats);
  if (!st && st.err().message.find("install gnuplot") != std::string::npos) GTEST_SKIP();
  ASSERT_TRUE(st) << st.err().message;
  const std::string gp = read(dir.path() + "/a.gp");
  const auto end = gp.find("unset output");
  ASSERT_NE(end, std::string::npos);
  std::ofstream(dir.path() + "/probe.gp")
      << gp.substr(0, end)
      << "unset output\nprint sprintf('%.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g', "
         "GPVAL_TERM_XMIN, GPVAL_TERM_XMAX, GPVAL_TERM_YMIN, GPVAL_TERM_YMAX, "
         "GPVAL_TERM_HCHAR * 1.0 / GPVAL_TERM_SCALE, GPVAL_TERM_VCHAR * 1.0 / GPVAL_TERM_SCALE, "
         "GPVAL_X_MIN, GPVAL_X_MAX, GPVAL_Y_MIN, GPVAL_Y_MAX)\n";
  ASSERT_EQ(std::system(("cd " + dir.path() + " && gnuplot probe.gp 2> geometry.txt").c_str()), 0);
  // The numbers are print's line, the last: gnuplot may warn before it (under the C locale of a
  // fresh Debian's chroot: "iconv failed to convert degree sign").
  std::string probe = read(dir.path() + "/geometry.txt");
  while (!probe.empty() && probe.back() == '\n') probe.pop_back();
  const auto last = probe.rfind('\n');
  gp_geometry g;
  std::istringstream(last == std::string::npos ? probe : probe.substr(last + 1)) >> g.x0 >> g.x1 >>
      g.y0 >> g.y1 >> g.hchar >> g.vchar >> g.xmin >> g.xmax >> g.ymin >> g.ymax;
  ASSERT_GT(g.x1, g.x0) << read(dir.path() + "/geometry.txt");
  ASSERT_GT(g.hchar, 0.0);
  const auto px = [&](double x) {
    return g.x0 + (g.x1 - g.x0) * std::log10(x / g.xmin) / std::log10(g.xmax / g.xmin);
  };
  const auto py = [&](double y) {
    return g.y0 + (g.y1 - g.y0) * std::log10(y / g.ymin) / std::log10(g.ymax / g.ymin);
  };
  // The data drawn: every error-bar series' file, joined when the script draws it with lines too.
  const std::string plot = gp.substr(gp.find("\nplot ") + 1, end);
  struct drawn {
    std::vector<std::array<double, 4>> rows;
    bool joined;
  };
  std::vector<drawn> data;
  for (std::size_t k = 1;; ++k) {
    const std::string file = "a_" + std::to_string(k) + ".dat";
    if (!fs::exists(dir.path() + "/" + file)) break;
    if (plot.find("'" + file + "' using 1:2:3:4 with yerrorbars") == std::string::npos) continue;
    drawn d{{}, plot.find("'" + file + "' using 1:2 with lines lw 1") != std::string::npos};
    std::istringstream in(read(dir.path() + "/" + file));
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::array<double, 4> r{};
      std::istringstream(line) >> r[0] >> r[1] >> r[2] >> r[3];
      d.rows.push_back(r);
    }
    data.push_back(std::move(d));
  }
  ASSERT_FALSE(data.empty());
  const std::regex label_re(
      R"(set label \d+ '([^']*)' at ([^,]+),(\S+) (left|right|center) .* offset ([^,]+),(\S+) )");
  int letters = 0;
  for (std::sregex_iterator it(gp.begin(), gp.begin() + static_cast<std::ptrdiff_t>(end), label_re),
       stop;
       it != stop; ++it) {
    ++letters;
    const auto& m = *it;
    const std::string text = m[1];
    double chars = 0.0;
    for (const char c : text) chars += (static_cast<unsigned char>(c) & 0xC0) != 0x80 ? 1.0 : 0.0;
    const double ax = px(std::stod(m[2])) + std::stod(m[5]) * g.hchar;
    const double ay = py(std::stod(m[3])) + std::stod(m[6]) * g.vchar;
    const double w = chars * g.hchar, h = 0.75 * g.vchar;
    const double bx0 = m[4] == "right" ? ax - w : m[4] == "left" ? ax : ax - w / 2.0;
    const double bx1 = bx0 + w, by0 = ay - h / 2.0, by1 = ay + h / 2.0;
    // A segment meets the box: sampled finely (the boxes are 10-20 px, the samples < 1 px apart).
    const auto meets = [&](double xa, double ya, double xb, double yb, double pad) {
      const int n = 2 + static_cast<int>(std::hypot(xb - xa, yb - ya));
      for (int i = 0; i <= n; ++i) {
        const double x = xa + (xb - xa) * i / n, y = ya + (yb - ya) * i / n;
        if (x > bx0 - pad && x < bx1 + pad && y > by0 - pad && y < by1 + pad) return true;
      }
      return false;
    };
    for (const auto& d : data)
      for (std::size_t i = 0; i < d.rows.size(); ++i) {
        const auto& r = d.rows[i];
        const double x = px(r[0]);
        EXPECT_FALSE(meets(x, py(r[1]), x, py(r[1]), 3.0))
            << what << ": '" << text << "' covers the point at tau " << r[0];
        EXPECT_FALSE(meets(x, py(r[2]), x, py(r[3]), 0.5))
            << what << ": '" << text << "' covers the error bar at tau " << r[0];
        if (d.joined && i > 0) {
          EXPECT_FALSE(meets(px(d.rows[i - 1][0]), py(d.rows[i - 1][1]), x, py(r[1]), 0.5))
              << what << ": '" << text << "' covers the line into tau " << r[0];
        }
      }
  }
  EXPECT_GT(letters, 0) << what;
}

TEST(ReportFigure, AllanLettersCoverNoData) {
  const auto curves = review_curves();
  expect_letters_clear_of_data(report::gyro_allan_figure(curves, "Allan deviation"), "report");
  const auto noise = report::noise_figure(curves, "deg/h", "Allan deviation");
  ASSERT_TRUE(noise);
  expect_letters_clear_of_data(*noise, "noise --plot");
  const std::vector<report::allan_curve> white{white_curve()};
  expect_letters_clear_of_data(report::allan_figure(white, "°/s", "Allan"), "white");
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
