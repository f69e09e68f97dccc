#include "dc/lcp/dat_file.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "dc/core/error.hpp"
#include "formats/dat_tokens.hpp"

namespace dc {

using dat::Tokens;

DatFile parse_dat_file(std::string_view text, const std::string& name) {
  Tokens tok(text, name);
  const long long n = tok.integer("the problem size n");
  if (n <= 0) tok.fail("problem size n = " + std::to_string(n) + " must be positive");
  if (n > kMaxDatSize)
    tok.fail("problem size n = " + std::to_string(n) + " exceeds the limit " + std::to_string(kMaxDatSize));
  const long long storage = tok.integer("the storage type");
  if (storage != 0 && storage != 1)
    tok.fail("storage type " + std::to_string(storage) + " is not supported (only 0 = dense, 1 = sparse block)");
  const long long rows = tok.integer("the row count"), cols = tok.integer("the column count");
  if (rows != n || cols != n)
    tok.fail("matrix is " + std::to_string(rows) + "x" + std::to_string(cols) + " but n = " + std::to_string(n));
  DatFile f;
  f.storage = storage == 0 ? DatStorage::Dense : DatStorage::SparseBlock;
  const SparseRowMatrix M = storage == 0 ? dat::parse_dense(tok, n) : dat::parse_sparse_block(tok, n);
  dat::need_numbers(tok, static_cast<long double>(n), "q");
  Eigen::VectorXd q(n);
  for (long long i = 0; i < n; ++i) q[i] = tok.number("q", i);
  dat::need_line_end(tok, "the last entry of q");
  f.comment = dat::clean_comment(tok.rest());  // Siconos' reader stops after q as well
  f.problem = LcpProblem::standard(M, q);
  return f;
}

LcpProblem parse_lcp_dat(std::string_view text, const std::string& name) { return parse_dat_file(text, name).problem; }

DatFile read_dat_file(const std::string& path) {
  return parse_dat_file(dat::read_whole_file(path, "LCP file"), path);
}

LcpProblem read_lcp_dat(const std::string& path) { return read_dat_file(path).problem; }

std::string format_lcp_dat(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  if (M.rows() != M.cols() || M.rows() != q.size())
    throw InvalidArgument("write_lcp_dat: M must be n×n and q of size n");
  dat::require_writable_values(M.data(), M.size(), "write_lcp_dat: M");
  dat::require_writable_values(q.data(), q.size(), "write_lcp_dat: q");
  const long long n = q.size();
  std::string out;
  char buf[40];
  out += std::to_string(n) + "\n0\n" + std::to_string(n) + "\n" + std::to_string(n) + "\n" +
         std::to_string(n) + "\t" + std::to_string(n) + "\n";
  for (long long j = 0; j < n; ++j) {
    for (long long i = 0; i < n; ++i) {
      std::snprintf(buf, sizeof buf, "%.17g ", M(i, j));
      out += buf;
    }
    out += "\n";
  }
  for (long long i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g ", q[i]);
    out += buf;
  }
  out += "\n";
  return out;
}

using dat::append_number;
using dat::write_text;

void write_lcp_dat(const std::string& path, const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  write_text(path, format_lcp_dat(M, q));
}

std::string format_lcp_dat_blocks(const SparseRowMatrix& M, const Eigen::VectorXd& q, int block_size) {
  if (M.rows() != M.cols() || M.rows() != q.size())
    throw InvalidArgument("write_lcp_dat_blocks: M must be n×n and q of size n");
  if (block_size < 1) throw InvalidArgument("write_lcp_dat_blocks: block size must be >= 1");
  for (int k = 0; k < M.outerSize(); ++k)
    for (SparseRowMatrix::InnerIterator it(M, k); it; ++it)
      if (!std::isfinite(it.value()))
        throw InvalidArgument("write_lcp_dat_blocks: M(" + std::to_string(it.row()) + "," + std::to_string(it.col()) +
                              ") is not finite; the reader refuses it");
  dat::require_writable_values(q.data(), q.size(), "write_lcp_dat_blocks: q");
  const int n = static_cast<int>(q.size());
  const int nb = (n + block_size - 1) / block_size;  // block rows = block columns
  auto start = [&](int b) { return std::min(n, b * block_size); };
  // Which blocks hold a non-zero entry: (block row, block column), row-major order.
  std::vector<std::vector<int>> cols(static_cast<size_t>(nb));
  for (int br = 0; br < nb; ++br) {
    std::vector<char> used(static_cast<size_t>(nb), 0);
    for (int i = start(br); i < start(br + 1); ++i)
      for (SparseRowMatrix::InnerIterator it(M, i); it; ++it)
        if (it.value() != 0.0) used[static_cast<size_t>(it.col() / block_size)] = 1;
    for (int bc = 0; bc < nb; ++bc)
      if (used[static_cast<size_t>(bc)]) cols[static_cast<size_t>(br)].push_back(bc);
  }
  int nblocks = 0, last_row = -1;
  for (int br = 0; br < nb; ++br) {
    nblocks += static_cast<int>(cols[static_cast<size_t>(br)].size());
    if (!cols[static_cast<size_t>(br)].empty()) last_row = br;
  }
  std::string out = std::to_string(n) + "\n1\n" + std::to_string(n) + "\n" + std::to_string(n) + "\n" +
                    std::to_string(nblocks) + "\n";
  if (nblocks > 0) {
    out += std::to_string(nb) + "\n" + std::to_string(nb) + "\n";
    for (int pass = 0; pass < 2; ++pass) {  // cumulative block-row, then block-column sizes
      for (int b = 0; b < nb; ++b) out += std::to_string(start(b + 1)) + "\t";
      out += "\n";
    }
    const int filled1 = last_row + 2;  // Siconos: index of the last non-empty block row + 2
    out += std::to_string(filled1) + "\n" + std::to_string(nblocks) + "\n";
    for (int br = 0, ptr = 0; br < filled1; ++br) {
      out += std::to_string(ptr) + "\t";
      if (br < nb) ptr += static_cast<int>(cols[static_cast<size_t>(br)].size());
    }
    out += "\n";
    for (int br = 0; br < nb; ++br)
      for (int bc : cols[static_cast<size_t>(br)]) out += std::to_string(bc) + "\t";
    out += "\n";
    for (int br = 0, k = 0; br < nb; ++br)
      for (int bc : cols[static_cast<size_t>(br)]) {
        out += std::to_string(k++) + "\n";
        for (int j = start(bc); j < start(bc + 1); ++j)  // column-major within the block
          for (int i = start(br); i < start(br + 1); ++i) append_number(out, M.coeff(i, j), "\n");
      }
  }
  for (int i = 0; i < n; ++i) append_number(out, q[i], " ");
  out += "\n";
  return out;
}

void write_lcp_dat_blocks(const std::string& path, const SparseRowMatrix& M, const Eigen::VectorXd& q,
                          int block_size) {
  write_text(path, format_lcp_dat_blocks(M, q, block_size));
}

}  // namespace dc
