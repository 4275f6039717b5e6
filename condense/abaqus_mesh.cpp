#include "condense/abaqus_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "common/error.hpp"

namespace nvh::condense {

int Mesh::node_index(std::int64_t id) const {
  if (node_ids.empty()) return -1;
  // Consecutive labels (the usual case): the label says where the node is.
  if (id >= node_ids.front()) {
    const std::uint64_t guess = static_cast<std::uint64_t>(id) - static_cast<std::uint64_t>(node_ids.front());
    if (guess < node_ids.size() && node_ids[guess] == id) return static_cast<int>(guess);
  }
  // Sorted labels: bisection (well defined on any order; verified below).
  std::size_t low = 0, high = node_ids.size();
  while (low < high) {
    const std::size_t mid = low + (high - low) / 2;
    if (node_ids[mid] < id) {
      low = mid + 1;
    } else {
      high = mid;
    }
  }
  if (low < node_ids.size() && node_ids[low] == id) return static_cast<int>(low);
  const auto it = std::find(node_ids.begin(), node_ids.end(), id);
  return it == node_ids.end() ? -1 : static_cast<int>(it - node_ids.begin());
}

int abaqus_solid_node_count(const std::string& type) {
  if (type == "C3D4") return 4;
  if (type == "C3D10") return 10;
  if (type == "C3D8") return 8;
  if (type == "C3D20") return 20;
  return 0;
}

namespace {

namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 16;

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

/// Upper case without blanks: Abaqus ignores blanks in keywords and parameter names.
std::string keyword_key(std::string_view s) {
  std::string out;
  for (char c : s)
    if (c != ' ' && c != '\t') out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

/// Upper case with runs of blanks made one, for messages and `skipped`: "*SOLID SECTION".
std::string keyword_name(std::string_view s) {
  std::string out;
  for (char c : trim(s)) {
    if (c == ' ' || c == '\t') {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
  }
  return out;
}

std::optional<std::string> read_text_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in || fs::is_directory(file)) return std::nullopt;
  std::string text;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > 0) {
    text.resize(static_cast<std::size_t>(size));
    in.seekg(0);
    in.read(text.data(), size);
    if (!in) return std::nullopt;
  }
  return text;
}

/// One comma-separated entry of a line, trimmed; line and 1-based column for messages.
struct Field {
  std::string_view text;
  int line = 0;
  int column = 0;
};

/// A keyword line or a data line, with the lines that continue it (a line ending with a comma).
struct Record {
  bool keyword = false;
  int line = 0;
  int lines = 1;
  std::vector<Field> fields;
};

/// The lines of one text, with the joining of continued lines and the skipping of comments.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}

  struct Position {
    std::size_t pos = 0;
    int line = 0;
  };
  Position position() const { return {pos_, line_}; }
  void rewind(Position p) {
    pos_ = p.pos;
    line_ = p.line;
  }

  /// The next record; false at the end of the text.
  bool next(Record& record) {
    std::string_view line;
    do {
      if (!next_line(line)) return false;
    } while (ignorable(line));
    record.keyword = trim(line).front() == '*';
    record.line = line_;
    record.lines = 1;
    record.fields.clear();
    bool goes_on = split(line, record.fields);
    while (goes_on) {
      const std::size_t before = pos_;
      const int line_before = line_;
      if (!next_line(line)) break;
      if (ignorable(line)) continue;
      if (trim(line).front() == '*') {  // a keyword ends the record even after a trailing comma
        pos_ = before;
        line_ = line_before;
        break;
      }
      ++record.lines;
      goes_on = split(line, record.fields);
    }
    return true;
  }

 private:
  bool next_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    return true;
  }
  static bool ignorable(std::string_view line) {
    const std::string_view t = trim(line);
    return t.empty() || t.substr(0, 2) == "**";
  }
  /// Append the fields of `line`; true if it ends with a comma (the record goes on).
  bool split(std::string_view line, std::vector<Field>& fields) const {
    const std::string_view body = trim(line);
    const bool goes_on = body.back() == ',';
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      const std::string_view raw =
          line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
      const std::string_view t = trim(raw);
      const int column = static_cast<int>(start + (t.empty() ? 0 : t.data() - raw.data())) + 1;
      if (comma == std::string_view::npos) {
        if (!goes_on) fields.push_back({t, line_, column});  // after a final comma: nothing
        break;
      }
      fields.push_back({t, line_, column});
      start = comma + 1;
    }
    return goes_on;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

