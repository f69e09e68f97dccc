#include "dc/warmstart/starter_argument.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "dc/core/error.hpp"

namespace dc {

namespace {

/// `parse(field, &used)` (a std::sto* function) when it reads the whole field; nothing when it
/// throws (no number, out of the type's range) or leaves text behind ("1x", "2.5" as an int).
template <class Parse>
auto whole(const std::string& field, Parse parse) -> std::optional<decltype(parse(field, nullptr))> {
  try {
    std::size_t used = 0;
    const auto value = parse(field, &used);
    if (used == field.size()) return value;
  } catch (const std::logic_error&) {  // std::invalid_argument, std::out_of_range
  }
  return std::nullopt;
}

std::optional<double> finite_double(const std::string& field) {
  const auto v = whole(field, [](const std::string& s, std::size_t* used) { return std::stod(s, used); });
  if (v && std::isfinite(*v)) return v;
  return std::nullopt;
}

}  // namespace

StarterArgument::StarterArgument(const WarmStartSpec& spec, std::string usage) : spec_(spec), usage_(std::move(usage)) {}

void StarterArgument::fail() const {
  throw ConfigError("warm starter '" + spec_.full() + "': expected " + usage_);
}

void StarterArgument::fail(const std::string& reason) const {
  throw ConfigError("warm starter '" + spec_.full() + "': expected " + usage_ + " (" + reason + ")");
}

std::vector<std::string> StarterArgument::fields(std::size_t min_fields, std::size_t max_fields) const {
  std::vector<std::string> out;
  if (!spec_.arg.empty()) {
    std::size_t begin = 0;
    for (;;) {
      const std::size_t colon = spec_.arg.find(':', begin);
      out.push_back(spec_.arg.substr(begin, colon - begin));
      if (colon == std::string::npos) break;
      begin = colon + 1;
    }
  }
  if (out.size() < min_fields || out.size() > max_fields) fail();
  return out;
}

int StarterArgument::integer(const std::string& field, int lo, int hi) const {
  const auto v = whole(field, [](const std::string& s, std::size_t* used) { return std::stoi(s, used); });
  if (!v || *v < lo || *v > hi) fail();
  return *v;
}

double StarterArgument::positive_number(const std::string& field) const {
  const auto v = finite_double(field);
  if (!v || !(*v > 0)) fail();
  return *v;
}

double StarterArgument::number(const std::string& field, double lo, double hi) const {
  const auto v = finite_double(field);
  if (!v || !(*v >= lo && *v <= hi)) fail();
  return *v;
}

std::uint64_t StarterArgument::unsigned_integer(const std::string& field) const {
  const auto v = whole(field, [](const std::string& s, std::size_t* used) { return std::stoull(s, used); });
  if (!v) fail();
  return *v;
}

void reject_argument(const WarmStartSpec& spec) {
  if (!spec.arg.empty()) StarterArgument(spec, spec.name + " without an argument").fail();
}

}  // namespace dc
