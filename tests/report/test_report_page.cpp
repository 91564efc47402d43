// Golden tests of the pages' structure (issue 22): the headings, banners, warnings, table
// captions, column headings and the row names of the key-value tables (identity, budget,
// provenance) of `gyroflip report` (a calibration, a compensation with --expected-rate) and of
// `gyroflip reproduce --quick`, compared with tests/report/golden/*.structure
// (GYROFLIP_UPDATE_GOLDEN=1 rewrites them: review the diff). Numbers, dates, hashes and the
// commit are not part of the structure (figure captions on the page carry none: the numbers are
// in the images); the temporary folder reads TMP.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/digits.hpp"
#include "gyroflip/report/page.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using gyroflip::test::read_page;
using gyroflip::test::read_text;
using gyroflip::test::run_cli;
using gyroflip::test::temp_dir;

const std::string golden_dir = std::string(GYROFLIP_SOURCE_DIR) + "/tests/report/golden/";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  for (auto at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// The text between `open`'s end and the next `close` (tags inside removed).
std::string inner(const std::string& html, std::size_t from, const std::string& close) {
  const auto start = html.find('>', from) + 1;
  const auto end = html.find(close, start);
  std::string t;
  bool tag = false;
  for (std::size_t k = start; k < end; ++k) {
    if (html[k] == '<') tag = true;
    if (!tag) t += html[k];
    if (html[k] == '>') tag = false;
  }
  return t;
}

// One line per structural element, in page order.
std::string structure(const std::string& html, const std::string& tmp) {
  struct mark {
    std::string open, close, name;
  };
  const std::vector<mark> marks{{"<h1>", "</h1>", "h1"},
                                {"<h2>", "</h2>", "h2"},
                                {"<p class=\"banner\">", "</p>", "banner"},
                                {"<div class=\"warn\">", "</div>", "warnings"},
                                {"<caption>", "</caption>", "table"},
                                {"<th", "</th>", "  column"},
                                {"<tr><td class=\"t\">", "</td>", "  row"},
                                {"<figcaption>", "</figcaption>", "figure"}};
  std::string out;
  std::size_t at = 0;
  while (true) {
    std::size_t best = std::string::npos;
    const mark* which = nullptr;
    for (const auto& m : marks) {
      const auto p = html.find(m.open, at);
      if (p < best) {
        best = p;
        which = &m;
      }
    }
    if (which == nullptr) break;
    std::string text = which->name == "warnings"
                           ? std::string("(list)")
                           : inner(html, best + which->open.size() - 1, which->close);
    // The build's own banner depends on the tree the tests were built from, not on the page.
    if (!text.starts_with("Built from a modified source tree"))
      out += which->name + ": " + replaced(text, tmp, "TMP") + "\n";
    at = best + which->open.size();
  }
  return out;
}

void expect_golden(const std::string& text, const std::string& name) {
  const auto path = golden_dir + name;
  if (std::getenv("GYROFLIP_UPDATE_GOLDEN") != nullptr)
    std::ofstream(path, std::ios::binary) << text;
  EXPECT_EQ(text, read_text(path))
      << "golden " << path << " (GYROFLIP_UPDATE_GOLDEN=1 rewrites it)";
}

std::string simulate(const temp_dir& d, const std::string& name, const std::string& temp,
                     const std::string& seed, const std::string& rate = "0") {
  const auto f = d.file(name);
  const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "600", "--temp",
                          temp, "--seed", seed, "--rate-profile", rate, "-o", f});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return f;
}

TEST(ReportPage, CalibrationPageStructureIsGolden) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), b = simulate(d, "b20.csv", "20", "2"),
             c = simulate(d, "c4.csv", "4", "3");
  const auto r =
      run_cli({"report", a, b, c, "--latitude", "42.6", "--axis", "north", "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto html = read_page(d.file("rep/index.html"));
  EXPECT_EQ(html.find("<pre"), std::string::npos);  // tables, not preformatted text
  expect_golden(structure(html, d.path()), "report_calibration.structure");
}

TEST(ReportPage, RateTablePageStructureIsGolden) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), b = simulate(d, "b20.csv", "20", "2");
  ASSERT_EQ(run_cli({"calibrate", a, b, "-o", d.file("cal.json")}).exit_code, 0);
  const auto t = simulate(d, "table.csv", "20", "4", "0.5");
  const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "--expected-rate",
                          "0.5", "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto html = read_page(d.file("rep/index.html"));
  expect_golden(structure(html, d.path()), "report_rate_table.structure");
  // The same run passed as a calibration: not stationary, warned about on the page.
  const auto w = run_cli({"report", t, "-o", d.file("rep2")});
  ASSERT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(read_page(d.file("rep2/index.html")).find("not a stationary run"), std::string::npos);
}

TEST(ReportPage, ReproducePageStructureIsGolden) {
  temp_dir d;
  const auto r = run_cli({"reproduce", "--quick", "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto html = read_page(d.file("rep/index.html"));
  EXPECT_EQ(html.find("<pre"), std::string::npos);
  expect_golden(structure(html, d.path()), "reproduce_quick.structure");
}

// Issue 31 (fourth review, lows): the pages printed a slope of 0 degrees of freedom as
// "4.42171e-06" (6 digits, no error) in a column of fixed numbers, and mixed notations elsewhere.
// Every number on a calibration page and a compensation page is in fixed notation, and every
// "v ± u" has the decimals of u (core/digits).
TEST(ReportPage, EveryNumberIsInOneNotationWithTheDigitsOfItsError) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), c = simulate(d, "c4.csv", "4", "3"),
             f = simulate(d, "f25.csv", "25", "9");
  ASSERT_EQ(run_cli({"report", a, c, "-o", d.file("cal")}).exit_code, 0);
  ASSERT_EQ(run_cli({"calibrate", a, c, "-o", d.file("cal.json")}).exit_code, 0);
  ASSERT_EQ(
      run_cli({"report", f, "--calibration", d.file("cal.json"), "-o", d.file("comp")}).exit_code,
      0);
  for (const auto* page : {"cal", "comp"}) {
    SCOPED_TRACE(page);
    // The page's text, tags gone (std::regex recurses per character: a page overflows its stack).
    const auto html = read_page(d.file(std::string(page) + "/index.html"));
    std::string text;
    bool tag = false;
    for (const char ch : html) {
      if (ch == '<') tag = true;
      if (!tag) text += ch;
      if (ch == '>') {
        tag = false;
        text += ' ';
      }
    }
    text = replaced(replaced(text, "&amp;", "&"), "&nbsp;", " ");
    const auto digit = [&](std::size_t k) {
      return k < text.size() && text[k] >= '0' && text[k] <= '9';
    };
    // No exponent: a digit, 'e', a sign, a digit.
    for (std::size_t k = 1; k + 2 < text.size(); ++k)
      if (text[k] == 'e' && digit(k - 1) && (text[k + 1] == '+' || text[k + 1] == '-') &&
          digit(k + 2))
        ADD_FAILURE() << "scientific notation: ..." << text.substr(k < 60 ? 0 : k - 60, 100);
    // Each "v ± u": v with the decimals of u.
    const std::string pm = " ± ";
    const auto decimals = [](const std::string& n) {
      const auto dot = n.find('.');
      return dot == std::string::npos ? std::size_t{0} : n.size() - dot - 1;
    };
    std::size_t pairs = 0;
    for (auto at = text.find(pm); at != std::string::npos; at = text.find(pm, at + 1)) {
      std::size_t b = at;
      while (b > 0 && (digit(b - 1) || text[b - 1] == '.' || text[b - 1] == '-')) --b;
      std::size_t e = at + pm.size();
      while (digit(e) || (e < text.size() && text[e] == '.')) ++e;
      const auto v = text.substr(b, at - b), u = text.substr(at + pm.size(), e - at - pm.size());
      if (v.empty() || u.empty() || !digit(b + v.size() - 1)) continue;  // not two numbers
      ++pairs;
      EXPECT_EQ(decimals(v), decimals(u)) << v << " ± " << u;
    }
    EXPECT_GT(pairs, 0u);
  }
}

