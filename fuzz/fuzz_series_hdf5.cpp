/// \file
/// \brief libFuzzer target: the HDF5 series reader (io::read_series on FILE.h5:/d) on HDF5 files
/// built from the input bytes: the bytes choose the dataset's type (float64/32, integers, string),
/// rank and shape, its values, and a `sample_rate_hz` attribute (absent, a number, an array, a
/// string). This fuzzes gyroflip's reader over the files libhdf5 can write; libhdf5's own parser
/// of arbitrary bytes is not gyroflip's code and is not hardened against them
/// (docs/RELIABILITY.md).
#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/series.hpp"

namespace {

struct reader {
  const std::uint8_t* p;
  std::size_t n;
  std::uint8_t byte() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
  double number() {
    double v = 0.0;
    std::uint8_t b[8] = {};
    for (auto& x : b) x = byte();
    std::memcpy(&v, b, 8);
    return v;
  }
};

void write_file(const std::string& path, reader in) {
  const hid_t types[] = {H5T_NATIVE_DOUBLE, H5T_NATIVE_FLOAT, H5T_NATIVE_INT32, H5T_NATIVE_INT16,
                         H5T_NATIVE_UINT8,  H5T_NATIVE_INT64, H5T_IEEE_F64BE,   H5T_C_S1};
  const hid_t type = types[in.byte() % 8];
  const int rank = 1 + in.byte() % 2;
  const int attr = in.byte() % 4;
  const double attr_value = in.number();
  const std::size_t elem = H5Tget_size(type);
  const std::size_t count = in.n / elem;
  hsize_t dims[2] = {rank == 1 ? count : count / 2, 2};
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t space = H5Screate_simple(rank, dims, nullptr);
  const hid_t d = H5Dcreate2(f, "/d", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (dims[0] > 0) H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, in.p);
  if (attr != 0) {
    const hsize_t three = 3;
    const hid_t as = attr == 2 ? H5Screate_simple(1, &three, nullptr) : H5Screate(H5S_SCALAR);
    const hid_t at = attr == 3 ? H5T_C_S1 : H5T_NATIVE_DOUBLE;
    const hid_t a = H5Acreate2(d, "sample_rate_hz", at, as, H5P_DEFAULT, H5P_DEFAULT);
    const double values[3] = {attr_value, attr_value, attr_value};
    H5Awrite(a, at, values);
    H5Aclose(a);
    H5Sclose(as);
  }
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path =
      std::string(dir) + "/gyroflip-fuzz-" + std::to_string(::getpid()) + ".h5";
  write_file(path, reader{data, size});
  auto s = gyroflip::io::read_series(path + ":/d", {});
  if (s)
    (void)gyroflip::analysis::phase_source::make(s->samples(), gyroflip::analysis::input_kind::rate,
                                                 s->tau0_s());
  std::remove(path.c_str());
  return 0;
}
