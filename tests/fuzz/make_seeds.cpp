// Writes the HDF5 seed inputs of the model and data-set harnesses:
//
//   fuzz_make_seeds OUT_DIR     → OUT_DIR/model/{tiny_conv,tiny_dense}.h5, OUT_DIR/dataset/tiny.h5
//
// The committed seeds in tests/fuzz/corpus/ were made with it; rerun it (and commit the
// result) when a file format changes, so the fuzzers start from files the readers accept.
// Kept deliberately tiny (a few KiB each): libFuzzer's default -max_len follows the largest
// seed, and small inputs mean more executions per second.
#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/core/rng.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/model_file.hpp"

namespace fs = std::filesystem;

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("HDF5 repack failed: " + what);
}

/// Copies every attribute of `src` onto `dst` with its stored type and shape.
void copy_attributes(hid_t src, hid_t dst) {
  H5O_info_t info;
  check(H5Oget_info2(src, &info, H5O_INFO_NUM_ATTRS) >= 0, "H5Oget_info2");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const hid_t a = H5Aopen_by_idx(src, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT);
    check(a >= 0, "H5Aopen_by_idx");
    char name[256];
    H5Aget_name(a, sizeof name, name);
    const hid_t type = H5Aget_type(a), space = H5Aget_space(a);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::vector<unsigned char> buf(static_cast<size_t>(std::max<hssize_t>(n, 1)) * H5Tget_size(type) + 16);
    check(H5Aread(a, type, buf.data()) >= 0, std::string("H5Aread ") + name);
    const hid_t b = H5Acreate2(dst, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    check(b >= 0 && H5Awrite(b, type, buf.data()) >= 0, std::string("H5Awrite ") + name);
    if (H5Tis_variable_str(type) > 0) H5Dvlen_reclaim(type, space, H5P_DEFAULT, buf.data());
    H5Aclose(b);
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(a);
  }
}

struct Repack {
  hid_t out;
};

herr_t visit(hid_t src_root, const char* name, const H5O_info_t* info, void* data) {
  const hid_t out = static_cast<Repack*>(data)->out;
  if (std::string(name) == ".") {
    copy_attributes(src_root, out);
    return 0;
  }
  if (info->type == H5O_TYPE_GROUP) {
    const hid_t g = H5Gopen2(src_root, name, H5P_DEFAULT);
    const hid_t h = H5Gcreate2(out, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    check(g >= 0 && h >= 0, std::string("group ") + name);
    copy_attributes(g, h);
    H5Gclose(h);
    H5Gclose(g);
  } else if (info->type == H5O_TYPE_DATASET) {
    const hid_t d = H5Dopen2(src_root, name, H5P_DEFAULT);
    check(d >= 0, std::string("H5Dopen2 ") + name);
    const hid_t type = H5Dget_type(d), space = H5Dget_space(d);
    // Same extent, no unlimited axis and no chunking: a contiguous copy (the reader reads
    // by hyperslab and does not care about the layout).
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(static_cast<size_t>(std::max(rank, 1)));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    const hid_t fixed = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims.data(), nullptr);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::vector<unsigned char> buf(static_cast<size_t>(std::max<hssize_t>(n, 1)) * H5Tget_size(type) + 16);
    if (n > 0) check(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) >= 0, std::string("H5Dread ") + name);
    const hid_t e = H5Dcreate2(out, name, type, fixed, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    check(e >= 0, std::string("H5Dcreate2 ") + name);
    if (n > 0) check(H5Dwrite(e, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) >= 0, std::string("H5Dwrite ") + name);
    if (n > 0 && H5Tis_variable_str(type) > 0) H5Dvlen_reclaim(type, space, H5P_DEFAULT, buf.data());
    copy_attributes(d, e);
    H5Dclose(e);
    H5Sclose(fixed);
    H5Sclose(space);
    H5Tclose(type);
    H5Dclose(d);
  }
  return 0;
}

/// Rewrites `from` into `to` with contiguous datasets: the writers' extendible datasets
/// pre-allocate ~256 KiB chunks, which would make a 3 MiB seed out of a few hundred bytes.
void repack(const fs::path& from, const fs::path& to) {
  const hid_t src = H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t dst = H5Fcreate(to.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  check(src >= 0 && dst >= 0, "open " + from.string());
  Repack r{dst};
  check(H5Ovisit2(src, H5_INDEX_NAME, H5_ITER_INC, visit, &r, H5O_INFO_BASIC) >= 0, "H5Ovisit2");
  H5Fclose(dst);
  H5Fclose(src);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_make_seeds OUT_DIR\n");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out / "model");
    fs::create_directories(out / "dataset");

    // Models: a two-layer conv net and a conv + dense head, on a 6 × 5 grid.
    const char* archs[2][2] = {
        {"tiny_conv",
         "name = \"tiny\"\n[[layer]]\nname = \"c1\"\ntype = \"conv\"\nout = 2\nrelu = true\n"
         "[[layer]]\nname = \"c2\"\ntype = \"conv\"\nout = 2\n"},
        {"tiny_dense",
         "name = \"tinyd\"\n[[layer]]\nname = \"c1\"\ntype = \"conv\"\nout = 2\nstride = 2\nrelu = true\n"
         "[[layer]]\nname = \"d\"\ntype = \"dense\"\nout = [2, 5, 6]\n"},
    };
    for (const auto& [name, text] : archs) {
      dc::ModelGrid g;
      g.image = dc::FeatureImageDef::for_box(2.5, 2.0);  // 6 x 5 nodes at d = 0.5
      g.image.channels = {dc::FeatureChannel::Mass, dc::FeatureChannel::Vx, dc::FeatureChannel::Vy,
                          dc::FeatureChannel::Omega};
      dc::Model m(dc::ArchSpec::parse(text, name), g, 4);
      dc::Rng rng(3);
      m.network().initialize(dc::HeNormal(), rng);
      dc::save_model(m, out / "model" / (std::string(name) + ".h5"));
    }

    // Data set: one simulation of 3 circles in a 4 × 4 box, 6 steps, d = h = 1 (5 × 5 grid).
    dc::DataSetParams p;
    p.scene.world.width = 4;
    p.scene.world.height = 4;
    p.scene.bodies.mean = {2, 1.5};
    p.scene.bodies.sigma = 1;
    p.scene.bodies.radius = 0.5;
    p.scene.time.steps = 6;
    p.image = dc::FeatureImageDef::for_box(4, 4);
    p.image.sph.grid.spacing = 1.0;
    p.image.sph.support = 1.0;
    p.seed = 5;
    p.count_min = p.count_max = 3;
    const dc::SimulationGenerator gen(p);
    const fs::path full = out / "dataset" / "tiny.chunked.h5.tmp";
    dc::DataSetWriter w = dc::DataSetWriter::create(full.string(), p);
    if (auto rec = gen.run(0)) w.append(*rec);
    w.close();
    repack(full, out / "dataset" / "tiny.h5");
    fs::remove(full);
    (void)dc::DataSetReader((out / "dataset" / "tiny.h5").string());  // the seed must be valid
    std::printf("wrote seeds under %s\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
