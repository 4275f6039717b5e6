#include "common/input.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <toml.hpp>
#include <tuple>
#include <utility>

namespace nvh::input {

namespace detail {

/// What a Document and all its Tables share: the parsed tree, the file name, and one record of known keys
/// per TOML table (so two Table views of the same table, e.g. from two calls of table("beam"), agree).
struct Shared {
  toml::value root;
  std::string file;
  std::map<const toml::value*, std::shared_ptr<std::set<std::string>>> known;

  std::shared_ptr<std::set<std::string>> known_keys_of(const toml::value* table) {
    auto& keys = known[table];
    if (!keys) keys = std::make_shared<std::set<std::string>>();
    return keys;
  }
};

}  // namespace detail

namespace {

// ---------------------------------------------------------------------------------------------------------
// Text helpers

/// Shortest text that reads back as the same double ("0.5", "-0.0031", "1e-09", "inf").
std::string format_double(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

/// A floating-point value as the user would recognise it: "3.0" rather than "3".
std::string format_float_value(double x) {
  std::string text = format_double(x);
  if (std::isfinite(x) && text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

std::string quote(std::string_view text) {
  constexpr std::size_t kMaxShown = 60;
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const char c = text[i];
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      out += c;
    }
  }
  if (text.size() > kMaxShown) out += "...";
  return out + "\"";
}

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

/// A key as written in TOML: bare if possible, else quoted.
std::string key_text(std::string_view key) {
  return is_bare_key(key) ? std::string(key) : quote(key);
}

std::string join(const std::string& path, std::string_view key) {
  return path.empty() ? key_text(key) : path + "." + key_text(key);
}

std::string indexed(const std::string& path, std::size_t zero_based) {
  return path + "[" + std::to_string(zero_based + 1) + "]";
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string plural(std::size_t n, const char* singular, const char* plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

/// What a value is, for "got ...": "a string \"abc\"", "an integer 3", "a table", ...
std::string describe(const toml::value& v) {
  std::ostringstream out;
  switch (v.type()) {
    case toml::value_t::boolean:
      out << "a boolean " << (v.as_boolean() ? "true" : "false");
      break;
    case toml::value_t::integer:
      out << "an integer " << v.as_integer();
      break;
    case toml::value_t::floating:
      out << "a number " << format_float_value(v.as_floating());
      break;
    case toml::value_t::string:
      out << "a string " << quote(v.as_string().str);
      break;
    case toml::value_t::offset_datetime:
      out << "a date-time " << v.as_offset_datetime();
      break;
    case toml::value_t::local_datetime:
      out << "a date-time " << v.as_local_datetime();
      break;
    case toml::value_t::local_date:
      out << "a date " << v.as_local_date();
      break;
    case toml::value_t::local_time:
      out << "a time " << v.as_local_time();
      break;
    case toml::value_t::array: {
      const auto n = v.as_array().size();
      if (n == 0) {
        out << "an empty array";
      } else {
        out << "an array of " << plural(n, "value", "values");
      }
      break;
    }
    case toml::value_t::table:
      out << "a table";
      break;
    default:
      out << "nothing";
      break;
  }
  return out.str();
}

/// A number's text for range messages: "-0.0031", "7", "3.0".
std::string number_text(const toml::value& v) {
  return v.is_integer() ? std::to_string(v.as_integer()) : format_float_value(v.as_floating());
}

std::string one_of(const std::vector<std::string>& choices) {
  std::string out = "one of ";
  for (std::size_t i = 0; i < choices.size(); ++i) out += (i ? ", " : "") + quote(choices[i]);
  return out;
}

std::string integer_description(const Range& range) {
  // Range::describe() starts with "a number"; integers read better as "an integer > 0".
  const std::string text = range.describe();
  const std::string prefix = "a number";
  return "an integer" + (text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : " " + text);
}

constexpr const char* kVec3 = "3 numbers [x, y, z]";

// ---------------------------------------------------------------------------------------------------------
// toml11 syntax errors -> nvh::Error

std::string strip_ansi(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\x1b' && i + 1 < text.size() && text[i + 1] == '[') {
      i += 2;
      while (i < text.size() && !std::isalpha(static_cast<unsigned char>(text[i]))) ++i;
      continue;
    }
    out += text[i];
  }
  return out;
}

std::string trim(std::string text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

/// toml11 v3 formats a syntax error as
///   [error] toml::parse_xxx: what went wrong
///    --> file.toml
///      |
///    2 | b =
///      |     ^--- expected value, but got nothing
/// possibly with several " N | ..." blocks (the last one is the offending spot) and "Hint:" lines.
/// Read the headline, the last location and its comment from that text.
Error syntax_error_to_error(const toml::exception& e, const std::string& file) {
  const std::string text = strip_ansi(e.what());
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }

  std::string headline = lines.empty() ? std::string() : lines.front();
  if (headline.rfind("[error]", 0) == 0) headline = headline.substr(7);
  headline = trim(headline);
  if (headline.rfind("toml::", 0) == 0) {
    const auto colon = headline.find(": ");
    headline = colon == std::string::npos ? std::string() : headline.substr(colon + 2);
  }
  headline = trim(headline);
  while (!headline.empty() && headline.back() == '.') headline.pop_back();

  int line_number = static_cast<int>(e.location().line());
  int column = static_cast<int>(e.location().column());
  std::string comment;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    // " 12 | source line" followed by "    |     ^--- comment"
    const std::string& source = lines[i];
    const auto digits_begin = source.find_first_not_of(' ');
    if (digits_begin == std::string::npos || !std::isdigit(static_cast<unsigned char>(source[digits_begin])))
      continue;
    const auto digits_end = source.find_first_not_of("0123456789", digits_begin);
    if (digits_end == std::string::npos || source.compare(digits_end, 3, " | ") != 0) continue;
    const std::string& marker_line = lines[i + 1];
    const auto bar = marker_line.find('|');
    if (bar == std::string::npos || marker_line.find_first_not_of(' ') != bar) continue;
    const std::string rest = bar + 2 <= marker_line.size() ? marker_line.substr(bar + 2) : std::string();
    const auto marker = rest.find_first_not_of(' ');
    if (marker == std::string::npos) continue;
    line_number = std::stoi(source.substr(digits_begin, digits_end - digits_begin));
    column = static_cast<int>(marker) + 1;
    const auto after_marker = rest.find_first_not_of("^-~", marker);
    comment = after_marker == std::string::npos ? std::string() : trim(rest.substr(after_marker));
    ++i;
  }

  while (!comment.empty() && comment.back() == '.') comment.pop_back();
  if (comment == "here") comment.clear();  // says nothing the location does not

  std::string message = "invalid TOML";
  if (!headline.empty()) message += ": " + headline;
  if (!comment.empty()) message += headline.empty() ? ": " + comment : " (" + comment + ")";
  return Error(message, SourceLocation{file, line_number, column}, "");
}

// ---------------------------------------------------------------------------------------------------------
// Limits checked before toml11 sees the text (kMaxNesting, kMaxLineLength in input.hpp)

/// Refuse arrays and inline tables nested deeper than kMaxNesting, dotted keys of more than kMaxNesting parts
/// and lines longer than kMaxLineLength, in one linear pass: toml11 would overflow the stack on the first two
/// and take quadratic time on the third. The scan follows TOML's strings and comments only as far as
/// brackets, dots and line ends need it: a [, { or . inside "...", '...', """...""", '''...''' or a comment
/// does not count, nor does a dot in a value (1.5). It never refuses a valid file within the limits; anything
/// else wrong is left to toml11, which reports it with its location.
void check_limits(const std::string& text, const std::string& name) {
  enum class State { kCode, kBasic, kLiteral, kMultiBasic, kMultiLiteral, kComment };
  State state = State::kCode;
  std::vector<char> open;  // the enclosing '[' (array) and '{' (inline table) of the value being read
  bool in_key = true;      // reading a key (or a [table] header) rather than a value
  int key_parts = 1;
  int line = 1;
  std::size_t line_start = 0;
  const std::size_t n = text.size();
  auto at = [&](std::size_t i) { return SourceLocation{name, line, static_cast<int>(i - line_start) + 1}; };
  auto starts = [&](std::size_t i, char quote) {
    return i + 2 < n && text[i] == quote && text[i + 1] == quote && text[i + 2] == quote;
  };
  auto check_line = [&](std::size_t end) {
    if (end - line_start <= kMaxLineLength) return;
    throw Error("a line of " + std::to_string(end - line_start) + " bytes; the limit is " +
                    std::to_string(kMaxLineLength) +
                    " bytes per line (the TOML parser's time grows with the square of a line's length): "
                    "split long arrays over several lines",
                SourceLocation{name, line, 1}, "");
  };
  auto start_key = [&] {
    in_key = true;
    key_parts = 1;
  };
  // The closing delimiter of a multi-line string may be followed by up to two quotes of its content.
  auto close_multi = [&](std::size_t& i, char quote) {
    i += 2;
    for (int extra = 0; extra < 2 && i + 1 < n && text[i + 1] == quote; ++extra) ++i;
    state = State::kCode;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '\n') {
      check_line(i);
      ++line;
      line_start = i + 1;
      // A comment ends here; so does a single-line string (unterminated: toml11 says so).
      if (state == State::kComment || state == State::kBasic || state == State::kLiteral)
        state = State::kCode;
      if (state == State::kCode && open.empty()) start_key();  // outside an array a line starts with a key
      continue;
    }
    switch (state) {
      case State::kCode:
        if (c == '#') {
          state = State::kComment;
        } else if (c == '"') {
          state = starts(i, '"') ? (i += 2, State::kMultiBasic) : State::kBasic;
        } else if (c == '\'') {
          state = starts(i, '\'') ? (i += 2, State::kMultiLiteral) : State::kLiteral;
        } else if (in_key) {
          if (c == '.' && ++key_parts > kMaxNesting) {
            throw Error("a dotted key of more than " + std::to_string(kMaxNesting) +
                            " parts (the limit of this reader)",
                        at(i), "");
          }
          if (c == '=' || c == ']') in_key = false;  // the value follows, or the [header] ends
          if (c == '}' && !open.empty()) {           // an empty inline table {}
            open.pop_back();
            in_key = false;
          }
        } else if (c == '[' || c == '{') {
          open.push_back(c);
          if (static_cast<int>(open.size()) > kMaxNesting) {
            throw Error("arrays and inline tables nested deeper than " + std::to_string(kMaxNesting) +
                            " levels (the limit of this reader)",
                        at(i), "");
          }
          if (c == '{') start_key();
        } else if ((c == ']' || c == '}') && !open.empty()) {
          open.pop_back();
        } else if (c == ',' && !open.empty() && open.back() == '{') {
          start_key();
        }
        break;
      case State::kBasic:
      case State::kMultiBasic:
        if (c == '\\') {
          if (i + 1 < n && text[i + 1] != '\n') ++i;  // an escaped character (a line-ending backslash stays)
        } else if (state == State::kBasic && c == '"') {
          state = State::kCode;
        } else if (state == State::kMultiBasic && starts(i, '"')) {
          close_multi(i, '"');
        }
        break;
      case State::kLiteral:
        if (c == '\'') state = State::kCode;
        break;
      case State::kMultiLiteral:
        if (starts(i, '\'')) close_multi(i, '\'');
        break;
      case State::kComment:
        break;
    }
  }
  check_line(n);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Range

namespace {
bool subnormal(double x) {
  return x != 0.0 && std::abs(x) < std::numeric_limits<double>::min();
}
}  // namespace

bool Range::contains(double x) const {
  if (std::isnan(x) || subnormal(x)) return false;
  if (std::isinf(x) && !infinite_allowed) return false;
  const bool above = lo_open ? x > lo : x >= lo;
  const bool below = hi_open ? x < hi : x <= hi;
  return above && below;
}

std::string Range::describe() const {
  const bool no_lo = std::isinf(lo) && lo < 0;
  const bool no_hi = std::isinf(hi) && hi > 0;
  if (no_lo && no_hi) return "a number";
  if (no_hi) return std::string("a number ") + (lo_open ? "> " : ">= ") + format_double(lo);
  if (no_lo) return std::string("a number ") + (hi_open ? "< " : "<= ") + format_double(hi);
  return std::string("a number in ") + (lo_open ? "(" : "[") + format_double(lo) + ", " + format_double(hi) +
         (hi_open ? ")" : "]");
}

std::string Range::refusal(double x) const {
  if (std::isnan(x)) return "numbers must be finite";
  if (std::isinf(x) && !infinite_allowed) return "numbers must be finite";
  if (subnormal(x))
    return "a subnormal number, below the smallest normal double 2.2e-308 in magnitude: write 0 or a "
           "physical value";
  return "";
}

// ---------------------------------------------------------------------------------------------------------
// Table::Impl: a pointer into the shared tree, the table's path, and its record of known keys.

struct Table::Impl {
  std::shared_ptr<detail::Shared> shared;
  const toml::value* value = nullptr;  // always a table
  std::string path;
  std::shared_ptr<std::set<std::string>> known;

  static Table make(std::shared_ptr<detail::Shared> shared, const toml::value* value, std::string path) {
    auto impl = std::make_shared<Impl>();
    impl->known = shared->known_keys_of(value);
    impl->shared = std::move(shared);
    impl->value = value;
    impl->path = std::move(path);
    return Table(std::move(impl));
  }

  Table child(const toml::value& v, std::string child_path) const {
    return make(shared, &v, std::move(child_path));
  }

  const toml::table& table() const { return value->as_table(); }

  const toml::value* find(std::string_view key) const {
    const auto it = table().find(std::string(key));
    return it == table().end() ? nullptr : &it->second;
  }

  /// Find a key and record it as known (whether or not it is there).
  const toml::value* lookup(std::string_view key) const {
    known->insert(std::string(key));
    return find(key);
  }

  std::string key_path(std::string_view key) const { return join(path, key); }

  SourceLocation where(const toml::value& v) const {
    const toml::source_location loc = v.location();
    return {shared->file, static_cast<int>(loc.line()), static_cast<int>(loc.column())};
  }

  SourceLocation table_where() const {
    if (!path.empty()) return where(*value);
    // The root has no header: use its first key (the earliest value in the file).
    SourceLocation first{shared->file, 0, 0};
    for (const auto& [key, v] : table()) {
      const SourceLocation loc = where(v);
      if (first.line == 0 || std::tie(loc.line, loc.column) < std::tie(first.line, first.column)) first = loc;
    }
    if (first.line == 0) first = {shared->file, 1, 1};
    return first;
  }

  [[noreturn]] void fail_at(const toml::value& v, const std::string& key_path_text,
                            const std::string& message) const {
    throw Error(message, where(v), key_path_text);
  }

  [[noreturn]] void missing(std::string_view key, const std::string& expected) const {
    // A misspelt key is the usual cause: point at the closest key nobody asked for, if there is one.
    // Only a key that contains the missing one (or the reverse) counts: "Iyy" for "Iy", not "Iz",
    // which is likely a valid key not yet read.
    std::string near;
    auto lower = [](std::string_view t) {
      std::string out(t);
      for (char& ch : out) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      return out;
    };
    const std::string wanted = lower(key);
    for (const auto& [name, v] : table()) {
      if (known->count(name)) continue;
      const std::string candidate = lower(name);
      if (candidate.find(wanted) != std::string::npos || wanted.find(candidate) != std::string::npos) {
        near = name;
        break;
      }
    }
    if (!near.empty()) {
      throw Error("missing required key (expected " + expected + "); found unknown key '" + near +
                      "' - did you mean '" + std::string(key) + "'?",
                  where(table().at(near)), key_path(key));
    }
    throw Error("missing required key (expected " + expected + ")", table_where(), key_path(key));
  }

  // --- conversions of one value; `kp` is the value's key path for messages ---

  double to_number(const toml::value& v, const std::string& kp, const Range& range) const {
    double x = 0.0;
    if (v.is_integer()) {
      x = static_cast<double>(v.as_integer());
    } else if (v.is_floating()) {
      x = v.as_floating();
    } else {
      fail_at(v, kp, "expected " + range.describe() + ", got " + describe(v));
    }
    if (!range.contains(x)) {
      const std::string why = range.refusal(x);
      fail_at(
          v, kp,
          "expected " + range.describe() + ", got " + number_text(v) + (why.empty() ? "" : " (" + why + ")"));
    }
    return x;
  }

  std::int64_t to_integer(const toml::value& v, const std::string& kp, const Range& range) const {
    if (!v.is_integer()) fail_at(v, kp, "expected " + integer_description(range) + ", got " + describe(v));
    const std::int64_t n = v.as_integer();
    if (!range.contains(static_cast<double>(n)))
      fail_at(v, kp, "expected " + integer_description(range) + ", got " + std::to_string(n));
    return n;
  }

  bool to_boolean(const toml::value& v, const std::string& kp) const {
    if (!v.is_boolean()) fail_at(v, kp, "expected a boolean (true or false), got " + describe(v));
    return v.as_boolean();
  }

  std::string to_string(const toml::value& v, const std::string& kp) const {
    if (!v.is_string()) fail_at(v, kp, "expected a string, got " + describe(v));
    return v.as_string().str;
  }

  std::string to_choice(const toml::value& v, const std::string& kp,
                        const std::vector<std::string>& choices) const {
    if (!v.is_string()) fail_at(v, kp, "expected " + one_of(choices) + ", got " + describe(v));
    const std::string& s = v.as_string().str;
    if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
    std::string message = "expected " + one_of(choices) + ", got " + quote(s);
    if (const std::string guess = closest(s, choices); !guess.empty())
      message += " (did you mean " + quote(guess) + "?)";
    fail_at(v, kp, message);
  }

  const toml::array& to_array(const toml::value& v, const std::string& kp,
                              const std::string& expected) const {
    if (!v.is_array()) fail_at(v, kp, "expected " + expected + ", got " + describe(v));
    return v.as_array();
  }

  std::array<double, 3> to_vec3(const toml::value& v, const std::string& kp, const Range& range) const {
    const auto& a = to_array(v, kp, kVec3);
    if (a.size() != 3) fail_at(v, kp, std::string("expected ") + kVec3 + ", got " + std::to_string(a.size()));
    std::array<double, 3> out{};
    for (std::size_t i = 0; i < 3; ++i) out[i] = to_number(a[i], indexed(kp, i), range);
    return out;
  }
};

// ---------------------------------------------------------------------------------------------------------
// Document

struct Document::Impl {
  std::shared_ptr<detail::Shared> shared;
};

Document::Document(Document&&) noexcept = default;
Document& Document::operator=(Document&&) noexcept = default;
Document::~Document() = default;

Document Document::parse(const std::string& text, const std::string& name) {
  check_limits(text, name);
  auto shared = std::make_shared<detail::Shared>();
  shared->file = name;
  std::istringstream in(text);
  try {
    shared->root = toml::parse(in, name);
  } catch (const toml::exception& e) {
    throw syntax_error_to_error(e, name);
  } catch (const std::exception& e) {
    // toml11 reports a few problems (e.g. integer overflow) as standard exceptions.
    throw Error(std::string("invalid TOML: ") + e.what(), SourceLocation{name, 0, 0}, "");
  }
  if (!shared->root.is_table())
    throw Error("invalid TOML: the file is not a table", SourceLocation{name, 1, 1}, "");
  Document doc;
  doc.impl_ = std::make_unique<Impl>();
  doc.impl_->shared = std::move(shared);
  return doc;
}

Document Document::load(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read the input file: it is a directory", SourceLocation{name, 0, 0}, "");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int code = errno;
    throw Error(
        std::string("cannot open the input file (") + (code ? std::strerror(code) : "unknown reason") + ")",
        SourceLocation{name, 0, 0}, "");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("cannot read the input file (I/O error)", SourceLocation{name, 0, 0}, "");
  return parse(text.str(), name);
}

Table Document::root() const {
  return Table::Impl::make(impl_->shared, &impl_->shared->root, "");
}

const std::string& Document::file_name() const {
  return impl_->shared->file;
}

// ---------------------------------------------------------------------------------------------------------
// Table

const std::string& Table::path() const {
  return impl_->path;
}

SourceLocation Table::location() const {
  return impl_->table_where();
}

SourceLocation Table::location(std::string_view key) const {
  const toml::value* v = impl_->find(key);
  return v ? impl_->where(*v) : impl_->table_where();
}

bool Table::has(std::string_view key) const {
  return impl_->find(key) != nullptr;
}

double Table::number(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, range.describe());
  return impl_->to_number(*v, impl_->key_path(key), range);
}

std::optional<double> Table::optional_number(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_number(*v, impl_->key_path(key), range);
}

double Table::number_or(std::string_view key, double fallback, const Range& range) const {
  return optional_number(key, range).value_or(fallback);
}

std::int64_t Table::integer(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, integer_description(range));
  return impl_->to_integer(*v, impl_->key_path(key), range);
}

std::optional<std::int64_t> Table::optional_integer(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_integer(*v, impl_->key_path(key), range);
}

bool Table::boolean(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, "a boolean (true or false)");
  return impl_->to_boolean(*v, impl_->key_path(key));
}

