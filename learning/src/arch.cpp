#include "dc/learning/arch.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "dc/core/error.hpp"

namespace dc {

namespace {

struct Ctx {
  std::string source;
  std::string layer;  // "layer 3 'e2'"
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const {
    throw ConfigError(source + ": " + layer + (key.empty() ? "" : " key '" + key + "'") + ": " + msg);
  }
};

int get_int(const toml::node& n, const Ctx& c, const std::string& key) {
  if (auto v = n.value_exact<int64_t>()) return static_cast<int>(*v);
  c.fail(key, "expected an integer");
}

std::vector<int> get_int_list(const toml::node& n, const Ctx& c, const std::string& key) {
  std::vector<int> out;
  if (const toml::array* a = n.as_array()) {
    for (const toml::node& e : *a) out.push_back(get_int(e, c, key));
  } else {
    out.push_back(get_int(n, c, key));
  }
  return out;
}

std::string get_string(const toml::node& n, const Ctx& c, const std::string& key) {
  if (auto v = n.value_exact<std::string>()) return *v;
  c.fail(key, "expected a string");
}

LayerSpec parse_layer(const toml::table& t, std::size_t index, const Ctx& outer) {
  LayerSpec s;
  s.name = "layer" + std::to_string(index);
  Ctx c = outer;
  c.layer = "layer " + std::to_string(index);
  if (const toml::node* n = t.get("name")) s.name = get_string(*n, c, "name");
  c.layer += " '" + s.name + "'";
  const toml::node* type = t.get("type");
  if (type == nullptr) c.fail("type", "missing (conv, relu, dropout, dense or upsample)");
  s.type = get_string(*type, c, "type");
  std::set<std::string> allowed{"name", "type", "input"};
  if (s.type == "conv") allowed.insert({"out", "kernel", "stride", "relu"});
  else if (s.type == "dense") allowed.insert({"out", "relu"});
  else if (s.type == "dropout") allowed.insert("rate");
  else if (s.type == "upsample") allowed.insert({"match", "size"});
  else if (s.type != "relu") c.fail("type", "unknown layer type '" + s.type + "'");
  for (auto&& [k, v] : t) {
    const std::string key(k.str());
    if (!allowed.count(key)) c.fail(key, "not a key of a '" + s.type + "' layer");
    if (key == "input") {
      if (const toml::array* a = v.as_array()) {
        for (const toml::node& e : *a) s.inputs.push_back(get_string(e, c, key));
        if (s.inputs.empty()) c.fail(key, "empty input list");
      } else {
        s.inputs.push_back(get_string(v, c, key));
      }
    } else if (key == "out") {
      std::vector<int> o = get_int_list(v, c, key);
      if (s.type == "conv" && (v.is_array() || o[0] <= 0)) c.fail(key, "expected a positive channel count");
      if (s.type == "dense") {
        if (v.is_array()) {
          if (o.size() != 3) c.fail(key, "expected [C, H, W]");
          s.out_shape = o;
        } else {
          s.out = o[0];
        }
        for (int x : o)
          if (x <= 0) c.fail(key, "extents must be positive");
      } else {
        s.out = o[0];
      }
    } else if (key == "kernel") {
      s.kernel = get_int(v, c, key);
      if (s.kernel <= 0 || s.kernel % 2 == 0) c.fail(key, "must be odd and positive");
    } else if (key == "stride") {
      s.stride = get_int(v, c, key);
      if (s.stride < 1) c.fail(key, "must be >= 1");
    } else if (key == "relu") {
      auto b = v.value_exact<bool>();
      if (!b) c.fail(key, "expected true or false");
      s.relu = *b;
    } else if (key == "rate") {
      auto r = v.value<double>();
      if (!r || !(*r >= 0.0 && *r < 1.0)) c.fail(key, "expected a number in [0, 1)");
      s.rate = *r;
    } else if (key == "match") {
      s.match = get_string(v, c, key);
    } else if (key == "size") {
      std::vector<int> sz = get_int_list(v, c, key);
      if (sz.size() != 2 || sz[0] <= 0 || sz[1] <= 0) c.fail(key, "expected [H, W] with positive extents");
      s.size = {sz[0], sz[1]};
    }
  }
  if ((s.type == "conv" || s.type == "dense") && s.out <= 0 && s.out_shape.empty()) c.fail("out", "missing");
  if (s.type == "dropout" && !t.get("rate")) c.fail("rate", "missing");
  if (!s.match.empty() && s.size[0] > 0) c.fail("size", "give either 'match' or 'size', not both");
  return s;
}

void quote(std::ostringstream& os, const std::string& s) {
  os << '"';
  for (char ch : s) {
    if (ch == '"' || ch == '\\') os << '\\';
    os << ch;
  }
  os << '"';
}

}  // namespace

ArchSpec ArchSpec::parse(std::string_view text, std::string_view source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ":" << e.source().begin.line << ": " << e.description();
    throw ConfigError(os.str());
  }
  Ctx c{std::string(source), "arch"};
  ArchSpec spec;
  for (auto&& [k, v] : root) {
    const std::string key(k.str());
    if (key == "name") spec.name = get_string(v, c, key);
    else if (key != "layer") c.fail(key, "unknown top-level key (expected name, [[layer]])");
  }
  const toml::array* layers = root["layer"].as_array();
  if (layers == nullptr || layers->empty()) c.fail("layer", "no [[layer]] tables");
  std::set<std::string> names;
  for (std::size_t i = 0; i < layers->size(); ++i) {
    const toml::table* t = (*layers)[i].as_table();
    if (t == nullptr) c.fail("layer", "entry " + std::to_string(i) + " is not a table");
    LayerSpec s = parse_layer(*t, i, c);
    Ctx lc{c.source, "layer " + std::to_string(i) + " '" + s.name + "'"};
    if (s.name == "input" || !names.insert(s.name).second) lc.fail("name", "duplicate or reserved node name");
    for (const std::string& in : s.inputs)
      if (in != "input" && !names.count(in) ) lc.fail("input", "'" + in + "' is not an earlier layer or 'input'");
    if (!s.match.empty() && s.match != "input" && !names.count(s.match))
      lc.fail("match", "'" + s.match + "' is not an earlier layer or 'input'");
    spec.layers.push_back(std::move(s));
  }
  return spec;
}