/// An entry of a set definition, resolved when the whole deck has been read.
struct SetItem {
  enum Kind { kLabel, kGenerate, kSet, kIndices } kind = kLabel;
  std::int64_t first = 0;  ///< label, or first label / index of a range
  std::int64_t last = 0;
  std::int64_t step = 1;
  std::string set;  ///< kSet: the name of another set
  int line = 0;
  int column = 0;
};

struct SetDefinition {
  bool nodes = true;  ///< NSET, else ELSET
  std::string name;
  int source = 0;
  std::string keyword;  ///< for messages: "*NSET", "*NODE", ...
  std::vector<SetItem> items;
};

class Reader {
 public:
  explicit Reader(std::vector<std::string>* skipped) : skipped_(skipped) {}

  void parse(std::string_view text, const std::string& name, const fs::path& folder, int depth) {
    const int source = static_cast<int>(sources_.size());
    sources_.push_back(name);
    Lines lines(text);
    Record record;
    while (lines.next(record)) {
      if (record.keyword) {
        keyword(record, source, folder, depth);
        continue;
      }
      // A 20-node element written as CalculiX reads it, without a final comma: the label and 15 nodes fill
      // the line (16 entries at most), the other nodes follow on the next.
      if (block_ == Block::kElement && element_nodes_ > 15 && record.lines == 1 &&
          record.fields.size() == 16) {
        const Lines::Position position = lines.position();
        Record more;
        if (lines.next(more) && !more.keyword) {
          record.fields.insert(record.fields.end(), more.fields.begin(), more.fields.end());
          record.lines += more.lines;
        } else {
          lines.rewind(position);
        }
      }
      data(record, source);
    }
  }

  Mesh finish(const std::string& file) {
    mesh_.file = file;
    resolve_element_nodes();
    for (const SetDefinition& definition : sets_) resolve_set(definition);
    for (auto* sets : {&mesh_.node_sets, &mesh_.element_sets}) {
      for (auto it = sets->begin(); it != sets->end();) {
        std::sort(it->second.begin(), it->second.end());
        it->second.erase(std::unique(it->second.begin(), it->second.end()), it->second.end());
        it = it->second.empty() ? sets->erase(it) : std::next(it);
      }
    }
    if (skipped_) {
      for (const std::string& type : skipped_type_order_) {
        skipped_->push_back("*ELEMENT, TYPE=" + type + " (" + std::to_string(skipped_types_[type]) +
                            " elements)");
      }
    }
    return std::move(mesh_);
  }

 private:
  enum class Block { kNone, kOther, kNode, kElement, kSkippedElement, kNset, kElset };

  [[noreturn]] void fail(const std::string& message, int source, int line, int column,
                         const std::string& key) const {
    throw Error(message, SourceLocation{sources_[source], line, column}, key);
  }
  [[noreturn]] void fail(const std::string& message, int source, const Field& field) const {
    fail(message, source, field.line, field.column, keyword_);
  }

  // ---- keyword lines

