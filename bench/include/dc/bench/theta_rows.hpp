#pragma once
// The bench's per-sweep convergence histories θ_k, one row of `sweeps` floats per evaluated
// step, kept on disk instead of in RAM: the largest part of a bench's results by far (the
// default bench: 4,800 steps × 3,000 sweeps × 4 B = 58 MB per starter, against ~0.7 KB per
// step for everything else). Rows are appended to a dc::ScratchFile (nameless: nothing stays
// on disk after the process ends) as they are produced; only their offsets (8 B per row) stay
// in RAM. Several records may share one file, from several threads.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "dc/io/scratch_file.hpp"

namespace dc::bench {

class ThetaRows {
 public:
  /// No file yet: append() makes one in $TMPDIR (or /tmp) on first use.
  ThetaRows() = default;
  /// Rows of `file` (shared with other records).
  explicit ThetaRows(std::shared_ptr<ScratchFile> file) : file_(std::move(file)) {}

  /// Appends one step's row (every row of a record has the same length). IoError when the
  /// row's length differs from the earlier rows' or the write fails.
  void append(std::span<const float> row);
  /// Appends every row of `other` in order: by reference when both share a file, else copied.
  void append(const ThetaRows& other);

  [[nodiscard]] std::size_t rows() const { return offsets_.size(); }
  /// Floats per row (0 before the first row).
  [[nodiscard]] std::size_t row_length() const { return length_; }
  /// Reads values first … first + out.size() − 1 of row i into `out` (the whole row by default).
  void read_row(std::size_t i, std::span<float> out, std::size_t first = 0) const;
  /// Every row, row-major (rows() × row_length()): for tests and small runs only.
  [[nodiscard]] std::vector<float> all() const;
  /// The file the rows are in (null before the first row of a default-made record).
  [[nodiscard]] const std::shared_ptr<ScratchFile>& file() const { return file_; }

 private:
  std::shared_ptr<ScratchFile> file_;
  std::vector<std::uint64_t> offsets_;  // byte offset of each row in file_
  std::size_t length_ = 0;
};

}  // namespace dc::bench
