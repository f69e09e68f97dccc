// libFuzzer harness: the CNN model file loader (dc::load_model, HDF5).
//
// HDF5 reads files by name, so the bytes go to a per-process temporary file first.
// Property: load_model either returns a model or throws IoError (its documented one-line
// error for missing, non-HDF5, truncated, wrong-version or wrong-shape files); ConfigError
// and InvalidArgument are tolerated. A loaded model must also run one forward pass on a
// zero input of its declared shape without crashing.
#include <cstddef>
#include <cstdint>

#include "dc/core/error.hpp"
#include "dc/learning/model_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static dc::fuzz::TempInputFile file(".model.h5");  // one per process; rewritten per input
  const std::string& path = file.write(data, size);
  try {
    dc::Model m = dc::load_model(path);
    // A loaded model must run: one forward pass on zeros of its declared input shape
    // (bounded, so a legitimately large grid does not turn into a slow input).
    const dc::Shape in = m.network().input_shape();
    if (static_cast<long long>(in.c) * in.h * in.w <= 64 * 64 * 8) {
      const dc::Tensor out = m.predict(dc::Tensor(1, in.c, in.h, in.w));
      (void)out;
    }
  } catch (const dc::IoError&) {
  } catch (const dc::ConfigError&) {
  } catch (const dc::InvalidArgument&) {
  }
  return 0;
}