  void keyword(const Record& record, int source, const fs::path& folder, int depth) {
    const Field& head = record.fields.front();
    keyword_ = keyword_name(head.text);
    const std::string key = keyword_key(head.text);
    std::map<std::string, Field> parameters;  // name -> value (text "" for a flag such as GENERATE)
    for (std::size_t i = 1; i < record.fields.size(); ++i) {
      const Field& f = record.fields[i];
      if (f.text.empty()) continue;
      const std::size_t eq = f.text.find('=');
      Field value = f;
      value.text = eq == std::string_view::npos ? std::string_view{} : trim(f.text.substr(eq + 1));
      if (value.text.size() >= 2 && value.text.front() == '"' && value.text.back() == '"')
        value.text = value.text.substr(1, value.text.size() - 2);
      if (eq != std::string_view::npos) value.column += static_cast<int>(value.text.data() - f.text.data());
      parameters[keyword_key(f.text.substr(0, eq))] = value;
    }
    const auto parameter = [&](const std::string& name) -> const Field* {
      const auto it = parameters.find(name);
      return it == parameters.end() ? nullptr : &it->second;
    };
    const auto required = [&](const std::string& name) -> const Field& {
      const Field* f = parameter(name);
      if (!f || f->text.empty()) fail(keyword_ + " needs " + name + "=", source, record.line, 0, keyword_);
      return *f;
    };

    block_ = Block::kOther;
    if (key == "*NODE") {
      if (const Field* system = parameter("SYSTEM"); system && upper(system->text) != "R") {
        fail("SYSTEM=" + std::string(system->text) + " is not supported; give rectangular coordinates",
             source, *system);
      }
      block_ = Block::kNode;
      open_set(parameter("NSET"), true, source, static_cast<std::int64_t>(mesh_.nodes.size()));
    } else if (key == "*ELEMENT") {
      element_type_ = upper(required("TYPE").text);
      element_nodes_ = abaqus_solid_node_count(element_type_);
      const Field* elset = parameter("ELSET");
      element_elset_ = elset ? upper(elset->text) : std::string();
      if (element_nodes_ > 0) {
        block_ = Block::kElement;
        open_set(elset, false, source, static_cast<std::int64_t>(mesh_.elements.size()));
      } else {
        block_ = Block::kSkippedElement;
        if (!skipped_types_.count(element_type_)) skipped_type_order_.push_back(element_type_);
        skipped_types_[element_type_];
        open_set(nullptr, false, source, 0);
      }
    } else if (key == "*NSET" || key == "*ELSET") {
      const bool nodes = key == "*NSET";
      const Field& name = required(nodes ? "NSET" : "ELSET");
      block_ = nodes ? Block::kNset : Block::kElset;
      generate_ = parameter("GENERATE") != nullptr;
      sets_.push_back({nodes, upper(name.text), source, keyword_, {}});
    } else if (key == "*INCLUDE") {
      include(required("INPUT"), source, folder, depth);
      // The included text stands in place of the keyword: its block goes on.
    } else if (key == "*HEADING") {
      // The title lines are skipped.
    } else if (skipped_ && std::find(skipped_->begin(), skipped_->end(), keyword_) == skipped_->end()) {
      skipped_->push_back(keyword_);
    }
  }

  /// Start the set that NSET=/ELSET= of *NODE/*ELEMENT adds to (the nodes or elements of the block).
  void open_set(const Field* name, bool nodes, int source, std::int64_t first_index) {
    block_set_ = -1;
    if (!name || name->text.empty()) return;
    SetItem item;
    item.kind = SetItem::kIndices;
    item.first = first_index;
    item.last = first_index - 1;  // grows with the block
    sets_.push_back({nodes, upper(name->text), source, keyword_, {item}});
    block_set_ = static_cast<int>(sets_.size()) - 1;
  }

  void include(const Field& input, int source, const fs::path& folder, int depth) {
    if (depth >= kMaxIncludeDepth) {
      fail("*INCLUDE nested more than " + std::to_string(kMaxIncludeDepth) +
               " deep (does a file include itself?)",
           source, input);
    }
    fs::path path(std::string(input.text));
    if (path.is_relative()) path = folder / path;
    const std::optional<std::string> text = read_text_file(path);
    if (!text) fail("cannot read the included file " + path.string(), source, input);
    const std::string keyword = keyword_;
    parse(*text, path.string(), path.parent_path(), depth + 1);
    keyword_ = keyword;
  }

  // ---- data lines

  void data(const Record& record, int source) {
    switch (block_) {
      case Block::kNone:
        fail("a data line before any keyword; expected a keyword such as *NODE or *ELEMENT first", source,
             record.line, 1, "");
      case Block::kOther:
        return;
      case Block::kNode:
        return node(record, source);
      case Block::kElement:
        return element(record, source);
      case Block::kSkippedElement:
        ++skipped_types_[element_type_];
        remember_label(record, source, -1);
        return;
      case Block::kNset:
      case Block::kElset:
        return set_data(record, source);
    }
  }

  std::int64_t label(const Field& f, int source) const {
    std::int64_t value = 0;
    const char* end = f.text.data() + f.text.size();
    const auto [ptr, ec] = std::from_chars(f.text.data(), end, value);
    if (f.text.empty() || ec != std::errc() || ptr != end) {
      fail("expected an integer label, found \"" + std::string(f.text) + "\"", source, f);
    }
    if (value <= 0) fail("expected a positive label, found " + std::string(f.text), source, f);
    return value;
  }

  double number(const Field& f, int source) const {
    if (f.text.empty()) return 0.0;  // Abaqus: a blank field is zero
    std::string_view t = f.text;
    if (t.front() == '+') t.remove_prefix(1);
    double value = 0.0;
    const char* end = t.data() + t.size();
    const auto [ptr, ec] = std::from_chars(t.data(), end, value);
    if (t.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
      fail("expected a number, found \"" + std::string(f.text) + "\"", source, f);
    }
    return value;
  }

