/// \file
/// \brief The harmonic fit of an indexed run and the heading (see harmonic.hpp).
#include "gyroflip/method/harmonic.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/least_squares.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/calibration.hpp"

namespace gyroflip::method {

std::vector<indexed_dwell> indexed_dwells(std::span<const row> rows) {
  std::vector<indexed_dwell> out;
  double t = 0.0, y = 0.0, w = 0.0;
  int pos = table_moving;
  const auto flush = [&] {
    if (w > 0.0) out.push_back({t / w, pos, y / w, w});
    t = y = w = 0.0;
  };
  for (const auto& r : rows) {
    if (r.position == table_moving) {
      flush();
      continue;
    }
    // A row that is a dwell of its own, or a raw conversion at another position, ends a dwell.
    if (r.n_avg > 1 || r.position != pos) flush();
    pos = r.position;
    const double n = static_cast<double>(r.n_avg);
    t += n * r.time_s;
    y += n * r.rate_dps;
    w += n;
    if (r.n_avg > 1) flush();
  }
  flush();
  return out;
}

namespace {

// The smallest period of the positions' sequence (2..2 x max_positions), checked over the
// first few periods; 0 if none.
std::size_t period_of(std::span<const indexed_dwell> d) {
  const std::size_t max_p = 2 * position_table::max_positions;
  for (std::size_t p = 2; p <= max_p; ++p) {
    const std::size_t span = std::min(d.size(), 4 * p);
    if (span < 2 * p) break;
    bool same = true;
    for (std::size_t k = 0; k + p < span && same; ++k) same = d[k].position == d[k + p].position;
    if (same) return p;
  }
  return 0;
}

// Cuts a stream into blocks that repeat `pattern` (positions): the window holds the latest
// items that are a prefix of the pattern; an item that breaks it drops items from the window's
// front until it is one again (as sliding a block's start by one dwell at a time). One rule for
// blocks_of and the harmonic demodulator.
template <class Item>
class block_cutter {
 public:
  explicit block_cutter(std::vector<int> pattern) : pattern_(std::move(pattern)) {}
  // Adds the next item; true when the window is a whole block (take it with take()).
  bool push(const Item& x) {
    window_.push_back(x);
    std::size_t drop = 0;
    while (drop < window_.size() && !prefix_from(drop)) ++drop;
    if (drop > 0) {
      window_.erase(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(drop));
      skipped_ += drop;
    }
    return window_.size() == pattern_.size();
  }
  std::vector<Item> take() {
    std::vector<Item> b;
    b.swap(window_);
    return b;
  }
  [[nodiscard]] std::size_t skipped() const noexcept { return skipped_; }
  [[nodiscard]] const std::vector<int>& pattern() const noexcept { return pattern_; }

