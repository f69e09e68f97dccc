#include "dc/bench/theta_rows.hpp"

#include <string>

#include "dc/core/error.hpp"

namespace dc::bench {

void ThetaRows::append(std::span<const float> row) {
  if (!offsets_.empty() && row.size() != length_)
    throw IoError("bench: theta row of " + std::to_string(row.size()) + " values after rows of " +
                  std::to_string(length_));
  if (!file_) file_ = std::make_shared<ScratchFile>();
  length_ = row.size();
  offsets_.push_back(file_->append(row.data(), row.size_bytes()));
}

void ThetaRows::append(const ThetaRows& other) {
  if (other.offsets_.empty()) return;
  if (!offsets_.empty() && other.length_ != length_)
    throw IoError("bench: the runs to join recorded theta rows of different lengths");
  if (!file_) file_ = other.file_;
  if (file_ == other.file_) {
    length_ = other.length_;
    offsets_.insert(offsets_.end(), other.offsets_.begin(), other.offsets_.end());
    return;
  }
  std::vector<float> row(other.length_);
  for (std::size_t i = 0; i < other.rows(); ++i) {
    other.read_row(i, row);
    append(row);
  }
}

void ThetaRows::read_row(std::size_t i, std::span<float> out, std::size_t first) const {
  if (i >= offsets_.size() || first + out.size() > length_)
    throw IoError("bench: theta row " + std::to_string(i) + " values " + std::to_string(first) + "+" +
                  std::to_string(out.size()) + " out of range");
  file_->read(offsets_[i] + first * sizeof(float), out.data(), out.size_bytes());
}

std::vector<float> ThetaRows::all() const {
  std::vector<float> out(rows() * length_);
  for (std::size_t i = 0; i < rows(); ++i) read_row(i, std::span<float>(out).subspan(i * length_, length_));
  return out;
}

}  // namespace dc::bench
