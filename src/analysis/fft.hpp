/// \file
/// \brief Private to the analysis module: correlations and convolutions of real series by one FFT
/// (Eigen's FFT module), used by the total variances and Theo1 (docs/ANALYSIS.md, "The extended
/// statistics").
#pragma once

#include <algorithm>
#include <complex>
#include <cstddef>
#include <vector>

#include <unsupported/Eigen/FFT>

namespace gyroflip::analysis::detail {

using cvec = std::vector<std::complex<double>>;

/// The smallest power of two >= n.
inline std::size_t fft_size(std::size_t n) {
  std::size_t s = 1;
  while (s < n) s *= 2;
  return s;
}

/// Spectrum of f[first, last) zero-padded to s points.
template <class It>
cvec spectrum(Eigen::FFT<double>& fft, It first, It last, std::size_t s) {
  std::vector<double> padded(s, 0.0);
  std::copy(first, last, padded.begin());
  cvec out;
  fft.fwd(out, padded);
  return out;
}

/// Spectrum of f zero-padded to s points.
inline cvec spectrum(Eigen::FFT<double>& fft, const std::vector<double>& f, std::size_t s) {
  return spectrum(fft, f.begin(), f.end(), s);
}

/// c(d) = sum_p f_p g_{p+d} for d < count, from the spectra of f and g (both padded to s >= their
/// lengths summed, so that nothing wraps; index s + d holds the negative lag d).
inline std::vector<double> correlation(Eigen::FFT<double>& fft, const cvec& f, const cvec& g,
                                       std::size_t count) {
  cvec prod(f.size());
  for (std::size_t k = 0; k < f.size(); ++k) prod[k] = std::conj(f[k]) * g[k];
  std::vector<double> out;
  fft.inv(out, prod);
  out.resize(count);
  return out;
}

/// c(s) = sum_p f_p g_{s-p} for s < count.
inline std::vector<double> convolution(Eigen::FFT<double>& fft, const cvec& f, const cvec& g,
                                       std::size_t count) {
  cvec prod(f.size());
  for (std::size_t k = 0; k < f.size(); ++k) prod[k] = f[k] * g[k];
  std::vector<double> out;
  fft.inv(out, prod);
  out.resize(count);
  return out;
}

}  // namespace gyroflip::analysis::detail