 private:
  bool prefix_from(std::size_t drop) const {
    for (std::size_t k = drop; k < window_.size(); ++k)
      if (window_[k].position != pattern_[k - drop]) return false;
    return true;
  }
  std::vector<int> pattern_;
  std::vector<Item> window_;
  std::size_t skipped_ = 0;
};

// A harmonic term's regressor at angle a (rad); p1 (the first harmonic's projection on the
// direction a0 of the table's position 0) is cos(a - a0).
double regressor(std::string_view term, double a, double a0 = 0.0) {
  if (term == "p1") return std::cos(a - a0);
  if (term == "c1") return std::cos(a);
  if (term == "s1") return std::sin(a);
  if (term == "c2") return std::cos(2.0 * a);
  if (term == "s2") return std::sin(2.0 * a);
  return 1.0;  // b
}

// One block's least-squares design: rows [1, (t - t_mean)/t_span, regressors of `terms`].
struct block_design {
  std::vector<std::string> terms;          // harmonic terms (not b)
  std::vector<std::vector<double>> slots;  // per slot of the period: the terms' regressors
  [[nodiscard]] std::size_t cols() const noexcept { return 2 + terms.size(); }
};

block_design design_of(const position_table& table, std::span<const int> pattern,
                       std::vector<std::string> terms) {
  block_design d;
  d.terms = std::move(terms);
  const double a0 = table.size() > 0 ? table.angle_deg(0) * units::rad_per_deg : 0.0;
  for (const int p : pattern) {
    const double a = table.angle_deg(p) * units::rad_per_deg;
    std::vector<double> r;
    for (const auto& t : d.terms) r.push_back(regressor(t, a, a0));
    d.slots.push_back(std::move(r));
  }
  return d;
}

// Least squares of one block (its dwells in pattern order): coefficients b, slope, terms.
template <class Item, class Dwell>
result<analysis::wls_fit> solve_block(const std::vector<Item>& b, const block_design& d,
                                      Dwell&& dwell_of) {
  const std::size_t period = b.size(), cols = d.cols();
  std::vector<double> design(period * cols), y(period), w(period, 1.0);  // OLS: equal dwells
  double t_mean = 0.0;
  for (const auto& x : b) t_mean += dwell_of(x).time_s;
  t_mean /= static_cast<double>(period);
  const double t_span = std::max(dwell_of(b.back()).time_s - dwell_of(b.front()).time_s, 1e-9);
  for (std::size_t k = 0; k < period; ++k) {
    double* row = &design[k * cols];
    row[0] = 1.0;
    row[1] = (dwell_of(b[k]).time_s - t_mean) / t_span;  // scaled: the solver equilibrates anyway
    for (std::size_t i = 0; i < d.terms.size(); ++i) row[2 + i] = d.slots[k][i];
    y[k] = dwell_of(b[k]).rate_dps;
  }
  return analysis::weighted_least_squares(design, cols, y, w);
}

// Whether a block of `pattern` (equally spaced dwells) separates the bias, its slope and `terms`.
bool block_separates(const position_table& table, std::span<const int> pattern,
                     const std::vector<std::string>& terms) {
  if (pattern.size() < 2 + terms.size()) return false;
  const auto d = design_of(table, pattern, terms);
  std::vector<indexed_dwell> b;
  for (std::size_t k = 0; k < pattern.size(); ++k)
    b.push_back({static_cast<double>(k), pattern[k], 0.0, 1.0});
  return static_cast<bool>(solve_block(b, d, [](const indexed_dwell& x) { return x; }));
}

// The terms the table separates that a block of `pattern` has room for (the last dropped until
// the block's design has full rank); the dropped ones in `dropped`.
std::vector<std::string> terms_for(const position_table& table, std::span<const int> pattern,
                                   std::vector<std::string>* dropped) {
  const auto sep = separability_of(table, table_axis_kind::horizontal);
  std::vector<std::string> terms(sep.estimable.begin() + 1, sep.estimable.end());
  while (!terms.empty() && !block_separates(table, pattern, terms)) {
    if (dropped) dropped->insert(dropped->begin(), terms.back());
    terms.pop_back();
  }
  return terms;
}

// The standard error of a series' mean with its correlation read from its own overlapping Allan
// variance (NIST SP1065 eqn 11): se^2 = the variance of the mean that AVAR(m) m / n gives at
// the octaves m = m*/4, m*/2, m* (m* = n/8, as method::correlated_stderr), pooled with weights
// 1/m (each octave's degrees of freedom ~ n/m; ~60 pooled against ~10 at m* alone). For white
// blocks it equals s^2/n in expectation; positively correlated (random walk, flicker of what the
// blocks measure) it is larger; anti-correlated (the bias's flicker leaks into neighbouring
// blocks' contrasts with opposite signs: docs/PLANNER.md, eqn 1) smaller. Not the maximum with
// s^2/n as correlated_stderr takes: with ~10 degrees of freedom that maximum is biased high
// (the heading's 1 sigma then covered 75 % of the errors instead of 68 %: docs/NORTH.md).
// Fewer than 32 blocks: the naive error.
double pooled_correlated_stderr(std::span<const double> y, double naive) {
  const std::size_t n = y.size();
  if (n < 32) return naive;
  const std::size_t m_top = n / 8;
  const auto phase = analysis::phase_from_rate(y, 1.0);
  double num = 0.0, den = 0.0;
  for (std::size_t m = std::max<std::size_t>(m_top / 4, 1); m <= m_top; m *= 2) {
    const double adev = analysis::deviation_at(analysis::dev_kind::oadev, phase, 1.0, m).dev;
    const double w = 1.0 / static_cast<double>(m);
    num += w * adev * adev * static_cast<double>(m) / static_cast<double>(n);
    den += w;
  }
  return std::sqrt(num / den);
}

std::vector<int> pattern_of(std::span<const indexed_dwell> dwells, std::size_t period) {
  std::vector<int> p;
  for (std::size_t k = 0; k < period; ++k) p.push_back(dwells[k].position);
  return p;
}

struct indexed_at {
  indexed_dwell d;
  std::size_t index = 0;
  int position = 0;
};

// The blocks of `period` dwells (the visiting period or a whole multiple of it) repeating the
// run's first `period` positions: blocks_of's rule for a block of any length.
harmonic_blocks blocks_with(std::span<const indexed_dwell> dwells, std::size_t period) {
  harmonic_blocks out;
  out.period = period;
  if (period == 0 || dwells.size() < period) return out;
  block_cutter<indexed_at> cut(pattern_of(dwells, period));
  for (std::size_t k = 0; k < dwells.size(); ++k)
    if (cut.push({dwells[k], k, dwells[k].position}))
      out.starts.push_back(cut.take().front().index);
  return out;
}

}  // namespace

harmonic_blocks blocks_of(std::span<const indexed_dwell> dwells) {
  return blocks_with(dwells, period_of(dwells));
}

result<harmonic_fit> fit_harmonics(std::span<const indexed_dwell> dwells,
                                   const position_table& table, const harmonic_options& options) {
  std::vector<std::string> terms;
  // A 0/180 table: the projection p1 (its own design and block rule, below).
  const bool projection = options.projection_of_two && table.size() == 2 &&
                          options.harmonics == 1 && options.terms.empty() && !options.separable;
  if (projection) {
    if (std::abs(angle_between_deg(table.angle_deg(0), table.angle_deg(1)) - 180.0) > 1e-6)
      return runtime_error(fmt::format(
          "two positions give the Earth rate's projection only when 180 deg apart; the table "
          "has {}",
          table.describe()));
    terms = {"p1"};
  } else if (!options.terms.empty()) {
    for (const auto& t : options.terms) {
      const auto at = std::find(harmonic_term_names.begin() + 1, harmonic_term_names.end(), t);
      if (at == harmonic_term_names.end())
        return usage_error(fmt::format("'{}' is not a harmonic term (c1, s1, c2, s2)", t));
      if (!terms.empty() &&
          std::find(harmonic_term_names.begin(), harmonic_term_names.end(), terms.back()) >= at)
        return usage_error("harmonic terms are given once each, in the order c1, s1, c2, s2");
      terms.push_back(t);
    }
    if (table.size() < terms.size() + 1)
      return runtime_error(
          fmt::format("{} terms and the bias need at least {} table positions; "
                      "the run has {} ({})",
                      terms.size(), terms.size() + 1, table.size(), table.describe()));
  } else {
    if (options.harmonics != 1 && options.harmonics != 2)
      return usage_error("one or two harmonics are fitted");
    const std::size_t n_h = static_cast<std::size_t>(options.harmonics);
    const std::size_t need = 2 * n_h + 1;
    if (table.size() < need)
      return runtime_error(
          fmt::format("{} harmonic{} need at least {} table positions; the run has {} ({})", n_h,
                      n_h == 1 ? "" : "s", need, table.size(), table.describe()));
    terms = {"c1", "s1"};
    if (n_h == 2) terms.insert(terms.end(), {"c2", "s2"});
  }
  const std::size_t visit_period = period_of(dwells);
  if (visit_period == 0)
    return runtime_error(
        "the dwells' positions do not repeat with a period of 2 to 16 dwells: not an indexed "
        "run");
  for (std::size_t k = 0; k < visit_period; ++k)
    if (!table.holds(dwells[k].position))
      return runtime_error(
          fmt::format("dwell {}: position {} is not in the table", k, dwells[k].position));
  harmonic_fit fit;
  if (options.separable) terms = terms_for(table, pattern_of(dwells, visit_period), &fit.dropped);
  // The block's design: bias, slope, then the terms. A projection's block spans whole visiting
  // periods up to a residual degree of freedom (A B A B for the paper's cycle).
  std::size_t period = visit_period;
  if (projection)
    while (period < 2 + terms.size() + 1) period += visit_period;
  if (dwells.size() < period)
    return runtime_error(
        fmt::format("{} dwells: fewer than one block of {}", dwells.size(), period));
  const auto blocks = blocks_with(dwells, period);
  const block_design design = design_of(table, pattern_of(dwells, period), terms);
  const std::size_t cols = design.cols();
  if (period < cols)
    return runtime_error(
        fmt::format("a visiting period of {} dwells cannot separate {} terms "
                    "and the bias's slope",
                    period, cols - 1));
  fit.names = {"b"};
  fit.names.insert(fit.names.end(), terms.begin(), terms.end());
  fit.period = period;
  const std::size_t n_terms = fit.names.size();
  std::vector<std::vector<double>> per_block(n_terms);
  double rss = 0.0, first_start_s = 0.0, last_start_s = 0.0, last_span_s = 0.0;
  std::size_t dof = 0;
  fit.skipped_dwells = 0;
  std::size_t expected_start = 0;
  for (const std::size_t start : blocks.starts) {
    fit.skipped_dwells += start - expected_start;
    expected_start = start + period;
    const auto b = dwells.subspan(start, period);
    const std::vector<indexed_dwell> block(b.begin(), b.end());
    auto f = solve_block(block, design, [](const indexed_dwell& x) { return x; });
    if (!f)
      return runtime_error(
          fmt::format("the table's positions ({} deg) cannot separate {} from the bias: {}",
                      table.describe(), fmt::join(terms, ", "), f.err().message));
    per_block[0].push_back(f->coeffs[0]);
    for (std::size_t i = 1; i < n_terms; ++i) per_block[i].push_back(f->coeffs[i + 1]);
    rss += f->chi2;
    dof += period - cols;
    if (fit.blocks == 0) first_start_s = b.front().time_s;
    last_start_s = b.front().time_s;
    last_span_s = std::max(b.back().time_s - b.front().time_s, 1e-9);
    ++fit.blocks;
  }
  if (fit.blocks < 3)
    return runtime_error(
        fmt::format("{} complete visiting period{} of {} dwells found; the fit "
                    "needs at least 3",
                    fit.blocks, fit.blocks == 1 ? "" : "s", period));
  const auto nb = static_cast<double>(fit.blocks);
  fit.dwells = fit.blocks * period;
  // From one block's first dwell to the next's (the blocks' spacing is uneven within a sweep).
  fit.block_s = (last_start_s - first_start_s) / (nb - 1.0);
  if (!(fit.block_s > last_span_s))
    fit.block_s = last_span_s * static_cast<double>(period) / static_cast<double>(period - 1);
  fit.dwell_sigma_dps = dof > 0 ? std::sqrt(rss / static_cast<double>(dof)) : 0.0;
  fit.value.assign(n_terms, 0.0);
  std::vector<double> inflate(n_terms, 1.0);
  for (std::size_t i = 0; i < n_terms; ++i) {
    double m = 0.0;
    for (const double v : per_block[i]) m += v;
    fit.value[i] = m / nb;
  }
  fit.covariance.assign(n_terms * n_terms, 0.0);
  for (std::size_t i = 0; i < n_terms; ++i)
    for (std::size_t j = 0; j < n_terms; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < fit.blocks; ++k)
        s += (per_block[i][k] - fit.value[i]) * (per_block[j][k] - fit.value[j]);
      fit.covariance[i * n_terms + j] = s / (nb - 1.0) / nb;
    }
  // Each term's variance widened to its correlated error (flicker, random walk of the bias).
  for (std::size_t i = 0; i < n_terms; ++i) {
    const double naive = std::sqrt(fit.covariance[i * n_terms + i]);
    const double se = pooled_correlated_stderr(per_block[i], naive);
    fit.correlated = fit.blocks >= 32;
    inflate[i] = naive > 0.0 ? se / naive : 1.0;
  }
  fit.correlated_factor = inflate;
  for (std::size_t i = 0; i < n_terms; ++i)
    for (std::size_t j = 0; j < n_terms; ++j)
      fit.covariance[i * n_terms + j] *= inflate[i] * inflate[j];
  return fit;
}