// Hostile review of issue 22: report skipped calibrate's checks. A report is on one sensor
// (calibrate's check: another sensor is refused, exit 2, no folder), a rig setting or power-on
// time that differs between runs is warned about, and the time the sensor was on before each
// run is shown beside the run.
// Fifth review of issue 31, F7: the page showed none of the stationarity test's statistics nor
// what a run cannot see, which calibrate prints. Its table holds each statistic with its limit
// and summary.json the library's one result, the numbers calibrate --json writes.
TEST(ReportChecks, ThePageShowsEachRunsStationarityStatisticsAndWhatItCannotSee) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1");
  const auto cal = run_cli({"calibrate", a, "--json"});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  const auto want = nlohmann::json::parse(cal.out)["files"][0]["stationarity"];
  const auto r = run_cli({"report", a, "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  ASSERT_TRUE(j["runs"][0].contains("stationarity")) << j["runs"][0];
  EXPECT_EQ(j["runs"][0]["stationarity"], want);
  const auto html = read_page(d.file("rep/index.html"));
  EXPECT_NE(html.find("Stationarity of each run"), std::string::npos);
  for (const char* row : {"step: sup-t", "ramp: slope t", "drift: CUSUM", "noise: std(r)",
                          "outlier: |r − median|", "g-term", "cannot see: a step of r"})
    EXPECT_NE(html.find(row), std::string::npos) << row;
  // Each statistic with its limit, in the page's digits.
  for (const char* key : {"step_statistic", "step_statistic_limit", "drift_statistic",
                          "outlier_limit", "scatter_ratio"})
    EXPECT_NE(html.find(">" + gyroflip::fixed_significant(want[key].get<double>(), 3) + "</td>"),
              std::string::npos)
        << key;
  EXPECT_NE(
      html.find(gyroflip::fixed_significant(want["step_hidden_dps"].get<double>(), 2) + " / " +
                gyroflip::fixed_significant(want["step_hidden_end_dps"].get<double>(), 2)),
      std::string::npos);
  EXPECT_NE(html.find(gyroflip::fixed_significant(want["ramp_hidden_dps"].get<double>(), 2)),
            std::string::npos);
}

TEST(ReportChecks, OneSensorRigAndPowerOnAsCalibrateChecksThem) {
  temp_dir d;
  const auto sim = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> a{"simulate", "--duration", "300", "--temp", "20", "-o", d.file(name)};
    a.insert(a.end(), extra.begin(), extra.end());
    const auto r = run_cli(a);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d.file(name);
  };
  const auto hz = sim("hz.csv", {"--sensor", "hz1-90-100a", "--seed", "1"});
  const auto adx = sim("adx.csv", {"--sensor", "adxrs150", "--seed", "2"});
  const auto hz128 = sim("hz128.csv", {"--sensor", "hz1-90-100a", "--seed", "3", "--n-avg", "128",
                                       "--power-on-before", "600"});
  const auto mixed = run_cli({"report", hz, adx, "-o", d.file("mixed")});
  EXPECT_EQ(mixed.exit_code, 2) << mixed.err;
  EXPECT_NE(mixed.err.find("report on one sensor at a time"), std::string::npos) << mixed.err;
  EXPECT_FALSE(std::filesystem::exists(d.file("mixed")));
  const auto rig = run_cli({"report", hz, hz128, "-o", d.file("rig")});
  ASSERT_EQ(rig.exit_code, 0) << rig.err;
  EXPECT_NE(rig.err.find("rig setting differs from " + hz + ": n_avg 256 vs 128"),
            std::string::npos)
      << rig.err;
  EXPECT_NE(rig.err.find("the sensor was on 600 s before the run"), std::string::npos) << rig.err;
  const auto html = read_page(d.file("rig/index.html"));
  EXPECT_NE(html.find("sensor on before the run"), std::string::npos);
  EXPECT_NE(html.find("600 s"), std::string::npos);
  EXPECT_NE(html.find("n_avg 256 vs 128"), std::string::npos);  // the warning on the page
}

