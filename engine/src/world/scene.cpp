// Scene files: TOML ⇄ WorldDef (docs/design.md §7, docs/scenes.md).
//
// One table of key specifications (scene_keys.hpp) drives parsing, `--set` overrides and
// writing, so a key added there is automatically readable, overridable and round-tripped.
// Checks are split in two layers on purpose:
//   * here: syntax, unknown keys, types, NaN/Inf, integer ranges, wall names — things only
//     the TOML layer can see (and report with line:column);
//   * WorldDef::validate(): value ranges (dt > 0, restitution ∈ [0, 1], ...), shared with
//     definitions built in code. Its messages are prefixed with the source name here.
// Overlap and out-of-box checks of explicit bodies need geometry and live in World.
#include "dc/engine/scene.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "dc/core/closest_name.hpp"
#include "dc/core/error.hpp"
#include "dc/core/install_paths.hpp"
#include "world/scene_keys.hpp"

namespace dc {
namespace {

using scene_detail::BodyKey;
using scene_detail::Kind;
using scene_detail::SectionKey;

/// Scene files larger than this are refused before parsing: a scene is a few kilobytes,
/// a huge file is a mistake (e.g. a trajectory passed by accident) and would just eat memory.
constexpr std::uintmax_t kMaxSceneBytes = 16u << 20;

/// Where a value came from, for one-line error messages.
struct Origin {
  std::string source;     ///< file name or "--set a.b=c"
  bool has_lines = true;  ///< false for overrides (line:column of a one-line snippet is noise)
};

[[noreturn]] void fail(const Origin& o, const toml::source_region* where, std::string_view key,
                       std::string_view what) {
  std::ostringstream os;
  os << o.source;
  if (o.has_lines && where != nullptr && where->begin.line > 0)
    os << ':' << where->begin.line << ':' << where->begin.column;
  os << ": ";
  if (!key.empty()) os << key << ": ";
  os << what;
  throw ConfigError(os.str());
}

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

// ---- "did you mean" -------------------------------------------------------------------

/// " (did you mean 'x'?)" for the closest candidate within a small edit distance, else "".
template <class Range>
std::string suggestion(std::string_view word, const Range& candidates) {
  const std::string best = closest_name(word, candidates);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

std::vector<std::string_view> section_names() {
  std::vector<std::string_view> out;
  for (const SectionKey& k : scene_detail::section_keys())
    if (out.empty() || out.back() != k.section) out.push_back(k.section);
  out.push_back("body");
  return out;
}

std::vector<std::string_view> keys_of(std::string_view section) {
  std::vector<std::string_view> out;
  if (section == "body") {
    for (const BodyKey& k : scene_detail::body_keys()) out.push_back(k.key);
  } else {
    for (const SectionKey& k : scene_detail::section_keys())
      if (k.section == section) out.push_back(k.key);
  }
  return out;
}

const SectionKey* find_key(std::string_view section, std::string_view key) {
  for (const SectionKey& k : scene_detail::section_keys())
    if (k.section == section && k.key == key) return &k;
  return nullptr;
}

// ---- typed readers ----------------------------------------------------------------------

double read_number(const toml::node& n, const Origin& o, std::string_view key) {
  double v = 0;
  if (const auto* f = n.as_floating_point()) v = f->get();
  else if (const auto* i = n.as_integer()) v = static_cast<double>(i->get());
  else fail(o, &n.source(), key, std::string("expected a number, got ") + type_name(n));
  if (!std::isfinite(v)) {
    fail(o, &n.source(), key,
         std::string("expected a finite number, got ") + (std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf"));
  }
  return v;
}

std::int64_t read_integer(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* i = n.as_integer();
  if (i == nullptr) fail(o, &n.source(), key, std::string("expected an integer, got ") + type_name(n));
  return i->get();
}

int read_int(const toml::node& n, const Origin& o, std::string_view key) {
  const std::int64_t v = read_integer(n, o, key);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(o, &n.source(), key, "integer " + std::to_string(v) + " is out of range");
  return static_cast<int>(v);
}

std::uint64_t read_seed(const toml::node& n, const Origin& o, std::string_view key) {
  const std::int64_t v = read_integer(n, o, key);
  if (v < 0) fail(o, &n.source(), key, "expected an integer >= 0, got " + std::to_string(v));
  return static_cast<std::uint64_t>(v);
}

std::string read_string(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* s = n.as_string();
  if (s == nullptr) fail(o, &n.source(), key, std::string("expected a string, got ") + type_name(n));
  return s->get();
}

Vec2 read_vec2(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* a = n.as_array();
  if (a == nullptr || a->size() != 2) {
    fail(o, &n.source(), key,
         a == nullptr ? std::string("expected an array of 2 numbers, got ") + type_name(n)
                      : "expected an array of 2 numbers, got " + std::to_string(a->size()) + " elements");
  }
  const std::string k(key);
  return {read_number((*a)[0], o, k + "[0]"), read_number((*a)[1], o, k + "[1]")};
}

std::array<double, 4> read_region(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* a = n.as_array();
  if (a == nullptr || a->size() != 4) {
    fail(o, &n.source(), key,
         a == nullptr ? std::string("expected an array [x0, y0, x1, y1], got ") + type_name(n)
                      : "expected an array [x0, y0, x1, y1], got " + std::to_string(a->size()) + " elements");
  }
  std::array<double, 4> r{};
  for (std::size_t i = 0; i < 4; ++i) r[i] = read_number((*a)[i], o, std::string(key) + "[" + std::to_string(i) + "]");
  return r;
}

std::array<bool, 4> read_walls(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* a = n.as_array();
  if (a == nullptr) fail(o, &n.source(), key, std::string("expected an array of wall names, got ") + type_name(n));
  std::array<bool, 4> walls{false, false, false, false};
  const auto& names = scene_detail::wall_names();
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string k = std::string(key) + "[" + std::to_string(i) + "]";
    const std::string name = read_string((*a)[i], o, k);
    std::size_t w = 0;
    while (w < names.size() && names[w] != name) ++w;
    if (w == names.size()) {
      fail(o, &(*a)[i].source(), k,
           "unknown wall '" + name + "' (expected left, right, bottom or top)" + suggestion(name, names));
    }
    if (walls[w]) fail(o, &(*a)[i].source(), k, "wall '" + name + "' is listed twice");
    walls[w] = true;
  }
  return walls;
}

/// An array of [x, y] pairs (polygon vertices).
std::vector<Vec2> read_points(const toml::node& n, const Origin& o, std::string_view key) {
  const auto* a = n.as_array();
  if (a == nullptr) fail(o, &n.source(), key, std::string("expected an array of [x, y] pairs, got ") + type_name(n));
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < a->size(); ++i)
    out.push_back(read_vec2((*a)[i], o, std::string(key) + "[" + std::to_string(i) + "]"));
  return out;
}

/// A named value (solver, shape, motion, order): the string parsed once, here, with the
/// messages these names have always had: the parser's line naming the key after the source
/// (as validate()'s), and for a solver make_solver's own line (it names the solver).
template <class F>
F read_named(const toml::node& n, const Origin& o, std::string_view key) {
  const std::string name = read_string(n, o, key);
  if constexpr (std::is_same_v<F, SolverId>) {
    return SolverId::parse(name);
  } else {
    const std::string k(key);
    try {
      if constexpr (std::is_same_v<F, BodyShape>) return parse_body_shape(name, k);
      else if constexpr (std::is_same_v<F, Motion>) return parse_motion(name, k);
      else if constexpr (std::is_same_v<F, BodyOrder>) return parse_body_order(name, k);
      else return parse_internal_order(name, k);
    } catch (const ConfigError& e) {
      throw ConfigError(o.source + ": " + e.what());
    }
  }
}

/// Reads `node` into the field `ref` points at; shared by sections and [[body]] keys.
template <class Owner>
void assign(Owner& owner, const scene_detail::Ref<Owner>& ref, const toml::node& node, const Origin& o,
            std::string_view key) {
  std::visit(
      [&](auto get) {
        auto& field = get(owner);
        using F = std::remove_reference_t<decltype(field)>;
        if constexpr (std::is_same_v<F, double>) field = read_number(node, o, key);
        else if constexpr (std::is_same_v<F, int>) field = read_int(node, o, key);
        else if constexpr (std::is_same_v<F, std::uint64_t>) field = read_seed(node, o, key);
        else if constexpr (std::is_same_v<F, std::string>) field = read_string(node, o, key);
        else if constexpr (std::is_same_v<F, Vec2>) field = read_vec2(node, o, key);
        else if constexpr (std::is_same_v<F, std::optional<Vec2>>) field = read_vec2(node, o, key);
        else if constexpr (std::is_same_v<F, std::vector<Vec2>>) field = read_points(node, o, key);
        else if constexpr (std::is_same_v<F, std::array<double, 4>>) field = read_region(node, o, key);
        else if constexpr (std::is_same_v<F, std::array<bool, 4>>) field = read_walls(node, o, key);
        else field = read_named<F>(node, o, key);
      },
      ref);
}

/// Joins pieces by appending (GCC 12 warns falsely, -Wrestrict, on `"[" + std::string`).
std::string concat(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (std::string_view p : parts) out += p;
  return out;
}

std::string section_key_name(std::string_view section, std::string_view key) {
  return concat({"[", section, "] ", key});
}

void read_body(WorldDef& def, const toml::node& node, std::size_t index, const Origin& o) {
  const std::string where = "[[body]] #" + std::to_string(index + 1);
  const auto* t = node.as_table();
  if (t == nullptr) fail(o, &node.source(), where, std::string("expected a table, got ") + type_name(node));
  BodyDef b;
  bool has_position = false;
  for (const auto& [k, v] : *t) {
    const BodyKey* spec = nullptr;
    for (const BodyKey& bk : scene_detail::body_keys())
      if (bk.key == k.str()) spec = &bk;
    if (spec == nullptr) {
      fail(o, &k.source(), where + " " + std::string(k.str()),
           "unknown key" + suggestion(k.str(), keys_of("body")));
    }
    assign(b, spec->ref, v, o, where + " " + std::string(k.str()));
    has_position = has_position || spec->key == "position";
  }
  if (!has_position) fail(o, &node.source(), where, "missing required key 'position'");
  def.body.push_back(b);
}

void read_document(WorldDef& def, const toml::table& doc, const Origin& o) {
  const auto sections = section_names();
  for (const auto& [name, node] : doc) {
    const std::string_view s = name.str();
    if (s == "body") {
      const auto* arr = node.as_array();
      if (arr == nullptr) {
        fail(o, &node.source(), "[body]", "explicit circles are an array of tables: write [[body]], not [body]");
      }
      for (std::size_t i = 0; i < arr->size(); ++i) read_body(def, (*arr)[i], i, o);
      continue;
    }
    if (std::find(sections.begin(), sections.end(), s) == sections.end()) {
      // A key at the top level is most likely a known key written outside its section.
      std::string hint;
      for (const SectionKey& k : scene_detail::section_keys())
        if (k.key == s) { hint = " (did you mean " + section_key_name(k.section, k.key) + "?)"; break; }
      if (hint.empty()) hint = suggestion(s, sections);
      fail(o, &name.source(), node.is_table() ? "[" + std::string(s) + "]" : std::string(s),
           (node.is_table() ? "unknown section" : "unknown top-level key") + hint);
    }
    const auto* t = node.as_table();
    if (t == nullptr) fail(o, &node.source(), "[" + std::string(s) + "]", std::string("expected a table, got ") + type_name(node));
    for (const auto& [k, v] : *t) {
      const SectionKey* spec = find_key(s, k.str());
      const std::string key = section_key_name(s, k.str());
      if (spec == nullptr) fail(o, &k.source(), key, "unknown key" + suggestion(k.str(), keys_of(s)));
      assign(def, spec->ref, v, o, key);
    }
  }
}

/// Runs WorldDef::validate() and prefixes its (key-naming) message with the source.
void validate(const WorldDef& def, const Origin& o) {
  try {
    def.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(o.source + ": " + e.what());
  }
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

/// `[left, bottom]` → `["left", "bottom"]`: lets `--set world.walls=[left,bottom]` survive a
/// shell that ate the quotes. Only bare words are quoted; anything else is left as is.
std::string quote_bare_words(std::string_view v) {
  std::string out;
  std::size_t i = 0;
  while (i < v.size()) {
    if (std::isalpha(static_cast<unsigned char>(v[i]))) {
      std::size_t j = i;
      while (j < v.size() && (std::isalnum(static_cast<unsigned char>(v[j])) || v[j] == '_' || v[j] == '-')) ++j;
      out += '"';
      out += v.substr(i, j - i);
      out += '"';
      i = j;
    } else {
      out += v[i++];
    }
  }
  return out;
}

// ---- writing ------------------------------------------------------------------------------

/// Shortest text that reads back to the same double (std::to_chars round-trips), always
/// spelled as a TOML float so the type survives a round trip through other tools.
std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "30" → "30.0"; nan/inf never get here
  return s;
}

std::string format_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

template <class Owner>
std::string format_value(Owner& owner, const scene_detail::Ref<Owner>& ref, std::string_view key) {
  return std::visit(
      [&](auto get) -> std::string {
        const auto& field = get(owner);
        using F = std::remove_cvref_t<decltype(field)>;
        if constexpr (std::is_same_v<F, double>) {
          return format_double(field);
        } else if constexpr (std::is_same_v<F, int>) {
          return std::to_string(field);
        } else if constexpr (std::is_same_v<F, std::uint64_t>) {
          // TOML integers are signed 64-bit; a larger seed cannot be written (or parsed).
          if (field > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
            throw ConfigError(std::string(key) + ": " + std::to_string(field) + " does not fit a TOML integer");
          return std::to_string(field);
        } else if constexpr (std::is_same_v<F, std::string>) {
          return format_string(field);
        } else if constexpr (std::is_same_v<F, SolverId>) {
          return format_string(to_string(field));
        } else if constexpr (std::is_same_v<F, Motion>) {
          return format_string(motion_name(field));
        } else if constexpr (std::is_same_v<F, BodyShape> || std::is_same_v<F, BodyOrder> ||
                             std::is_same_v<F, InternalOrder>) {
          return format_string(to_string(field));
        } else if constexpr (std::is_same_v<F, Vec2>) {
          return concat({"[", format_double(field.x), ", ", format_double(field.y), "]"});
        } else if constexpr (std::is_same_v<F, std::optional<Vec2>>) {
          return field ? concat({"[", format_double(field->x), ", ", format_double(field->y), "]"}) : std::string();
        } else if constexpr (std::is_same_v<F, std::vector<Vec2>>) {
          std::string out = "[";
          for (std::size_t i = 0; i < field.size(); ++i)
            out += concat({i ? ", [" : "[", format_double(field[i].x), ", ", format_double(field[i].y), "]"});
          return out + "]";
        } else if constexpr (std::is_same_v<F, std::array<double, 4>>) {
          return concat({"[", format_double(field[0]), ", ", format_double(field[1]), ", ", format_double(field[2]),
                         ", ", format_double(field[3]), "]"});
        } else {
          std::string out = "[";
          const auto& names = scene_detail::wall_names();
          for (std::size_t w = 0; w < field.size(); ++w) {
            if (!field[w]) continue;
            if (out.size() > 1) out += ", ";
            out += format_string(names[w]);
          }
          return out + "]";
        }
      },
      ref);
}

std::string comment(std::string_view value, std::string_view doc) {
  std::string line(value);
  if (!doc.empty()) {
    line.resize(std::max<std::size_t>(line.size() + 1, 40), ' ');
    line += "# ";
    line += doc;
  }
  return line;
}

}  // namespace

WorldDef parse_scene(std::string_view toml_text, std::string_view source_name) {
  const Origin origin{std::string(source_name), true};
  toml::table doc;
  try {
    doc = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    std::string desc(e.description());
    for (char& c : desc)
      if (c == '\n' || c == '\r') c = ' ';
    throw ConfigError(origin.source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) +
                      ": TOML syntax error: " + desc);
  }
  WorldDef def;
  read_document(def, doc, origin);
  validate(def, origin);
  return def;
}

std::string find_scene(const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(name, ec) || name.find('/') != std::string::npos) return name;
  const std::string stem = name.ends_with(".toml") ? name.substr(0, name.size() - 5) : name;
  const fs::path dir = data_path("scenes");
  const fs::path shipped = dir / (stem + ".toml");
  if (!stem.empty() && fs::is_regular_file(shipped, ec)) return shipped.string();
  return name;
}

std::vector<std::string> shipped_scenes() {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(data_path("scenes"), ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".toml") names.push_back(it->path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

WorldDef load_scene(const std::string& name) {
  namespace fs = std::filesystem;
  const std::string path = find_scene(name);
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    std::string shipped;
    for (const auto& n : shipped_scenes()) shipped += (shipped.empty() ? "" : ", ") + n;
    throw IoError(path + ": cannot read scene file: no such file, nor a shipped scene of that name (shipped: " +
                  (shipped.empty() ? "none found" : shipped) + ")");
  }
  if (!fs::is_regular_file(status)) throw IoError(path + ": cannot read scene file: not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) throw IoError(path + ": cannot read scene file: " + ec.message());
  if (size > kMaxSceneBytes) {
    throw IoError(path + ": scene file is " + std::to_string(size) + " bytes, more than the limit of " +
                  std::to_string(kMaxSceneBytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open scene file for reading");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.gcount() != static_cast<std::streamsize>(text.size())) throw IoError(path + ": read error");
  return parse_scene(text, path);
}

void apply_override(WorldDef& def, std::string_view assignment) {
  const Origin origin{"--set " + std::string(assignment), false};
  const auto eq = assignment.find('=');
  if (eq == std::string_view::npos) fail(origin, nullptr, "", "expected section.key=value");
  const std::string lhs = trim(assignment.substr(0, eq));
  const std::string value = trim(assignment.substr(eq + 1));
  const auto dot = lhs.find('.');
  if (dot == std::string::npos || lhs.find('.', dot + 1) != std::string::npos)
    fail(origin, nullptr, lhs, "expected section.key=value");
  const std::string section = lhs.substr(0, dot);
  const std::string key = lhs.substr(dot + 1);
  if (section == "body")
    fail(origin, nullptr, "[[body]]", "explicit circles cannot be overridden; edit the scene file");
  const auto sections = section_names();
  if (std::find(sections.begin(), sections.end(), section) == sections.end())
    fail(origin, nullptr, "[" + section + "]", "unknown section" + suggestion(section, sections));
  const SectionKey* spec = find_key(section, key);
  const std::string name = section_key_name(section, key);
  if (spec == nullptr) fail(origin, nullptr, name, "unknown key" + suggestion(key, keys_of(section)));
  if (value.empty()) fail(origin, nullptr, name, "missing value");

  // A string key takes a bare word as is (`solver.name=psor`); quoted text is TOML.
  std::string toml_value = value;
  if (spec->kind == Kind::String && value.front() != '"' && value.front() != '\'') toml_value = format_string(value);
  toml::table parsed;
  auto parse_value = [&](const std::string& v) -> bool {
    try {
      const std::string snippet = "v = " + v + "\n";
      parsed = toml::parse(std::string_view(snippet), std::string_view("--set"));
    } catch (const toml::parse_error&) {
      return false;
    }
    return parsed.size() == 1 && parsed.contains("v");  // rejects "1\nother = 2" smuggling
  };
  if (!parse_value(toml_value) && !(spec->kind == Kind::Walls && parse_value(quote_bare_words(value))))
    fail(origin, nullptr, name, "value '" + value + "' is not a TOML value");

  WorldDef updated = def;  // strong guarantee: `def` is untouched on error
  assign(updated, spec->ref, *parsed.get("v"), origin, name);
  validate(updated, origin);
  def = std::move(updated);
}

std::string scene_to_toml(const WorldDef& def_in) {
  WorldDef def = def_in;  // the accessors hand out mutable references
  std::ostringstream os;
  os << "# DeepContact scene (docs/scenes.md). Every key is written; omitted keys take their defaults.\n";
  std::string_view current;
  for (const SectionKey& k : scene_detail::section_keys()) {
    if (k.section != current) {
      os << (current.empty() ? "" : "\n") << "[" << k.section << "]\n";
      current = k.section;
    }
    os << comment(std::string(k.key) + " = " + format_value(def, k.ref, section_key_name(k.section, k.key)), k.doc)
       << "\n";
  }
  for (std::size_t i = 0; i < def.body.size(); ++i) {
    os << "\n[[body]]\n";
    for (const BodyKey& k : scene_detail::body_keys()) {
      const std::string v = format_value(def.body[i], k.ref, "[[body]] " + std::string(k.key));
      if (!v.empty()) os << k.key << " = " << v << "\n";  // an absent optional key (pivot) is not written
    }
  }
  return os.str();
}

}  // namespace dc