namespace {

// Removes from `v` its projections on the orthonormal vectors `basis` (modified Gram-Schmidt);
// returns what is left's norm.
double orthogonalize(const std::vector<std::vector<double>>& basis, std::vector<double>& v) {
  for (const auto& e : basis) {
    double d = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) d += e[i] * v[i];
    for (std::size_t i = 0; i < v.size(); ++i) v[i] -= d * e[i];
  }
  double n = 0.0;
  for (const double x : v) n += x * x;
  return std::sqrt(n);
}

std::string_view regressor_text(std::string_view term) {
  if (term == "c1") return "cos t";
  if (term == "s1") return "sin t";
  if (term == "c2") return "cos 2t";
  if (term == "s2") return "sin 2t";
  return "1";
}

std::string angles_text(const position_table& table) {
  std::string out;
  for (std::size_t i = 0; i < table.size(); ++i)
    out += fmt::format("{}{:g}", i == 0 ? "" : ", ", table.angle_deg(static_cast<int>(i)));
  return out;
}

constexpr std::string_view more_positions =
    "a table of 5 or more positions not all at multiples of 90 or 120 deg (e.g. 0, 72, 144, 216, "
    "288) separates b and both harmonics";

void add_meanings(separability& s, table_axis_kind axis) {
  const bool vertical = axis == table_axis_kind::vertical;
  for (const auto& t : s.estimable) {
    std::string m;
    if (t == "b")
      m = vertical ? "the gyro's bias (the vertical Earth rate W_E sin(lat) and gravity enter "
                     "only through the sensitive axis's tilt out of the table's plane)"
                   : "the gyro's bias (the Earth rate and gravity along the table axis enter only "
                     "through the sensitive axis's misalignment to the table's plane)";
    else if (t == "c1" || t == "s1")
      m = fmt::format(
          "{}, projected on the sensitive axis at table {} deg, x (1 + scale-factor error)",
          vertical ? "the horizontal Earth rate W_E cos(lat) (north finding: heading = "
                     "atan2(s1, c1)) + table tilt x g-sensitivity"
                   : "the Earth rate in the table's plane + g-sensitivity x gravity (paper eqn "
                     "11, dN = W_E.s + d_g, for the 0/180 pair)",
          t == "c1" ? 0 : 90);
    else
      m = "no term linear in the Earth rate or gravity (each turns once per table turn): an "
          "anisoelastic (g^2) sensitivity, a table wobble at twice the turn, a mount error; 0 in "
          "the simulator";
    s.meanings.push_back({t, std::move(m)});
  }
  const auto has = [&s](std::string_view t) {
    return std::find(s.estimable.begin(), s.estimable.end(), t) != s.estimable.end();
  };
  const std::string first = has("s1") ? "c1, s1" : "c1";
  if (vertical) {
    s.pairs.push_back(
        {"horizontal Earth rate", "table tilt x g-sensitivity", first,
         "a tilted table axis puts a component of gravity in the table's plane, fixed to the "
         "rig: it reads as a first harmonic exactly like the Earth's (1 mrad x 0.39 deg/s/g = 7 "
         "deg of heading on an ADXRS150)",
         "nothing within one run, whatever the positions; a second base azimuth (the rig turned "
         "between runs: `heading RUN1 RUN2`) separates them"});
    s.pairs.push_back({"bias", "vertical Earth rate x axis tilt", "b",
                       "both are constant over the table angle",
                       "a known latitude and a measured tilt of the sensitive axis"});
  } else {
    s.pairs.push_back(
        {"Earth rate", "g-sensitivity", first,
         "the Earth's rate and gravity are both fixed vectors in the table's plane: each reads "
         "as a first harmonic; no number of positions separates them",
         "a second base azimuth (the rig turned about the vertical between runs) separates the "
         "Earth rate's horizontal part (it turns with the base, gravity does not); only a known "
         "latitude separates its vertical part (W_E sin(lat), which no turn of the base "
         "changes)"});
  }
  s.pairs.push_back({"Earth rate", "a steady rate of the rig's base", first,
                     "any rate fixed in the world reads as the Earth's",
                     "a base at rest (checked by eye or a second run)"});
}

}  // namespace