  void node(const Record& record, int source) {
    const std::vector<Field>& fields = record.fields;
    if (fields.size() > 4) {
      fail("expected a node line \"label, x, y, z\", found " + std::to_string(fields.size()) +
               " entries (is an *ELEMENT keyword missing above this line?)",
           source, fields[4]);
    }
    const std::int64_t id = label(fields[0], source);
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (std::size_t k = 1; k < fields.size(); ++k) x[static_cast<int>(k) - 1] = number(fields[k], source);
    const int index = static_cast<int>(mesh_.nodes.size());
    const auto [it, inserted] = node_of_label_.emplace(id, index);
    if (!inserted) {
      const Where& first = node_where_[it->second];
      fail("node " + std::to_string(id) + " is defined twice (first at " + sources_[first.source] + ":" +
               std::to_string(first.line) + ")",
           source, fields[0]);
    }
    mesh_.nodes.push_back(x);
    mesh_.node_ids.push_back(id);
    node_where_.push_back({source, record.line});
    if (block_set_ >= 0) sets_[block_set_].items.front().last = index;
  }

  /// Check that an element label is new; `index` is the element's index, -1 for a skipped element.
  std::int64_t remember_label(const Record& record, int source, int index) {
    const Field& f = record.fields.front();
    const std::int64_t id = label(f, source);
    const auto [it, inserted] = element_of_label_.emplace(id, index);
    if (!inserted) {
      std::string first;
      if (it->second >= 0) {
        first = " (first at " + sources_[element_source_[it->second]] + ":" +
                std::to_string(mesh_.elements[it->second].line) + ")";
      }
      fail("element " + std::to_string(id) + " is defined twice" + first, source, f);
    }
    return id;
  }

  void element(const Record& record, int source) {
    const int index = static_cast<int>(mesh_.elements.size());
    MeshElement e;
    e.type = element_type_;
    e.elset = element_elset_;
    e.line = record.line;
    e.id = remember_label(record, source, index);
    int count = 0;
    for (std::size_t k = 1; k < record.fields.size(); ++k) {
      if (record.fields[k].text.empty()) continue;
      element_labels_.push_back(label(record.fields[k], source));
      ++count;
    }
    if (count != element_nodes_) {
      std::string hint;
      if (count < element_nodes_ && element_nodes_ > 15)
        hint = " (a line that goes on onto the next must end with a comma)";
      fail(e.type + " element " + std::to_string(e.id) + " has " + std::to_string(count) +
               " nodes, expected " + std::to_string(element_nodes_) + hint,
           source, record.line, 0, keyword_);
    }
    e.nodes.reserve(count);
    mesh_.elements.push_back(std::move(e));
    element_source_.push_back(source);
    if (block_set_ >= 0) sets_[block_set_].items.front().last = index;
  }

  void set_data(const Record& record, int source) {
    SetDefinition& set = sets_.back();
    if (generate_) {
      std::vector<Field> fields;
      for (const Field& f : record.fields)
        if (!f.text.empty()) fields.push_back(f);
      if (fields.size() < 2 || fields.size() > 3) {
        fail("expected \"first, last[, increment]\" after GENERATE", source, record.line, 1, keyword_);
      }
      SetItem item;
      item.kind = SetItem::kGenerate;
      item.first = label(fields[0], source);
      item.last = label(fields[1], source);
      item.step = fields.size() == 3 ? label(fields[2], source) : 1;
      item.line = fields[0].line;
      item.column = fields[0].column;
      if (item.last < item.first) fail("the last label is smaller than the first", source, fields[1]);
      if ((item.last - item.first) / item.step > 100'000'000) fail("too large a range", source, fields[1]);
      set.items.push_back(item);
      return;
    }
    for (const Field& f : record.fields) {
      if (f.text.empty()) continue;
      SetItem item;
      item.line = f.line;
      item.column = f.column;
      if (std::isalpha(static_cast<unsigned char>(f.text.front())) || f.text.front() == '_') {
        item.kind = SetItem::kSet;
        item.set = upper(f.text);
      } else {
        item.first = label(f, source);
      }
      set.items.push_back(std::move(item));
    }
  }

  // ---- resolving labels once everything is read

