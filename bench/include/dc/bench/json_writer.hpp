#pragma once
// The one JSON writer of the deepcontact executable (summary.json of `bench --out`, the
// result of `lcp solve`): a streaming builder, e.g.
//   j.begin_object(JsonWriter::Layout::Lines); j.key("a").value(1); j.end_object(); j.str();
// Policy (docs/bench.md, docs/lcp.md): strings escaped per RFC 8259 (quote and backslash by a
// backslash, \n and \t short, other control characters below 0x20 as \u00XX, bytes ≥ 0x80
// copied: the input is taken to be UTF-8); doubles with %.17g (round-trip exact), NaN and ±Inf
// as null; integers exactly; booleans true / false. Inline containers separate members by
// ", " and keys by ": " on one line; Lines containers put each member on its own line,
// indented two spaces per level. Misuse (value without key in an object, key outside one,
// unbalanced end_*, str() on an incomplete top-level value) throws InvalidArgument.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace dc {

class JsonWriter {
 public:
  enum class Layout { Inline, Lines };

  JsonWriter& begin_object(Layout layout = Layout::Inline);
  JsonWriter& end_object();
  JsonWriter& begin_array(Layout layout = Layout::Inline);
  JsonWriter& end_array();
  /// The next member's key (objects only).
  JsonWriter& key(std::string_view name);

  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(const std::string& text) { return value(std::string_view(text)); }
  JsonWriter& value(double number);  ///< %.17g; NaN/Inf → null
  JsonWriter& value(bool flag);
  /// Any integer type, written exactly.
  template <class I>
    requires(std::is_integral_v<I> && !std::is_same_v<I, bool>)
  JsonWriter& value(I number) {
    return integer(std::to_string(number));
  }
  JsonWriter& null();
  /// A value, or null when empty.
  JsonWriter& value(std::optional<double> number) { return number ? value(*number) : null(); }
  /// An inline array of doubles.
  JsonWriter& array(std::span<const double> numbers);

  /// The document followed by a newline. InvalidArgument unless exactly one complete
  /// top-level value was written.
  [[nodiscard]] std::string str() const;

 private:
  struct Level {
    bool object;
    Layout layout;
    int members = 0;
    bool key_pending = false;
  };
  void before_value();
  void close(bool object);
  void raw(std::string_view text);
  void newline();  ///< newline + indentation of the current depth
  JsonWriter& integer(const std::string& digits);

  std::string out_;
  std::vector<Level> stack_;
  bool done_ = false;
};

/// A JSON string literal of `text` (with the quotes), escaped as described above.
std::string json_quote(std::string_view text);
/// A JSON number of `v` (%.17g) or null for NaN/Inf.
std::string json_number(double v);

}  // namespace dc