table_axis_kind table_axis_kind_of(std::string_view text) {
  if (text.empty()) return table_axis_kind::horizontal;
  const auto a = earth::parse_axis(text);
  if (!a) return table_axis_kind::horizontal;
  return std::abs(a->down) > std::cos(8.0 * units::rad_per_deg) ? table_axis_kind::vertical
                                                                : table_axis_kind::horizontal;
}

separability separability_of(const position_table& table, table_axis_kind axis) {
  separability s;
  s.positions = angles_text(table);
  s.axis = axis == table_axis_kind::vertical ? "vertical" : "horizontal";
  const std::size_t n = table.size();
  std::vector<std::vector<double>> basis;  // orthonormal, over the table's angles
  std::vector<std::string> kept;
  std::vector<double> cols;  // the kept terms' regressors, column by column
  for (const auto term : harmonic_term_names) {
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i)
      v[i] = regressor(term, table.angle_deg(static_cast<int>(i)) * units::rad_per_deg);
    double norm = 0.0;
    for (const double x : v) norm += x * x;
    norm = std::sqrt(norm);
    if (norm < 1e-9 * std::sqrt(static_cast<double>(n))) {
      s.unobservable.emplace_back(term);
      s.pairs.push_back(
          {std::string(term), "0", std::string(term),
           fmt::format("{} is 0 at every position ({} deg)", regressor_text(term), s.positions),
           std::string(more_positions)});
      continue;
    }
    auto r = v;
    const double rn = orthogonalize(basis, r);
    if (rn > 1e-9 * norm) {
      for (double& x : r) x /= rn;
      basis.push_back(std::move(r));
      kept.emplace_back(term);
      cols.insert(cols.end(), v.begin(), v.end());
      continue;
    }
    // Aliased: v as a combination of the kept terms' regressors.
    const std::size_t k = kept.size();
    std::vector<double> design(n * k);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < k; ++j) design[i * k + j] = cols[j * n + i];
    const std::vector<double> w(n, 1.0);
    const auto f = analysis::weighted_least_squares(design, k, v, w);
    for (std::size_t j = 0; f && j < k; ++j)
      if (std::abs(f->coeffs[j]) > 1e-9)
        s.pairs.push_back({std::string(term), kept[j], kept[j],
                           fmt::format("at {} deg {} = {:+.6g} x {} (aliased)", s.positions,
                                       regressor_text(term), f->coeffs[j], regressor_text(kept[j])),
                           std::string(more_positions)});
  }
  s.estimable = std::move(kept);
  add_meanings(s, axis);
  return s;
}

