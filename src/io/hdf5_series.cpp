/// \file
/// \brief HDF5 1-D dataset reader for `io::read_series` (the HDF5 C API stays in this file).
#include "hdf5_series.hpp"

#include <hdf5.h>

#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/hdf5_table.hpp"

namespace gyroflip::io::detail {
namespace {

// Closes an HDF5 handle on scope exit.
struct handle {
  hid_t id;
  herr_t (*close)(hid_t);
  handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  handle(const handle&) = delete;
  handle& operator=(const handle&) = delete;
  ~handle() {
    if (id >= 0) close(id);
  }
};

// Samples an HDF5 series may hold in memory (8 GiB).
constexpr hsize_t max_samples = hsize_t{1} << 30;

}  // namespace

result<hdf5_data> read_hdf5_dataset(const std::string& file, const std::string& dataset,
                                    std::optional<std::size_t> column) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are returned, not printed
  if (H5Fis_hdf5(file.c_str()) <= 0) return input_error({file}, "not an HDF5 file");
  const handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (f.id < 0) return io_error(file, "cannot open as HDF5");
  if (H5Lexists(f.id, dataset.c_str(), H5P_DEFAULT) <= 0)
    return input_error({file}, fmt::format("no dataset '{}'", printable(dataset, 120)));
  const handle d(H5Dopen2(f.id, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (d.id < 0)
    return input_error({file}, fmt::format("'{}' is not a dataset", printable(dataset, 120)));
  const handle space(H5Dget_space(d.id), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank != 1 && rank != 2)
    return input_error({file}, fmt::format("dataset '{}' must be 1-D or 2-D (samples x columns)",
                                           printable(dataset, 120)));
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  const hsize_t n = dims[0];
  // A 2-D dataset (samples x columns, as a logger writes all axes): one column of it.
  if (rank == 2 && (!column || *column >= dims[1]))
    return about_parameter(
        input_error({file}, fmt::format("dataset '{}' has {} columns: give a column number from 1 "
                                        "to {}",
                                        printable(dataset, 120), dims[1], dims[1])),
        "column");
  // A dataset declares its size; a chunked one may hold fill values without storage, so a tiny
  // file can announce 1e12 samples. Held in memory (8 bytes a sample), it must fit.
  if (n > max_samples)
    return input_error({file}, fmt::format("dataset '{}' has {} samples, more than the {} an HDF5 "
                                           "series may hold in memory (use .npy or raw float64)",
                                           printable(dataset, 120), n, max_samples));
  hdf5_data out;
  out.values.resize(static_cast<std::size_t>(n));
  // H5T_NATIVE_DOUBLE converts float32, integers and other byte orders on the fly.
  hid_t file_space = H5S_ALL;
  const handle memory(rank == 2 ? H5Screate_simple(1, &dims[0], nullptr) : -1, H5Sclose);
  if (rank == 2) {
    const hsize_t start[2] = {0, *column};
    const hsize_t count[2] = {n, 1};
    if (memory.id < 0 ||
        H5Sselect_hyperslab(space.id, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0)
      return input_error({file}, fmt::format("dataset '{}': cannot select column {}",
                                             printable(dataset, 120), *column + 1));
    file_space = space.id;
  }
  if (n > 0 && H5Dread(d.id, H5T_NATIVE_DOUBLE, rank == 2 ? memory.id : H5S_ALL, file_space,
                       H5P_DEFAULT, out.values.data()) < 0)
    return input_error(
        {file}, fmt::format("dataset '{}' cannot be read as numbers", printable(dataset, 120)));
  if (H5Aexists(d.id, "sample_rate_hz") > 0) {
    const handle a(H5Aopen(d.id, "sample_rate_hz", H5P_DEFAULT), H5Aclose);
    // One number only: H5Aread writes every element of the attribute, so an array or string
    // attribute read into one double would overrun it.
    const handle aspace(a.id >= 0 ? H5Aget_space(a.id) : -1, H5Sclose);
    const handle atype(a.id >= 0 ? H5Aget_type(a.id) : -1, H5Tclose);
    const H5T_class_t cls = atype.id >= 0 ? H5Tget_class(atype.id) : H5T_NO_CLASS;
    if (aspace.id < 0 || H5Sget_simple_extent_npoints(aspace.id) != 1 ||
        (cls != H5T_FLOAT && cls != H5T_INTEGER))
      return input_error({file}, fmt::format("dataset '{}': attribute sample_rate_hz must be one "
                                             "number",
                                             printable(dataset, 120)));
    double hz = 0.0;
    if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &hz) < 0)
      return input_error({file},
                         fmt::format("dataset '{}': attribute sample_rate_hz cannot be read "
                                     "as a number",
                                     printable(dataset, 120)));
    out.sample_rate_hz = hz;
  }
  return out;
}

}  // namespace gyroflip::io::detail

namespace gyroflip::io {

namespace {

using detail_handle = detail::handle;

// A variable-free fixed-length string attribute on `obj`.
bool put_string_attribute(hid_t obj, const std::string& name, const std::string& value) {
  const detail_handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (type.id < 0 || H5Tset_size(type.id, value.empty() ? 1 : value.size()) < 0) return false;
  const detail_handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const detail_handle attr(
      H5Acreate2(obj, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  return attr.id >= 0 && H5Awrite(attr.id, type.id, value.empty() ? "" : value.c_str()) >= 0;
}

}  // namespace

result<std::vector<std::uint8_t>> hdf5_table_image(std::span<const hdf5_column> columns,
                                                   std::span<const csv_metadata> attributes) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are returned, not printed
  for (const auto& c : columns) {
    if (c.values.size() != columns.front().values.size())
      return runtime_error("HDF5 table: columns of different lengths");
    for (const double v : c.values)
      if (!std::isfinite(v))
        return runtime_error(fmt::format("HDF5 table: column {} has a non-finite value", c.name));
  }
  const auto failed = [] { return runtime_error("HDF5: building the file in memory failed"); };
  const detail_handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  // In memory only (no backing store): the caller writes the bytes.
  if (fapl.id < 0 || H5Pset_fapl_core(fapl.id, 1 << 20, 0) < 0) return failed();
  const detail_handle file(H5Fcreate("gyroflip-export.h5", H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id),
                           H5Fclose);
  if (file.id < 0) return failed();
  for (const auto& a : attributes)
    if (!put_string_attribute(file.id, a.key, a.value)) return failed();
  for (const auto& c : columns) {
    const hsize_t n = c.values.size();
    const detail_handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
    const detail_handle set(H5Dcreate2(file.id, c.name.c_str(), H5T_IEEE_F64LE, space.id,
                                       H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                            H5Dclose);
    if (set.id < 0) return failed();
    if (n != 0 &&
        H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.values.data()) < 0)
      return failed();
    if (!put_string_attribute(set.id, "unit", c.unit)) return failed();
  }
  if (H5Fflush(file.id, H5F_SCOPE_GLOBAL) < 0) return failed();
  const ssize_t size = H5Fget_file_image(file.id, nullptr, 0);
  if (size <= 0) return failed();
  std::vector<std::uint8_t> image(static_cast<std::size_t>(size));
  if (H5Fget_file_image(file.id, image.data(), image.size()) != size) return failed();
  return image;
}

}  // namespace gyroflip::io
