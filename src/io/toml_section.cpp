#include "clearshape/io/toml_section.hpp"

#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::io {

toml::table parse_toml(std::string_view text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(file, static_cast<std::size_t>(e.source().begin.line), "", std::string(e.description()));
  }
}

std::size_t line_of(const toml::node& node) noexcept {
  return static_cast<std::size_t>(node.source().begin.line);
}

TomlSection::TomlSection(const toml::table& table, std::string path, std::string file)
    : table_(&table), path_(std::move(path)), file_(std::move(file)), line_(line_of(table)) {}

std::string TomlSection::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

void TomlSection::fail(std::string_view key, const std::string& problem) const {
  const toml::node* n = key.empty() ? nullptr : table_->get(key);
  throw InputError(file_, n ? line_of(*n) : line_, key.empty() ? path_ : key_path(key), problem);
}

bool TomlSection::has(std::string_view key) const { return table_->contains(key); }

const toml::node* TomlSection::node(std::string_view key) const {
  const toml::node* n = table_->get(key);
  if (n) read_.emplace(key);
  return n;
}

const toml::node& TomlSection::require(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) fail(key, fmt::format("missing key '{}' in [{}]", key, path_.empty() ? "top level" : path_));
  return *n;
}

double TomlSection::number(std::string_view key) const {
  const toml::node& n = require(key);
  if (!(n.is_integer() || n.is_floating_point())) fail(key, "must be a number");
  const double v = *n.value<double>();
  if (!std::isfinite(v)) fail(key, "must be a finite number");
  return v;
}

double TomlSection::number(std::string_view key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

double TomlSection::positive(std::string_view key, double fallback) const {
  const double v = number(key, fallback);
  if (!(v > 0.0)) fail(key, fmt::format("= {} is out of range; allowed: > 0", v));
  return v;
}

std::int64_t TomlSection::integer(std::string_view key, std::int64_t fallback, std::int64_t lo,
                                  std::int64_t hi) const {
  if (!has(key)) return fallback;
  const toml::node& n = require(key);
  if (!n.is_integer()) fail(key, "must be an integer");
  const std::int64_t v = *n.value<std::int64_t>();
  if (v < lo || v > hi) fail(key, fmt::format("= {} is out of range; allowed: {} … {}", v, lo, hi));
  return v;
}

bool TomlSection::boolean(std::string_view key, bool fallback) const {
  if (!has(key)) return fallback;
  const toml::node& n = require(key);
  if (!n.is_boolean()) fail(key, "must be true or false");
  return *n.value<bool>();
}

std::string TomlSection::text(std::string_view key) const {
  const toml::node& n = require(key);
  if (!n.is_string()) fail(key, "must be a string");
  return *n.value<std::string>();
}

std::string TomlSection::text(std::string_view key, std::string fallback) const {
  return has(key) ? text(key) : std::move(fallback);
}

std::vector<std::string> TomlSection::texts(std::string_view key) const {
  std::vector<std::string> out;
  if (!has(key)) return out;
  const toml::node& n = require(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, "must be an array of strings");
  for (const auto& item : *a) {
    if (!item.is_string()) fail(key, "must be an array of strings");
    out.push_back(*item.value<std::string>());
  }
  return out;
}

std::vector<double> TomlSection::numbers(std::string_view key) const {
  std::vector<double> out;
  if (!has(key)) return out;
  const toml::node& n = require(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, "must be an array of numbers");
  for (const auto& item : *a) {
    if (!(item.is_integer() || item.is_floating_point())) fail(key, "must be an array of numbers");
    const double v = *item.value<double>();
    if (!std::isfinite(v)) fail(key, "must hold finite numbers");
    out.push_back(v);
  }
  return out;
}

std::optional<TomlSection> TomlSection::table(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  const toml::node& n = require(key);
  const toml::table* t = n.as_table();
  if (!t) fail(key, "must be a table");
  return TomlSection(*t, key_path(key), file_);
}

std::vector<TomlSection> TomlSection::tables(std::string_view key) const {
  std::vector<TomlSection> out;
  if (!has(key)) return out;
  const toml::node& n = require(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, fmt::format("must be an array of tables ([[{}]])", key_path(key)));
  std::size_t i = 0;
  for (const auto& item : *a) {
    const toml::table* t = item.as_table();
    if (!t) fail(key, fmt::format("must be an array of tables ([[{}]])", key_path(key)));
    out.emplace_back(*t, fmt::format("{}[{}]", key_path(key), i++), file_);
  }
  return out;
}

std::vector<std::string> TomlSection::keys() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : *table_) {
    out.emplace_back(k.str());
    read_.emplace(k.str());
  }
  return out;
}

void TomlSection::finish(std::string_view allowed) const {
  for (const auto& [k, v] : *table_) {
    if (read_.count(k.str()) == 0) {
      throw InputError(file_, line_of(v), key_path(k.str()),
                       allowed.empty() ? std::string("unknown key")
                                       : fmt::format("unknown key; allowed here: {}", allowed));
    }
  }
}

}  // namespace clearshape::io