std::vector<std::string> separability::lines() const {
  std::vector<std::string> out;
  out.push_back(fmt::format("separability at positions {} deg (table axis {}{}):", positions, axis,
                            axis_recorded ? "" : "; not recorded, taken as horizontal"));
  out.push_back(fmt::format("  estimable: {}", fmt::join(estimable, ", ")));
  if (!unobservable.empty())
    out.push_back(fmt::format("  not observable: {}", fmt::join(unobservable, ", ")));
  for (const auto& m : meanings) out.push_back(fmt::format("  {} holds {}", m.term, m.holds));
  for (const auto& p : pairs)
    out.push_back(fmt::format("  inseparable: {} and {} (in {}): {}; separated by: {}", p.first,
                              p.second, p.in_terms, p.why, p.separated_by));
  return out;
}

namespace {

// The harmonic (N-position) demodulator: see make_harmonic_demodulator.
class harmonic_demodulator final : public demodulator {
 public:
  explicit harmonic_demodulator(position_table table) : table_(std::move(table)) {
    for (std::size_t i = 0; i < table_.size(); ++i) uses_ |= std::uint32_t{1} << i;
  }
  [[nodiscard]] std::string_view name() const noexcept override { return "harmonic"; }
  [[nodiscard]] std::uint32_t uses() const noexcept override { return uses_; }
  [[nodiscard]] bool dwell_per_row() const noexcept override { return true; }
  [[nodiscard]] std::optional<cycle> push(const dwell& d) override {
    const item x{
        {d.time_s, d.position, d.rate_dps, static_cast<double>(d.weight)}, d.temp_c, d.position};
    if (cut_) {
      take(x);
    } else {
      pending_.push_back(x);
      // The period from the first dwells, as fit_harmonics finds it (4 periods of up to 16).
      if (pending_.size() >= 4 * 2 * position_table::max_positions) start(false);
    }
    return pop();
  }
  [[nodiscard]] std::optional<cycle> flush() override {
    if (!cut_ && !pending_.empty()) start(true);
    if (auto c = pop()) return c;
    *this = harmonic_demodulator(table_);
    return std::nullopt;
  }
  [[nodiscard]] std::unique_ptr<demodulator> fresh() const override {
    return std::make_unique<harmonic_demodulator>(table_);
  }

 private:
  struct item {
    indexed_dwell d;
    double temp_c = no_value;
    int position = 0;
  };
  void start(bool at_end) {
    std::vector<indexed_dwell> d;
    for (const auto& x : pending_) d.push_back(x.d);
    const std::size_t p = period_of(d);
    if (p == 0) {  // no pattern yet (a gap among the first dwells): slide on
      if (at_end)
        pending_.clear();
      else
        pending_.erase(pending_.begin());
      return;
    }
    const auto pattern = pattern_of(d, p);
    design_ = design_of(table_, pattern, terms_for(table_, pattern, nullptr));
    cut_.emplace(pattern);
    auto held = std::move(pending_);
    pending_.clear();
    for (const auto& x : held) take(x);
  }
  void take(const item& x) {
    if (!cut_->push(x)) return;
    const auto b = cut_->take();
    if (design_.terms.empty()) return;
    const auto f =
        solve_block(b, design_, [](const item& i) -> const indexed_dwell& { return i.d; });
    if (!f) return;
    cycle c;
    double t = 0.0, temp = 0.0;
    for (const auto& i : b) {
      t += i.d.time_s;
      temp += i.temp_c;
    }
    c.time_s = t / static_cast<double>(b.size());
    c.temp_c = temp / static_cast<double>(b.size());
    c.rate_dps = f->coeffs[2];  // c1: always separable with 3 or more positions
    c.bias_dps = f->coeffs[0];
    queue_.push_back(c);
  }
  std::optional<cycle> pop() {
    if (queue_.empty()) return std::nullopt;
    const cycle c = queue_.front();
    queue_.erase(queue_.begin());
    return c;
  }
  position_table table_;
  std::uint32_t uses_ = 0;
  std::vector<item> pending_;
  std::optional<block_cutter<item>> cut_;
  block_design design_;
  std::vector<cycle> queue_;
};

// Cholesky factor of a symmetric positive definite n x n matrix (row-major, in place, lower);
// false if not positive definite.
bool cholesky(std::vector<double>& a, std::size_t n) {
  for (std::size_t j = 0; j < n; ++j) {
    double d = a[j * n + j];
    for (std::size_t k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0.0)) return false;
    const double l = std::sqrt(d);
    a[j * n + j] = l;
    for (std::size_t i = j + 1; i < n; ++i) {
      double x = a[i * n + j];
      const double* ri = &a[i * n];
      const double* rj = &a[j * n];
      for (std::size_t k = 0; k < j; ++k) x -= ri[k] * rj[k];
      a[i * n + j] = x / l;
    }
  }
  return true;
}

