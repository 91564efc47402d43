/// \file
/// \brief GRADEV, GCODEV, the three-cornered hat and the dynamic Allan deviation (cross.hpp).
#include "gyroflip/analysis/cross.hpp"

#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis {
namespace {

status check_tau0(double tau0_s) {
  if (!(tau0_s >= phase_source::min_tau0_s && tau0_s <= phase_source::max_tau0_s))
    return parameter_error("tau0", fmt::format("sample interval {} s is not in [{}, {}] s", tau0_s,
                                               phase_source::min_tau0_s, phase_source::max_tau0_s));
  return ok();
}

// The phase of gappy data and, per phase point, its run: a term of lag 2m at i exists when
// run[i] == run[i + 2m] and its three points are finite.
struct gappy_phase {
  std::vector<double> x;
  std::vector<std::size_t> run;
};

result<gappy_phase> phase_with_gaps(std::span<const double> data, input_kind in, double tau0_s) {
  for (std::size_t k = 0; k < data.size(); ++k)
    if (std::isinf(data[k]))
      return runtime_error(
          fmt::format("sample {} (0-based) is infinite; a missing sample is NaN", k));
  gappy_phase p;
  if (in == input_kind::angle) {
    p.x.assign(data.begin(), data.end());
    p.run.assign(data.size(), 0);
    return p;
  }
  long double mean = 0.0L;
  std::size_t finite = 0;
  for (double v : data)
    if (!std::isnan(v)) {
      mean += static_cast<long double>(v);
      ++finite;
    }
  if (finite > 0) mean /= static_cast<long double>(finite);
  p.x.assign(data.size() + 1, 0.0);
  p.run.assign(data.size() + 1, 0);
  long double acc = 0.0L;
  std::size_t run = 0;
  for (std::size_t k = 0; k < data.size(); ++k) {
    if (std::isnan(data[k])) {  // the phase after a missing sample starts a new run
      ++run;
      acc = 0.0L;
    } else {
      acc += (static_cast<long double>(data[k]) - mean) * static_cast<long double>(tau0_s);
    }
    p.x[k + 1] = static_cast<double>(acc);
    p.run[k + 1] = run;
  }
  return p;
}

}  // namespace

result<std::vector<deviation_point>> gradev(std::span<const double> data, input_kind in,
                                            double tau0_s, const tau_spec& taus) {
  if (auto s = check_tau0(tau0_s); !s) return s.err();
  auto p = phase_with_gaps(data, in, tau0_s);
  if (!p) return p.err();
  const auto& x = p->x;
  if (x.size() < 3)
    return runtime_error(
        fmt::format("{} phase points are too few for an Allan deviation", x.size()));
  std::vector<deviation_point> out;
  for (std::size_t m : averaging_factors(taus, dev_kind::oadev, x.size())) {
    if (x.size() < 2 * m + 1) continue;
    long double sum = 0.0L;
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 * m < x.size(); ++i) {
      if (p->run[i] != p->run[i + 2 * m]) continue;
      const double v = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
      if (std::isnan(v)) continue;
      sum += static_cast<long double>(v) * v;
      ++n;
    }
    if (n == 0) continue;
    const double tau = static_cast<double>(m) * tau0_s;
    deviation_point d;
    d.m = m;
    d.tau_s = tau;
    d.n = n;
    d.dev = static_cast<double>(std::sqrt(sum / (2.0L * n * static_cast<long double>(tau) * tau)));
    out.push_back(d);
  }
  if (out.empty()) return runtime_error("no averaging time has a complete term between the gaps");
  return out;
}