  void resolve_element_nodes() {
    std::size_t next = 0;
    for (std::size_t i = 0; i < mesh_.elements.size(); ++i) {
      MeshElement& e = mesh_.elements[i];
      const int count = abaqus_solid_node_count(e.type);
      for (int k = 0; k < count; ++k) {
        const std::int64_t id = element_labels_[next++];
        const auto it = node_of_label_.find(id);
        if (it == node_of_label_.end()) {
          fail(e.type + " element " + std::to_string(e.id) + " refers to node " + std::to_string(id) +
                   ", which is not defined",
               element_source_[i], e.line, 0, "*ELEMENT");
        }
        e.nodes.push_back(it->second);
      }
    }
    element_labels_ = {};
  }

  void resolve_set(const SetDefinition& definition) {
    auto& sets = definition.nodes ? mesh_.node_sets : mesh_.element_sets;
    std::vector<int>& members = sets[definition.name];
    const auto& of_label = definition.nodes ? node_of_label_ : element_of_label_;
    const char* what = definition.nodes ? "node" : "element";
    for (const SetItem& item : definition.items) {
      const auto where = [&](const std::string& message) {
        fail(message, definition.source, item.line, item.column, definition.keyword);
      };
      switch (item.kind) {
        case SetItem::kIndices:
          for (std::int64_t i = item.first; i <= item.last; ++i) members.push_back(static_cast<int>(i));
          break;
        case SetItem::kLabel: {
          const auto it = of_label.find(item.first);
          if (it == of_label.end()) {
            where(std::string(what) + " " + std::to_string(item.first) + " in set " + definition.name +
                  " is not defined");
          }
          if (it->second >= 0) members.push_back(it->second);  // -1: an element of a skipped type
          break;
        }
        case SetItem::kGenerate:
          // Labels in the range that do not exist are passed over (numbering with gaps).
          for (std::int64_t id = item.first; id <= item.last; id += item.step) {
            const auto it = of_label.find(id);
            if (it != of_label.end() && it->second >= 0) members.push_back(it->second);
          }
          break;
        case SetItem::kSet: {
          const auto it = sets.find(item.set);
          if (it == sets.end()) {
            where("unknown " + std::string(definition.nodes ? "node" : "element") + " set " + item.set +
                  " (a set must be defined before it is used)");
          }
          if (&it->second != &members) members.insert(members.end(), it->second.begin(), it->second.end());
          break;
        }
      }
    }
  }

  struct Where {
    int source = 0;
    int line = 0;
  };

  std::vector<std::string>* skipped_;
  Mesh mesh_;
  std::vector<std::string> sources_;  // file names, for messages
  std::unordered_map<std::int64_t, int> node_of_label_;
  std::unordered_map<std::int64_t, int> element_of_label_;  // -1: an element of a skipped type
  std::vector<Where> node_where_;
  std::vector<int> element_source_;
  std::vector<std::int64_t> element_labels_;  // node labels of all elements, resolved at the end
  std::vector<SetDefinition> sets_;
  std::map<std::string, int> skipped_types_;  // element type -> count
  std::vector<std::string> skipped_type_order_;

  // The block being read.
  Block block_ = Block::kNone;
  std::string keyword_;  // as written, for messages
  std::string element_type_;
  std::string element_elset_;
  int element_nodes_ = 0;
  int block_set_ = -1;  // index into sets_ of the NSET=/ELSET= of a *NODE/*ELEMENT block
  bool generate_ = false;
};

// ---- writing

/// A coordinate in at most 20 characters (CalculiX reads them with Fortran's f20.0): the shortest text
/// that reads back exactly when that fits.
void append_coordinate(std::string& out, double value) {
  if (!std::isfinite(value)) throw Error("write_abaqus_mesh: a node coordinate is not finite");
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  for (int precision = 14; result.ptr - buffer > 20; --precision) {
    result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::scientific, precision);
  }
  out.append(buffer, result.ptr);
}

void append_integer(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

/// Lines of labels, `per_line` a line, each line but the last ending with a comma.
void append_label_lines(std::string& out, const std::vector<std::int64_t>& labels, std::size_t per_line) {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    append_integer(out, labels[i]);
    if (i + 1 == labels.size()) {
      out += '\n';
    } else if ((i + 1) % per_line == 0) {
      out += ",\n";
    } else {
      out += ", ";
    }
  }
}

}  // namespace

Mesh read_abaqus_mesh(const std::filesystem::path& file, std::vector<std::string>* skipped) {
  const std::optional<std::string> text = read_text_file(file);
  if (!text) throw Error("cannot read the mesh file", SourceLocation{file.string(), 0, 0}, "");
  Reader reader(skipped);
  reader.parse(*text, file.string(), file.parent_path(), 0);
  return reader.finish(file.string());
}