ArchSpec ArchSpec::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open architecture file");
  std::ostringstream os;
  os << in.rdbuf();
  return parse(os.str(), path.string());
}

std::string ArchSpec::to_toml() const {
  std::ostringstream os;
  os << "# DeepContact CNN architecture\nname = ";
  quote(os, name);
  os << "\n";
  for (const LayerSpec& s : layers) {
    os << "\n[[layer]]\nname = ";
    quote(os, s.name);
    os << "\ntype = ";
    quote(os, s.type);
    os << "\n";
    if (s.inputs.size() == 1) {
      os << "input = ";
      quote(os, s.inputs[0]);
      os << "\n";
    } else if (s.inputs.size() > 1) {
      os << "input = [";
      for (std::size_t i = 0; i < s.inputs.size(); ++i) {
        if (i) os << ", ";
        quote(os, s.inputs[i]);
      }
      os << "]\n";
    }
    if (s.type == "conv") {
      os << "out = " << s.out << "\nkernel = " << s.kernel << "\nstride = " << s.stride << "\nrelu = "
         << (s.relu ? "true" : "false") << "\n";
    } else if (s.type == "dense") {
      if (!s.out_shape.empty())
        os << "out = [" << s.out_shape[0] << ", " << s.out_shape[1] << ", " << s.out_shape[2] << "]\n";
      else
        os << "out = " << s.out << "\n";
      os << "relu = " << (s.relu ? "true" : "false") << "\n";
    } else if (s.type == "dropout") {
      std::ostringstream r;
      r.precision(17);
      r << s.rate;
      std::string rs = r.str();
      if (rs.find_first_of(".e") == std::string::npos) rs += ".0";  // keep it a TOML float
      os << "rate = " << rs << "\n";
    } else if (s.type == "upsample") {
      if (!s.match.empty()) {
        os << "match = ";
        quote(os, s.match);
        os << "\n";
      } else if (s.size[0] > 0) {
        os << "size = [" << s.size[0] << ", " << s.size[1] << "]\n";
      }
    }
  }
  return os.str();
}

namespace {
LayerSpec conv(std::string name, int out, int stride, bool relu, std::vector<std::string> inputs = {}) {
  LayerSpec s;
  s.name = std::move(name);
  s.type = "conv";
  s.out = out;
  s.stride = stride;
  s.relu = relu;
  s.inputs = std::move(inputs);
  return s;
}
LayerSpec upsample(std::string name, std::string input, std::string match) {
  LayerSpec s;
  s.name = std::move(name);
  s.type = "upsample";
  s.inputs = {std::move(input)};
  s.match = std::move(match);
  return s;
}
LayerSpec dropout(std::string name, double rate) {
  LayerSpec s;
  s.name = std::move(name);
  s.type = "dropout";
  s.rate = rate;
  return s;
}
}  // namespace

ArchSpec default_arch(int out_channels, double drop) {
  ArchSpec a;
  a.name = "unet-small";
  a.layers.push_back(conv("e1", 16, 1, true, {"input"}));
  a.layers.push_back(conv("e2", 32, 2, true));
  a.layers.push_back(conv("e3", 32, 2, true));
  std::string bottom = "e3";
  if (drop > 0.0) {
    a.layers.push_back(dropout("drop", drop));
    bottom = "drop";
  }
  a.layers.push_back(upsample("u2", bottom, "e2"));
  a.layers.push_back(conv("d2", 32, 1, true, {"u2", "e2"}));
  a.layers.push_back(upsample("u1", "d2", "e1"));
  a.layers.push_back(conv("d1", 16, 1, true, {"u1", "e1"}));
  a.layers.push_back(conv("out", out_channels, 1, false));
  return a;
}

ArchSpec seed_dense_arch(int out_channels, int out_h, int out_w, double drop) {
  ArchSpec a;
  a.name = "seed-dense";
  a.layers.push_back(conv("c1", 32, 2, true, {"input"}));
  a.layers.push_back(conv("c2", 32, 2, true));
  if (drop > 0.0) a.layers.push_back(dropout("drop", drop));
  LayerSpec d;
  d.name = "head";
  d.type = "dense";
  d.out_shape = {out_channels, out_h, out_w};
  a.layers.push_back(d);
  return a;
}

bool is_builtin_arch(const std::string& name) { return name.empty() || name == "default" || name == "seed-dense"; }

ArchSpec select_arch(const std::string& name, int out_channels, int out_h, int out_w, double dropout) {
  if (name.empty() || name == "default") return default_arch(out_channels, dropout);
  if (name == "seed-dense") return seed_dense_arch(out_channels, out_h, out_w, dropout);
  if (!std::filesystem::exists(name))
    throw ConfigError("--arch '" + name + "': not 'default', 'seed-dense' or an existing TOML file");
  return ArchSpec::load(name);
}

}  // namespace dc