// Solves L y = b in place (L the lower factor of cholesky), b with `m` columns (row-major n x m).
void forward_solve(const std::vector<double>& l, std::size_t n, std::vector<double>& b,
                   std::size_t m) {
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < m; ++c) {
      double x = b[i * m + c];
      for (std::size_t k = 0; k < i; ++k) x -= l[i * n + k] * b[k * m + c];
      b[i * m + c] = x / l[i * n + i];
    }
}

// An orthonormal basis (columns, row-major p x (p - 2)) of the vectors orthogonal to 1 and t.
std::vector<double> contrasts_basis(std::span<const double> t) {
  const std::size_t p = t.size();
  std::vector<std::vector<double>> basis;
  const auto add = [&basis](std::vector<double> v) {
    const double n = orthogonalize(basis, v);
    if (n < 1e-8) return false;
    for (double& x : v) x /= n;
    basis.push_back(std::move(v));
    return true;
  };
  add(std::vector<double>(p, 1.0));
  add(std::vector<double>(t.begin(), t.end()));
  for (std::size_t k = 0; k < p && basis.size() < p; ++k) {
    std::vector<double> e(p, 0.0);
    e[k] = 1.0;
    add(std::move(e));
  }
  const std::size_t q = basis.size() - 2;
  std::vector<double> out(p * q);
  for (std::size_t a = 0; a < q; ++a)
    for (std::size_t i = 0; i < p; ++i) out[i * q + a] = basis[a + 2][i];
  return out;
}

}  // namespace

result<std::unique_ptr<demodulator>> make_harmonic_demodulator(const position_table& table,
                                                               const std::string& source) {
  if (table.size() < 3)
    return input_error({source},
                       fmt::format("the harmonic scheme needs a table of 3 or more positions; this "
                                   "recording's has {} ({} deg)",
                                   table.size(), table.describe()));
  return std::unique_ptr<demodulator>(std::make_unique<harmonic_demodulator>(table));
}

result<noise_transfer> harmonic_transfer(const position_table& table,
                                         std::span<const int> visiting_order) {
  for (const int p : visiting_order)
    if (!table.holds(p)) return usage_error(fmt::format("position {} is not in the table", p));
  const auto terms = terms_for(table, visiting_order, nullptr);
  if (terms.empty() || terms.front() != "c1")
    return runtime_error(
        fmt::format("a visiting period of {} dwells at {} deg separates no "
                    "first harmonic from the bias and its slope",
                    visiting_order.size(), table.describe()));
  const auto d = design_of(table, visiting_order, terms);
  const std::size_t p = visiting_order.size(), cols = d.cols();
  std::vector<double> design(p * cols), y(p, 0.0), w(p, 1.0);
  const double t_mean = static_cast<double>(p - 1) / 2.0, t_span = static_cast<double>(p - 1);
  for (std::size_t k = 0; k < p; ++k) {
    design[k * cols] = 1.0;
    design[k * cols + 1] = (static_cast<double>(k) - t_mean) / t_span;
    for (std::size_t i = 0; i < terms.size(); ++i) design[k * cols + 2 + i] = d.slots[k][i];
  }
  const auto f = analysis::weighted_least_squares(design, cols, y, w);
  if (!f) return f.err();
  noise_transfer t;
  t.cycle_dwells = p;
  t.kernel_offset = 0;
  t.rate_kernel.assign(p, 0.0);
  t.bias_kernel.assign(p, 0.0);
  for (std::size_t k = 0; k < p; ++k)
    for (std::size_t j = 0; j < cols; ++j) {
      t.rate_kernel[k] += f->cov[2 * cols + j] * design[k * cols + j];
      t.bias_kernel[k] += f->cov[0 * cols + j] * design[k * cols + j];
    }
  return t;
}

double gauss_markov_gap_avar(double variance, double time_constant_s, double tau_s,
                             double spacing_s) noexcept {
  const double x = tau_s / time_constant_s, k = variance / (x * x);
  const double var = 2.0 * k * (x - 1.0 + std::exp(-x));
  // e^{-S/T} (e^{x} + e^{-x} - 2) = e^{-S/T} 2 (cosh x - 1), written to stay finite for x >> 1
  const double cov =
      k * (std::exp(x - spacing_s / time_constant_s) + std::exp(-x - spacing_s / time_constant_s) -
           2.0 * std::exp(-spacing_s / time_constant_s));
  return var - cov;
}

result<std::vector<double>> harmonic_crlb(const harmonic_fit& fit,
                                          std::span<const indexed_dwell> dwells,
                                          const position_table& table, const plan_noise& noise,
                                          double dwell_s) {
  if (!(dwell_s > 0.0)) return usage_error("the dwell length must be positive");
  return harmonic_crlb(fit, dwells, table, [&noise, dwell_s](double spacing_s) {
    return gap_avar(noise, dwell_s, std::max(spacing_s, dwell_s));
  });
}

