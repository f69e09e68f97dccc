#pragma once
// The one JSON writer of the deepcontact executable (summary.json of `bench --out`, the
// result of `lcp solve`): a small streaming builder, so no command writes JSON by hand.
//
//   JsonWriter j;
//   j.begin_object(JsonWriter::Layout::Lines);     // {\n  "a": 1,\n  "b": [1, 2]\n}\n
//   j.key("a").value(1);
//   j.key("b").begin_array().value(1).value(2).end_array();
//   j.end_object();
//   std::string text = j.str();
//
// Policy (docs/bench.md, docs/lcp.md):
//   * strings are escaped per RFC 8259: quote and backslash by a backslash, \n and \t by their
//     short escapes, every other control character below 0x20 as \u00XX; bytes ≥ 0x80 are
//     copied unchanged (the input is taken to be UTF-8);
//   * a double is written with %.17g (round-trip exact: parsing the text gives the same
//     double); NaN and ±Inf, which JSON cannot express, are written as null;
//   * integers are written exactly; booleans as true / false.
// Layout: Inline containers separate members by ", " and keys from values by ": " on one
// line; Lines containers put each member on its own line, indented two spaces per level.
// A misuse (value without key inside an object, key outside one, unbalanced end_*, str()
// before the top-level value is complete) throws InvalidArgument.
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
