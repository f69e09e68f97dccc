// H5File::require_in_file: whether an object's values live in this file (h5.hpp).
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {

using namespace h5_detail;

namespace {

/// The link type of every component of `name` ("/a", "/a/b", …), first external or
/// user-defined one reported by its prefix; nullopt when all are hard or soft links.
std::optional<std::string> foreign_link(hid_t file, const std::string& name) {
  for (std::size_t pos = name.find('/', 1);; pos = name.find('/', pos + 1)) {
    const std::string prefix = name.substr(0, pos);
    H5L_info_t info{};
    if (prefix.size() > 1 && H5Lget_info(file, prefix.c_str(), &info, H5P_DEFAULT) >= 0 &&
        info.type != H5L_TYPE_HARD && info.type != H5L_TYPE_SOFT)
      return prefix;
    if (pos == std::string::npos) return std::nullopt;
  }
}

}  // namespace

void H5File::require_in_file(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  const std::string name = object_name(path);
  if (const auto link = foreign_link(id_, name))
    fail(path, "reached through an external link (" + *link + "): its values are in another file; refused");
  // A soft link may still lead through an external one: compare the file the object is in.
  if (!exists(path)) return;  // nothing stored anywhere: the caller's read names it missing
  H5O_info_t root{}, object{};
  if (H5Oget_info2(id_, &root, H5O_INFO_BASIC) < 0 ||
      H5Oget_info_by_name2(id_, name.c_str(), &object, H5O_INFO_BASIC, H5P_DEFAULT) < 0)
    fail(path, with_reason("cannot open the object to check where its values are"));
  if (object.fileno != root.fileno) fail(path, "is stored in another file (external link); refused");
  if (object.type != H5O_TYPE_DATASET) return;
  Handle ds(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  Handle dcpl(ds.valid() ? H5Dget_create_plist(ds.get()) : -1, H5Pclose);
  if (!dcpl.valid()) fail(path, with_reason("cannot open the dataset to check where its values are"));
  if (H5Pget_layout(dcpl.get()) == H5D_VIRTUAL)
    fail(path, "is a virtual dataset: its values are in other files (a missing one reads as zeros); refused");
  if (H5Pget_external_count(dcpl.get()) > 0)
    fail(path, "keeps its values in external raw files; refused");
}

}  // namespace dc