result<std::vector<double>> harmonic_crlb(const harmonic_fit& fit,
                                          std::span<const indexed_dwell> dwells,
                                          const position_table& table,
                                          const std::function<double(double)>& gap_avar_of) {
  // The fit's blocks: the visiting period, or whole periods of it (the projection p1).
  const std::size_t visit = period_of(dwells);
  const auto blocks = blocks_with(dwells, visit == 0 ? 0 : fit.period);
  if (visit == 0 || fit.period % visit != 0 || blocks.starts.size() != fit.blocks)
    return usage_error("the dwells are not those of the fit");
  const std::size_t p = blocks.period, q = p - 2, nb = blocks.starts.size();
  const std::vector<std::string> terms(fit.names.begin() + 1, fit.names.end());
  const std::size_t m = terms.size(), big = nb * q;
  const auto pattern = pattern_of(dwells, p);
  const auto design = design_of(table, pattern, terms);
  // Each block's contrasts (orthogonal to its constant and slope) and projected regressors.
  std::vector<std::vector<double>> basis(nb);
  std::vector<double> z(big * m, 0.0);
  for (std::size_t j = 0; j < nb; ++j) {
    std::vector<double> t(p);
    for (std::size_t k = 0; k < p; ++k) t[k] = dwells[blocks.starts[j] + k].time_s;
    const double t0 = t.front();
    for (double& x : t) x -= t0;
    basis[j] = contrasts_basis(t);
    if (basis[j].size() != p * q) return runtime_error("a block's times are degenerate");
    for (std::size_t a = 0; a < q; ++a)
      for (std::size_t i = 0; i < m; ++i) {
        double s = 0.0;
        for (std::size_t k = 0; k < p; ++k) s += basis[j][k * q + a] * design.slots[k][i];
        z[(j * q + a) * m + i] = s;
      }
  }
  // The contrasts' covariance from the structure function: -sum u_a v_b gap_avar(|t_a - t_b|).
  const auto gap = [&gap_avar_of](double dt) { return gap_avar_of(std::abs(dt)); };
  std::vector<double> c(big * big, 0.0), g(p * p), tmp(p * q);
  for (std::size_t j = 0; j < nb; ++j)
    for (std::size_t l = 0; l <= j; ++l) {
      for (std::size_t u = 0; u < p; ++u)
        for (std::size_t v = 0; v < p; ++v)
          g[u * p + v] =
              (j == l && u == v)
                  ? 0.0
                  : gap(dwells[blocks.starts[j] + u].time_s - dwells[blocks.starts[l] + v].time_s);
      // tmp = G Q_l (p x q); block = -Q_j^T tmp
      for (std::size_t u = 0; u < p; ++u)
        for (std::size_t b = 0; b < q; ++b) {
          double s = 0.0;
          for (std::size_t v = 0; v < p; ++v) s += g[u * p + v] * basis[l][v * q + b];
          tmp[u * q + b] = s;
        }
      for (std::size_t a = 0; a < q; ++a)
        for (std::size_t b = 0; b < q; ++b) {
          double s = 0.0;
          for (std::size_t u = 0; u < p; ++u) s += basis[j][u * q + a] * tmp[u * q + b];
          c[(j * q + a) * big + (l * q + b)] = -s;
          c[(l * q + b) * big + (j * q + a)] = -s;
        }
    }
  if (!cholesky(c, big))
    return runtime_error("the noise model's covariance of the contrasts is not positive definite");
  forward_solve(c, big, z, m);
  std::vector<double> fisher(m * m, 0.0);
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t k = 0; k < m; ++k) {
      double s = 0.0;
      for (std::size_t r = 0; r < big; ++r) s += z[r * m + i] * z[r * m + k];
      fisher[i * m + k] = s;
    }
  // The bound: the Fisher information's inverse (by the solver: (I^T I)^-1 with I = L^T).
  std::vector<double> lf = fisher;
  if (!cholesky(lf, m)) return runtime_error("the terms carry no information (singular Fisher)");
  std::vector<double> inv(m * m, 0.0);
  for (std::size_t col = 0; col < m; ++col) {
    std::vector<double> e(m, 0.0);
    e[col] = 1.0;
    forward_solve(lf, m, e, 1);
    for (std::size_t i = m; i-- > 0;) {  // L^T x = e
      double x = e[i];
      for (std::size_t k = i + 1; k < m; ++k) x -= lf[k * m + i] * inv[k * m + col];
      inv[i * m + col] = x / lf[i * m + i];
    }
  }
  return inv;
}

heading_estimate heading_of(double c1, double s1, double var_c1, double var_s1, double cov_c1_s1,
                            bool table_axis_up) {
  if (!table_axis_up) {
    s1 = -s1;
    cov_c1_s1 = -cov_c1_s1;
  }
  heading_estimate h;
  const double a2 = c1 * c1 + s1 * s1;
  h.amplitude_dps = std::sqrt(a2);
  double psi = std::atan2(s1, c1) / units::rad_per_deg;
  if (psi < 0.0) psi += 360.0;
  h.heading_deg = psi >= 360.0 ? 0.0 : psi;
  // d psi = (c1 ds1 - s1 dc1) / a2
  const double var = (s1 * s1 * var_c1 + c1 * c1 * var_s1 - 2.0 * c1 * s1 * cov_c1_s1) / (a2 * a2);
  h.sigma_deg = std::sqrt(std::max(var, 0.0)) / units::rad_per_deg;
  return h;
}