// Hostile review of issue 22: `--expected-rate nan` was read as "not given" (NaN was the
// CLI's "not given") and ignored, while Python's report(expected_rate=nan) raises ValueError.
// A non-finite value is refused (exit 2, the flag named, no folder), as is a NaN latitude.
TEST(ReportChecks, NonFiniteNumbersAreRefused) {
  temp_dir d;
  const auto t = simulate(d, "t.csv", "20", "4");
  for (const char* v : {"nan", "inf", "-inf"}) {
    const auto r = run_cli({"report", t, "--expected-rate", v, "-o", d.file("rep")});
    EXPECT_EQ(r.exit_code, 2) << v << ": " << r.err;
    EXPECT_NE(r.err.find("--expected-rate"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("must be a finite number"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(d.file("rep")));
  }
  for (const char* cmd : {"report", "calibrate"}) {
    const auto r = run_cli({cmd, t, "--latitude", "nan", "--axis", "north", "-o", d.file("rep")});
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.err;
    EXPECT_NE(r.err.find("must be a finite number"), std::string::npos) << r.err;
  }
}

// The numbers (digits, with sign, decimals and exponent) in `text`.
std::vector<std::string> numbers_in(const std::string& text) {
  std::vector<std::string> out;
  const std::regex number(R"([-+]?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
       it != std::sregex_iterator(); ++it)
    out.push_back(it->str());
  return out;
}

// The conclusion paragraph and the text of every table (cells, captions, notes) of a page.
std::pair<std::string, std::string> conclusion_and_tables(const std::string& html) {
  const auto h = html.find(">Conclusion</h2>");
  EXPECT_NE(h, std::string::npos);
  const auto p = html.find("<p", h);
  std::string cells;
  for (const auto& [open, close] : {std::pair{"<td", "</td>"}, std::pair{"<caption", "</caption>"},
                                    std::pair{"<p class=\"note\"", "</p>"}})
    for (auto at = html.find(open); at != std::string::npos; at = html.find(open, at + 1))
      cells += inner(html, at, close) + "\n";
  return {inner(html, p, "</p>"), cells};
}

std::vector<std::vector<std::string>> table_rows(const std::string& html,
                                                 const std::string& caption);

// Hostile review of issue 22: the conclusion stated an unresolved dN(T) slope as fact, quoted
// numbers in no table, and gave the dN applied of the first run only. Every number of the
// conclusion is now in a table of the page; a slope with no degrees of freedom is "not resolved";
// the dN applied is given per run with the run's name.
TEST(ReportChecks, TheConclusionQuotesOnlyTheTablesNumbers) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), c = simulate(d, "c4.csv", "4", "3");
  const auto r =
      run_cli({"report", a, c, "--latitude", "42.6", "--axis", "north", "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto [text, cells] = conclusion_and_tables(read_page(d.file("rep/index.html")));
  EXPECT_NE(text.find("not resolved"), std::string::npos) << text;
  EXPECT_NE(text.find("no degrees of freedom"), std::string::npos) << text;
  EXPECT_EQ(text.find("changing by"), std::string::npos) << text;
  for (const auto& n : numbers_in(text))
    EXPECT_NE(cells.find(n.front() == '+' ? n.substr(1) : n), std::string::npos)
        << n << " of the conclusion is in no table: " << text;
  // Two runs at 20 and 4 degC compensated with the dN(T) of both: each run's dN applied.
  ASSERT_EQ(run_cli({"calibrate", a, c, "-o", d.file("cal.json")}).exit_code, 0);
  const auto t20 = simulate(d, "t20.csv", "20", "5", "0.5"),
             t4 = simulate(d, "t4.csv", "4", "6", "0.5");
  const auto rc =
      run_cli({"report", t20, t4, "--calibration", d.file("cal.json"), "-o", d.file("rep2")});
  ASSERT_EQ(rc.exit_code, 0) << rc.err;
  const auto [text2, cells2] = conclusion_and_tables(read_page(d.file("rep2/index.html")));
  EXPECT_NE(text2.find(t20 + " "), std::string::npos) << text2;
  EXPECT_NE(text2.find(t4 + " "), std::string::npos) << text2;
  for (const auto& n : numbers_in(text2))
    EXPECT_NE(cells2.find(n.front() == '+' ? n.substr(1) : n), std::string::npos)
        << n << " of the conclusion is in no table: " << text2;
  // Third review of issue 31 (M3): with three runs (1 degree of freedom) the unresolved slope was
  // quoted as "0.00035 ± 0.000519", its error in no table (which prints 0.00052): every number
  // of the conclusion is now a whole number of a table, not a part of one. M1: the 2-run table
  // printed "0" for the errors nothing determines.
  const auto b = simulate(d, "b20.csv", "20", "2");
  const auto r3 =
      run_cli({"report", a, b, c, "--latitude", "42.6", "--axis", "north", "-o", d.file("rep3")});
  ASSERT_EQ(r3.exit_code, 0) << r3.err;
  const auto [text3, cells3] = conclusion_and_tables(read_page(d.file("rep3/index.html")));
  EXPECT_NE(text3.find("ΔN(T) of 3 runs"), std::string::npos) << text3;
  for (const auto& [t, tables] :
       {std::pair{text, cells}, std::pair{text2, cells2}, std::pair{text3, cells3}}) {
    const auto in_tables = numbers_in(tables);
    for (const auto& n : numbers_in(t))
      EXPECT_NE(std::find(in_tables.begin(), in_tables.end(), n.front() == '+' ? n.substr(1) : n),
                in_tables.end())
          << n << " of the conclusion is no number of a table: " << t;
  }
  const auto two = table_rows(read_page(d.file("rep/index.html")), "ΔN(T) =");
  ASSERT_EQ(two.size(), 2U);
  for (const auto& row : two)
    for (std::size_t k = 2; k < row.size(); ++k)
      EXPECT_NE(row[k], "0") << "an error of 0 where there are no degrees of freedom";
}

// The cells of each row of the table captioned `caption` (tags removed, &lt; as <).
std::vector<std::vector<std::string>> table_rows(const std::string& html,
                                                 const std::string& caption) {
  std::vector<std::vector<std::string>> rows;
  const auto from = html.find("<caption>" + caption);
  const auto to = html.find("</table>", from);
  for (auto r = html.find("<tr><td", from); r < to; r = html.find("<tr><td", r + 1)) {
    std::vector<std::string> cells;
    const auto end = html.find("</tr>", r);
    for (auto c = html.find("<td", r); c < end; c = html.find("<td", c + 1))
      cells.push_back(replaced(inner(html, c, "</td>"), "&lt;", "<"));
    rows.push_back(cells);
  }
  return rows;
}

struct plot_label {
  std::string text;
  double x = 0.0, y = 0.0;
  std::string color;
};

// The read-off marks ("set label K 'TEXT' at X,Y ... tc rgb 'COLOUR'") of a gnuplot script.
std::vector<plot_label> labels_of(const std::string& gp) {
  std::vector<plot_label> out;
  const std::regex re(R"(set label \d+ '([^']*)' at ([^,]+),(\S+) \w+ front tc rgb '([^']*)')");
  for (std::sregex_iterator it(gp.begin(), gp.end(), re), e; it != e; ++it)
    out.push_back({(*it)[1], std::stod((*it)[2]), std::stod((*it)[3]), (*it)[4]});
  return out;
}

// The points of a figure data file (x y ...; the stamp line skipped).
std::vector<std::pair<double, double>> points_of(const std::string& file) {
  std::vector<std::pair<double, double>> out;
  std::istringstream in(read_text(file));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.front() == '#') continue;
    std::istringstream l(line);
    double x = 0.0, y = 0.0;
    l >> x >> y;
    out.emplace_back(x, y);
  }
  return out;
}

// Issue 22 (review): the B mark sat on the compensated curve's first local minimum (1.86 deg/h at
// 115 s: B = 2.8 deg/h) while the table said B < 1.63 deg/h; the raw curve's resolved N and B were
// not drawn; the table's raw "floor 10.2 at 57.3" was not the plotted minimum (8.91 at 229 s).
// Every mark is now the table's number, where it belongs: N on its line at 1 h, K at 3 h, B on its
// floor 0.664 B inside the data, "extrapolated" outside it; upper limits named, not drawn.
TEST(ReportChecks, TheAllanPlotDrawsTheNoiseTablesTerms) {
  temp_dir d;
  const auto f = d.file("c20.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "1800", "--temp", "20",
                     "--seed", "1", "-o", f})
                .exit_code,
            0);
  const auto r = run_cli({"report", f, "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = table_rows(read_page(d.file("rep/index.html")), "IEEE 952 noise terms");
  const auto gp = read_text(d.file("rep/figures/run1_allan.gp"));
  const auto labels = labels_of(gp);
  // The title's lines joined (it is broken into lines that fit the image: issue 31).
  const auto caption = replaced(
      gp.substr(gp.find("set title"), gp.find('\n', gp.find("set title")) - gp.find("set title")),
      "\\n", " ");
  ASSERT_EQ(rows.size(), 2u);
  std::size_t drawn = 0, bounds = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& c = rows[k];
    ASSERT_EQ(c.size(), 8u);
    const std::string who = c[1].rfind("raw", 0) == 0 ? "raw" : "compensated";
    const double tau_lo = std::stod(c[2]), tau_hi = std::stod(c[2].substr(c[2].find("–") + 3));
    // The lowest OADEV is the plotted curve's lowest point (file K: the K-th curve).
    const std::regex curve(
        "'(run1_allan_\\d+\\.dat)' using 1:2:3:4 with yerrorbars[^,]* lc rgb '([^']*)' title '" +
        who);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(gp, m, curve)) << who;
    const std::string colour = m[2];
    const auto pts = points_of(d.file("rep/figures/" + m[1].str()));
    const auto low = *std::min_element(pts.begin(), pts.end(),
                                       [](auto a, auto b) { return a.second < b.second; });
    EXPECT_EQ(c[6], fmt::format("{:.3g} at {:.3g}", low.second, low.first)) << who;
    const struct {
      const char* sym;
      const std::string& cell;
      double tau_s;  // 0: B, on its floor inside the data
      double on_line;
    } terms[] = {{"N", c[3], 3600.0, 1.0}, {"B", c[4], 0.0, 0.6643}, {"K", c[5], 10800.0, 1.0}};
    for (const auto& t : terms) {
      const std::string head = who + ": " + t.sym;
      // The mark on the plot is the term's letter in its curve's colour (issue 31: whole
      // sentences beside the points collided); the key entry of its line reads it out.
      const auto mark = std::find_if(labels.begin(), labels.end(), [&](const plot_label& l) {
        return l.text == t.sym && l.color == colour;
      });
      if (t.cell.rfind("< ", 0) == 0) {  // an upper limit: named in the caption, not drawn
        ++bounds;
        EXPECT_EQ(mark, labels.end()) << head << " is an upper limit but drawn";
        EXPECT_NE(caption.find(head + " " + t.cell.substr(0, t.cell.find(' ', 2))),
                  std::string::npos)
            << caption;
        EXPECT_EQ(gp.find("title '" + head + " ="), std::string::npos);
        continue;
      }
      ++drawn;
      const auto value = t.cell.substr(0, t.cell.find(' '));
      ASSERT_NE(mark, labels.end()) << head << " = " << value << " not marked";
      const auto title_at = gp.find("title '" + head + " = " + value + " ");
      ASSERT_NE(title_at, std::string::npos) << head;
      const auto title = gp.substr(title_at, gp.find('\'', title_at + 7) - title_at);
      // On its line where it is read: the table's value within its 3 printed digits.
      EXPECT_NEAR(mark->y, t.on_line * std::stod(value), 0.006 * std::stod(value)) << title;
      const bool inside = mark->x >= tau_lo * 0.99 && mark->x <= tau_hi * 1.01;
      if (t.tau_s > 0.0)
        EXPECT_EQ(mark->x, t.tau_s) << title;
      else
        EXPECT_TRUE(inside) << title;
      EXPECT_EQ(title.find(", extrapolated)") != std::string::npos, !inside) << title;
    }
  }
  EXPECT_EQ(labels.size(), drawn);
  EXPECT_GE(drawn, 3u);  // both N and the raw B (main drew one N only)
  EXPECT_GE(bounds, 1u);
}

