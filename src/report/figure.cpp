/// \file
/// \brief Figures as gnuplot scripts and data files, rendered by gnuplot (figure.hpp).
#include "gyroflip/report/figure.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/report/page.hpp"
#include "run_program.hpp"

namespace gyroflip::report {

namespace {

// Okabe & Ito (2008), "Color Universal Design": distinguishable with every common colour-vision
// deficiency. Blue, vermillion, bluish green, reddish purple, orange, sky blue, black.
constexpr std::array<std::string_view, 7> okabe_ito = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                       "#E69F00", "#56B4E9", "#000000"};

// A gnuplot single-quoted string: only the quote itself is special (doubled).
std::string gp_string(std::string_view text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') out += '\'';
    if (c != '\n') out += c;
  }
  return out + "'";
}

std::string_view color(int k) {
  return okabe_ito[static_cast<std::size_t>(k) % okabe_ito.size()];
}

bool finite_point(const series& s, std::size_t i) {
  if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) return false;
  if (s.how != series::style::errorbars && s.how != series::style::band) return true;
  return std::isfinite(s.y_lo[i]) && std::isfinite(s.y_hi[i]);
}

bool has_bounds(const series& s) {
  return s.how == series::style::errorbars || s.how == series::style::band;
}

// Points [0, usable) of a series exist in every column it plots.
std::size_t usable(const series& s) {
  std::size_t n = std::min(s.x.size(), s.y.size());
  if (has_bounds(s)) n = std::min({n, s.y_lo.size(), s.y_hi.size()});
  return n;
}

bool has_points(const series& s) {
  for (std::size_t i = 0; i < usable(s); ++i)
    if (finite_point(s, i)) return true;
  return false;
}

// The data file of one series: "x y" or "x y lo hi" per finite point; empty when none is.
std::string data_text(const series& s) {
  std::string out;
  for (std::size_t i = 0; i < usable(s); ++i) {
    if (!finite_point(s, i)) continue;
    if (has_bounds(s))
      fmt::format_to(std::back_inserter(out), "{} {} {} {}\n", s.x[i], s.y[i], s.y_lo[i],
                     s.y_hi[i]);
    else
      fmt::format_to(std::back_inserter(out), "{} {}\n", s.x[i], s.y[i]);
  }
  return out;
}

std::string data_name(std::string_view stem, std::size_t k) {
  return fmt::format("{}_{}.dat", stem, k + 1);
}

std::string plot_clause(const series& s, const std::string& file) {
  const std::string title =
      s.title.empty() ? "notitle" : "title " + gp_string(s.title) + " noenhanced";
  const auto c = color(s.color);
  switch (s.how) {
    case series::style::points:
      return fmt::format("{} using 1:2 with points {} lc rgb '{}' {}", gp_string(file),
                         s.open ? "pt 6 ps 1.3 lw 1.5" : "pt 7 ps 0.5", c, title);
    case series::style::lines:
      return fmt::format("{} using 1:2 with lines lw 2 {}lc rgb '{}' {}", gp_string(file),
                         s.dashed ? "dt 2 " : "", c, title);
    case series::style::errorbars:
      return fmt::format("{} using 1:2:3:4 with yerrorbars pt 7 ps 0.7 lw 1.2 lc rgb '{}' {}",
                         gp_string(file), c, title) +
             (s.joined ? fmt::format(", {} using 1:2 with lines lw 1 lc rgb '{}' notitle",
                                     gp_string(file), c)
                       : std::string());
    case series::style::band:
      return fmt::format(
          "{} using 1:3:4 with filledcurves fs transparent solid 0.18 noborder lc rgb '{}' {}",
          gp_string(file), c, title);
  }
  return {};
}

// The house style, the same in every script. The key sits below the plot, where it can hide no
// data (inside, an opaque key covered points).
constexpr std::string_view style = R"(set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
)";

std::string terminal(image_format f) {
  switch (f) {
    case image_format::png:
      return "set terminal pngcairo size 1100,680 font 'DejaVu Sans,12' enhanced";
    case image_format::svg:
      return "set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb "
             "'white'";
    case image_format::pdf:
      return "set terminal pdfcairo size 7in,4.3in font 'DejaVu Sans,10' enhanced";
  }
  return {};
}

}  // namespace

