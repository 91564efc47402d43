/// \file
/// \brief The decimated phase z_k = x_{km}: ADEV and HDEV sums, noise-identification series
/// (see decimate.hpp).
#include "decimate.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>

#include "kernels.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis::detail {
namespace {

constexpr std::size_t block_terms = 4096;  // ADEV/HDEV terms summed in double at a time
constexpr std::size_t read_points = std::size_t{1} << 16;   // longest single read
constexpr std::size_t chunk_points = std::size_t{1} << 20;  // phase points per work item

// out[i] = x_{(k0 + i) m} for i < count.
void read_decimated(phase_reader& r, std::size_t m, std::size_t k0, std::size_t count,
                    double* out) {
  if (m >= phase_source::block_points) {  // sparse: a point costs at most one block
    for (std::size_t i = 0; i < count; ++i) out[i] = r.read((k0 + i) * m, 1)[0];
    return;
  }
  for (std::size_t i = 0; i < count;) {
    const std::size_t take = std::min(count - i, read_points / m);
    const auto v = r.read((k0 + i) * m, (take - 1) * m + 1);
    for (std::size_t t = 0; t < take; ++t) out[i + t] = v[t * m];
    i += take;
  }
}

// Terms per work item of factor m: whole blocks spanning about chunk_points phase points, so
// that the threads work on separate regions of the phase (and a reader continues within one).
std::size_t item_terms(std::size_t m) {
  return std::max<std::size_t>(1, chunk_points / m / block_terms) * block_terms;
}

// ---- The octave pyramid of block sums (octave_block_sums) ----

constexpr std::size_t pyramid_chunk = std::size_t{1} << 18;  // samples per work item (2 MB)
constexpr std::size_t kept_level = 10;  // levels of 2^10 samples a block and up: kept whole
constexpr std::size_t max_edge = 2;     // order - 1 values at each end of a chunk's level

// Sum of the squared (order-1)-th differences of v[0, n) (terms t + order - 1 < n): ADEV's
// (order 2: v_{t+1} - v_t) and HDEV's (order 3: v_{t+2} - 2 v_{t+1} + v_t) terms on block sums;
// double per block of block_terms, long double across.
long double block_difference_sum(const double* v, std::size_t n, std::size_t order) {
  long double total = 0.0L;
  if (n < order) return total;
  const std::size_t terms = n - order + 1;
  for (std::size_t t0 = 0; t0 < terms; t0 += block_terms) {
    const std::size_t count = std::min(block_terms, terms - t0);
    const double* p = v + t0;
    total += static_cast<long double>(
        order == 2 ? sum_squares(count, [p](std::size_t t) { return p[t + 1] - p[t]; })
                   : sum_second_differences(p, p + 1, p + 2, count));
  }
  return total;
}

// A chunk's values at one level below kept_level: its sum of squared differences, its first and
// last order - 1 values and how many it has (the terms across chunk ends are added afterwards).
struct chunk_level {
  long double sum = 0.0L;
  std::array<double, max_edge> first{};
  std::array<double, max_edge> last{};
  std::size_t count = 0;
};

void note_level(chunk_level& out, const double* v, std::size_t n, std::size_t order, bool want) {
  if (want) out.sum = block_difference_sum(v, n, order);
  out.count = n;
  const std::size_t e = std::min(order - 1, n);
  for (std::size_t i = 0; i < e; ++i) {
    out.first[i] = v[i];
    out.last[max_edge - e + i] = v[n - e + i];  // right-aligned
  }
}

}  // namespace