// Review of issue 22: the raw series (0-deg dwell means, 256 conversions averaged every 896 of the
// 1.79-s cycle: schedule.hpp) has the white noise of 0.512-s averages spaced 1.79 s, so its fitted
// N is the sensor's times sqrt(7/2) = 1.87. The report names the share d = 2/7 and gives the
// sensor's N = fitted N times sqrt(d), which must find the simulated sensor's ARW (HZ1 preset
// 0.0046 deg/s/rtHz = 0.276 deg/rth; 9000 s, seed 3: tolerance 10 %, about 5 standard errors of
// the fitted N) where the fitted N misses it by 87 %. From one row per dwell (d from the
// recorded AD7739 settings) and from raw rows (d from the rows' spacing).
TEST(ReportChecks, TheRawSeriesNIsTheSensorsWithItsDeadTimeRemoved) {
  temp_dir d;
  const double truth_deg_rth = 0.0046 * 60.0;
  for (const bool raw : {false, true}) {
    const auto f = d.file(raw ? "raw.csv" : "dwells.csv");
    std::vector<std::string> sim{
        "simulate", "--sensor", "hz1-90-100a", "--duration", raw ? "1200" : "9000", "--seed", "3",
        "-o",       f};
    if (raw) sim.emplace_back("--raw");
    ASSERT_EQ(run_cli(sim).exit_code, 0);
    const auto out = d.file(raw ? "rep_raw" : "rep");
    const auto r = run_cli({"report", f, "-o", out});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(read_text(out + "/summary.json"));
    const auto& n = j["runs"][0]["raw_noise"];
    ASSERT_TRUE(n["duty"].is_number()) << n;
    // Raw rows leave the settling conversions out of the dwell, as the rig does (they used to
    // carry the angle: 297/896, and the sensor's N came out 54 % high).
    EXPECT_NEAR(n["duty"].get<double>(), 2.0 / 7.0, raw ? 1e-3 : 1e-12) << n;
    if (raw) continue;  // 1200 s: the duty only
    const double fitted = n["arw_deg_rth"].get<double>(),
                 sensor = n["sensor_arw_deg_rth"].get<double>();
    EXPECT_NEAR(fitted / sensor, std::sqrt(3.5), 1e-9);
    EXPECT_NEAR(sensor, truth_deg_rth, 0.1 * truth_deg_rth) << n;
    EXPECT_GT(fitted, 1.6 * truth_deg_rth) << n;
    const auto rows = table_rows(read_page(out + "/index.html"), "IEEE 952 noise terms");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0][7].rfind(fmt::format("{:.3g} [", sensor), 0), 0u) << rows[0][7];
    EXPECT_NE(rows[0][7].find("(d = 0.286)"), std::string::npos) << rows[0][7];
    EXPECT_EQ(rows[1][7], "–");
  }
}

// `gyroflip report RUN --calibration cal.json --expected-rate RATE -o OUT`: its index.html.
std::string compensation_page(const temp_dir& d, const std::string& run, const std::string& rate,
                              const std::string& out) {
  const auto r = run_cli({"report", run, "--calibration", d.file("cal.json"), "--expected-rate",
                          rate, "-o", d.file(out)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_page(d.file(out + "/index.html"));
}

// `gyroflip calibrate` of simulated runs of `sensor` at 20 degC, one per seed, into cal.json.
void calibrate_at_20c(const temp_dir& d, const std::string& sensor, const std::string& duration_s,
                      const std::vector<std::string>& seeds) {
  std::vector<std::string> cal{"calibrate"};
  for (const auto& seed : seeds) {
    const auto f = d.file("c" + seed + ".csv");
    ASSERT_EQ(run_cli({"simulate", "--sensor", sensor, "--duration", duration_s, "--seed", seed,
                       "--temp", "20", "-o", f})
                  .exit_code,
              0);
    cal.push_back(f);
  }
  cal.insert(cal.end(), {"-o", d.file("cal.json")});
  ASSERT_EQ(run_cli(cal).exit_code, 0);
}

// Review R3: a constant dN calibrated at 20 degC (three HZ1 runs) applied to a 0.5 deg/s run at
// 4 degC. The truth file gives the run's own dN (0.006135 deg/s against the 0.002104 applied: an
// error of 0.0040 deg/s); the stated uncertainty of the dN applied must cover it at 2 sigma. It
// did not (+-0.0015, the 20-degC budget unchanged): the budget now has the preset's temperature
// term (its g-term coefficient and that coefficient's power-up spread, x 16 degC). A sensor whose
// preset states no coefficient (ADXRS150) gets "not valid", not a +-.
TEST(ReportChecks, AConstantDeltaNFarFromItsTemperatureCarriesATemperatureTerm) {
  temp_dir d;
  calibrate_at_20c(d, "hz1-90-100a", "3600", {"1", "2", "3"});
  const auto t4 = d.file("t4.csv"), truth = d.file("t4_truth.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "2000", "--seed", "11",
                     "--temp", "4", "--rate-profile", "0.5", "-o", t4, "--truth", truth})
                .exit_code,
            0);
  const auto r = run_cli({"report", t4, "--calibration", d.file("cal.json"), "--expected-rate",
                          "0.5", "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The run's true dN: the g-term and Earth terms as the sensor sees them, + at 0 deg, - at 180.
  const auto rows = [](const std::string& file) {
    std::vector<std::vector<std::string>> out;
    std::istringstream in(read_text(file));
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::vector<std::string> cells;
      std::stringstream ss(line);
      for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
      out.push_back(cells);
    }
    return out;
  };
  const auto rec = rows(t4), tru = rows(truth);
  ASSERT_EQ(rec.size(), tru.size());
  ASSERT_EQ(rec[0][1], "angle_deg");
  ASSERT_EQ(tru[0][2], "g_term_dps");
  ASSERT_EQ(tru[0][3], "earth_dps");
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 1; i < rec.size(); ++i) {
    if (rec[i][1].empty()) continue;
    const double s = std::stod(tru[i][2]) + std::stod(tru[i][3]);
    sum += std::stod(rec[i][1]) == 0.0 ? s : -s;
    ++n;
  }
  const double true_dn = sum / static_cast<double>(n);
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  const double applied = j["runs"][0]["compensated"]["delta_n_applied_min_dps"];
  const double u = j["budget"]["new_power_up_dps"];
  // The reviewer's numbers were 0.0040 with the weighted mean of the three runs (0.002104 applied);
  // their random-effects mean (issue 31) is nearer their plain mean: 0.0036.
  EXPECT_NEAR(true_dn - applied, 0.00364, 0.0001);
  EXPECT_TRUE(j["budget"]["valid"].get<bool>());
  EXPECT_NEAR(j["budget"]["outside_calibration_c"].get<double>(), 16.0, 0.1);
  EXPECT_GT(j["budget"]["temperature_dps"].get<double>(), 0.0);
  EXPECT_LE(std::abs(true_dn - applied), 2.0 * u) << "u " << u;
  const auto html = read_page(d.file("rep/index.html"));
  // The +- is a standard uncertainty, and the page says so (review N5: the truth lies 1.9 sigma
  // out, plausible only when the reader knows it is 1 sigma); the preset's mean coefficient is
  // stated, not applied.
  EXPECT_NE(html.find("from the preset's temperature coefficient (assumed, 1 σ)"),
            std::string::npos);
  EXPECT_NE(html.find("not applied as a correction"), std::string::npos);
  EXPECT_NE(html.find("68.3 % intervals: 1 σ, × Student's t"), std::string::npos) << html;
  const auto [text, cells] = conclusion_and_tables(html);
  EXPECT_NE(text.find("its temperature term included"), std::string::npos) << text;
  for (const auto& num : numbers_in(text))
    EXPECT_NE(cells.find(num.front() == '+' ? num.substr(1) : num), std::string::npos)
        << num << " of the conclusion is in no table: " << text;

  // No coefficient known: not valid, no +- in the conclusion.
  for (const auto& [name, temp] : {std::pair{"a20.csv", "20"}, std::pair{"a4.csv", "4"}})
    ASSERT_EQ(
        run_cli({"simulate", "--sensor", "adxrs150", "--duration", "600", "--seed", "7", "--temp",
                 temp, "--rate-profile", temp[0] == '4' ? "0.5" : "0", "-o", d.file(name)})
            .exit_code,
        0);
  ASSERT_EQ(run_cli({"calibrate", d.file("a20.csv"), "-o", d.file("acal.json")}).exit_code, 0);
  const auto ra = run_cli({"report", d.file("a4.csv"), "--calibration", d.file("acal.json"),
                           "--expected-rate", "0.5", "-o", d.file("repa")});
  ASSERT_EQ(ra.exit_code, 0) << ra.err;
  const auto ja = nlohmann::json::parse(read_text(d.file("repa/summary.json")));
  EXPECT_FALSE(ja["budget"]["valid"].get<bool>());
  EXPECT_TRUE(ja["budget"]["new_power_up_dps"].is_null());
  const auto [texta, cellsa] = conclusion_and_tables(read_page(d.file("repa/index.html")));
  EXPECT_NE(texta.find("not valid outside the calibration"), std::string::npos) << texta;
  EXPECT_EQ(texta.find("power-up ±"), std::string::npos) << texta;
  EXPECT_NE(texta.find("its uncertainty is not known"), std::string::npos) << texta;
}