std::optional<bool> Table::optional_boolean(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_boolean(*v, impl_->key_path(key));
}

std::string Table::string(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, "a string");
  return impl_->to_string(*v, impl_->key_path(key));
}

std::string Table::name(std::string_view key) const {
  const std::string text = string(key);
  auto refuse = [&](const std::string& why) {
    fail(key, "expected a name (1 to 128 characters, no '/' or control character): " + why);
  };
  if (text.empty()) refuse("it is empty");
  if (text.size() > 128) refuse("it has " + std::to_string(text.size()) + " characters");
  if (text == "." || text == "..") refuse("\"" + text + "\" is a path of its own");
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '/') refuse("'/' separates the groups of the output file");
    if (u < 0x20 || u == 0x7f) refuse("it holds the control character " + std::to_string(u));
  }
  return text;
}

std::optional<std::string> Table::optional_string(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_string(*v, impl_->key_path(key));
}

std::string Table::choice(std::string_view key, const std::vector<std::string>& choices) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, one_of(choices));
  return impl_->to_choice(*v, impl_->key_path(key), choices);
}

std::optional<std::string> Table::optional_choice(std::string_view key,
                                                  const std::vector<std::string>& choices) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_choice(*v, impl_->key_path(key), choices);
}

std::vector<double> Table::numbers(std::string_view key, const Range& range) const {
  const std::string expected = "an array of numbers";
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, expected);
  const std::string kp = impl_->key_path(key);
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<double> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(impl_->to_number(a[i], indexed(kp, i), range));
  return out;
}

