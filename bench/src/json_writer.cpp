#include "dc/bench/json_writer.hpp"

#include <cmath>
#include <cstdio>

#include "dc/core/error.hpp"

namespace dc {

std::string json_quote(std::string_view text) {
  std::string o = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN/Inf
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

void JsonWriter::raw(std::string_view text) { out_ += text; }

void JsonWriter::newline() {
  out_ += '\n';
  out_.append(2 * stack_.size(), ' ');
}

void JsonWriter::before_value() {
  if (done_) throw InvalidArgument("JsonWriter: a second top-level value");
  if (stack_.empty()) return;
  Level& l = stack_.back();
  if (l.object) {
    if (!l.key_pending) throw InvalidArgument("JsonWriter: a value inside an object needs a key first");
    l.key_pending = false;
    return;  // key() wrote the separator and indentation
  }
  if (l.members++ > 0) raw(",");
  if (l.layout == Layout::Lines)
    newline();
  else if (l.members > 1)
    raw(" ");
}

JsonWriter& JsonWriter::key(std::string_view name) {
  if (stack_.empty() || !stack_.back().object) throw InvalidArgument("JsonWriter: key '" + std::string(name) + "' outside an object");
  Level& l = stack_.back();
  if (l.key_pending) throw InvalidArgument("JsonWriter: key '" + std::string(name) + "' after a key without value");
  if (l.members++ > 0) raw(",");
  if (l.layout == Layout::Lines)
    newline();
  else if (l.members > 1)
    raw(" ");
  raw(json_quote(name));
  raw(": ");
  l.key_pending = true;
  return *this;
}

JsonWriter& JsonWriter::begin_object(Layout layout) {
  before_value();
  raw("{");
  stack_.push_back({true, layout});
  return *this;
}

JsonWriter& JsonWriter::begin_array(Layout layout) {
  before_value();
  raw("[");
  stack_.push_back({false, layout});
  return *this;
}

void JsonWriter::close(bool object) {
  if (stack_.empty() || stack_.back().object != object)
    throw InvalidArgument(std::string("JsonWriter: ") + (object ? "end_object" : "end_array") + " without its begin");
  const Level l = stack_.back();
  if (l.key_pending) throw InvalidArgument("JsonWriter: an object ends after a key without value");
  stack_.pop_back();
  if (l.layout == Layout::Lines && l.members > 0) newline();
  raw(object ? "}" : "]");
  if (stack_.empty()) done_ = true;
}

JsonWriter& JsonWriter::end_object() {
  close(true);
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  close(false);
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view text) {
  before_value();
  raw(json_quote(text));
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  before_value();
  raw(json_number(number));
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::integer(const std::string& digits) {
  before_value();
  raw(digits);
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(bool flag) {
  before_value();
  raw(flag ? "true" : "false");
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::null() {
  before_value();
  raw("null");
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::array(std::span<const double> numbers) {
  begin_array();
  for (const double v : numbers) value(v);
  return end_array();
}

std::string JsonWriter::str() const {
  if (!done_ || !stack_.empty()) throw InvalidArgument("JsonWriter: the document is not complete");
  return out_ + "\n";
}

}  // namespace dc