Mesh parse_abaqus_mesh(const std::string& text, const std::string& name, std::vector<std::string>* skipped) {
  Reader reader(skipped);
  reader.parse(text, name, fs::path(name).parent_path(), 0);
  return reader.finish(name);
}

void write_abaqus_mesh(const Mesh& mesh, std::ostream& out) {
  const int node_count = static_cast<int>(mesh.nodes.size());
  if (mesh.node_ids.size() != mesh.nodes.size())
    throw Error("write_abaqus_mesh: node_ids and nodes differ in size");
  const auto check_index = [&](int i, int size, const char* what) {
    if (i < 0 || i >= size) throw Error(std::string("write_abaqus_mesh: ") + what + " index out of range");
  };

  std::string text;
  text.reserve(64 * mesh.nodes.size() + 80 * mesh.elements.size());
  text += "** ";
  text += mesh.file.empty() ? "mesh" : mesh.file;
  text += ": " + std::to_string(mesh.nodes.size()) + " nodes, " + std::to_string(mesh.elements.size()) +
          " elements\n*NODE\n";
  for (int i = 0; i < node_count; ++i) {
    append_integer(text, mesh.node_ids[i]);
    for (int k = 0; k < 3; ++k) {
      text += ", ";
      append_coordinate(text, mesh.nodes[i][k]);
    }
    text += '\n';
  }

  // One block per run of equal type and elset. A line has at most 16 entries (C3D20: the label and 15
  // nodes, then 5); entries are separated by ", " unless that would make a line longer than 132.
  std::map<std::string, std::vector<int>> block_sets;  // elset -> elements of its blocks
  std::string line;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const MeshElement& e = mesh.elements[i];
    const int count = abaqus_solid_node_count(e.type);
    if (count == 0) throw Error("write_abaqus_mesh: unknown element type \"" + e.type + "\"");
    if (static_cast<int>(e.nodes.size()) != count)
      throw Error("write_abaqus_mesh: element " + std::to_string(e.id) + " has the wrong number of nodes");
    if (i == 0 || e.type != mesh.elements[i - 1].type || e.elset != mesh.elements[i - 1].elset) {
      text += "*ELEMENT, TYPE=" + e.type;
      if (!e.elset.empty()) text += ", ELSET=" + e.elset;
      text += '\n';
    }
    if (!e.elset.empty()) block_sets[e.elset].push_back(static_cast<int>(i));
    std::vector<std::int64_t> entries{e.id};
    for (int n : e.nodes) {
      check_index(n, node_count, "element node");
      entries.push_back(mesh.node_ids[n]);
    }
    for (std::size_t start = 0; start < entries.size(); start += 16) {
      const std::size_t end = std::min(entries.size(), start + 16);
      for (const char* separator : {", ", ","}) {
        line.clear();
        for (std::size_t k = start; k < end; ++k) {
          append_integer(line, entries[k]);
          if (k + 1 < end || end < entries.size()) line += k + 1 < end ? separator : ",";
        }
        if (line.size() <= 132) break;
      }
      text += line;
      text += '\n';
    }
  }

  std::vector<std::int64_t> labels;
  for (const auto& [name, members] : mesh.element_sets) {
    std::vector<int> sorted = members;
    std::sort(sorted.begin(), sorted.end());
    const std::vector<int>& from_blocks = block_sets[name];  // sorted: built in element order
    std::vector<int> extra;
    std::set_difference(sorted.begin(), sorted.end(), from_blocks.begin(), from_blocks.end(),
                        std::back_inserter(extra));
    if (extra.empty()) continue;
    labels.clear();
    for (int i : extra) {
      check_index(i, static_cast<int>(mesh.elements.size()), "element set");
      labels.push_back(mesh.elements[i].id);
    }
    text += "*ELSET, ELSET=" + name + '\n';
    append_label_lines(text, labels, 10);
  }
  for (const auto& [name, members] : mesh.node_sets) {
    if (members.empty()) continue;
    labels.clear();
    for (int i : members) {
      check_index(i, node_count, "node set");
      labels.push_back(mesh.node_ids[i]);
    }
    text += "*NSET, NSET=" + name + '\n';
    append_label_lines(text, labels, 10);
  }
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

}  // namespace nvh::condense