std::vector<std::int64_t> Table::integers(std::string_view key, const Range& range) const {
  const std::string expected = "an array of integers";
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, expected);
  const std::string kp = impl_->key_path(key);
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<std::int64_t> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(impl_->to_integer(a[i], indexed(kp, i), range));
  return out;
}

std::vector<std::string> Table::strings(std::string_view key) const {
  const std::string expected = "an array of strings";
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, expected);
  const std::string kp = impl_->key_path(key);
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<std::string> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(impl_->to_string(a[i], indexed(kp, i)));
  return out;
}

std::array<double, 3> Table::vec3(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, kVec3);
  return impl_->to_vec3(*v, impl_->key_path(key), range);
}

std::optional<std::array<double, 3>> Table::optional_vec3(std::string_view key, const Range& range) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  return impl_->to_vec3(*v, impl_->key_path(key), range);
}

std::vector<std::array<double, 3>> Table::vec3_list(std::string_view key, const Range& range) const {
  const std::string expected = "an array of 3-vectors [[x, y, z], ...]";
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, expected);
  const std::string kp = impl_->key_path(key);
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<std::array<double, 3>> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(impl_->to_vec3(a[i], indexed(kp, i), range));
  return out;
}

std::vector<std::vector<double>> Table::number_rows(std::string_view key, std::size_t columns,
                                                    const Range& range) const {
  const std::string expected = "an array of rows of " + std::to_string(columns) + " numbers [[a, b, ...], ...]";
  const toml::value* v = impl_->lookup(key);
  if (!v) impl_->missing(key, expected);
  const std::string kp = impl_->key_path(key);
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<std::vector<double>> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string rp = indexed(kp, i);
    const auto& row = impl_->to_array(a[i], rp, expected);
    if (row.size() != columns)
      impl_->fail_at(a[i], rp, "expected " + std::to_string(columns) + " numbers, got " + std::to_string(row.size()));
    std::vector<double> r;
    for (std::size_t j = 0; j < columns; ++j) r.push_back(impl_->to_number(row[j], indexed(rp, j), range));
    out.push_back(std::move(r));
  }
  return out;
}