// Review R12: a commanded rate of the opposite sign (-200 % scale-factor error) or far beyond the
// sensor's tolerance (HZ1 +-2 %, paper Tab. 2) came with "Nothing in the runs looks wrong". Both
// are warned about on the page and counted in the conclusion; the right commanded rate is not.
TEST(ReportChecks, ACommandedRateTheRunCannotMatchIsWarnedAbout) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), b = simulate(d, "b20.csv", "20", "2");
  ASSERT_EQ(run_cli({"calibrate", a, b, "-o", d.file("cal.json")}).exit_code, 0);
  const auto t = simulate(d, "t.csv", "20", "8", "0.5");
  const auto page_of = [&](const std::string& rate, const std::string& out) {
    const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "--expected-rate",
                            rate, "-o", d.file(out)});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_page(d.file(out + "/index.html"));
  };
  const auto neg = page_of("-0.5", "neg");
  EXPECT_NE(neg.find("has the opposite sign of the commanded -0.5 °/s"), std::string::npos);
  EXPECT_EQ(neg.find("Nothing in the runs looks wrong"), std::string::npos);
  const auto far = page_of("0.4", "far");
  EXPECT_NE(far.find("scale-factor error of 25"), std::string::npos);
  EXPECT_NE(far.find("times the HZ1-90-100A specification's"), std::string::npos);
  EXPECT_EQ(far.find("Nothing in the runs looks wrong"), std::string::npos);
  const auto right = page_of("0.5", "right");
  EXPECT_EQ(right.find("opposite sign"), std::string::npos);
  EXPECT_EQ(right.find("specification's scale-factor tolerance"), std::string::npos);
  // Re-review of issue 22: a run at exactly its commanded 0.002 deg/s, whose scale-factor error
  // is uncertain by ~75 % (the dN error against so slow a rate), was told its table or sensor
  // was wrong. It is told the rate is too slow for a scale factor, nothing else.
  const auto page =
      compensation_page(d, simulate(d, "slow.csv", "20", "15", "0.002"), "0.002", "slow");
  EXPECT_NE(page.find("is too slow to measure a scale factor"), std::string::npos);
  EXPECT_EQ(page.find("opposite sign"), std::string::npos);
  EXPECT_EQ(page.find("times the HZ1-90-100A specification's"), std::string::npos);
}

