// H5File::create_virtual: a dataset that concatenates rows of datasets in other files
// (HDF5's virtual datasets; h5.hpp).
#include <limits>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {

using namespace h5_detail;

template <H5Element T>
void H5File::create_virtual(std::string_view path, const H5Shape& row_shape,
                            const std::vector<H5VirtualSource>& sources) {
  require_writable(path);
  hsize_t total = 0;
  for (const H5VirtualSource& s : sources) total += s.rows;
  H5Shape dims = row_shape;
  dims.insert(dims.begin(), total);
  if (total == 0) {
    create_dataset<T>(path, dims);
    return;
  }
  if (exists(path)) fail(path, "cannot create dataset: an object of that name exists");
  const ErrorSilencer quiet;
  const int rank = static_cast<int>(dims.size());
  Handle vspace(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!vspace.valid() || !dcpl.valid() || !keep_links_and_attributes_compact(dcpl.get(), false))
    fail(path, "cannot set up virtual dataset " + to_string(dims));
  if (!create_parent_groups(id_, object_name(path))) fail(path, "cannot create the parent groups");
  if constexpr (std::is_floating_point_v<T>) {  // a missing source reads as NaN, not as zeros
    const T nan = std::numeric_limits<T>::quiet_NaN();
    if (H5Pset_fill_value(dcpl.get(), memory_type(type_of<T>()), &nan) < 0) fail(path, "cannot set the fill value");
  }
  hsize_t first = 0;
  for (const H5VirtualSource& s : sources) {
    if (s.rows == 0) continue;
    H5Shape start(dims.size(), 0), count = dims;
    start[0] = first;
    count[0] = s.rows;
    Handle src(H5Screate_simple(rank, count.data(), nullptr), H5Sclose);
    if (!src.valid() ||
        H5Sselect_hyperslab(vspace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) < 0 ||
        H5Pset_virtual(dcpl.get(), vspace.get(), s.file.c_str(), s.dataset.c_str(), src.get()) < 0)
      fail(path, "cannot map rows of " + s.file + ":" + s.dataset);
    first += s.rows;
  }
  H5Sselect_all(vspace.get());
  const Handle lcpl = intermediate_groups_lcpl();
  Handle ds(H5Dcreate2(id_, object_name(path).c_str(), file_type(type_of<T>()), vspace.get(), lcpl.get(), dcpl.get(),
                       H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) fail(path, "cannot create virtual dataset " + to_string(dims));
}

#define DC_H5_INSTANTIATE(T) \
  template void H5File::create_virtual<T>(std::string_view, const H5Shape&, const std::vector<H5VirtualSource>&);
DC_H5_INSTANTIATE(double)
DC_H5_INSTANTIATE(float)
DC_H5_INSTANTIATE(std::int32_t)
DC_H5_INSTANTIATE(std::int64_t)
DC_H5_INSTANTIATE(std::uint8_t)
#undef DC_H5_INSTANTIATE

}  // namespace dc