Table Table::table(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  const std::string kp = impl_->key_path(key);
  if (!v) impl_->missing(key, "a table [" + kp + "]");
  if (!v->is_table()) impl_->fail_at(*v, kp, "expected a table [" + kp + "], got " + describe(*v));
  return impl_->child(*v, kp);
}

std::optional<Table> Table::optional_table(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return std::nullopt;
  const std::string kp = impl_->key_path(key);
  if (!v->is_table()) impl_->fail_at(*v, kp, "expected a table [" + kp + "], got " + describe(*v));
  return impl_->child(*v, kp);
}

std::vector<Table> Table::table_array(std::string_view key) const {
  const toml::value* v = impl_->lookup(key);
  if (!v) return {};
  const std::string kp = impl_->key_path(key);
  const std::string expected = "an array of tables [[" + kp + "]]";
  if (v->is_table()) impl_->fail_at(*v, kp, "expected " + expected + ", got a single table [" + kp + "]");
  const auto& a = impl_->to_array(*v, kp, expected);
  std::vector<Table> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string element = indexed(kp, i);
    if (!a[i].is_table()) impl_->fail_at(a[i], element, "expected a table, got " + describe(a[i]));
    out.push_back(impl_->child(a[i], element));
  }
  return out;
}

std::vector<std::string> Table::table_keys() const {
  std::vector<std::tuple<int, int, std::string>> found;
  for (const auto& [key, v] : impl_->table()) {
    if (!v.is_table()) continue;
    impl_->known->insert(key);
    const SourceLocation loc = impl_->where(v);
    found.emplace_back(loc.line, loc.column, key);
  }
  std::sort(found.begin(), found.end());  // in the order of the file
  std::vector<std::string> keys;
  keys.reserve(found.size());
  for (auto& entry : found) keys.push_back(std::move(std::get<2>(entry)));
  return keys;
}

