#pragma once
// The registry of element types: a scene keyword -> its reader and factory (force_element.hpp says how to add
// one). The scene reader looks types up here; the accepted names, --help and the docs' list come from it.
//
// Sections of a scene that hold elements: [[force]] (two markers i, j, or lists of markers), [[load]] (one
// marker `at`) and [[driver]] types that are force elements (a motor curve). A type declares the marker keys
// it reads; the scene reader resolves them (with its located errors) before the factory runs, in the order of
// the keys: a key written `name[]` is a list `name = ["body.m1", ...]` (at least one), its markers in turn.
// A key written `name[]?` is an optional list: absent, it adds no markers.
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

/// Bounds of a scene's numbers (docs/scene-format.md, "Numbers"), shared by the scene reader and the element
/// readers. Every number is finite (input::Range); these bounds lie orders of magnitude beyond any machine,
/// so that no product the model forms of them overflows into inf and NaN results, and no run is without end.
namespace bounds {
inline constexpr double kLength = 1e3;        ///< m: positions, lengths (the assembly resolves 1e-13 m)
inline constexpr double kClearance = 1.0;     ///< m: contact clearances (either sign)
inline constexpr double kSpeed = 1e5;         ///< m/s
inline constexpr double kAngularSpeed = 1e6;  ///< rad/s
inline constexpr double kRpm = 1e7;           ///< rpm (about kAngularSpeed)
inline constexpr double kAcceleration = 1e6;  ///< m/s^2 (gravity)
inline constexpr double kMass = 1e12;         ///< kg
inline constexpr double kInertia = 1e12;      ///< kg m^2
inline constexpr double kCoefficient = 1e20;  ///< stiffness, damping, forces, torques, table values (SI)
inline constexpr double kAngleDeg = 1e6;      ///< deg: angles, offsets, periods
inline constexpr double kFrequencyHz = 1e9;   ///< Hz: load frequencies, the output sample rate
inline constexpr double kTime = 1e12;         ///< s: start and end of a run
inline constexpr double kMaxSamples = 1e9;    ///< output samples of a run ending by time
inline constexpr double kMaxSteps = 1e10;     ///< fixed generalized-alpha steps of a run ending by time
}  // namespace bounds

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
