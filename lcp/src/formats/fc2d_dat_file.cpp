#include "dc/lcp/fc2d_dat_file.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/dat_file.hpp"
#include "formats/dat_tokens.hpp"

namespace dc {
namespace {

using dat::Tokens;

/// Expects the literal token `word` (e.g. "col", ":", "locations").
void expect(Tokens& tok, std::string_view word, const char* where) {
  const std::string_view t = tok.next();
  if (t != word)
    tok.fail(std::string("expected '") + std::string(word) + "' " + where + ", got '" +
             dat::printable(t) + "'");
}

/// An integer token with an optional trailing comma ("3822," in CSparse's header).
long long integer_comma(Tokens& tok, const char* what) {
  std::string_view t = tok.next();
  if (!t.empty() && t.back() == ',') t.remove_suffix(1);
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || ptr != t.data() + t.size())
    tok.fail(std::string(what) + " must be an integer, got '" + dat::printable(t) + "'");
  return v;
}

/// "M-by-N," of CSparse's header.
void parse_size_token(Tokens& tok, long long n) {
  const std::string_view t = tok.next();
  long long m = -1, c = -1;
  const char* b = t.data();
  const char* e = t.data() + t.size();
  auto [p1, ec1] = std::from_chars(b, e, m);
  bool ok = ec1 == std::errc() && e - p1 > 4 && std::string_view(p1, 4) == "-by-";
  if (ok) {
    auto [p2, ec2] = std::from_chars(p1 + 4, e, c);
    ok = ec2 == std::errc() && (p2 == e || (p2 + 1 == e && *p2 == ','));
  }
  if (!ok) tok.fail("expected the CSparse size 'M-by-N,', got '" + dat::printable(t) + "'");
  if (m != n || c != n)
    tok.fail("CSparse matrix is " + std::to_string(m) + "x" + std::to_string(c) + " but the header says " +
             std::to_string(n) + "x" + std::to_string(n));
}

/// An index token in [0, n).
long long index_in(Tokens& tok, long long n, const char* what) {
  const long long v = tok.integer(what);
  if (v < 0 || v >= n)
    tok.fail(std::string(what) + " " + std::to_string(v) + " out of range 0 … " + std::to_string(n - 1));
  return v;
}

/// Compressed columns (or rows, `by_row`) of CSparse's print: "col j : locations a to b" and
/// b − a + 1 lines "i : x".
void parse_compressed(Tokens& tok, long long n, long long nnz, bool by_row,
                      std::vector<Eigen::Triplet<double, int>>& trip) {
  const char* word = by_row ? "row" : "col";
  std::vector<long long> seen(static_cast<size_t>(n), -1);  // outer index that last used an inner index
  long long next = 0;
  for (long long j = 0; j < n; ++j) {
    expect(tok, word, "(a column/row header of the CSparse matrix)");
    if (const long long jj = tok.integer("a column/row number"); jj != j)
      tok.fail(std::string(word) + " " + std::to_string(jj) + " where " + std::to_string(j) + " was expected");
    expect(tok, ":", "after the column/row number");
    expect(tok, "locations", "in the column/row header");
    const long long a = tok.integer("the first location");
    expect(tok, "to", "in the column/row header");
    const long long b = tok.integer("the last location");
    if (a != next || b < a - 1 || b >= nnz)
      tok.fail(std::string(word) + " " + std::to_string(j) + ": locations " + std::to_string(a) + " to " +
               std::to_string(b) + " do not continue at " + std::to_string(next) + " within nnz = " +
               std::to_string(nnz));
    for (long long k = a; k <= b; ++k) {
      const long long i = index_in(tok, n, "an index");
      if (seen[static_cast<size_t>(i)] == j)
        tok.fail("entry (" + std::to_string(by_row ? j : i) + "," + std::to_string(by_row ? i : j) + ") is given twice");
      seen[static_cast<size_t>(i)] = j;
      expect(tok, ":", "between an index and its value");
      const double x = tok.number("W", k);
      if (x != 0.0)
        trip.emplace_back(static_cast<int>(by_row ? j : i), static_cast<int>(by_row ? i : j), x);
    }
    next = b + 1;
  }
  if (next != nnz)
    tok.fail("the columns/rows hold " + std::to_string(next) + " entries, but nnz = " + std::to_string(nnz));
}

/// CSparse's triplet list: nnz lines "i j : x". An entry given twice is refused (CSparse's
/// cs_compress would sum the two; formats.md calls it an error), named by its row and column.
void parse_triplets(Tokens& tok, long long n, long long nnz, std::vector<Eigen::Triplet<double, int>>& trip) {
  std::vector<std::pair<long long, long long>> at;  // (row, column) of every entry, zeros included
  at.reserve(static_cast<size_t>(nnz));
  for (long long k = 0; k < nnz; ++k) {
    const long long i = index_in(tok, n, "a row index"), j = index_in(tok, n, "a column index");
    expect(tok, ":", "between a triplet's indices and its value");
    at.emplace_back(i, j);
    if (const double x = tok.number("W", k); x != 0.0) trip.emplace_back(static_cast<int>(i), static_cast<int>(j), x);
  }
  std::sort(at.begin(), at.end());
  if (const auto dup = std::adjacent_find(at.begin(), at.end()); dup != at.end())
    tok.fail("entry (" + std::to_string(dup->first) + "," + std::to_string(dup->second) +
             ") is given twice in the triplet list");
}

/// Sparse storage (2): origin, then CSparse's cs_print text (layout in fc2d_dat_file.hpp).
SparseRowMatrix parse_csparse(Tokens& tok, long long n) {
  const long long origin = tok.integer("the sparse origin (1 triplet, 2 csc, 3 csr)");
  if (origin < 1 || origin > 3)
    tok.fail("sparse origin " + std::to_string(origin) + " is not supported (1 triplet, 2 csc, 3 csr)");
  expect(tok, "CSparse", "(CSparse's version line)");
  tok.skip_line();
  const std::string_view tag = tok.peek();
  const bool triplet = tag == "triplet:", csr = tag == "csr:";
  if (triplet || csr) tok.next();
  const long long want = triplet ? 1 : csr ? 3 : 2;
  if (want != origin)
    tok.fail("sparse origin " + std::to_string(origin) + " disagrees with the CSparse header (" +
             (triplet ? "triplet" : csr ? "csr" : "csc") + ")");
  parse_size_token(tok, n);
  expect(tok, "nzmax:", "in the CSparse header");
  const long long nzmax = integer_comma(tok, "nzmax");
  expect(tok, "nnz:", "in the CSparse header");
  const long long nnz = integer_comma(tok, "nnz");
  if (nnz < 0 || nzmax < nnz || static_cast<long double>(nnz) > static_cast<long double>(n) * n)
    tok.fail("nnz = " + std::to_string(nnz) + " (nzmax " + std::to_string(nzmax) + ") impossible for " +
             std::to_string(n) + "x" + std::to_string(n));
  if (!triplet) {
    expect(tok, "1-norm:", "in the CSparse header");
    tok.next();  // the norm, printed with %g; not needed
  }
  // Each entry is at least "i : x" (5 bytes); each column header at least 8 numbers' worth.
  dat::need_numbers(tok, static_cast<long double>(nnz) * (triplet ? 4 : 3) + (triplet ? 0 : 7.0L * n),
                    "the " + std::to_string(nnz) + " CSparse entries");
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(static_cast<size_t>(nnz));
  if (triplet) {
    parse_triplets(tok, n, nnz, trip);
  } else {
    parse_compressed(tok, n, nnz, csr, trip);
  }
  SparseRowMatrix M(n, n);
  M.setFromTriplets(trip.begin(), trip.end());  // no entry twice (checked above)
  return M;
}

/// The first `count` whitespace-separated tokens of `text` as integers (fewer if not numbers).
std::vector<long long> leading_integers(std::string_view text, int count) {
  std::string name = "header";
  Tokens tok(text, name);
  std::vector<long long> v;
  for (int k = 0; k < count; ++k) {
    const std::string_view t = tok.next();
    long long x = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    if (t.empty() || ec != std::errc() || ptr != t.data() + t.size()) break;
    v.push_back(x);
  }
  return v;
}

/// The line L of a Tokens::fail message "NAME: line L: …" (0 when it has none).
long long error_line(std::string_view message, const std::string& name) {
  const std::string prefix = name + ": line ";
  if (!message.starts_with(prefix)) return 0;
  long long line = 0;
  std::from_chars(message.data() + prefix.size(), message.data() + message.size(), line);
  return line;
}

/// Siconos' isComplete flag at the start of `rest` (the text after μ): a lone 0 or 1 followed by
/// white space or the end. Returns it (−1 when absent) and removes it from `rest`.
int take_is_complete_flag(std::string_view& rest) {
  auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  std::size_t i = 0;
  while (i < rest.size() && space(rest[i])) ++i;
  if (i >= rest.size() || (rest[i] != '0' && rest[i] != '1')) return -1;
  if (i + 1 < rest.size() && !space(rest[i + 1])) return -1;
  const int flag = rest[i] - '0';
  rest.remove_prefix(i + 1);
  return flag;
}

}  // namespace