void Table::finish() const {
  const toml::value* first = nullptr;
  std::string first_key;
  SourceLocation first_loc;
  for (const auto& [key, v] : impl_->table()) {
    if (impl_->known->count(key)) continue;
    const SourceLocation loc = impl_->where(v);
    if (!first ||
        std::tie(loc.line, loc.column, key) < std::tie(first_loc.line, first_loc.column, first_key)) {
      first = &v;
      first_key = key;
      first_loc = loc;
    }
  }
  if (!first) return;
  const std::vector<std::string> accepted(impl_->known->begin(), impl_->known->end());
  std::string message = "unknown key '" + first_key + "'";
  if (const std::string guess = closest(first_key, accepted); !guess.empty())
    message += " (did you mean '" + guess + "'?)";
  if (accepted.empty()) {
    message += "; no keys are accepted here";
  } else {
    message += "; accepted keys: ";
    for (std::size_t i = 0; i < accepted.size(); ++i) message += (i ? ", " : "") + accepted[i];
  }
  throw Error(message, first_loc, impl_->key_path(first_key));
}

void Table::fail(std::string_view key, const std::string& message) const {
  throw Error(message, location(key), impl_->key_path(key));
}

void Table::fail(const std::string& message) const {
  throw Error(message, location(), impl_->path);
}

void Table::accept(std::string_view key) const {
  impl_->known->insert(std::string(key));
}

// ---------------------------------------------------------------------------------------------------------
// Suggestions

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  if (word.empty() || candidates.empty()) return "";
  const std::string w = lower(word);
  // 1. The nearest candidate by (case-insensitive) edit distance, if it is close: within max(2, length / 3)
  //    edits and fewer edits than the shorter of the two is long ("zzz" is no typo of "Iz").
  const std::string* best = nullptr;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& candidate : candidates) {
    const std::size_t d = edit_distance(w, lower(candidate));
    if (d < best_distance) {
      best = &candidate;
      best_distance = d;
    }
  }
  const std::size_t threshold = std::max<std::size_t>(2, word.size() / 3);
  if (best && best_distance <= threshold && best_distance < std::min(word.size(), best->size())) return *best;
  // 2. An abbreviation: "craig" for "craig-bampton".
  if (w.size() >= 3) {
    for (const auto& candidate : candidates)
      if (lower(candidate).rfind(w, 0) == 0) return candidate;
  }
  return "";
}

}  // namespace nvh::input
