#include "dc/engine/dat_file.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "dc/engine/error.hpp"

namespace dc {
namespace {

/// Whitespace tokenizer over the file text that tracks line numbers for messages.
class Tokens {
 public:
  Tokens(std::string_view text, const std::string& name) : t_(text), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(name_ + ": line " + std::to_string(line_) + ": " + what);
  }

  /// Next token, or empty at the end of the text.
  std::string_view next() {
    while (pos_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[pos_]))) {
      if (t_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < t_.size() && !std::isspace(static_cast<unsigned char>(t_[pos_]))) ++pos_;
    return t_.substr(start, pos_ - start);
  }

  long long integer(const char* what) {
    const std::string_view tok = next();
    if (tok.empty()) fail(std::string("file ends before ") + what);
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      fail(std::string(what) + " must be an integer, got '" + std::string(tok.substr(0, 40)) + "'");
    return v;
  }

  double number(const char* what, long long index) {
    const std::string_view tok = next();
    if (tok.empty())
      fail(std::string("file ends after ") + std::to_string(index) + " entries of " + what + " (truncated)");
    double v = 0;
    const char* b = tok.data();
    const char* e = tok.data() + tok.size();
    if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+', fscanf accepts it
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec == std::errc::result_out_of_range)
      fail(std::string("entry ") + std::to_string(index) + " of " + what + " is out of the double range: '" +
           std::string(tok.substr(0, 40)) + "'");
    if (ec != std::errc() || ptr != e)
      fail(std::string("entry ") + std::to_string(index) + " of " + what + " is not a number: '" +
           std::string(tok.substr(0, 40)) + "'");
    if (!std::isfinite(v))
      fail(std::string("entry ") + std::to_string(index) + " of " + what + " is not finite: '" +
           std::string(tok.substr(0, 40)) + "'");
    return v;
  }

  [[nodiscard]] size_t remaining_bytes() const { return t_.size() - pos_; }

 private:
  std::string_view t_;
  const std::string& name_;
  size_t pos_ = 0;
  long long line_ = 1;
};

}  // namespace

LcpProblem parse_lcp_dat(std::string_view text, const std::string& name) {
  Tokens tok(text, name);
  const long long n = tok.integer("the problem size n");
  if (n <= 0) tok.fail("problem size n = " + std::to_string(n) + " must be positive");
  if (n > kMaxDatSize)
    tok.fail("problem size n = " + std::to_string(n) + " exceeds the limit " + std::to_string(kMaxDatSize));
  const long long storage = tok.integer("the storage type");
  if (storage != 0)
    tok.fail("storage type " + std::to_string(storage) + " is not supported (only 0 = dense)");
  const long long rows = tok.integer("the row count"), cols = tok.integer("the column count");
  if (rows != n || cols != n)
    tok.fail("matrix is " + std::to_string(rows) + "x" + std::to_string(cols) + " but n = " + std::to_string(n));
  const long long rows2 = tok.integer("the repeated row count"), cols2 = tok.integer("the repeated column count");
  if (rows2 != rows || cols2 != cols)
    tok.fail("repeated size line " + std::to_string(rows2) + "\t" + std::to_string(cols2) + " disagrees with " +
             std::to_string(rows) + "x" + std::to_string(cols));
  // Each number needs at least one character and one separator (the last one none).
  const long long needed = n * n + n;
  if (static_cast<long double>(needed) * 2 - 1 > static_cast<long double>(tok.remaining_bytes()))
    tok.fail("file too short for n = " + std::to_string(n) + ": " + std::to_string(needed) +
             " numbers need at least " + std::to_string(2 * needed - 1) + " bytes, " +
             std::to_string(tok.remaining_bytes()) + " left (truncated?)");
  Eigen::MatrixXd M(n, n);
  for (long long j = 0; j < n; ++j)  // column-major: a column per line
    for (long long i = 0; i < n; ++i) M(i, j) = tok.number("M", j * n + i);
  Eigen::VectorXd q(n);
  for (long long i = 0; i < n; ++i) q[i] = tok.number("q", i);
  if (const std::string_view extra = tok.next(); !extra.empty())
    tok.fail("unexpected content after the " + std::to_string(n) + " entries of q: '" +
             std::string(extra.substr(0, 40)) + "'");
  return LcpProblem::standard(M, q);
}

LcpProblem read_lcp_dat(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open LCP file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError(path + ": read error");
  const std::string text = ss.str();
  if (text.empty()) throw IoError(path + ": file is empty");
  return parse_lcp_dat(text, path);
}

std::string format_lcp_dat(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  if (M.rows() != M.cols() || M.rows() != q.size())
    throw InvalidArgument("write_lcp_dat: M must be n×n and q of size n");
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

void write_lcp_dat(const std::string& path, const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const std::string text = format_lcp_dat(M, q);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(path + ": cannot open for writing");
  out << text;
  out.flush();
  if (!out) throw IoError(path + ": write error");
}

}  // namespace dc
