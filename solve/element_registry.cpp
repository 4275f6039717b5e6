// The element registry and the table helper every element reader shares (element_registry.hpp).
#include "solve/element_registry.hpp"

#include "common/error.hpp"

namespace nvh::solve {

void ElementRegistry::add(ElementType type) {
  const auto key = std::pair{type.section, type.name};
  if (types_.count(key)) throw Error("element type '" + type.name + "' is registered twice in [[" + type.section + "]]");
  types_.emplace(key, std::move(type));
}

const ElementType* ElementRegistry::find(const std::string& section, const std::string& name) const {
  const auto it = types_.find({section, name});
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> ElementRegistry::names(const std::string& section) const {
  std::vector<std::string> out;
  for (const auto& [key, type] : types_)
    if (key.first == section) out.push_back(key.second);
  return out;
}

std::vector<const ElementType*> ElementRegistry::all() const {
  std::vector<const ElementType*> out;
  for (const auto& [key, type] : types_) out.push_back(&type);
  return out;
}

Table1D ElementContext::table_from(const std::string& what, double period) const {
  const input::Table& t = table;
  if (t.has("table") && t.has("file")) t.fail("file", "give either 'table' or 'file', not both");
  try {
    if (t.has("file")) {
      const auto file = base / t.string("file");
      const std::vector<std::string> cols = t.has("columns") ? t.strings("columns") : std::vector<std::string>{"", ""};
      if (cols.size() != 2) t.fail("columns", "expected two column names [abscissa, value]");
      input_files.push_back(file);
      return read_csv_table(file, cols[0], cols[1], period);
    }
    if (!t.has("table")) t.fail("the " + what + " needs 'table' = [[x, y], ...] or 'file' = \"table.csv\"");
    std::vector<double> x, y;
    for (const auto& row : t.number_rows("table", 2, input::Range::magnitude(bounds::kCoefficient))) {
      x.push_back(row[0]);
      y.push_back(row[1]);
    }
    return Table1D(std::move(x), std::move(y), "the table", period);
  } catch (const Error& e) {
    if (!e.where().file.empty()) throw;
    t.fail(t.has("file") ? "file" : "table", e.what());
  }
}

}  // namespace nvh::solve