projection_heading heading_of_projection(double p1, double var_p1, double earth_horizontal_dps,
                                         double axis_angle_deg, bool table_axis_up) {
  projection_heading h;
  const double x = p1 / earth_horizontal_dps;
  const double sx = std::sqrt(std::max(var_p1, 0.0)) / earth_horizontal_dps;
  h.cos_value = x;
  const double a = std::acos(std::clamp(x, -1.0, 1.0)) / units::rad_per_deg;  // [0, 180]
  const auto wrap = [](double v) {
    v = std::fmod(v, 360.0);
    if (v < 0.0) v += 360.0;
    return v >= 360.0 ? 0.0 : v;
  };
  const double base = table_axis_up ? axis_angle_deg : -axis_angle_deg;
  h.heading_deg = wrap(base + a);
  h.mirror_deg = wrap(base - a);
  h.at_edge = std::abs(x) > 1.0 - sx;
  if (h.at_edge)
    h.sigma_deg = std::acos(std::max(-1.0, 1.0 - sx)) / units::rad_per_deg;
  else
    h.sigma_deg = sx / std::sqrt(1.0 - x * x) / units::rad_per_deg;
  return h;
}

result<two_projection_heading> heading_of_two_projections(
    double p1, double var_p1, double p2, double var_p2, double earth_horizontal_dps,
    double axis_angle_deg, double base_turn_deg, bool table_axis_up) {
  const double half = 0.5 * base_turn_deg * units::rad_per_deg;
  const double k = 2.0 * earth_horizontal_dps * std::sin(half);
  if (std::abs(std::remainder(base_turn_deg, 360.0)) < 1.0)
    return usage_error(fmt::format(
        "base azimuths {:g} deg apart: the difference of two 0/180 runs then holds no Earth rate",
        base_turn_deg));
  const double x = (p1 - p2) / k;
  const double sx = std::sqrt(std::max(var_p1, 0.0) + std::max(var_p2, 0.0)) / std::abs(k);
  const double as = std::asin(std::clamp(x, -1.0, 1.0)) / units::rad_per_deg;
  const double half_deg = 0.5 * base_turn_deg;
  const double phi = 180.0 - half_deg - as, phi_mirror = as - half_deg;
  const auto wrap = [](double v) {
    v = std::fmod(v, 360.0);
    if (v < 0.0) v += 360.0;
    return v >= 360.0 ? 0.0 : v;
  };
  // phi = psi - theta_0 with the axis up; psi + theta_0 with it down (heading_of_projection).
  const double base = table_axis_up ? axis_angle_deg : -axis_angle_deg;
  two_projection_heading out;
  auto& h = out.heading;
  h.heading_deg = wrap(base + phi);
  h.mirror_deg = wrap(base + phi_mirror);
  h.cos_value = x;
  h.at_edge = std::abs(x) > 1.0 - sx;
  h.sigma_deg = h.at_edge ? std::acos(std::max(-1.0, 1.0 - sx)) / units::rad_per_deg
                          : sx / std::sqrt(1.0 - x * x) / units::rad_per_deg;
  out.table_term_dps = p1 - earth_horizontal_dps * std::cos(phi * units::rad_per_deg);
  out.table_term_mirror_dps = p1 - earth_horizontal_dps * std::cos(phi_mirror * units::rad_per_deg);
  return out;
}

double heading_white_limit_deg(double arw_dps_rthz, double lat_deg, double run_s, double k) {
  const double w_h = earth::earth_rate_wgs84_dps * std::cos(lat_deg * units::rad_per_deg);
  return k * arw_dps_rthz / (w_h * std::sqrt(run_s)) / units::rad_per_deg;
}

double heading_dead_time_limit_deg(double arw_dps_rthz, double bias_instability_dps,
                                   double dead_time_s, double lat_deg, double run_s, double k) {
  return heading_white_limit_deg(
      arw_dps_rthz + 0.664 * bias_instability_dps * std::sqrt(dead_time_s), lat_deg, run_s, k);
}

result<two_azimuth_heading> heading_two_azimuths(std::array<double, 2> h1,
                                                 std::array<double, 4> cov1,
                                                 std::array<double, 2> h2,
                                                 std::array<double, 4> cov2, double base_turn_deg,
                                                 bool table_axis_up) {
  if (!table_axis_up) {  // as seen with the axis up: s1 -> -s1
    h1[1] = -h1[1];
    h2[1] = -h2[1];
    cov1[1] = cov1[2] = -cov1[1];
    cov2[1] = cov2[2] = -cov2[1];
  }
  const double turn = base_turn_deg * units::rad_per_deg;
  // w = 1 / (1 - e^{i turn})
  const double den_r = 1.0 - std::cos(turn), den_i = -std::sin(turn);
  const double den2 = den_r * den_r + den_i * den_i;
  if (!(den2 > 1e-6))
    return usage_error(
        fmt::format("base azimuths {} deg apart do not separate the table's term from the Earth's",
                    base_turn_deg));
  const double wr = den_r / den2, wi = -den_i / den2;
  const double dr = h1[0] - h2[0], di = h1[1] - h2[1];
  const double qr = wr * dr - wi * di, qi = wi * dr + wr * di;
  // cov(q) = M cov(d) M^T, M = [[wr, -wi], [wi, wr]]
  const double c00 = cov1[0] + cov2[0], c01 = cov1[1] + cov2[1], c11 = cov1[3] + cov2[3];
  const double q00 = wr * wr * c00 - 2.0 * wr * wi * c01 + wi * wi * c11;
  const double q11 = wi * wi * c00 + 2.0 * wr * wi * c01 + wr * wr * c11;
  const double q01 = wr * wi * c00 + (wr * wr - wi * wi) * c01 - wr * wi * c11;
  two_azimuth_heading out;
  out.first = heading_of(qr, qi, q00, q11, q01, true);
  out.table_term_c1_dps = h1[0] - qr;
  out.table_term_s1_dps = (h1[1] - qi) * (table_axis_up ? 1.0 : -1.0);
  out.table_term_dps = std::hypot(h1[0] - qr, h1[1] - qi);
  return out;
}

}  // namespace gyroflip::method