// Fifth review of issue 31 (leftover): compensate refitted a calibration's runs for the band of
// a between-run variance that changes with temperature (tau^2(T)), while report quoted the file's
// model, which holds no fitted runs, so always the constant (the widest band, at the runs' ends).
// HZ1 runs at 4-36 degC (the preset's turn-on spread of the g-term's temperature coefficient: a
// spread that grows away from the middle) calibrated, then a new run at 20 degC: report's "for
// this power-up ±" and summary.json are compensate's number for that run, below the widest.
// Fails on main: report quoted ±0.0031 (the widest band) where compensate quoted ±0.00059, and
// summary.json had no per-run number.
TEST(ReportChecks, ReportAndCompensateQuoteOneNewPowerUpErrorForARun) {
  temp_dir d;
  std::vector<std::string> cal{"calibrate"};
  int seed = 60;
  for (const char* t : {"4", "12", "20", "28", "36"})
    cal.push_back(simulate(d, fmt::format("c{}.csv", t), t, std::to_string(++seed)));
  cal.insert(cal.end(), {"-o", d.file("cal.json")});
  ASSERT_EQ(run_cli(cal).exit_code, 0);
  const auto t = simulate(d, "t20.csv", "20", "9");
  const auto c = run_cli({"compensate", t, "--calibration", d.file("cal.json"), "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const double quoted = nlohmann::json::parse(c.out)["delta_n"]["new_power_up_dps"].get<double>();
  const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  EXPECT_NEAR(j["runs"][0]["compensated"]["delta_n_new_power_up_dps"].get<double>(), quoted,
              1e-12 * quoted);
  // The band at 20 degC, not the budget's widest (the runs' ends).
  EXPECT_LT(quoted, 0.95 * j["budget"]["new_power_up_dps"].get<double>()) << j["budget"];
  const std::string text = j["conclusion"];
  EXPECT_NE(
      text.find(fmt::format("for this power-up ±{} °/s", gyroflip::fixed_significant(quoted, 2))),
      std::string::npos)
      << quoted << ": " << text;
  // And the per-run table holds that number (the conclusion quotes only the tables' numbers).
  const auto rows = table_rows(read_page(d.file("rep/index.html")), "Per run");
  ASSERT_EQ(rows.size(), 1U);
  ASSERT_GE(rows[0].size(), 3U);
  EXPECT_NE(rows[0][2].find("± " + gyroflip::fixed_significant(quoted, 2)), std::string::npos)
      << rows[0][2];
}

// Fifth review of issue 31, F13: `--expected-rate 0` was refused, yet a run at rest (a stationary
// run, a rate table stopped) compensated and compared with 0 is legitimate. It is accepted: the
// error against 0 with its uncertainty (the run's and the ΔN's), no scale factor (none at rest:
// "–" in the table, null in summary.json), and nothing divided by 0 (every number finite or
// null). Fails on main: exit 2, "must be a non-zero rate".
TEST(ReportChecks, ARunAtRestIsComparedWithZero) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), b = simulate(d, "b20.csv", "20", "2");
  ASSERT_EQ(run_cli({"calibrate", a, b, "-o", d.file("cal.json")}).exit_code, 0);
  const auto t = simulate(d, "rest.csv", "20", "8");
  const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "--expected-rate", "0",
                          "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  const auto& c = j["runs"][0]["compensated"];
  EXPECT_EQ(c["expected_rate_dps"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(c["error_dps"].get<double>(), c["mean_dps"].get<double>());
  EXPECT_TRUE(c["scale_factor_error_ppm"].is_null()) << c.dump();
  EXPECT_TRUE(c["scale_factor_error_u_ppm"].is_null()) << c.dump();
  const auto html = read_page(d.file("rep/index.html"));
  const auto [text, cells] = conclusion_and_tables(html);
  EXPECT_NE(text.find("against the commanded 0 °/s (at rest: no scale factor to measure): an "
                      "error of "),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("scale-factor error of"), std::string::npos) << text;
  for (const auto& words : {text, cells})
    for (const auto& bad : {std::regex(R"(\bnan\b)"), std::regex(R"(\binf\b)")})
      EXPECT_FALSE(std::regex_search(words, bad)) << words;
  EXPECT_EQ(html.find("opposite sign"), std::string::npos);
  EXPECT_EQ(html.find("too slow to measure"), std::string::npos);
}

// Re-review of issue 22: where no temperature coefficient is known (the ADXRS150) the ΔN's
// uncertainty is "not valid"; the page said "the ΔN applied adds not valid ... to every cycle
// alike ... includes both" and printed the scale-factor error as "-46796.2 ppm". Now a sentence
// for the case and the error rounded, its uncertainty said to be unknown.
TEST(ReportChecks, AnUnknownTemperatureTermIsSaidInWords) {
  temp_dir d;
  calibrate_at_20c(d, "adxrs150", "600", {"6", "41"});
  const auto t = d.file("t4.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "adxrs150", "--duration", "600", "--seed", "12",
                     "--temp", "4", "--rate-profile", "0.5", "-o", t})
                .exit_code,
            0);
  const auto page = compensation_page(d, t, "0.5", "rep");
  EXPECT_EQ(page.find("adds not valid"), std::string::npos);
  EXPECT_NE(page.find("has no known uncertainty here"), std::string::npos);
  EXPECT_NE(page.find("the scale-factor error's uncertainty is not known either"),
            std::string::npos);
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  const std::string text = j["conclusion"];
  EXPECT_NE(text.find("a scale-factor error of about "), std::string::npos) << text;
  EXPECT_EQ(text.find(" ppm"), std::string::npos) << text;
}

// Re-review of issue 22: a dN(T) line applied 16 degC beyond its runs (4-20 degC) quoted its
// error at the calibration runs' temperatures (the largest of them, at 20 degC), 2.6 times too
// small, and said "some cycles" were outside when all were. Its error is now taken at the run's
// temperature: far larger than at 20 degC (the line's standard error grows with the distance
// from its runs' mean temperature, closed form of a weighted line fit).
TEST(ReportChecks, ADeltaNLineFarOutsideItsRunsCarriesItsErrorThere) {
  temp_dir d;
  const auto a = simulate(d, "a20.csv", "20", "1"), b = simulate(d, "b4.csv", "4", "4"),
             c = simulate(d, "c12.csv", "12", "5");
  ASSERT_EQ(run_cli({"calibrate", a, b, c, "--degree", "1", "-o", d.file("cal.json")}).exit_code,
            0);
  const auto budget_of = [&](const std::string& temp, const std::string& out) {
    const auto t = simulate(d, out + ".csv", temp, "14", "0.5");
    const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "-o", d.file(out)});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(read_text(d.file(out + "/summary.json")));
  };
  const auto in = budget_of("20", "t20"), far = budget_of("36", "t36");
  const double m_in = in["budget"]["model_dps"].get<double>();
  const double m_far = far["budget"]["model_dps"].get<double>();
  EXPECT_GT(m_far, 2.0 * m_in) << in["budget"] << far["budget"];
  EXPECT_NE(far["budget"]["model_note"].get<std::string>().find("extrapolated"), std::string::npos)
      << far["budget"];
  bool all = false;
  for (const auto& w : far["warnings"])
    all = all || w.get<std::string>().find("all ") != std::string::npos;
  EXPECT_TRUE(all) << far["warnings"];
}

// Review R17/R11: a calibration run whose temperature ramps 20 -> 4 degC was taken as one
// isothermal calibration, a 5-s run (3 cycles) as a calibration with a "correlated" error, and two
// runs pooled at 20.0 and 21.9 degC were described as "at 20.0 degC". Now: warnings, and the
// conclusion names the pooled runs' temperature range.
TEST(ReportChecks, ARampAShortRunAndThePooledRunsTemperaturesAreNamed) {
  temp_dir d;
  const auto warnings_of = [&](const std::vector<std::string>& files, const std::string& out) {
    std::vector<std::string> a{"report"};
    a.insert(a.end(), files.begin(), files.end());
    a.insert(a.end(), {"-o", d.file(out)});
    const auto r = run_cli(a);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(read_text(d.file(out + "/summary.json")));
  };
  const auto has = [](const nlohmann::json& j, const std::string& what) {
    for (const auto& w : j["warnings"])
      if (w.get<std::string>().find(what) != std::string::npos) return true;
    return false;
  };
  const auto ramp = d.file("ramp.csv"), shrt = d.file("short.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "600", "--seed", "32",
                     "--temp-profile", "ramp:20:4:600", "-o", ramp})
                .exit_code,
            0);
  ASSERT_EQ(
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "5", "--seed", "1", "-o", shrt})
          .exit_code,
      0);
  const auto jr = warnings_of({ramp}, "ramp");
  EXPECT_TRUE(has(jr, "not isothermal")) << jr["warnings"];
  EXPECT_FALSE(has(jr, "too few")) << jr["warnings"];
  const auto js = warnings_of({shrt}, "short");
  EXPECT_TRUE(has(js, "3 cycles: too few for a standard error")) << js["warnings"];
  EXPECT_FALSE(has(js, "not isothermal")) << js["warnings"];
  const auto a = simulate(d, "a20.csv", "20", "1"), w = simulate(d, "w219.csv", "21.9", "31");
  const auto jp = warnings_of({a, w}, "pooled");
  const std::string text = jp["conclusion"];
  EXPECT_NE(text.find("the mean of 2 runs at 20.0–21.9 °C"), std::string::npos) << text;
  // Review R16: the per-cycle scatter is a std, and the conclusion says so.
  EXPECT_NE(text.find("per-cycle standard deviation is up to"), std::string::npos) << text;
  EXPECT_EQ(text.find("scatters by up to"), std::string::npos) << text;
  EXPECT_FALSE(has(jp, "not isothermal")) << jp["warnings"];
}

