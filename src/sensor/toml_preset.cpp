/// \file
/// \brief User sensor presets from TOML (toml++), with `FILE:LINE:COL` in every error.
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::sensor {
namespace {

source_location where(std::string_view file, const toml::source_region& r) {
  return {file, r.begin.line, r.begin.column};
}

std::string toml_error_text(const toml::parse_error& e) {
  return std::string(e.description());
}

}  // namespace

result<preset> parse_toml_preset(std::string_view text, std::string_view file) {
  toml::table tbl;
  try {
    tbl = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    return input_error(where(file, e.source()), toml_error_text(e));
  }
  preset out;
  out.name = std::string(file);
  if (const auto* base = tbl.get("base")) {
    const auto* name = base->as_string();
    const preset* b = name != nullptr ? find_builtin(name->get()) : nullptr;
    if (b == nullptr) {
      return input_error(where(file, base->source()),
                         "base: must be the name of a built-in preset (adxrs150, hz1-90-100a)");
    }
    out = *b;
  }
  for (const auto& [key, node] : tbl) {
    const auto loc = where(file, key.source());
    const std::string_view k = key.str();
    if (k == "base") continue;
    if (k == "name" || k == "description") {
      const auto* s = node.as_string();
      if (s == nullptr) return input_error(loc, fmt::format("{}: must be a string", k));
      (k == "name" ? out.name : out.description) = s->get();
      continue;
    }
    const auto* f = find_field(k);
    if (f == nullptr) return input_error(loc, fmt::format("unknown key '{}'", printable(k, 60)));
    const auto v = node.value<double>();  // integers are accepted as numbers too
    if (!v || !(node.is_floating_point() || node.is_integer())) {
      return input_error(loc, fmt::format("{}: must be a number ({})", k, f->unit));
    }
    if (!std::isfinite(*v) || *v < f->min_value || *v > f->max_value) {
      return input_error(loc, fmt::format("{} = {}: must be within [{}, {}] {}", k, *v,
                                          f->min_value, f->max_value, f->unit));
    }
    out.params.*f->member = *v;
    std::string src = fmt::format("{}:{}", file, loc.line);
    bool replaced = false;
    for (auto& [sk, sv] : out.sources) {
      if (sk == k) {
        sv = src;
        replaced = true;
      }
    }
    if (!replaced) out.sources.emplace_back(std::string(k), std::move(src));
  }
  if (auto s = validate(out.params); !s) {
    const auto* node = tbl.get("flicker_tau_max_s");
    return input_error(node != nullptr ? where(file, node->source()) : source_location{file},
                       s.err().message);
  }
  // A preset names itself and says every figure, directly or through its base: a file that
  // forgot them (an empty file, a wrong file) must not become a silent noise-free sensor.
  if (tbl.get("name") == nullptr)
    return input_error({file},
                       "a preset needs name = \"...\" (and base = \"adxrs150\" or "
                       "\"hz1-90-100a\", or every parameter)");
  if (tbl.get("base") == nullptr) {
    std::vector<std::string_view> missing;
    for (const auto& f : fields())
      if (tbl.get(f.key) == nullptr) missing.push_back(f.key);
    if (!missing.empty())
      return input_error(
          {file}, fmt::format("no base preset, so every parameter must be given; missing: {} (or "
                              "start from a built-in one: base = \"hz1-90-100a\")",
                              fmt::join(missing, ", ")));
  }
  return out;
}

result<preset> load_preset(std::string_view name_or_file) {
  if (const preset* p = find_builtin(name_or_file)) return *p;
  const std::string path(name_or_file);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return io_error(path, fmt::format("cannot open: {} (and not a built-in sensor: adxrs150, "
                                      "hz1-90-100a)",
                                      std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) return io_error(path, "not a regular file (expected a TOML preset)");
  std::ifstream in(path, std::ios::binary);
  if (!in) return io_error(path, fmt::format("cannot open: {}", std::strerror(errno)));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_toml_preset(ss.str(), path);
}

}  // namespace gyroflip::sensor
