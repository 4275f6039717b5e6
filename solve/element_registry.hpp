#pragma once
// The registry of element types: a scene keyword -> its reader and factory (force_element.hpp says how to add
// one). The scene reader looks types up here; the accepted names, --help and the docs' list come from it.
//
// Sections of a scene that hold elements: [[force]] (two markers i, j, or lists of markers), [[load]] (one
// marker `at`) and [[driver]] types that are force elements (a motor curve). A type declares the marker keys
// it reads; the scene reader resolves them (with its located errors) before the factory runs, in the order of
// the keys: a key written `name[]` is a list `name = ["body.m1", ...]` (at least one), its markers in turn.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/input.hpp"
#include "solve/force_element.hpp"
#include "solve/table.hpp"

namespace nvh::solve {

/// What a factory gets: its table (located errors: t.fail(key, what)), the scene's folder, the list of input
/// files (for provenance), its markers' initial motion, and the shared table helper.
struct ElementContext {
  const input::Table& table;
  std::filesystem::path base;                      // folder of the scene file: relative paths start here
  std::vector<std::filesystem::path>& input_files;  // append every file read
  std::vector<MarkerMotion> initial;                // the markers' motion at the initial state as given
  std::vector<std::string> marker_bodies;           // the body (its name) of each marker

  /// A table y(x) from 'table' = [[x, y], ...] or 'file' = "t.csv" with 'columns' = ["x", "y"]; errors name
  /// the key. `what` describes it for messages; a period > 0 makes it periodic.
  Table1D table_from(const std::string& what, double period = 0.0) const;
};

struct ElementType {
  std::string section;                   // "force", "load" or "driver"
  std::string name;                      // the scene's `type` value
  std::string summary;                   // one line for --help and docs
  std::vector<std::string> marker_keys;  // e.g. {"i", "j"} or {"at"}; {"points[]", "j"}: a list, then j
  std::function<std::unique_ptr<ForceElement>(ElementContext&)> make;
};

class ElementRegistry {
 public:
  /// Throws if the (section, name) pair is taken.
  void add(ElementType type);
  const ElementType* find(const std::string& section, const std::string& name) const;
  /// The type names of a section, sorted.
  std::vector<std::string> names(const std::string& section) const;
  std::vector<const ElementType*> all() const;

 private:
  std::map<std::pair<std::string, std::string>, ElementType> types_;
};

/// The registry with every element type shipped with solve (solve/elements/builtin.cpp).
const ElementRegistry& builtin_elements();

}  // namespace nvh::solve
