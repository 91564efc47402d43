/// \file
/// \brief A figure as data (series, axes, caption) and its rendering by gnuplot: each figure is a
/// gnuplot script `STEM.gp` plus its data files `STEM_K.dat` next to the images `STEM.png`,
/// `STEM.svg`, `STEM.pdf`, so that a user can restyle the script and run `gnuplot STEM.gp` again.
/// One style for every figure (style.gp's content is written into each script): DejaVu Sans,
/// the Okabe-Ito colour-blind-safe palette, light grid, log axes with 10^k labels and minor
/// ticks. gnuplot-nox 5.4 (terminals pngcairo, svg, pdfcairo; STACK.md §2) runs as a separate
/// program; the library never links a plotting library.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::report {

enum class image_format { png, svg, pdf };

/// The file suffix of a format ("png", ...).
[[nodiscard]] std::string_view suffix(image_format f) noexcept;

/// One series: points (x, y), optionally with error bars [y_lo, y_hi] (absolute values).
struct series {
  enum class style { points, lines, errorbars, band };
  std::string title;  ///< legend entry (empty: none)
  std::vector<double> x, y;
  std::vector<double> y_lo, y_hi;  ///< for errorbars and band (same length as x)
  style how = style::points;
  int color = 0;        ///< index into the palette (0 blue, 1 vermillion, 2 green, 3 purple, ...)
  bool dashed = false;  ///< lines: dashed (models and fits)
  /// errorbars: a thin line through the points, for the points of one curve (an Allan curve);
  /// never for independent values (runs), which are not a series in time.
  bool joined = false;
  /// points: larger open circles (values set beside the data, as a paper's), not small dots.
  bool open = false;
};

struct axis {
  std::string label;  ///< with its unit, e.g. "time (s)"
  bool log = false;
  double tic_step = 0.0;  ///< > 0: tics every this much (whole run numbers: 1); 0: gnuplot's
  /// Both finite: the axis spans [from, to] (runs 1..n: [0.5, n + 0.5], so that the first and
  /// last runs' error bars are not cut by the frame); else gnuplot's autoscale.
  double from = std::numeric_limits<double>::quiet_NaN();
  double to = std::numeric_limits<double>::quiet_NaN();
};

/// A point with a short text beside it (the read-off points of the Allan plot: "N", "B", "K";
/// what they read is in the key, where it hides no data).
struct annotation {
  double x = 0.0, y = 0.0;
  std::string text;
  bool text_left = false;  ///< the text ends left of the point instead of starting right of it
  int color = 6;           ///< the point's and the text's colour (palette index; 6 black)
};

struct figure {
  std::string title;
  std::string caption;  ///< a second title line (mean and std of the plotted series, ...)
  axis x, y;
  std::vector<series> data;
  std::vector<annotation> notes;
  /// The key inside the frame, at its bottom left, opaque (the noise figure: an Allan curve
  /// leaves that corner empty); otherwise below the plot, where it hides no data.
  bool key_inside = false;
};

/// The Okabe-Ito palette, in the order figures use it (hex RGB).
[[nodiscard]] std::span<const std::string_view> palette() noexcept;

/// The axes' ranges a figure with marks is drawn with: an axis's own [from, to] when given, else
/// its data's (points, error bars, marks), a log axis widened to whole decades. NaN for an axis
/// without data.
struct plot_ranges {
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
};
[[nodiscard]] plot_ranges ranges_of(const figure& f);

/// Where each mark's text goes, in gnuplot's terms: an offset from its point in characters and the
/// text's alignment there (-1 ends at it, 1 starts at it, 0 centred).
struct label_place {
  double dx = 0.0, dy = 0.0;
  int align = 1;
};

/// For each of f.notes, the nearest place beside its point (its preferred side first, then the
/// other, above, below, diagonals, farther) where its text covers no data point, error bar or
/// data line, no fitted line, no other mark and no letter placed before it, in a model of the
/// PNG's frame and font (several frame sizes); failing that, the nearest clear of the data.
[[nodiscard]] std::vector<label_place> place_labels(const figure& f);

/// The gnuplot script of `f` for the images `stem`.<format> and data files `stem`_K.dat (K from
/// 1; names relative to the script's folder). Non-finite points are left out of the data.
[[nodiscard]] std::string script(const figure& f, std::string_view stem,
                                 std::span<const image_format> formats);

/// Every file render() may write for a figure of `series` data series: DIR/STEM_K.dat (K from 1
/// to `series`), DIR/STEM.gp and DIR/STEM.<format> per format. For checking, before any work,
/// that none of them is an input of the run.
[[nodiscard]] std::vector<std::string> rendered_files(const std::string& dir,
                                                      const std::string& stem, std::size_t series,
                                                      std::span<const image_format> formats);

/// Whether render() may write DIR/STEM.gp and DIR/STEM_K.dat (K from 1 to `series`): each is
/// absent, or a file render() wrote and nobody changed since. Every such file starts with a line
/// holding the SHA-256 of the rest; a file without it (the user's, or one from a gyroflip before
/// the stamp) or not matching it (a restyled script) is refused (bad input, naming it). For
/// checking before any work; render() checks again.
[[nodiscard]] status check_rendered_files(const std::string& dir, const std::string& stem,
                                          std::size_t series);

/// Writes DIR/STEM.gp and its data files and runs `gnuplot STEM.gp` in DIR, which makes
/// DIR/STEM.<format>. Errors: a script or data file it may not replace (check_rendered_files), a
/// file that cannot be written, gnuplot missing or failing (its message), a figure without any
/// finite point.
[[nodiscard]] status render(const figure& f, const std::string& dir, const std::string& stem,
                            std::span<const image_format> formats,
                            const std::string& gnuplot = "gnuplot");

}  // namespace gyroflip::report
