#pragma once
// Small architectures shared by the learning tests (one copy, not one per test file).
#include <string>

#include "dc/learning/arch.hpp"

namespace dc::test {

// The shape of models/arch/unet-fast.toml in small: a stride-2 encoder, a decoder at half
// resolution, a nearest upsampling to the input's size and a 1×1 head over [upsampled, raw input].
// inner_relu = false: a linear network (exact central differences with a large ε).
inline ArchSpec fast_head_arch(bool head_relu, bool inner_relu = true) {
  std::string text = std::string(R"(
name = "fast-head"
[[layer]]
name = "e1"
type = "conv"
out = 4
stride = 2
relu = true
[[layer]]
name = "e2"
type = "conv"
out = 5
stride = 2
relu = true
[[layer]]
name = "u1"
type = "upsample"
match = "e1"
[[layer]]
name = "d1"
type = "conv"
input = ["u1", "e1"]
out = 4
relu = true
[[layer]]
name = "u0"
type = "upsample"
match = "input"
[[layer]]
name = "out"
type = "conv"
input = ["u0", "input"]
out = 2
kernel = 1
)") + (head_relu ? "relu = true\n" : "");
  if (!inner_relu)
    for (std::size_t at = text.find("relu = true"); at != std::string::npos; at = text.find("relu = true", at))
      text.replace(at, 11, "relu = false");
  return ArchSpec::parse(text);
}

}  // namespace dc::test
