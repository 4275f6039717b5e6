#pragma once
// Typed reading of TOML input files (over toml11) with errors a user can act on.
//
// Every error names the file, line and column, the key as a dotted path (e.g. "beam.section[2].A") and
// what was expected (a type, a range, one of a list). Each Table remembers which keys the reader asked
// for; finish() then reports any other key as unknown, with a did-you-mean among the known ones.
//
//   auto doc = nvh::input::Document::load("crank.toml");
//   auto beam = doc.root().table("beam");
//   double A = section.number("A", nvh::input::Range::positive());
//   beam.finish();
#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.hpp"

namespace nvh::input {

/// An accepted interval for a number: (lo, hi) with each end open or closed; defaults to all finite reals.
///
/// Every range is finite by default: NaN, +inf and -inf are refused whatever the bounds (an infinite
/// stiffness, clearance or sample rate never means what its writer hoped; it ends as NaN results or a run
/// without end), and so are subnormal numbers (0 < |x| < 2.2e-308: no SI quantity of a machine is that small,
/// and such a value overflows as soon as it divides). allow_infinite() lets +-inf through for a key that
/// gives infinity a meaning (none does today).
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  bool infinite_allowed = false;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
  static Range at_most(double hi) { return {-std::numeric_limits<double>::infinity(), hi, false, false}; }
  /// |x| <= bound.
  static Range magnitude(double bound) { return closed(-bound, bound); }
  /// The same range, accepting +-inf where the bounds do.
  Range allow_infinite() const {
    Range r = *this;
    r.infinite_allowed = true;
    return r;
  }

  bool contains(double x) const;
  /// e.g. "a number > 0", "a number in [0, 0.5)"
  std::string describe() const;
  /// Why `x` is refused beyond the bounds ("numbers must be finite", ...), or "" if only the bounds refuse
  /// it.
  std::string refusal(double x) const;
};

class Table;

/// Limits a file must keep before toml11 parses it (checked by a cheap scan of the text; docs/cli.md):
/// toml11's parser recurses once per level of nested arrays and inline tables, so a file of a few KB such as
/// `a = [[[[...` overflows the stack; and its time grows with the square of a line's length (100k numbers on
/// one line take 12 s, the same numbers one per line 0.14 s). No real input comes near either limit.
inline constexpr int kMaxNesting = 64;                ///< levels of [ and { (outside strings and comments)
inline constexpr std::size_t kMaxLineLength = 65536;  ///< bytes on one line

/// A parsed TOML file. Owns the parsed tree; Tables refer into it and must not outlive it.
class Document {
 public:
  /// Parse a file; a syntax error (or a file beyond kMaxNesting / kMaxLineLength) becomes nvh::Error with
  /// file, line and column.
  static Document load(const std::filesystem::path& path);
  /// Parse text (tests); `name` stands for the file name in messages.
  static Document parse(const std::string& text, const std::string& name);

  Document(Document&&) noexcept;
  Document& operator=(Document&&) noexcept;
  ~Document();

  Table root() const;
  const std::string& file_name() const;

 private:
  struct Impl;
  Document() = default;
  std::unique_ptr<Impl> impl_;
};

/// A view of one TOML table. Getters record the key as known; finish() reports unknown keys.
/// Copies share the record of known keys.
class Table {
 public:
  /// Dotted path of this table, e.g. "beam.section[2]" ("" for the root).
  const std::string& path() const;
  /// Location of the table (its header, or its first key) for messages about missing keys.
  SourceLocation location() const;
  /// Location of a key's value (the table's location if the key is missing).
  SourceLocation location(std::string_view key) const;
  bool has(std::string_view key) const;

  // --- scalars: required (error if missing) and optional; integers are accepted where numbers are ---
  double number(std::string_view key, const Range& range = {}) const;
  std::optional<double> optional_number(std::string_view key, const Range& range = {}) const;
  double number_or(std::string_view key, double fallback, const Range& range = {}) const;
  std::int64_t integer(std::string_view key, const Range& range = {}) const;
  std::optional<std::int64_t> optional_integer(std::string_view key, const Range& range = {}) const;
  bool boolean(std::string_view key) const;
  std::optional<bool> optional_boolean(std::string_view key) const;
  std::string string(std::string_view key) const;
  std::optional<std::string> optional_string(std::string_view key) const;
  /// A name that becomes part of an HDF5 path in an output file (a body, marker, element, interface): 1 to 128
  /// bytes, no control character, no '/' (the path separator), not "." or "..". Error otherwise.
  std::string name(std::string_view key) const;
  /// A string that must be one of `choices` (error lists them, with a did-you-mean).
  std::string choice(std::string_view key, const std::vector<std::string>& choices) const;
  std::optional<std::string> optional_choice(std::string_view key,
                                             const std::vector<std::string>& choices) const;

  // --- arrays ---
  std::vector<double> numbers(std::string_view key, const Range& range = {}) const;
  std::vector<std::int64_t> integers(std::string_view key, const Range& range = {}) const;
  std::vector<std::string> strings(std::string_view key) const;
  /// Exactly three numbers: a point or a direction in m (or as the key says).
  /// Each component must lie in `range` (finite by default).
  std::array<double, 3> vec3(std::string_view key, const Range& range = {}) const;
  std::optional<std::array<double, 3>> optional_vec3(std::string_view key, const Range& range = {}) const;
  /// An array of 3-vectors: [[x,y,z], ...].
  std::vector<std::array<double, 3>> vec3_list(std::string_view key, const Range& range = {}) const;
  /// An array of rows of exactly `columns` numbers: [[x, y], ...] (tables, matrices).
  std::vector<std::vector<double>> number_rows(std::string_view key, std::size_t columns,
                                               const Range& range = {}) const;

  // --- nested tables ---
  Table table(std::string_view key) const;
  std::optional<Table> optional_table(std::string_view key) const;
  /// An array of tables ([[key]]); empty if the key is absent. Element paths are "key[1]", "key[2]", ...
  std::vector<Table> table_array(std::string_view key) const;
  /// Keys of this table whose values are tables (e.g. the names under [material]); marks them known.
  std::vector<std::string> table_keys() const;

  /// Error if this table holds a key no getter asked for: "unknown key 'Iyy' (did you mean 'Iy'?)".
  /// Also lists the accepted keys. Call after all getters.
  void finish() const;

  /// Throw nvh::Error located at `key` (or at the table if the key is missing) with `message`.
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  /// Throw nvh::Error located at the table itself.
  [[noreturn]] void fail(const std::string& message) const;

  /// Mark a key as known without reading it (for keys handled elsewhere).
  void accept(std::string_view key) const;

 private:
  friend class Document;
  struct Impl;
  explicit Table(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

/// Levenshtein distance; used for did-you-mean suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// The closest candidate within a small distance, or "" if none is close.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace nvh::input
