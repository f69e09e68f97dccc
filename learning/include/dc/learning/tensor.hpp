#pragma once
// Tensor: a dense, owning, NCHW float32 array — the one data type of the CNN library.
//
// Layout: element (n, c, y, x) lives at ((n·C + c)·H + y)·W + x. One sample is C
// contiguous H×W planes, which is exactly a column-major (H·W) × C matrix; the
// convolutions exploit this to write GEMM results straight into the output without
// transposes (see conv2d.hpp). Storage is aligned to EIGEN_MAX_ALIGN_BYTES so that
// Eigen::Map<..., Eigen::Aligned> views are legal on the whole buffer.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace dc {

/// Shape of an NCHW tensor. A "sample shape" has n = 1.
struct Shape {
  int n = 0, c = 0, h = 0, w = 0;
  [[nodiscard]] std::size_t count() const {
    return static_cast<std::size_t>(n) * static_cast<std::size_t>(c) *
           static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
  }
  [[nodiscard]] std::size_t sample_count() const {  ///< C·H·W
    return static_cast<std::size_t>(c) * static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
  }
  [[nodiscard]] std::size_t plane() const {  ///< H·W
    return static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
  }
  [[nodiscard]] Shape with_batch(int batch) const { return {batch, c, h, w}; }
  [[nodiscard]] std::string str() const;  ///< "[n, c, h, w]"
  friend bool operator==(const Shape&, const Shape&) = default;
};

class Tensor {
 public:
  using Storage = std::vector<float, Eigen::aligned_allocator<float>>;
  using FlatMap = Eigen::Map<Eigen::VectorXf, Eigen::Aligned>;
  using ConstFlatMap = Eigen::Map<const Eigen::VectorXf, Eigen::Aligned>;
  using SampleMap = Eigen::Map<Eigen::MatrixXf>;            ///< (H·W) × C, column-major
  using ConstSampleMap = Eigen::Map<const Eigen::MatrixXf>;

  Tensor() = default;
  /// Zero-filled tensor; throws InvalidArgument for a negative extent.
  Tensor(int n, int c, int h, int w);
  explicit Tensor(const Shape& shape);

  [[nodiscard]] const Shape& shape() const { return shape_; }
  [[nodiscard]] int n() const { return shape_.n; }
  [[nodiscard]] int c() const { return shape_.c; }
  [[nodiscard]] int h() const { return shape_.h; }
  [[nodiscard]] int w() const { return shape_.w; }
  [[nodiscard]] std::size_t size() const { return data_.size(); }
  [[nodiscard]] bool empty() const { return data_.empty(); }

  [[nodiscard]] float* data() { return data_.data(); }
  [[nodiscard]] const float* data() const { return data_.data(); }
  /// Pointer to sample i (C·H·W floats). Not bounds-checked: hot path.
  [[nodiscard]] float* sample(int i) { return data_.data() + static_cast<std::size_t>(i) * shape_.sample_count(); }
  [[nodiscard]] const float* sample(int i) const { return data_.data() + static_cast<std::size_t>(i) * shape_.sample_count(); }

  /// Element access; not bounds-checked (use at() for a checked access).
  float& operator()(int n, int c, int y, int x) { return data_[index(n, c, y, x)]; }
  float operator()(int n, int c, int y, int x) const { return data_[index(n, c, y, x)]; }
  float& operator[](std::size_t i) { return data_[i]; }
  float operator[](std::size_t i) const { return data_[i]; }
  /// Bounds-checked element access; throws InvalidArgument.
  float& at(int n, int c, int y, int x);
  [[nodiscard]] float at(int n, int c, int y, int x) const;

  /// Change the shape, keeping the allocation when it is large enough. Contents are
  /// unspecified afterwards unless `zero` is set. Used by layers to reuse output buffers.
  void resize(const Shape& shape, bool zero = false);
  void set_zero();
  void fill(float v);

  /// All elements as one aligned Eigen vector.
  [[nodiscard]] FlatMap flat() { return {data_.data(), static_cast<Eigen::Index>(data_.size())}; }
  [[nodiscard]] ConstFlatMap flat() const { return {data_.data(), static_cast<Eigen::Index>(data_.size())}; }
  /// Sample i as an (H·W) × C column-major matrix (one column per channel plane).
  [[nodiscard]] SampleMap sample_matrix(int i) {
    return {sample(i), static_cast<Eigen::Index>(shape_.plane()), shape_.c};
  }
  [[nodiscard]] ConstSampleMap sample_matrix(int i) const {
    return {sample(i), static_cast<Eigen::Index>(shape_.plane()), shape_.c};
  }

 private:
  [[nodiscard]] std::size_t index(int n, int c, int y, int x) const {
    return ((static_cast<std::size_t>(n) * shape_.c + c) * shape_.h + y) * shape_.w + x;
  }
  Shape shape_{};
  Storage data_;
};

/// Throws InvalidArgument("<what>: shape [..] != [..]") unless a and b have equal shapes.
void require_shape(const Shape& actual, const Shape& expected, const std::string& what);

}  // namespace dc