std::vector<long double> decimated_sums(const phase_source& x, std::size_t order,
                                        const std::vector<std::size_t>& factors,
                                        const progress_fn& on_progress) {
  const std::size_t nf = factors.size();
  const std::size_t n = x.size();
  std::vector<std::size_t> terms(nf, 0);
  for (std::size_t f = 0; f < nf; ++f) terms[f] = decimated_terms(n, factors[f], order);
  // Factors below block_points share one contiguous read of the phase per chunk ("dense": a pass
  // for all of them instead of one each); larger factors read their points one by one, in items
  // of their own ("sparse": a point costs at most one block).
  std::vector<std::size_t> dense, sparse;
  for (std::size_t f = 0; f < nf; ++f)
    (factors[f] < phase_source::block_points ? dense : sparse).push_back(f);
  const std::size_t dense_chunks = dense.empty() ? 0 : (n + chunk_points - 1) / chunk_points;
  std::vector<std::size_t> first_item(sparse.size() + 1, dense_chunks);
  for (std::size_t s_i = 0; s_i < sparse.size(); ++s_i) {
    const std::size_t f = sparse[s_i];
    const std::size_t per_item = item_terms(factors[f]);
    first_item[s_i + 1] = first_item[s_i] + (terms[f] + per_item - 1) / per_item;
  }
  const std::size_t items = first_item.back();
  const std::size_t workers = worker_count(n);
  std::vector<std::unique_ptr<phase_reader>> readers(workers);
  std::vector<std::vector<double>> z(workers);
  // Per dense chunk a sum for each dense factor, per sparse item one sum: added in item order,
  // so the sums do not depend on the threads.
  std::vector<long double> dense_partial(dense_chunks * dense.size(), 0.0L);
  std::vector<long double> sparse_partial(items - dense_chunks, 0.0L);
  const auto sum_block = [order](const double* p, std::size_t count) {
    return order == 2 ? sum_second_differences(p, p + 1, p + 2, count)
                      : sum_third_differences(p, p + 1, p + 2, p + 3, count);
  };
  for_each_item(
      items, workers,
      [&](std::size_t w, std::size_t item) {
        if (!readers[w]) readers[w] = std::make_unique<phase_reader>(x);
        if (item < dense_chunks) {
          // Terms k of factor m whose first point k m lies in this chunk; their last points reach
          // at most order (block_points - 1) beyond it.
          const std::size_t c0 = item * chunk_points;
          const std::size_t c1 = std::min(n, c0 + chunk_points);
          const std::size_t reach = std::min(n, c1 + order * (phase_source::block_points - 1));
          const auto v = readers[w]->read(c0, reach - c0);
          for (std::size_t j = 0; j < dense.size(); ++j) {
            const std::size_t f = dense[j];
            const std::size_t m = factors[f];
            const std::size_t k_begin = (c0 + m - 1) / m;
            const std::size_t k_end = std::min(terms[f], (c1 + m - 1) / m);
            for (std::size_t k0 = k_begin; k0 < k_end; k0 += block_terms) {
              const std::size_t count = std::min(block_terms, k_end - k0);
              z[w].resize(count + order);
              for (std::size_t t = 0; t < count + order; ++t) z[w][t] = v[(k0 + t) * m - c0];
              dense_partial[item * dense.size() + j] +=
                  static_cast<long double>(sum_block(z[w].data(), count));
            }
          }
          return;
        }
        const std::size_t s_i =
            static_cast<std::size_t>(std::upper_bound(first_item.begin(), first_item.end(), item) -
                                     first_item.begin()) -
            1;
        const std::size_t f = sparse[s_i];
        const std::size_t per_item = item_terms(factors[f]);
        const std::size_t k_begin = (item - first_item[s_i]) * per_item;
        const std::size_t k_end = std::min(terms[f], k_begin + per_item);
        z[w].resize(block_terms + order);
        for (std::size_t k0 = k_begin; k0 < k_end; k0 += block_terms) {
          const std::size_t count = std::min(block_terms, k_end - k0);
          read_decimated(*readers[w], factors[f], k0, count + order, z[w].data());
          sparse_partial[item - dense_chunks] +=
              static_cast<long double>(sum_block(z[w].data(), count));
        }
      },
      on_progress);
  std::vector<long double> out(nf, 0.0L);
  for (std::size_t c = 0; c < dense_chunks; ++c)
    for (std::size_t j = 0; j < dense.size(); ++j)
      out[dense[j]] += dense_partial[c * dense.size() + j];
  for (std::size_t s_i = 0; s_i < sparse.size(); ++s_i)
    for (std::size_t i = first_item[s_i]; i < first_item[s_i + 1]; ++i)
      out[sparse[s_i]] += sparse_partial[i - dense_chunks];
  return out;
}

