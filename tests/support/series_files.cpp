/// \file
/// \brief .npy, raw float64 and HDF5 writers for tests (see series_files.hpp).
#include "support/series_files.hpp"

#include <hdf5.h>

#include <cstdint>
#include <fstream>

namespace gyroflip::test {

void write_npy(const std::string& path, const std::vector<double>& values,
               const std::string& descr) {
  // Header padded with spaces so that magic + length + header is a multiple of 64 bytes.
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" +
                       std::to_string(values.size()) + ",), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream f(path, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const auto len = static_cast<std::uint16_t>(header.size());
  f.put(static_cast<char>(len & 0xFF));
  f.put(static_cast<char>(len >> 8));
  f << header;
  f.write(reinterpret_cast<const char*>(values.data()),  // NOLINT: bytes of float64
          static_cast<std::streamsize>(values.size() * sizeof(double)));
}

void write_f64(const std::string& path, const std::vector<double>& values) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(values.data()),  // NOLINT: bytes of float64
          static_cast<std::streamsize>(values.size() * sizeof(double)));
}

void write_h5(const std::string& path, const std::string& dataset,
              const std::vector<double>& values, std::optional<double> sample_rate_hz,
              bool float32) {
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t groups = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(groups, 1);
  const hsize_t n = values.size();
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t d = H5Dcreate2(f, dataset.c_str(), float32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE, space,
                             groups, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  if (sample_rate_hz) {
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t a =
        H5Acreate2(d, "sample_rate_hz", H5T_NATIVE_DOUBLE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, &*sample_rate_hz);
    H5Aclose(a);
    H5Sclose(scalar);
  }
  H5Dclose(d);
  H5Sclose(space);
  H5Pclose(groups);
  H5Fclose(f);
}

}  // namespace gyroflip::test