// `gyroflip report` of simulated HZ1 runs (name, temperature, seed) into rep/: its index.html.
struct sim_run {
  std::string name, temp, seed;
};
std::string calibration_page(const temp_dir& d, const std::vector<sim_run>& runs) {
  std::vector<std::string> args{"report"};
  for (const auto& r : runs) args.push_back(simulate(d, r.name, r.temp, r.seed));
  args.insert(args.end(), {"-o", d.file("rep")});
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_page(d.file("rep/index.html"));
}

// Review R4: the conclusion of a dN(T) calibration (HZ1 at 20, 4 and 12 degC: a line of 1 degree
// of freedom) quoted the error at the worst temperature as the error at the reference
// temperature. It now gives the table's c_0 error at the temperature it names and the budget's
// largest for the span; the 1-degree-of-freedom repeatability is warned about (review R5b).
TEST(ReportChecks, ADeltaNLineIsQuotedAtTheTemperatureItNames) {
  temp_dir d;
  const auto html =
      calibration_page(d, {{"a20.csv", "20", "1"}, {"d4.csv", "4", "4"}, {"e12.csv", "12", "5"}});
  const auto rows = table_rows(html, "ΔN(T) = Σ c_k");
  ASSERT_GE(rows.size(), 2u);
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  const std::string text = j["conclusion"];
  // c_0 as the table prints it, with its 68.3 % interval (issue 31: the digits it supports).
  EXPECT_NE(text.find(rows[0][1] + " ± " + rows[0][3] + " °/s at 12.00 °C, ± "), std::string::npos)
      << text;
  EXPECT_NE(text.find("anywhere in 4.0–20.0 °C"), std::string::npos) << text;
  bool flagged = false;
  for (const auto& w : j["warnings"])
    flagged = flagged || w.get<std::string>().find("1 degree of freedom") != std::string::npos;
  EXPECT_TRUE(flagged) << j["warnings"];
}

}  // namespace