namespace {

// Code points of UTF-8 text.
std::size_t code_points(std::string_view s) {
  std::size_t n = 0;
  for (const char c : s)
    if ((static_cast<unsigned char>(c) & 0xC0U) != 0x80U) ++n;
  return n;
}

// The widest line of a title or a key, in characters: the PDF's 7-in width holds ~90 of DejaVu
// Sans 10 pt (the PNG's 1100 px ~135 of 12 pt), so a longer title line was clipped (the Tab.
// 3/4 figures' second line, review of issue 31).
constexpr std::size_t line_chars = 88;

// `text` broken at spaces into lines of at most line_chars characters (a longer word alone),
// never between a number and its unit ("2.19 °/h") or a sign and its number ("< 4.33").
std::vector<std::string> lines_of(std::string_view text) {
  std::vector<std::string> words;
  bool glue_next = false;
  for (std::size_t at = 0; at <= text.size();) {
    const auto end = std::min(text.find(' ', at), text.size());
    const auto word = text.substr(at, end - at);
    at = end + 1;
    if (word.empty()) continue;
    const bool unit = word.starts_with("°") || word.starts_with("%") || word.starts_with("σ");
    const bool relation = word == "<" || word == ">" || word == "±" || word == "≤" || word == "≥" ||
                          word == "=" || word == "≈";
    // A relation stays with a short name before it too ("K < 4.33").
    const bool after_name = relation && !words.empty() && code_points(words.back()) <= 3;
    if (!words.empty() && (glue_next || unit || after_name)) {
      words.back() += ' ';
      words.back() += word;
    } else {
      words.emplace_back(word);
    }
    glue_next = relation;
  }
  std::vector<std::string> out;
  std::string line;
  for (const auto& word : words) {
    if (!line.empty() && code_points(line) + 1 + code_points(word) > line_chars) {
      out.push_back(line);
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += word;
  }
  if (!line.empty()) out.push_back(line);
  return out;
}

// A gnuplot double-quoted string: backslashes and quotes escaped, line breaks as "\n".
std::string gp_text(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The key below the plot, in as many columns as fit its longest entry (each ~8 characters
// more than its text: sample and gaps), so that it never runs off the image.
std::string key_line(const figure& f) {
  if (f.key_inside)
    return "set key inside bottom left vertical opaque box lc rgb '#bbbbbb' samplen 2 spacing "
           "1.0 font ',10'\n";
  std::size_t entries = 0, longest = 0;
  for (const auto& s : f.data)
    if (!s.title.empty() && has_points(s)) {
      ++entries;
      longest = std::max(longest, code_points(s.title));
    }
  const std::size_t columns =
      std::clamp<std::size_t>(line_chars / (longest + 8), 1, std::max<std::size_t>(entries, 1));
  return fmt::format(
      "set key below left vertical maxrows {} width 2 box lc rgb '#bbbbbb' samplen 2 spacing "
      "1.1\n",
      std::max<std::size_t>(1, (entries + columns - 1) / columns));
}

}  // namespace

std::string_view suffix(image_format f) noexcept {
  switch (f) {
    case image_format::png:
      return "png";
    case image_format::svg:
      return "svg";
    case image_format::pdf:
      return "pdf";
  }
  return "png";
}

namespace {

// Where a read-off letter goes (review of issue 31: the Allan plot's "B" sat on the raw curve's
// last point and the line into it). The plot is modelled in pixels of the PNG: its frame about
// 988 x 379 px (measured with GPVAL_TERM_* for a 5-row key and a 4-line title; a smaller frame
// is tried too, and a larger one, so that the choice holds for other keys and titles), a
// character 10 x 18.6 px (GPVAL_TERM_HCHAR/VCHAR of pngcairo at 12 pt), axes spanning their
// range (plot_ranges). A letter's box must stay clear of every data point, error bar and data
// line, of the other marks and of the letters placed before it.
struct frame_model {
  double width_px, height_px;
};
constexpr frame_model frames[] = {{988.0, 379.0}, {860.0, 290.0}, {1000.0, 470.0}};
constexpr double char_w_px = 10.0, char_h_px = 18.6;

struct box {
  double x0, y0, x1, y1;  // pixels, y up
};

struct axis_map {
  double lo, hi;
  bool log;
  [[nodiscard]] double frac(double v) const {
    return log ? std::log10(v / lo) / std::log10(hi / lo) : (v - lo) / (hi - lo);
  }
};

bool segment_hits(const box& b, double ax, double ay, double bx, double by) {
  // Liang-Barsky clipping of the segment against the box.
  double t0 = 0.0, t1 = 1.0;
  const double dx = bx - ax, dy = by - ay;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {ax - b.x0, b.x1 - ax, ay - b.y0, b.y1 - ay};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double t = q[i] / p[i];
      if (p[i] < 0.0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1) return false;
    }
  }
  return true;
}

bool circle_hits(const box& b, double cx, double cy, double r) {
  const double dx = std::max({b.x0 - cx, 0.0, cx - b.x1});
  const double dy = std::max({b.y0 - cy, 0.0, cy - b.y1});
  return dx * dx + dy * dy < r * r;
}

// The box of a label's text at (px, py) with offset (dx, dy) characters, aligned `align`.
box text_box(double px, double py, const std::string& text, double dx, double dy, int align) {
  // Characters, not bytes: a UTF-8 continuation byte is no character.
  double n = 0.0;
  for (const char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80 ? 1.0 : 0.0;
  const double w = n * char_w_px * 0.8, h = char_h_px * 0.8;
  const double ax = px + dx * char_w_px, ay = py + dy * char_h_px;
  const double x0 = align < 0 ? ax - w : align > 0 ? ax : ax - w / 2.0;
  return {x0, ay - h / 2.0, x0 + w, ay + h / 2.0};
}

struct placement {
  double dx, dy;
  int align;  // -1: text ends at the anchor (gnuplot "right"), 1: starts there ("left"), 0: centred
};

// The positions tried, nearest first, the preferred side first.
std::vector<placement> candidates(bool left) {
  const double s = left ? -1.0 : 1.0;
  const int a = left ? -1 : 1;
  return {{1.2 * s, 0.0, a}, {-1.2 * s, 0.0, -a}, {0.0, 1.1, 0},       {0.0, -1.1, 0},
          {1.0 * s, 1.0, a}, {1.0 * s, -1.0, a},  {-1.0 * s, 1.0, -a}, {-1.0 * s, -1.0, -a},
          {0.0, 2.0, 0},     {0.0, -2.0, 0},      {2.5 * s, 0.0, a},   {-2.5 * s, 0.0, -a},
          {2.0 * s, 2.0, a}, {2.0 * s, -2.0, a},  {-2.0 * s, 2.0, -a}, {-2.0 * s, -2.0, -a}};
}

}  // namespace

plot_ranges ranges_of(const figure& f) {
  plot_ranges r;
  for (const auto* a : {&f.x, &f.y}) {
    const bool is_x = a == &f.x;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const auto take = [&](double v) {
      if (std::isfinite(v) && (!a->log || v > 0.0)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    };
    for (const auto& s : f.data)
      for (std::size_t i = 0; i < usable(s); ++i) {
        if (!finite_point(s, i)) continue;
        if (is_x) {
          take(s.x[i]);
        } else {
          take(s.y[i]);
          if (has_bounds(s)) {
            take(s.y_lo[i]);
            take(s.y_hi[i]);
          }
        }
      }
    for (const auto& n : f.notes)
      if (std::isfinite(n.x) && std::isfinite(n.y)) take(is_x ? n.x : n.y);
    if (std::isfinite(a->from) && std::isfinite(a->to)) {
      lo = a->from;
      hi = a->to;
    } else if (!(lo < hi)) {
      lo = hi = std::numeric_limits<double>::quiet_NaN();
    } else if (a->log) {
      // Whole decades, as gnuplot's autoscale of a log axis with a tic at each decade.
      lo = std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
      hi = std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
    }
    (is_x ? r.x_lo : r.y_lo) = lo;
    (is_x ? r.x_hi : r.y_hi) = hi;
  }
  return r;
}

std::vector<label_place> place_labels(const figure& f) {
  std::vector<label_place> out;
  const auto r = ranges_of(f);
  const bool mapped = std::isfinite(r.x_lo) && std::isfinite(r.y_lo);
  std::vector<std::pair<std::size_t, box>> placed;  // earlier letters, per frame model
  for (std::size_t k = 0; k < f.notes.size(); ++k) {
    const auto& n = f.notes[k];
    const auto options = candidates(n.text_left);
    label_place best{options[0].dx, options[0].dy, options[0].align};
    if (mapped && std::isfinite(n.x) && std::isfinite(n.y)) {
      const axis_map mx{r.x_lo, r.x_hi, f.x.log}, my{r.y_lo, r.y_hi, f.y.log};
      // The first candidate clear of everything in every frame model; failing that, the first
      // clear of the data alone.
      int fallback = -1;
      bool found = false;
      for (std::size_t c = 0; c < options.size() && !found; ++c) {
        bool clear_data = true, clear_all = true;
        for (std::size_t fm = 0; fm < std::size(frames); ++fm) {
          const auto& fr = frames[fm];
          const auto px = [&](double x) { return mx.frac(x) * fr.width_px; };
          const auto py = [&](double y) { return my.frac(y) * fr.height_px; };
          const box b0 =
              text_box(px(n.x), py(n.y), n.text, options[c].dx, options[c].dy, options[c].align);
          const box b{b0.x0 - 2.0, b0.y0 - 2.0, b0.x1 + 2.0, b0.y1 + 2.0};
          // Inside the frame.
          if (b.x0 < 0.0 || b.x1 > fr.width_px || b.y0 < 0.0 || b.y1 > fr.height_px)
            clear_all = clear_data = false;
          for (const auto& s : f.data) {
            const bool data = s.how == series::style::errorbars || s.how == series::style::points;
            if (s.how == series::style::band) continue;
            std::size_t prev = usable(s);
            for (std::size_t i = 0; i < usable(s); ++i) {
              if (!finite_point(s, i) || (f.x.log && s.x[i] <= 0.0) || (f.y.log && s.y[i] <= 0.0))
                continue;
              const double x = px(s.x[i]), y = py(s.y[i]);
              bool hit = false;
              if (data) {
                hit = circle_hits(b, x, y, 5.0);
                if (has_bounds(s) && s.y_lo[i] > 0.0 && s.y_hi[i] > 0.0)
                  hit = hit || segment_hits(b, x, py(s.y_lo[i]), x, py(s.y_hi[i]));
              }
              if (prev < usable(s) && (s.how == series::style::lines || s.joined))
                hit = hit || segment_hits(b, px(s.x[prev]), py(s.y[prev]), x, y);
              prev = i;
              if (hit) {
                clear_all = false;
                if (data) clear_data = false;
              }
            }
          }
          for (std::size_t j = 0; j < f.notes.size(); ++j)
            if (j != k && std::isfinite(f.notes[j].x) && std::isfinite(f.notes[j].y) &&
                circle_hits(b, px(f.notes[j].x), py(f.notes[j].y), 8.0))
              clear_all = false;
          for (const auto& [fm_placed, pb] : placed)
            if (fm_placed == fm && pb.x0 < b.x1 && b.x0 < pb.x1 && pb.y0 < b.y1 && b.y0 < pb.y1)
              clear_all = false;
        }
        if (clear_all) {
          best = {options[c].dx, options[c].dy, options[c].align};
          found = true;
        } else if (clear_data && fallback < 0) {
          fallback = static_cast<int>(c);
        }
      }
      if (!found && fallback >= 0) {
        const auto& o = options[static_cast<std::size_t>(fallback)];
        best = {o.dx, o.dy, o.align};
      }
      for (std::size_t fm = 0; fm < std::size(frames); ++fm) {
        const auto& fr = frames[fm];
        placed.emplace_back(fm, text_box(mx.frac(n.x) * fr.width_px, my.frac(n.y) * fr.height_px,
                                         n.text, best.dx, best.dy, best.align));
      }
    }
    out.push_back(best);
  }
  return out;
}

std::span<const std::string_view> palette() noexcept {
  return okabe_ito;
}

std::string script(const figure& f, std::string_view stem, std::span<const image_format> formats) {
  std::string s = fmt::format(
      "# gyroflip figure: {}\n# Data: {}_K.dat (x y [low high]), one file per series. Restyle "
      "and run again with: gnuplot {}.gp\n",
      f.title, stem, stem);
  s += style;
  s += key_line(f);
  // The title and its caption, each broken into lines that fit the image.
  std::string title;
  for (const auto* part : {&f.title, &f.caption})
    for (const auto& line : lines_of(*part)) {
      if (!title.empty()) title += '\n';
      title += line;
    }
  fmt::format_to(std::back_inserter(s), "set title {} noenhanced\n", gp_text(title));
  // The x label with an empty line under it: gnuplot places the key below as if the tic labels
  // were one plain line, and the 10^k labels' superscripts pushed the label into the key.
  fmt::format_to(std::back_inserter(s), "set xlabel {} noenhanced\nset ylabel {} noenhanced\n",
                 gp_text(f.x.label + "\n"), gp_string(f.y.label));
  for (const auto* a : {&f.x, &f.y}) {
    const char name = a == &f.x ? 'x' : 'y';
    if (a->log)
      fmt::format_to(std::back_inserter(s), "set logscale {} 10\nset format {} '10^{{%L}}'\n", name,
                     name);
    if (a->tic_step > 0.0)
      fmt::format_to(std::back_inserter(s), "set {}tics {}\n", name, a->tic_step);
    if (std::isfinite(a->from) && std::isfinite(a->to))
      fmt::format_to(std::back_inserter(s), "set {}range [{}:{}]\n", name, a->from, a->to);
  }
  // Points at the extremes of a linear y axis would sit on the frame, half clipped (the paper's
  // 0.00107 on Tab. 3's 4 degC figure): 5 % of room above and below.
  if (!f.y.log) s += "set offsets 0, 0, graph 0.05, graph 0.05\n";
  // Marks with letters: the axes' ranges fixed (the letters are placed against them), and each
  // letter beside its point where it covers no data (place_labels; the text's full reading is
  // the key's).
  if (!f.notes.empty()) {
    const auto r = ranges_of(f);
    for (const auto& [name, lo, hi, a] :
         {std::tuple{'x', r.x_lo, r.x_hi, &f.x}, std::tuple{'y', r.y_lo, r.y_hi, &f.y}})
      if (std::isfinite(lo) && std::isfinite(hi) &&
          !(std::isfinite(a->from) && std::isfinite(a->to)))
        fmt::format_to(std::back_inserter(s), "set {}range [{}:{}]\n", name, lo, hi);
  }
  const auto places = place_labels(f);
  int label = 1;
  for (std::size_t k = 0; k < f.notes.size(); ++k) {
    const auto& n = f.notes[k];
    if (!std::isfinite(n.x) || !std::isfinite(n.y)) continue;
    const auto& p = places[k];
    fmt::format_to(std::back_inserter(s),
                   "set label {} {} at {},{} {} front tc rgb '{}' point pt 6 ps 1.6 lw 2 lc rgb "
                   "'{}' offset {},{} noenhanced\n",
                   label++, gp_string(n.text), n.x, n.y,
                   p.align < 0   ? "right"
                   : p.align > 0 ? "left"
                                 : "center",
                   color(n.color), color(n.color), p.dx, p.dy);
  }
  std::string plot;
  for (std::size_t k = 0; k < f.data.size(); ++k) {
    if (!has_points(f.data[k])) continue;
    plot += (plot.empty() ? "plot " : ", \\\n     ") + plot_clause(f.data[k], data_name(stem, k));
  }
  for (const auto fmt_ : formats)
    fmt::format_to(std::back_inserter(s), "\n{}\nset output '{}.{}'\n{}\nunset output\n",
                   terminal(fmt_), stem, suffix(fmt_), plot);
  return s;
}

std::vector<std::string> rendered_files(const std::string& dir, const std::string& stem,
                                        std::size_t series, std::span<const image_format> formats) {
  std::vector<std::string> out;
  const auto file = [&](const std::string& name) { return fmt::format("{}/{}", dir, name); };
  for (std::size_t k = 0; k < series; ++k) out.push_back(file(data_name(stem, k)));
  out.push_back(file(stem + ".gp"));
  for (const auto f : formats) out.push_back(fmt::format("{}/{}.{}", dir, stem, suffix(f)));
  return out;
}

namespace {

// The first line of every script and data file render() writes: the SHA-256 of the rest of the
// file, by which a later render knows that the file is its own and unchanged (a restyled script
// is the user's: it is never overwritten).
constexpr std::string_view stamp_prefix = "# gyroflip figure file; SHA-256 of the lines below: ";

result<std::string> stamped(const std::string& text) {
  auto sum = sha256_text(text);
  if (!sum) return sum.err();
  return fmt::format("{}{}\n{}", stamp_prefix, *sum, text);
}

// Whether the file `path` may be replaced by render(): absent, or a file render() wrote that has
// not changed since (its stamp matches its content).
status check_replaceable(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return ok();
  std::string text;
  if (S_ISREG(st.st_mode)) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    text = all.str();
  }
  const auto eol = text.find('\n');
  if (text.rfind(stamp_prefix, 0) == 0 && eol != std::string::npos) {
    const auto sum = sha256_text(std::string_view(text).substr(eol + 1));
    if (sum && text.compare(stamp_prefix.size(), eol - stamp_prefix.size(), *sum) == 0) return ok();
  }
  return input_error({path},
                     "exists and is not a figure file as gyroflip wrote it (it is "
                     "someone else's, or was edited since): not replaced; move it aside, "
                     "or draw the figure under another name");
}

}  // namespace

status check_rendered_files(const std::string& dir, const std::string& stem, std::size_t series) {
  for (const auto& path : rendered_files(dir, stem, series, {}))
    if (auto s = check_replaceable(path); !s) return s;
  return ok();
}

namespace {

// Runs `gnuplot stem.gp` in `dir`.
status run_gnuplot(const std::string& gnuplot, const std::string& dir, const std::string& stem) {
  const std::string script_name = stem + ".gp";
  auto r = detail::run_program({gnuplot, script_name}, dir);
  if (!r) return r.err();
  if (r->exit_code == 0) return ok();
  if (r->exit_code == 127)
    return runtime_error(fmt::format("cannot run {} (install gnuplot-nox)", gnuplot));
  return runtime_error(
      fmt::format("gnuplot failed on {}: {}", script_name, printable(r->messages, 400)));
}

}  // namespace

status render(const figure& f, const std::string& dir, const std::string& stem,
              std::span<const image_format> formats, const std::string& gnuplot) {
  namespace fs = std::filesystem;
  // Everything is made in a private folder beside the target and then renamed into place, so
  // that a failed or killed run leaves no half-drawn image under the figure's name (the folder
  // goes when `work` does, and on a signal).
  // A script or data file of the user's (or one restyled) is never replaced.
  if (auto s = check_rendered_files(dir, stem, f.data.size()); !s) return s;
  auto work = io::temporary_folder::create(dir, stem + ".figure");
  if (!work) return work.err();
  const fs::path tmp = work->path();
  std::vector<std::string> made;
  for (std::size_t k = 0; k < f.data.size(); ++k) {
    const auto text = data_text(f.data[k]);
    if (text.empty()) continue;
    made.push_back(data_name(stem, k));
    auto file = stamped(text);
    if (!file) return file.err();
    if (auto s = io::write_file_atomically((tmp / made.back()).string(), *file); !s) return s;
  }
  if (made.empty())
    return runtime_error(fmt::format("figure '{}' has no finite point to plot", f.title));
  made.push_back(stem + ".gp");
  auto gp = stamped(script(f, stem, formats));
  if (!gp) return gp.err();
  if (auto s = io::write_file_atomically((tmp / made.back()).string(), *gp); !s) return s;
  if (auto s = run_gnuplot(gnuplot, tmp.string(), stem); !s) return s;
  for (const auto fmt_ : formats) made.push_back(stem + "." + std::string(suffix(fmt_)));
  // Checked again: gnuplot took a while, and the user may have written a script meanwhile.
  if (auto s = check_rendered_files(dir, stem, f.data.size()); !s) return s;
  for (const auto& name : made) {
    std::error_code ec;
    fs::rename(tmp / name, fs::path(dir) / name, ec);
    if (ec) return io_error((fs::path(dir) / name).string(), ec.message());
  }
  return ok();
}

}  // namespace gyroflip::report
