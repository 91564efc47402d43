/// \file
/// \brief Series readers: CSV column, NumPy .npy, raw float64 (see series.hpp).
#include "gyroflip/io/series.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/mapped_file.hpp"
#include "hdf5_series.hpp"

namespace gyroflip::io {
namespace {

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

status check_rate(const std::string& path, const std::optional<double>& rate_hz) {
  if (!rate_hz) return input_error({path}, "binary input has no time column: give --rate HZ");
  if (!(*rate_hz > 0.0) || !std::isfinite(*rate_hz))
    return usage_error(
        fmt::format("--rate {} must be a positive number of samples per second", *rate_hz));
  return ok();
}

// NumPy format 1.0-3.0: magic "\x93NUMPY", major, minor, header length (2 or 4 bytes LE), a
// Python dict literal padded with spaces; data follow. Only 1-D little-endian float64 in C order.
result<std::size_t> npy_data_offset(const std::string& path, std::string_view d) {
  if (d.size() < 10 || d.substr(0, 6) != "\x93NUMPY")
    return input_error({path}, "not a NumPy .npy file (bad magic)");
  const auto major = static_cast<unsigned char>(d[6]);
  std::size_t header_len = 0;
  std::size_t start = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(d[8]) |
                 (static_cast<std::size_t>(static_cast<unsigned char>(d[9])) << 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    if (d.size() < 12) return input_error({path}, "truncated .npy header");
    for (int i = 0; i < 4; ++i)
      header_len |=
          static_cast<std::size_t>(static_cast<unsigned char>(d[8 + static_cast<std::size_t>(i)]))
          << (8 * i);
    start = 12;
  } else {
    return input_error({path}, fmt::format(".npy format version {} is not supported", major));
  }
  if (start + header_len > d.size()) return input_error({path}, "truncated .npy header");
  const std::string_view h = d.substr(start, header_len);
  if (h.find("'descr': '<f8'") == std::string_view::npos &&
      h.find("'descr':'<f8'") == std::string_view::npos)
    return input_error(
        {path}, fmt::format(".npy dtype must be little-endian float64 ('<f8'); header: {}", h));
  if (h.find("'fortran_order': True") != std::string_view::npos)
    return input_error({path}, ".npy array must be in C order");
  const auto shape = h.find("'shape':");
  const auto open = h.find('(', shape);
  const auto close = h.find(')', open);
  if (shape == std::string_view::npos || open == std::string_view::npos ||
      close == std::string_view::npos)
    return input_error({path}, "no shape in the .npy header");
  const std::string_view dims = h.substr(open + 1, close - open - 1);
  const auto comma = dims.find(',');
  if (comma != std::string_view::npos &&
      dims.find_first_not_of(' ', comma + 1) != std::string_view::npos)
    return input_error({path}, fmt::format(".npy array must be 1-D; shape ({})", dims));
  return start + header_len;
}

// Little-endian float64 samples of a mapped file from byte `offset` (8-byte aligned, checked by
// the caller). Released samples' pages leave the process; viewing them again re-reads them from
// the page cache.
class mapped_samples final : public analysis::sample_source {
 public:
  mapped_samples(mapped_file file, std::size_t offset, std::size_t count)
      : file_(std::move(file)), offset_(offset), count_(count) {}
  [[nodiscard]] std::size_t size() const noexcept override { return count_; }
  [[nodiscard]] std::span<const double> view(std::size_t begin,
                                             std::size_t count) const noexcept override {
    // cppcheck-suppress invalidPointerCast ; mapped little-endian float64, alignment checked
    const auto* p = reinterpret_cast<const double*>(file_.data().data() + offset_);  // NOLINT
    return {p + begin, count};
  }
  // Whole 64 KB windows of address: a page fault maps the aligned 64 KB around it (the kernel's
  // default fault-around), which a release of only the pages read would leave resident.
  void release(std::size_t begin, std::size_t end) const noexcept override {
    file_.release(offset_ + begin * sizeof(double), offset_ + end * sizeof(double),
                  std::size_t{1} << 16);
  }
  // 2 MB: one madvise per 2 MB consumed per reader (cheap), ~100 MB resident at most.
  [[nodiscard]] std::size_t release_step() const noexcept override { return std::size_t{1} << 18; }

