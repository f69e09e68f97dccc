#include "dc/learning/tensor.hpp"

#include <algorithm>

#include "dc/core/error.hpp"

namespace dc {

std::string Shape::str() const {
  return "[" + std::to_string(n) + ", " + std::to_string(c) + ", " + std::to_string(h) + ", " +
         std::to_string(w) + "]";
}

Tensor::Tensor(int n, int c, int h, int w) : Tensor(Shape{n, c, h, w}) {}

Tensor::Tensor(const Shape& shape) {
  if (shape.n < 0 || shape.c < 0 || shape.h < 0 || shape.w < 0)
    throw InvalidArgument("Tensor: negative extent in shape " + shape.str());
  shape_ = shape;
  data_.assign(shape.count(), 0.0f);
}

float& Tensor::at(int n, int c, int y, int x) {
  if (n < 0 || n >= shape_.n || c < 0 || c >= shape_.c || y < 0 || y >= shape_.h || x < 0 || x >= shape_.w)
    throw InvalidArgument("Tensor::at: index (" + std::to_string(n) + ", " + std::to_string(c) + ", " +
                          std::to_string(y) + ", " + std::to_string(x) + ") outside " + shape_.str());
  return data_[index(n, c, y, x)];
}

float Tensor::at(int n, int c, int y, int x) const { return const_cast<Tensor*>(this)->at(n, c, y, x); }

void Tensor::resize(const Shape& shape, bool zero) {
  if (shape.n < 0 || shape.c < 0 || shape.h < 0 || shape.w < 0)
    throw InvalidArgument("Tensor::resize: negative extent in shape " + shape.str());
  shape_ = shape;
  // std::vector::resize keeps the capacity when shrinking, so a layer's output buffer is
  // allocated once per batch size, not once per call.
  data_.resize(shape.count());
  if (zero) set_zero();
}

void Tensor::set_zero() { std::fill(data_.begin(), data_.end(), 0.0f); }
void Tensor::fill(float v) { std::fill(data_.begin(), data_.end(), v); }

void require_shape(const Shape& actual, const Shape& expected, const std::string& what) {
  if (!(actual == expected))
    throw InvalidArgument(what + ": shape " + actual.str() + " != expected " + expected.str());
}

}  // namespace dc
