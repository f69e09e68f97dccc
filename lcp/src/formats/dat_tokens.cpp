#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/lcp/dat_file.hpp"
#include "formats/dat_tokens.hpp"

namespace dc::dat {


/// Remark after q: trimmed, capped at kMaxDatComment bytes, invalid UTF-8 replaced by '?' so
/// that it can be printed in JSON as it is.
std::string clean_comment(std::string_view rest) {
  auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!rest.empty() && space(rest.front())) rest.remove_prefix(1);
  while (!rest.empty() && space(rest.back())) rest.remove_suffix(1);
  rest = rest.substr(0, kMaxDatComment);
  std::string out;
  out.reserve(rest.size());
  for (size_t i = 0; i < rest.size();) {
    const auto c = static_cast<unsigned char>(rest[i]);
    const size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = len > 0 && i + len <= rest.size();
    for (size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(rest[i + k]) >> 6) == 0x2;
    if (ok && len == 1 && c < 0x20 && c != '\n' && c != '\t' && c != '\r') ok = false;  // control characters
    if (ok) {
      out.append(rest.substr(i, len));
      i += len;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

/// Fails unless `count` more numbers (each at least one character plus a separator, the
/// last one none) fit into the bytes left: checked before anything of that size is allocated.
void need_numbers(Tokens& tok, long double count, const std::string& what) {
  if (count * 2 - 1 > static_cast<long double>(tok.remaining_bytes()))
    tok.fail("file too short for " + what + ": " + std::to_string(static_cast<long long>(count)) +
             " numbers need at least " + std::to_string(static_cast<long long>(2 * count - 1)) + " bytes, " +
             std::to_string(tok.remaining_bytes()) + " left (truncated?)");
}

/// Dense storage (0): the repeated size line, then M column-major.
SparseRowMatrix parse_dense(Tokens& tok, long long n) {
  const long long rows2 = tok.integer("the repeated row count"), cols2 = tok.integer("the repeated column count");
  if (rows2 != n || cols2 != n)
    tok.fail("repeated size line " + std::to_string(rows2) + "\t" + std::to_string(cols2) + " disagrees with " +
             std::to_string(n) + "x" + std::to_string(n));
  need_numbers(tok, static_cast<long double>(n) * n + n, "n = " + std::to_string(n));
  std::vector<Eigen::Triplet<double, int>> trip;
  for (long long j = 0; j < n; ++j)  // column-major: a column per line
    for (long long i = 0; i < n; ++i)
      if (const double v = tok.number("M", j * n + i); v != 0.0)
        trip.emplace_back(static_cast<int>(i), static_cast<int>(j), v);
  SparseRowMatrix M(n, n);
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

/// Cumulative block sizes r_0 < r_1 < … = n of `count` block rows or columns.
std::vector<long long> parse_block_sizes(Tokens& tok, long long count, long long n, const char* what) {
  std::vector<long long> cum(static_cast<size_t>(count));
  for (long long i = 0; i < count; ++i) {
    const long long v = tok.integer(what);
    const long long prev = i == 0 ? 0 : cum[static_cast<size_t>(i - 1)];
    if (v <= prev || v > n)
      tok.fail(std::string(what) + " " + std::to_string(i) + " = " + std::to_string(v) +
               " must be cumulative: greater than " + std::to_string(prev) + " and at most n = " + std::to_string(n));
    cum[static_cast<size_t>(i)] = v;
  }
  if (cum.back() != n)
    tok.fail(std::string("the ") + what + "s add up to " + std::to_string(cum.back()) + ", not n = " +
             std::to_string(n));
  return cum;
}

/// Sparse-block storage (1), Siconos' SparseBlockStructuredMatrix (layout in dat_file.hpp).
SparseRowMatrix parse_sparse_block(Tokens& tok, long long n) {
  SparseRowMatrix M(n, n);
  const long long nblocks = tok.integer("the number of blocks");
  if (nblocks < 0) tok.fail("number of blocks " + std::to_string(nblocks) + " is negative");
  if (nblocks == 0) return M;  // Siconos writes a zero matrix as "0" and nothing else
  const long long R = tok.integer("the number of block rows"), C = tok.integer("the number of block columns");
  if (R < 1 || R > n || C < 1 || C > n)
    tok.fail("block grid " + std::to_string(R) + "x" + std::to_string(C) + " must be between 1x1 and " +
             std::to_string(n) + "x" + std::to_string(n));
  if (static_cast<long double>(nblocks) > static_cast<long double>(R) * C)
    tok.fail(std::to_string(nblocks) + " blocks do not fit into a " + std::to_string(R) + "x" + std::to_string(C) +
             " block grid");
  need_numbers(tok, static_cast<long double>(R) + C, "the block sizes");
  const std::vector<long long> rsize = parse_block_sizes(tok, R, n, "cumulative block-row size");
  const std::vector<long long> csize = parse_block_sizes(tok, C, n, "cumulative block-column size");
  const long long filled1 = tok.integer("filled1 (the number of row pointers)");
  const long long filled2 = tok.integer("filled2 (the number of column indices)");
  if (filled1 < 2 || filled1 > R + 1)
    tok.fail("filled1 = " + std::to_string(filled1) + " row pointers, expected 2 … " + std::to_string(R + 1) +
             " (block rows + 1)");
  if (filled2 != nblocks)
    tok.fail("filled2 = " + std::to_string(filled2) + " column indices but " + std::to_string(nblocks) + " blocks");
  need_numbers(tok, static_cast<long double>(filled1) + filled2, "the block index arrays");
  std::vector<long long> rowptr(static_cast<size_t>(filled1));
  for (long long i = 0; i < filled1; ++i) {
    const long long v = tok.integer("a row pointer");
    const long long prev = i == 0 ? 0 : rowptr[static_cast<size_t>(i - 1)];
    if ((i == 0 && v != 0) || v < prev || v > nblocks)
      tok.fail("row pointer " + std::to_string(i) + " = " + std::to_string(v) + " out of range (must be " +
               (i == 0 ? std::string("0") : std::to_string(prev) + " … " + std::to_string(nblocks)) + ")");
    rowptr[static_cast<size_t>(i)] = v;
  }
  if (rowptr.back() != nblocks)
    tok.fail("the last row pointer is " + std::to_string(rowptr.back()) + ", not the number of blocks " +
             std::to_string(nblocks));
  std::vector<long long> colidx(static_cast<size_t>(filled2));
  for (long long b = 0; b < filled2; ++b) {
    const long long v = tok.integer("a block-column index");
    if (v < 0 || v >= C)
      tok.fail("block-column index " + std::to_string(b) + " = " + std::to_string(v) + " out of range 0 … " +
               std::to_string(C - 1));
    colidx[static_cast<size_t>(b)] = v;
  }
  // Entry count of every block, and repeated blocks, before the entries are allocated.
  long double entries = 0;
  std::vector<long long> seen(static_cast<size_t>(C), -1);  // block row that last used column c
  for (long long i = 0; i + 1 < filled1; ++i)
    for (long long b = rowptr[static_cast<size_t>(i)]; b < rowptr[static_cast<size_t>(i + 1)]; ++b) {
      const long long c = colidx[static_cast<size_t>(b)];
      if (seen[static_cast<size_t>(c)] == i)
        tok.fail("block (" + std::to_string(i) + "," + std::to_string(c) + ") is given twice");
      seen[static_cast<size_t>(c)] = i;
      const long long rows = rsize[static_cast<size_t>(i)] - (i ? rsize[static_cast<size_t>(i - 1)] : 0);
      const long long cols = csize[static_cast<size_t>(c)] - (c ? csize[static_cast<size_t>(c - 1)] : 0);
      entries += static_cast<long double>(rows) * cols;
    }
  need_numbers(tok, entries + nblocks + n, "the " + std::to_string(nblocks) + " blocks and q");
  std::vector<Eigen::Triplet<double, int>> trip;
  for (long long i = 0; i + 1 < filled1; ++i) {
    const long long r0 = i ? rsize[static_cast<size_t>(i - 1)] : 0, rows = rsize[static_cast<size_t>(i)] - r0;
    for (long long b = rowptr[static_cast<size_t>(i)]; b < rowptr[static_cast<size_t>(i + 1)]; ++b) {
      const long long c = colidx[static_cast<size_t>(b)];
      const long long c0 = c ? csize[static_cast<size_t>(c - 1)] : 0, cols = csize[static_cast<size_t>(c)] - c0;
      if (const long long k = tok.integer("a block number"); k != b)
        tok.fail("block number " + std::to_string(k) + " where block " + std::to_string(b) + " was expected");
      const std::string what = "block " + std::to_string(b);
      for (long long jj = 0; jj < cols; ++jj)  // column-major within the block
        for (long long ii = 0; ii < rows; ++ii)
          if (const double v = tok.number(what.c_str(), jj * rows + ii); v != 0.0)
            trip.emplace_back(static_cast<int>(r0 + ii), static_cast<int>(c0 + jj), v);
    }
  }
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}


void append_number(std::string& out, double v, const char* sep) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g%s", v, sep);
  out += buf;
}

void write_text(const std::string& path, const std::string& text) {
  write_file_atomically(path, text);  // PATH.tmp, fsync, rename: a failed write leaves PATH as it was
}

namespace {

/// Reads up to `limit` bytes of `fd` (fewer at its end). False with errno set on a read error.
bool read_up_to(int fd, std::uintmax_t limit, std::string& text) {
  while (text.size() < limit) {
    const size_t chunk = static_cast<size_t>(std::min<std::uintmax_t>(limit - text.size(), size_t{1} << 20));
    const size_t old = text.size();
    text.resize(old + chunk);
    const ssize_t n = ::read(fd, text.data() + old, chunk);
    if (n < 0 && errno == EINTR) {
      text.resize(old);
      continue;
    }
    text.resize(old + static_cast<size_t>(std::max<ssize_t>(n, 0)));
    if (n < 0) return false;
    if (n == 0) break;
  }
  return true;
}

}  // namespace

std::string read_whole_file(const std::string& path, const char* what) {
  // O_NONBLOCK: opening a FIFO that no process has open for writing returns at once instead
  // of waiting for a writer forever; such a FIFO then reads as empty and is refused below.
  // The reads themselves block (a writer that is there is waited for).
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  // A directory opens and fails only at the first read; name it instead.
  if (S_ISDIR(st.st_mode)) throw IoError(path + ": is a directory, not a " + what);
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) < 0)
    throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  const bool regular = S_ISREG(st.st_mode);
  // A regular file: its size, and no more (it may grow while read). Anything else: chunks
  // up to the cap, one byte more tells that it is longer.
  const std::uintmax_t limit = regular ? static_cast<std::uintmax_t>(st.st_size) : kMaxDatStreamBytes + 1;
  std::string text;
  if (!read_up_to(fd, limit, text)) throw IoError(path + ": read error: " + std::strerror(errno));
  if (!regular && text.size() > kMaxDatStreamBytes)
    throw IoError(path + ": not a regular file and longer than " + std::to_string(kMaxDatStreamBytes >> 20) +
                  " MiB (the limit for a pipe or device); refused");
  if (text.empty() && S_ISFIFO(st.st_mode))
    throw IoError(path + ": a FIFO with nothing written to it (no writer had it open when it was read); refused");
  if (text.empty()) throw IoError(path + ": file is empty");
  return text;
}

void need_line_end(Tokens& tok, const std::string& what) {
  if (tok.rest().find('\n') == std::string_view::npos)
    tok.fail(what + " is not followed by a line end: the file may be cut inside its last number (truncated?)");
}

void require_writable_values(const double* v, long long count, const std::string& where) {
  if (count <= 0) throw InvalidArgument(where + ": no values (n = 0): the reader refuses an empty problem");
  for (long long i = 0; i < count; ++i)
    if (!std::isfinite(v[i]))
      throw InvalidArgument(where + ": entry " + std::to_string(i) + " is not finite; the reader refuses it");
}

}  // namespace dc::dat