Fc2dDatFile parse_fc2d_dat(std::string_view text, const std::string& name) {
  Tokens tok(text, name);
  const long long dim = tok.integer("the dimension");
  if (dim == 3) tok.fail("dimension 3 (3D friction) is not supported: only 2D frictional-contact problems");
  if (dim != 2) tok.fail("dimension " + std::to_string(dim) + " is not 2 (a 2D frictional-contact problem)");
  const long long nc = tok.integer("the number of contacts");
  if (nc <= 0) tok.fail("number of contacts " + std::to_string(nc) + " must be positive");
  if (nc > kMaxDatSize / 2)  // compared before 2·nc is formed: a huge nc would overflow
    tok.fail("number of contacts " + std::to_string(nc) + " exceeds the limit " + std::to_string(kMaxDatSize / 2));
  const long long n = 2 * nc;
  const long long storage = tok.integer("the storage type");
  if (storage < 0 || storage > 2)
    tok.fail("storage type " + std::to_string(storage) + " is not supported (0 dense, 1 sparse block, 2 sparse)");
  const long long rows = tok.integer("the row count"), cols = tok.integer("the column count");
  if (rows != n || cols != n)
    tok.fail("W is " + std::to_string(rows) + "x" + std::to_string(cols) + " but " + std::to_string(nc) +
             " contacts need " + std::to_string(n) + "x" + std::to_string(n));
  Fc2dDatFile f;
  f.storage = static_cast<Fc2dStorage>(storage);
  f.problem.W = storage == 0 ? dat::parse_dense(tok, n) : storage == 1 ? dat::parse_sparse_block(tok, n)
                                                                         : parse_csparse(tok, n);
  dat::need_numbers(tok, static_cast<long double>(n + nc), "q and mu");
  f.problem.q.resize(n);
  for (long long i = 0; i < n; ++i) f.problem.q[i] = tok.number("q", i);
  f.problem.mu.resize(nc);
  for (long long c = 0; c < nc; ++c) {
    f.problem.mu[c] = tok.number("mu", c);
    if (f.problem.mu[c] < 0) tok.fail("mu of contact " + std::to_string(c) + " is negative");
  }
  dat::need_line_end(tok, "the last friction coefficient mu");
  std::string_view rest = tok.rest();
  f.is_complete = take_is_complete_flag(rest);
  f.comment = dat::clean_comment(rest);
  return f;
}