 private:
  mapped_file file_;
  std::size_t offset_;
  std::size_t count_;
};

}  // namespace

void series::hold(std::vector<double> values) {
  owned_ = std::move(values);
  samples_ = std::make_unique<analysis::span_samples>(owned_);
}

result<series> read_series(const std::string& path_in, const series_options& opt) {
  series s;
  s.source_ = path_in;
  // HDF5: `FILE.h5:/dataset` or FILE.h5 with `dataset` set in the options.
  std::string path = path_in;
  std::string dataset = opt.dataset;
  for (const char* ext : {".h5:", ".hdf5:", ".hdf:"}) {
    const auto at = path.find(ext);
    if (at != std::string::npos) {
      dataset = path.substr(at + std::string_view(ext).size() - 1 + 1);
      path.resize(at + std::string_view(ext).size() - 1);
    }
  }
  if (!dataset.empty() || ends_with(path, ".h5") || ends_with(path, ".hdf5")) {
    if (dataset.empty())
      return usage_error(
          fmt::format("{}: name the dataset, as FILE.h5:/path or --dataset /path", path));
    auto h = detail::read_hdf5_dataset(path, dataset);
    if (!h) return h.err();
    const auto rate = opt.sample_rate_hz ? opt.sample_rate_hz : h->sample_rate_hz;
    if (!rate)
      return input_error(
          {path},
          fmt::format("dataset '{}' has no sample_rate_hz attribute: give --rate HZ", dataset));
    if (auto c = check_rate(path, rate); !c) return c.err();
    for (std::size_t i = 0; i < h->values.size(); ++i)
      if (!std::isfinite(h->values[i]))
        return input_error({path}, fmt::format("{}[{}] is not finite", dataset, i));
    if (h->values.size() < 3)
      return input_error({path},
                         fmt::format("{}: {} samples are too few", dataset, h->values.size()));
    s.hold(std::move(h->values));
    s.tau0_s_ = 1.0 / *rate;
    return s;
  }
  const bool npy = ends_with(path, ".npy");
  if (npy || ends_with(path, ".f64") || ends_with(path, ".bin") || ends_with(path, ".raw")) {
    if (auto r = check_rate(path, opt.sample_rate_hz); !r) return r.err();
    auto f = mapped_file::open(path);
    if (!f) return f.err();
    std::size_t offset = 0;
    if (npy) {
      auto o = npy_data_offset(path, f->data());
      if (!o) return o.err();
      offset = *o;
    }
    const std::size_t bytes = f->data().size() - offset;
    if (bytes % sizeof(double) != 0)
      return input_error(
          {path}, fmt::format("{} data bytes are not a whole number of float64 values", bytes));
    static_assert(std::endian::native == std::endian::little,
                  "raw and .npy readers assume a little-endian host");
    const char* p = f->data().data() + offset;
    if (reinterpret_cast<std::uintptr_t>(p) % alignof(double) != 0)  // NOLINT: checking alignment
      return input_error({path}, "float64 data are not 8-byte aligned in the file");
    // Not read here: phase_source::make checks every sample (finite) as it passes over them.
    s.samples_ = std::make_unique<mapped_samples>(std::move(*f), offset, bytes / sizeof(double));
    s.tau0_s_ = 1.0 / *opt.sample_rate_hz;
    return s;
  }
  // CSV
  auto r = csv_reader::open(path);
  if (!r) return r.err();
  auto col = r->require_column(opt.column);
  if (!col) return col.err();
  auto time = r->find_column("time_s");
  if (!time) return time.err();
  const bool use_time = !opt.sample_rate_hz;
  if (use_time && !*time)
    return input_error({path}, "no time_s column: give --rate HZ for the sample rate");
  r->select({*col, use_time ? **time : csv_reader::absent_column});
  std::vector<double> t;
  std::vector<double> values;
  while (true) {
    const auto st = r->next();
    if (st == csv_reader::step::end) break;
    if (st == csv_reader::step::failed) return r->last_error();
    double v = 0.0;
    if (!r->parse(0, v)) return r->last_error();
    values.push_back(v);
    if (use_time) {
      double ts = 0.0;
      if (!r->parse(1, ts)) return r->last_error();
      if (!t.empty() && !(ts > t.back()))
        return r->error_at(1,
                           fmt::format("time_s {} does not increase (previous {})", ts, t.back()));
      t.push_back(ts);
    }
  }
  if (values.size() < 3)
    return input_error({path}, fmt::format("{} samples: too few for an analysis", values.size()));
  s.hold(std::move(values));
  if (!use_time) {
    if (auto c = check_rate(path, opt.sample_rate_hz); !c) return c.err();
    s.tau0_s_ = 1.0 / *opt.sample_rate_hz;
    return s;
  }
  // The interval comes from the whole record; each stamp may be rounded or jittered by up to
  // half an interval, but a gap or a duplicate breaks the uniform grid the deviations assume.
  const double step = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double off = t[k] - (t.front() + static_cast<double>(k) * step);
    if (std::abs(off) > 0.5 * step)
      return input_error(
          {path},
          fmt::format("sample {} (time_s {}) is {:.3g} s off the uniform grid of {:.6g} s: "
                      "the record has a gap or uneven sampling (resample, or give --rate HZ)",
                      k + 1, t[k], off, step));
  }
  s.tau0_s_ = step;
  return s;
}

}  // namespace gyroflip::io