// Review R18: a CSV that names no maker, compensated with a calibration made from simulated runs,
// was reported as "recorded" without a banner, and cal.json kept no trace of its runs' bytes or
// origin. The calibration now records each run's SHA-256, size and origin; the report shows them,
// bannered when any run was simulated, and warns when a run is compensated with a calibration
// that contains it.
TEST(ReportChecks, ACalibrationFromSimulatedRunsIsNamedWithItsRunsSources) {
  temp_dir d;
  calibrate_at_20c(d, "hz1-90-100a", "600", {"1", "2"});
  const auto cal = nlohmann::json::parse(read_text(d.file("cal.json")));
  EXPECT_EQ(cal["schema"], "gyroflip.calibration/5");
  ASSERT_EQ(cal["files"].size(), 2u);
  const auto sha_of = [](const std::string& file) {
    auto s = gyroflip::report::sha256_file(file);
    EXPECT_TRUE(static_cast<bool>(s));
    return s ? *s : std::string();
  };
  for (const auto& f : cal["files"]) {
    EXPECT_EQ(f["sha256"], sha_of(f["file"].get<std::string>())) << f;
    EXPECT_EQ(f["size_bytes"].get<std::uintmax_t>(),
              std::filesystem::file_size(f["file"].get<std::string>()));
    EXPECT_EQ(f["origin"], "simulated") << f;
    EXPECT_NE(f["origin_detail"].get<std::string>().find("seed"), std::string::npos) << f;
  }
  // The run: a simulated CSV with its maker's lines removed (as a hand-made CSV would be).
  const auto sim = simulate(d, "t.csv", "20", "9", "0.5");
  std::string csv = "# sensor: hz1-90-100a\n";
  {
    std::istringstream in(read_text(sim));
    for (std::string line; std::getline(in, line);)
      if (line.empty() || line[0] != '#') csv += line + "\n";
  }
  std::ofstream(d.file("plain.csv")) << csv;
  const auto r = run_cli(
      {"report", d.file("plain.csv"), "--calibration", d.file("cal.json"), "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto html = read_page(d.file("rep/index.html"));
  EXPECT_NE(html.find("Simulated calibration: the ΔN applied comes from a calibration of which 2 "
                      "of the 2 runs"),
            std::string::npos);
  EXPECT_EQ(html.find("Simulated data:"), std::string::npos);  // the run itself is not known to be
  EXPECT_NE(html.find("origin not known"), std::string::npos);
  EXPECT_NE(html.find(cal["files"][0]["sha256"].get<std::string>()), std::string::npos);
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  EXPECT_EQ(j["calibration_simulated_runs"], 2);
  EXPECT_EQ(j["simulated_runs"], 0);
  ASSERT_EQ(j["calibration_runs"].size(), 2u);
  EXPECT_EQ(j["calibration_runs"][1]["sha256"], cal["files"][1]["sha256"]);
  // A calibration run compensated with its own calibration: not an independent test.
  const auto self = run_cli(
      {"report", d.file("c1.csv"), "--calibration", d.file("cal.json"), "-o", d.file("rep_self")});
  ASSERT_EQ(self.exit_code, 0) << self.err;
  EXPECT_NE(self.err.find("the same bytes as the calibration's run"), std::string::npos)
      << self.err;
  EXPECT_EQ(r.err.find("the same bytes"), std::string::npos) << r.err;
}

// Review R5: runs at one temperature are pooled by a weighted mean; the page says how and gives
// the plain mean beside it. Issue 31: the weights hold the runs' scatter (random effects).
TEST(ReportChecks, ThePooledMeansWeightingIsOnThePage) {
  temp_dir d;
  const auto html =
      calibration_page(d, {{"a.csv", "20", "1"}, {"b.csv", "20", "2"}, {"c.csv", "20", "3"}});
  EXPECT_NE(html.find("weights each run by 1/(its within-run error² + τ²)"), std::string::npos);
  EXPECT_NE(html.find("all runs (random-effects mean)"), std::string::npos);
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  double plain = 0.0, ss = 0.0;
  for (const auto& run : j["runs"]) plain += run["delta_n_dps"].get<double>() / 3.0;
  for (const auto& run : j["runs"]) ss += std::pow(run["delta_n_dps"].get<double>() - plain, 2);
  // With the digits its own error, the runs' std / sqrt(3), supports (third review, M4).
  EXPECT_NE(html.find(fmt::format("The plain mean of the 3 runs is {} °/s",
                                  gyroflip::to_digits_of(plain, std::sqrt(ss / 2.0 / 3.0), 6))),
            std::string::npos)
      << plain;
}

// Third review of issue 22: a calibration that lists no runs got a budget of exactly 0 ("±0
// °/s", D1); a model edited by hand was applied with its runs' ± (D4); one recording under two
// names was pooled as two runs (D2).
TEST(ReportChecks, ACalibrationsDeltaNIsCheckedAgainstItsRuns) {
  temp_dir d;
  calibrate_at_20c(d, "hz1-90-100a", "600", {"1", "2"});
  const auto t = simulate(d, "t.csv", "20", "9", "0.5");
  const auto cal = nlohmann::json::parse(read_text(d.file("cal.json")));
  const auto report_with = [&](const nlohmann::json& c, const std::string& name) {
    std::ofstream(d.file(name + ".json")) << c.dump();
    const auto r = run_cli(
        {"report", t, "--calibration", d.file(name + ".json"), "-o", d.file("rep_" + name)});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return std::pair{r.err,
                     nlohmann::json::parse(read_text(d.file("rep_" + name + "/summary.json")))};
  };
  // No runs and no error: no ± at all.
  auto bare = nlohmann::json{{"delta_n_dps", cal["model"]["coeffs_dps"][0]}};
  const auto [bare_err, bare_j] = report_with(bare, "bare");
  EXPECT_FALSE(bare_j["budget"]["valid"].get<bool>());
  EXPECT_TRUE(bare_j["budget"]["new_power_up_dps"].is_null());
  EXPECT_NE(bare_err.find("lists no runs and states no error: nothing shows that its ΔN was "
                          "measured on a stationary table"),
            std::string::npos)
      << bare_err;
  // No runs, its own error: that error as one run's, with the preset's turn-on spread (HZ1 at
  // 20 degC: 0.000959 deg/s, paper Tab. 3) for a new power-up.
  bare["stderr_correlated_dps"] = 0.0005;
  const auto [own_err, own_j] = report_with(bare, "own");
  EXPECT_TRUE(own_j["budget"]["valid"].get<bool>());
  EXPECT_DOUBLE_EQ(own_j["budget"]["within_run_dps"].get<double>(), 0.0005);
  // (as one run's: its power-up and a new one are two draws of the spread, fifth review of
  // issue 31, F17)
  EXPECT_NEAR(own_j["budget"]["new_power_up_dps"].get<double>(),
              std::hypot(0.0005, std::sqrt(2.0) * 0.000959), 1e-9);
  EXPECT_NE(own_err.find("lists no runs"), std::string::npos) << own_err;
  EXPECT_NE(read_page(d.file("rep_own/index.html"))
                .find("the calibration's own stated error (it lists no runs)"),
            std::string::npos);
  // As calibrate wrote it: no complaint; a model edited by hand: named, with how far it is.
  const auto [as_made_err, as_made_j] = report_with(cal, "as_made");
  EXPECT_EQ(as_made_err.find("is not the fit"), std::string::npos) << as_made_err;
  auto edited = cal;
  edited["model"]["coeffs_dps"][0] = 0.05;
  const auto [edited_err, edited_j] = report_with(edited, "edited");
  EXPECT_NE(edited_err.find("its ΔN model is not the fit of the 2 runs it lists"),
            std::string::npos)
      << edited_err;
  EXPECT_FALSE(edited_j["budget"]["valid"].get<bool>());  // not the runs' ± (review N4)
  EXPECT_TRUE(edited_j["budget"]["new_power_up_dps"].is_null());
  auto moved = cal;
  moved["model"]["cov"][0] = cal["model"]["cov"][0].get<double>() / 100.0;
  EXPECT_NE(report_with(moved, "moved").first.find("is not the fit"), std::string::npos);
  // No runs but a model: the model's own error is the one applied (review N2: not the
  // top-level within-run error, 11 times smaller).
  auto model_only = cal;
  model_only["files"] = nlohmann::json::array();
  const auto [mo_err, mo_j] = report_with(model_only, "model_only");
  EXPECT_DOUBLE_EQ(mo_j["budget"]["within_run_dps"].get<double>(),
                   std::sqrt(cal["model"]["cov"][0].get<double>()));
  // The same cycles in other bytes (a copy with one more newline): refused by calibrate too.
  std::ofstream(d.file("nl.csv")) << read_text(d.file("c1.csv")) << "\n";
  const auto nl =
      run_cli({"calibrate", d.file("c1.csv"), d.file("nl.csv"), "-o", d.file("nl.json")});
  EXPECT_EQ(nl.exit_code, 2);
  EXPECT_NE(nl.err.find("the same recording twice is not two runs"), std::string::npos) << nl.err;
  const auto nlr = run_cli({"report", d.file("c1.csv"), d.file("nl.csv"), "-o", d.file("rep_nl")});
  EXPECT_EQ(nlr.exit_code, 2);  // report too (fifth review)
  EXPECT_FALSE(std::filesystem::exists(d.file("rep_nl")));
  // One recording under two names: refused, naming both.
  std::filesystem::copy_file(d.file("c1.csv"), d.file("copy.csv"));
  for (const auto& cmd : {std::vector<std::string>{"calibrate", d.file("c1.csv"),
                                                   d.file("copy.csv"), "-o", d.file("dup.json")},
                          std::vector<std::string>{"report", d.file("c1.csv"), d.file("copy.csv"),
                                                   "-o", d.file("rep_dup")}}) {
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd[0];
    EXPECT_NE(r.err.find("has the same bytes as"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(cmd[cmd.size() - 1])) << cmd[0];
  }
}

// A build from a tree with uncommitted changes says so on its pages (re-review of issue 22, R14).
TEST(ReportPage, AModifiedBuildIsBannered) {
  EXPECT_EQ(gyroflip::report::modified_build_note("0123abcd"), "");
  EXPECT_NE(gyroflip::report::modified_build_note("0123abcd+modified").find("0123abcd+modified"),
            std::string::npos);
  gyroflip::report::page p;
  p.title = "t";
  p.made.commit = "0123abcd+modified";
  temp_dir d;
  const auto html = gyroflip::report::html(p, d.path());
  ASSERT_TRUE(html) << html.err().message;
  EXPECT_NE(html->find("<p class=\"banner\">Built from a modified source tree"), std::string::npos);
}

// Review N1 (fourth review of issue 22): runs without temperatures give a constant ΔN whose
// t_ref_c is null; the report of a run compensated with it failed ("a computed value is not
// finite") although compensate took it.
TEST(ReportChecks, ACalibrationOfRunsWithoutTemperaturesIsApplied) {
  temp_dir d;
  std::vector<std::string> cal{"calibrate"};
  for (const char* seed : {"1", "2"}) {
    const auto f = simulate(d, std::string("s") + seed + ".csv", "20", seed);
    std::string plain;
    std::istringstream in(read_text(f));
    for (std::string line; std::getline(in, line);) {  // drop the temp_c column (the 4th)
      if (!line.empty() && line[0] != '#') {
        std::size_t at = 0;
        for (int c = 0; c < 3; ++c) at = line.find(',', at) + 1;
        line.erase(at, line.find(',', at) + 1 - at);
      }
      plain += line + "\n";
    }
    ASSERT_NE(plain.find("time_s,angle_deg,rate_dps,n_avg"), std::string::npos)
        << plain.substr(0, 300);
    std::ofstream(d.file(std::string("n") + seed + ".csv")) << plain;
    cal.push_back(d.file(std::string("n") + seed + ".csv"));
  }
  auto constant = cal;  // a constant needs no temperatures, asked for or not
  constant.insert(constant.end(), {"--degree", "0", "-o", d.file("cal0.json")});
  EXPECT_EQ(run_cli(constant).exit_code, 0);
  cal.insert(cal.end(), {"-o", d.file("cal.json")});
  ASSERT_EQ(run_cli(cal).exit_code, 0);
  const auto t = simulate(d, "t.csv", "20", "9", "0.5");
  const auto r = run_cli({"report", t, "--calibration", d.file("cal.json"), "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(read_text(d.file("rep/summary.json")));
  EXPECT_TRUE(j["delta_n_model"]["t_ref_c"].is_null());
}

// Review N6 (a): a recording's own header reaches the page; a direction override in it must not
// reorder the page's text around it (it is shown as \u202e). summary.json keeps the text as
// recorded (JSON data, escaped by its readers).
TEST(ReportPage, DirectionControlsInARecordingAreShownNotObeyed) {
  temp_dir d;
  const auto a = simulate(d, "a.csv", "20", "1");
  const auto b = simulate(d, "b.csv", "20", "2");
  const std::string rlo = "\xe2\x80\xae";
  std::string text = read_text(a);
  const auto at = text.find("# seed: 1\n");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "# seed: 1" + rlo + "evil\xe2\x80\xac\n");
  std::ofstream(d.file("bidi.csv"), std::ios::binary) << text;
  const auto r = run_cli({"report", d.file("bidi.csv"), b, "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto html = read_page(d.file("rep/index.html"));
  EXPECT_EQ(html.find(rlo), std::string::npos);
  EXPECT_NE(html.find("\\u202eevil\\u202c"), std::string::npos);
}