Fc2dDatFile read_fc2d_dat(const std::string& path) {
  return parse_fc2d_dat(dat::read_whole_file(path, "frictional-contact file"), path);
}

DatKind detect_dat_kind(std::string_view text, const std::string& name) {
  const std::vector<long long> h = leading_integers(text, 5);
  const bool lcp = h.size() >= 4 && (h[1] == 0 || h[1] == 1) && h[2] == h[0] && h[3] == h[0];
  long long dnc = 0;  // d·nc, checked: a huge nc must not wrap onto the row count
  const bool fc = h.size() >= 5 && (h[0] == 2 || h[0] == 3) && h[2] >= 0 && h[2] <= 2 &&
                  !__builtin_mul_overflow(h[0], h[1], &dnc) && h[3] == dnc && h[4] == h[3];
  if (lcp && fc) {  // "2 1 2 2 2 …": a 2×2 LCP of storage 1 or one contact; the kind that reads
    long long fc_line = 0;
    try {
      parse_fc2d_dat(text, name);
      return DatKind::Fc2d;
    } catch (const IoError& e) {
      fc_line = error_line(e.what(), name);
    }
    try {
      parse_dat_file(text, name);
      return DatKind::Lcp;
    } catch (const IoError& e) {  // neither: the kind read further names the damage
      return error_line(e.what(), name) >= fc_line ? DatKind::Lcp : DatKind::Fc2d;
    }
  }
  if (fc) return DatKind::Fc2d;
  if (lcp) return DatKind::Lcp;
  throw IoError(name + ": not a Siconos LCP (n storage n n) or frictional-contact (d nc storage d*nc d*nc) file");
}

std::string format_fc2d_dat(const Fc2dProblem& p, Fc2dStorage storage) {
  p.validate();
  std::string lcp;  // "n\n" + W in the LCP layout + q line: W and q are laid out alike
  if (storage == Fc2dStorage::Dense)
    lcp = format_lcp_dat(Eigen::MatrixXd(p.W), p.q);
  else if (storage == Fc2dStorage::SparseBlock)
    lcp = format_lcp_dat_blocks(p.W, p.q, 2);
  else
    throw InvalidArgument("format_fc2d_dat: only storage 0 (dense) and 1 (sparse block) are written");
  std::string out = "2\n" + std::to_string(p.contacts()) + "\n" + lcp.substr(lcp.find('\n') + 1);
  for (int c = 0; c < p.contacts(); ++c) dat::append_number(out, p.mu[c], " ");
  out += "\n";
  return out;
}

void write_fc2d_dat(const std::string& path, const Fc2dProblem& p, Fc2dStorage storage) {
  dat::write_text(path, format_fc2d_dat(p, storage));
}

}  // namespace dc
