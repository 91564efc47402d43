/// \file
/// \brief The decimated phase z_k = x_{km}: ADEV and HDEV sums, noise-identification series
/// (see decimate.hpp).
#include "decimate.hpp"

#include <algorithm>
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
