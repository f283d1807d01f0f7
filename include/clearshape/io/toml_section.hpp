#pragma once
// Strict typed access to a toml++ table: every key read is remembered, finish() rejects the
// rest; every error is an InputError naming the file, the line and the key path
// (docs/design.md §4). Used by the study protocol, the recordings manifest and the arm's TOML.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace clearshape::io {

std::size_t line_of(const toml::node& node) noexcept;

/// `text` parsed as TOML; a syntax error is an InputError naming `file` and the line.
toml::table parse_toml(std::string_view text, const std::string& file);

class TomlSection {
 public:
  /// `path` is the key path of the table ("" for the root, "study", "input[2]", …).
  TomlSection(const toml::table& table, std::string path, std::string file);

  bool has(std::string_view key) const;
  double number(std::string_view key) const;
  double number(std::string_view key, double fallback) const;
  double positive(std::string_view key, double fallback) const;
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string text(std::string_view key) const;
  std::string text(std::string_view key, std::string fallback) const;
  std::vector<std::string> texts(std::string_view key) const;
  std::vector<double> numbers(std::string_view key) const;
  const toml::node* node(std::string_view key) const;
  std::optional<TomlSection> table(std::string_view key) const;
  /// An array of tables ([[key]]); empty if absent.
  std::vector<TomlSection> tables(std::string_view key) const;
  /// Every key of the table (marks them all as read).
  std::vector<std::string> keys() const;

  /// Throws InputError for a key that was never read, listing `allowed` when given.
  void finish(std::string_view allowed = {}) const;

  [[noreturn]] void fail(std::string_view key, const std::string& problem) const;
  std::string key_path(std::string_view key) const;
  std::size_t line() const noexcept { return line_; }
  const std::string& file() const noexcept { return file_; }
  const toml::table& raw() const noexcept { return *table_; }

 private:
  const toml::node& require(std::string_view key) const;
  const toml::table* table_;
  std::string path_;
  std::string file_;
  std::size_t line_;
  mutable std::set<std::string, std::less<>> read_;
};

}  // namespace clearshape::io
