#pragma once
// The tokenizer and matrix blocks shared by the Siconos `.dat` readers (dat_file.cpp: LCP
// files; fc2d_dat_file.cpp: 2D frictional-contact files). Private to dc_engine. Every count
// is checked against the bytes left before anything of that size is allocated.
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc::dat {

/// The first 40 bytes of a token as printable ASCII, every other byte as \xNN: a binary file's
/// bytes (NUL, control characters, invalid UTF-8) would cut or garble the one-line message —
/// Python could not even decode it and raised with an empty message.
inline std::string printable(std::string_view token) {
  std::string out;
  for (const char ch : token.substr(0, 40)) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f) {
      out += ch;
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

/// Whitespace tokenizer over the file text that tracks line numbers for messages.
class Tokens {
 public:
  Tokens(std::string_view text, const std::string& name) : t_(text), name_(&name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(*name_ + ": line " + std::to_string(line_) + ": " + what);
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
      fail(std::string(what) + " must be an integer, got '" + printable(tok) + "'");
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
           printable(tok) + "'");
    if (ec != std::errc() || ptr != e)
      fail(std::string("entry ") + std::to_string(index) + " of " + what + " is not a number: '" +
           printable(tok) + "'");
    if (!std::isfinite(v))
      fail(std::string("entry ") + std::to_string(index) + " of " + what + " is not finite: '" +
           printable(tok) + "'");
    return v;
  }

  /// Skips the rest of the current line (the newline included).
  void skip_line() {
    while (pos_ < t_.size() && t_[pos_] != '\n') ++pos_;
    if (pos_ < t_.size()) {
      ++pos_;
      ++line_;
    }
  }

  /// The next token without consuming it.
  [[nodiscard]] std::string_view peek() const {
    Tokens copy = *this;
    return copy.next();
  }

  [[nodiscard]] size_t remaining_bytes() const { return t_.size() - pos_; }

  /// The text not consumed yet.
  [[nodiscard]] std::string_view rest() const { return t_.substr(pos_); }

 private:
  std::string_view t_;
  const std::string* name_;
  size_t pos_ = 0;
  long long line_ = 1;
};

/// Remark after the last vector: trimmed, capped at kMaxDatComment bytes, invalid UTF-8 and
/// control characters replaced by '?' (printable in JSON as it is).
std::string clean_comment(std::string_view rest);

/// Fails unless `count` more numbers (each at least one character plus a separator, the
/// last one none) fit into the bytes left.
void need_numbers(Tokens& tok, long double count, const std::string& what);

/// Fails unless a line end follows the last number read (`what` names it): a file cut
/// inside its last number (0.9 → 9) would otherwise be read with another value. Siconos
/// ends every vector with "\n", and so do the writers here.
void need_line_end(Tokens& tok, const std::string& what);

/// InvalidArgument unless every value is finite and there is at least one (`where` names
/// the writer and the vector): the writers refuse what the reader refuses.
void require_writable_values(const double* v, long long count, const std::string& where);

/// Dense storage (0) of an n × n matrix: the repeated size line, then M column-major.
SparseRowMatrix parse_dense(Tokens& tok, long long n);

/// Sparse-block storage (1), Siconos' SparseBlockStructuredMatrix (layout in dat_file.hpp).
SparseRowMatrix parse_sparse_block(Tokens& tok, long long n);

/// Appends v with %.17g and `sep` (exact round trip).
void append_number(std::string& out, double v, const char* sep);

/// Writes `text` to `path`. Throws IoError.
void write_text(const std::string& path, const std::string& text);

/// The whole file (IoError when missing, unreadable or empty; `what` names the kind of file):
/// a regular file up to its size, anything else (a pipe, /dev/zero) up to kMaxDatStreamBytes
/// (IoError beyond).
std::string read_whole_file(const std::string& path, const char* what);

}  // namespace dc::dat