result<std::vector<deviation_point>> gcodev(std::span<const double> a, std::span<const double> b,
                                            input_kind in, double tau0_s, const tau_spec& taus) {
  if (a.size() != b.size())
    return runtime_error(
        fmt::format("the two series have {} and {} samples; GCODEV needs "
                    "simultaneous samples of one length",
                    a.size(), b.size()));
  // Each series' checks (finite, tau0, length) are deviation's own.
  const auto pa = deviation(dev_kind::oadev, a, in, tau0_s, taus);
  if (!pa) return pa.err();
  if (auto pb = deviation(dev_kind::oadev, b, in, tau0_s, taus); !pb) return pb.err();
  const auto xa =
      in == input_kind::rate ? phase_from_rate(a, tau0_s) : std::vector<double>(a.begin(), a.end());
  const auto xb =
      in == input_kind::rate ? phase_from_rate(b, tau0_s) : std::vector<double>(b.begin(), b.end());
  std::vector<deviation_point> out;
  for (const auto& q : *pa) {
    const std::size_t m = q.m;
    long double sum = 0.0L;
    const std::size_t n = xa.size() - 2 * m;
    for (std::size_t i = 0; i < n; ++i)
      sum += static_cast<long double>(xa[i + 2 * m] - 2.0 * xa[i + m] + xa[i]) *
             (xb[i + 2 * m] - 2.0 * xb[i + m] + xb[i]);
    const long double cov = sum / (2.0L * n * static_cast<long double>(q.tau_s) * q.tau_s);
    deviation_point d = q;
    d.dev = static_cast<double>(cov < 0 ? -std::sqrt(-cov) : std::sqrt(cov));
    out.push_back(d);
  }
  return out;
}

result<std::array<std::vector<deviation_point>, 3>> three_cornered_hat(
    dev_kind k, std::span<const double> ab, std::span<const double> bc, std::span<const double> ca,
    input_kind in, double tau0_s, const tau_spec& taus) {
  if (ab.size() != bc.size() || ab.size() != ca.size())
    return runtime_error(
        fmt::format("the comparisons have {}, {} and {} samples; the "
                    "three-cornered hat needs three of one length",
                    ab.size(), bc.size(), ca.size()));
  std::array<std::vector<deviation_point>, 3> pair;
  const std::array<std::span<const double>, 3> data{ab, bc, ca};
  for (std::size_t i = 0; i < 3; ++i) {
    auto d = deviation(k, data[i], in, tau0_s, taus);
    if (!d) return d.err();
    pair[i] = std::move(*d);
  }
  // var_A = (AB + CA - BC)/2, var_B = (AB + BC - CA)/2, var_C = (BC + CA - AB)/2.
  std::array<std::vector<deviation_point>, 3> out;
  for (std::size_t j = 0; j < pair[0].size(); ++j) {
    const double vab = pair[0][j].dev * pair[0][j].dev;
    const double vbc = pair[1][j].dev * pair[1][j].dev;
    const double vca = pair[2][j].dev * pair[2][j].dev;
    const double var[3] = {0.5 * (vab + vca - vbc), 0.5 * (vab + vbc - vca),
                           0.5 * (vbc + vca - vab)};
    for (std::size_t c = 0; c < 3; ++c) {
      deviation_point p = pair[0][j];
      p.dev = var[c] > 0.0 ? std::sqrt(var[c]) : 0.0;
      out[c].push_back(p);
    }
  }
  return out;
}

result<std::vector<dynamic_window>> dynamic_deviation(dev_kind k, std::span<const double> data,
                                                      input_kind in, double tau0_s,
                                                      std::size_t window, std::size_t step,
                                                      const tau_spec& taus,
                                                      const progress_fn& on_progress) {
  if (window < 3 || window > data.size())
    return parameter_error("window", fmt::format("a window of {} samples does not fit {} samples "
                                                 "(at least 3, at most all)",
                                                 window, data.size()));
  if (step == 0)
    return parameter_error("step", "the step between windows must be at least 1 sample");
  const std::size_t count = (data.size() - window) / step + 1;
  std::vector<result<std::vector<deviation_point>>> curves(count, runtime_error("not computed"));
  // Windows on all cores, each a short series on its own (one thread each).
  detail::for_each_item(
      count, detail::worker_count(data.size()),
      [&](std::size_t, std::size_t w) {
        curves[w] = deviation(k, data.subspan(w * step, window), in, tau0_s, taus);
      },
      on_progress);
  std::vector<dynamic_window> out;
  for (std::size_t w = 0; w < count; ++w) {
    if (!curves[w]) return curves[w].err();
    out.push_back({static_cast<double>(w * step) * tau0_s, std::move(*curves[w])});
  }
  return out;
}

}  // namespace gyroflip::analysis
