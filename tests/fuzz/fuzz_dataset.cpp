// libFuzzer harness: the HDF5 data-set reader (dc::DataSetReader, learning/data_set.hpp).
//
// The bytes go to a per-process temporary file (HDF5 reads by name). Opening validates the
// layout; then the harness reads everything a trainer would: every sample's feature and
// label image, the training samples of every simulation, and every sample's contacts.
// Property: only IoError (or ConfigError / InvalidArgument) escapes, nothing crashes.
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static dc::fuzz::TempInputFile file(".dataset.h5");
  const std::string& path = file.write(data, size);
  try {
    const dc::DataSetReader reader(path);
    // Bound the work per input: a mutated header may announce huge counts that the reader
    // must reject, but a consistent small file is read completely.
    const std::int64_t n = std::min<std::int64_t>(reader.samples(), 64);
    std::vector<std::int64_t> rows(static_cast<std::size_t>(n));
    std::iota(rows.begin(), rows.end(), std::int64_t{0});
    (void)reader.features(rows);
    (void)reader.labels(rows);
    for (std::int64_t s : rows) (void)reader.contacts(s);
    std::vector<int> sims;
    for (std::size_t i = 0; i < reader.simulations().size() && i < 8; ++i) sims.push_back(static_cast<int>(i));
    (void)reader.training_samples(sims);
  } catch (const dc::IoError&) {
  } catch (const dc::ConfigError&) {
  } catch (const dc::InvalidArgument&) {
  }
  return 0;
}