std::optional<std::vector<long double>> octave_block_sums(const sample_source& y, double tau0_s,
                                                          std::size_t order,
                                                          const std::vector<std::size_t>& factors,
                                                          const progress_fn& on_progress,
                                                          block_heads* heads) {
  const std::size_t n = y.size();
  if (!(tau0_s >= phase_source::min_tau0_s && tau0_s <= phase_source::max_tau0_s) || n == 0 ||
      (order != 2 && order != 3))
    return std::nullopt;
  std::size_t top = 0;  // highest level asked for
  std::vector<char> want;
  for (std::size_t m : factors) {
    if (m == 0 || !std::has_single_bit(m)) return std::nullopt;
    const auto level = static_cast<std::size_t>(std::countr_zero(m));
    top = std::max(top, level);
    if (want.size() <= level) want.resize(level + 1, 0);
    want[level] = 1;
  }
  // c: the sums are of y - c, so that they stay small where the mean is large (it cancels).
  const auto head = y.view(0, std::min<std::size_t>(n, 1024));
  double c = 0.0;
  for (double v : head) c += v;
  c /= static_cast<double>(head.size());
  if (!std::isfinite(c)) return std::nullopt;
  const std::size_t low = std::min(top + 1, kept_level);  // levels summed within chunks
  const std::size_t chunks = (n + pyramid_chunk - 1) / pyramid_chunk;
  const std::size_t workers = worker_count(n);
  std::vector<chunk_level> levels(chunks * low);
  std::vector<double> kept(top >= kept_level ? n >> kept_level : 0);
  std::vector<std::vector<double>> buf(workers);
  std::vector<char> bad(chunks, 0);
  const double limit = phase_source::max_sample_magnitude;
  // Per wanted level the first min(cap, n >> level) block sums, for `heads`; written by the chunk
  // holding them (levels below kept_level) or from the kept level after the pass.
  if (heads != nullptr) {
    heads->offset = c;
    heads->sums.clear();
    heads->sums.resize(top + 1);
    heads->counts.assign(top + 1, 0);
    for (std::size_t j = 0; j <= top; ++j)
      if (want[j] != 0) {
        heads->counts[j] = std::min(heads->cap, n >> j);
        heads->sums[j] = std::make_unique_for_overwrite<double[]>(heads->counts[j] + 1);
      }
  }
  const auto keep_head = [heads](std::size_t j, std::size_t first, const double* v,
                                 std::size_t count, double minus) {
    if (heads == nullptr || !heads->sums[j] || first >= heads->counts[j]) return;
    double* out = heads->sums[j].get() + first;
    const std::size_t end = std::min(heads->counts[j] - first, count);
    for (std::size_t i = 0; i < end; ++i) out[i] = v[i] - minus;
  };
  for_each_item(
      chunks, workers,
      [&](std::size_t w, std::size_t item) {
        const std::size_t c0 = item * pyramid_chunk;
        const std::size_t len = std::min(pyramid_chunk, n - c0);
        const double* v = y.view(c0, len).data();
        auto& b = buf[w];
        b.resize(len / 2);
        chunk_level* out = levels.data() + item * low;
        // Level 0 (the samples) tile by tile: the limit check, the squared differences and the
        // pair sums of level 1 while the tile is in cache.
        unsigned ok = 1;
        long double sum0 = 0.0L;
        const std::size_t terms0 = len >= order ? len - order + 1 : 0;
        for (std::size_t t0 = 0; t0 < len; t0 += block_terms) {
          const std::size_t t1 = std::min(len, t0 + block_terms);
          for (std::size_t i = t0; i < t1; ++i)
            ok &= static_cast<unsigned>(std::abs(v[i]) <= limit);
          if (want[0] != 0 && t0 < terms0) {
            const std::size_t count = std::min(t1, terms0) - t0;
            const double* p = v + t0;
            sum0 += static_cast<long double>(
                order == 2 ? sum_squares(count, [p](std::size_t t) { return p[t + 1] - p[t]; })
                           : sum_second_differences(p, p + 1, p + 2, count));
          }
          for (std::size_t i = t0 / 2; i < t1 / 2; ++i) b[i] = (v[2 * i] - c) + (v[2 * i + 1] - c);
        }
        if (ok == 0) {
          bad[item] = 1;
          return;
        }
        keep_head(0, c0, v, len, c);
        note_level(out[0], v, len, order, false);
        for (std::size_t i = 0; i < std::min(order - 1, len); ++i) {
          out[0].first[i] -= c;
          out[0].last[max_edge - 1 - i] -= c;
        }
        out[0].sum = sum0;
        // Levels 1 .. low - 1 in place (level j's value i is the sum of values 2i, 2i + 1 of j -
        // 1).
        std::size_t count = len / 2;
        for (std::size_t j = 1; j <= top && (j < low || j == kept_level); ++j) {
          if (j > 1) {
            count /= 2;
            for (std::size_t i = 0; i < count; ++i) b[i] = b[2 * i] + b[2 * i + 1];
          }
          if (j == kept_level) {
            std::copy(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(count),
                      kept.begin() + static_cast<std::ptrdiff_t>(c0 >> kept_level));
            break;
          }
          note_level(out[j], b.data(), count, order, want[j] != 0);
          keep_head(j, c0 >> j, b.data(), count, 0.0);
        }
        y.release(c0, c0 + len);
      },
      on_progress);
  if (std::find(bad.begin(), bad.end(), 1) != bad.end()) return std::nullopt;
  std::vector<long double> by_level(top + 1, 0.0L);
  // Below kept_level: the chunks' sums, then the terms across each chunk end, in chunk order.
  for (std::size_t j = 0; j < low; ++j) {
    if (want[j] == 0) continue;
    for (std::size_t k = 0; k < chunks; ++k) {
      const auto& cur = levels[k * low + j];
      by_level[j] += cur.sum;
      if (k == 0 || cur.count == 0) continue;
      // The last order - 1 values before this chunk, its first ones: the windows across.
      std::array<double, 2 * max_edge> across{};
      std::size_t a = 0;
      const auto& prev = levels[(k - 1) * low + j];
      for (std::size_t i = max_edge - (order - 1); i < max_edge; ++i) across[a++] = prev.last[i];
      for (std::size_t i = 0; i < std::min(order - 1, cur.count); ++i) across[a++] = cur.first[i];
      by_level[j] += block_difference_sum(across.data(), a, order);
    }
  }
  // From kept_level on: the kept level, summed and halved in place up to the top.
  std::size_t count = kept.size();
  for (std::size_t j = kept_level; j <= top; ++j) {
    if (j > kept_level) {
      count /= 2;
      for (std::size_t i = 0; i < count; ++i) kept[i] = kept[2 * i] + kept[2 * i + 1];
    }
    if (want[j] != 0) by_level[j] = block_difference_sum(kept.data(), count, order);
    keep_head(j, 0, kept.data(), count, 0.0);
  }
  std::vector<long double> out;
  const auto t2 = static_cast<long double>(tau0_s) * static_cast<long double>(tau0_s);
  for (std::size_t m : factors)
    out.push_back(t2 * by_level[static_cast<std::size_t>(std::countr_zero(m))]);
  return out;
}

std::span<double> decimated_from_heads(block_heads& heads, std::size_t level, double mean,
                                       double tau0_s) {
  const std::size_t count = heads.counts[level];
  double* z = heads.sums[level].get();
  const long double step = static_cast<long double>(std::size_t{1} << level) *
                           (static_cast<long double>(mean) - heads.offset);  // m (ybar - c)
  const auto tau0 = static_cast<long double>(tau0_s);
  long double run = 0.0L;  // sum_{i<k} S_i
  for (std::size_t k = 0; k <= count; ++k) {
    const double s = k < count ? z[k] : 0.0;
    z[k] = static_cast<double>(tau0 * (run - static_cast<long double>(k) * step));
    run += static_cast<long double>(s);
  }
  return {z, count + 1};
}

std::vector<std::vector<double>> decimated_prefixes(const phase_source& x,
                                                    const std::vector<std::size_t>& factors,
                                                    std::size_t cap,
                                                    const progress_fn& on_progress) {
  std::vector<std::vector<double>> z;
  std::size_t span = 0;  // phase points the pass covers
  for (std::size_t m : factors) {
    const std::size_t len = x.size() > 0 ? std::min(cap, (x.size() - 1) / m + 1) : 0;
    z.emplace_back(len);
    if (len > 0) span = std::max(span, (len - 1) * m + 1);
  }
  const std::size_t chunks = (span + chunk_points - 1) / chunk_points;
  const std::size_t workers = worker_count(span);
  std::vector<std::unique_ptr<phase_reader>> readers(workers);
  for_each_item(
      chunks, workers,
      [&](std::size_t w, std::size_t c) {
        if (!readers[w]) readers[w] = std::make_unique<phase_reader>(x);
        const std::size_t end = std::min(span, (c + 1) * chunk_points);
        for (std::size_t s = c * chunk_points; s < end; s += read_points) {
          const std::size_t e = std::min(end, s + read_points);
          const auto v = readers[w]->read(s, e - s);
          for (std::size_t f = 0; f < factors.size(); ++f) {
            const std::size_t m = factors[f];
            for (std::size_t k = (s + m - 1) / m; k < z[f].size() && k * m < e; ++k)
              z[f][k] = v[k * m - s];
          }
        }
      },
      on_progress);
  return z;
}

}  // namespace gyroflip::analysis::detail
