#pragma once
// Solid meshes in Abaqus/CalculiX .inp form: the nodes, solid elements and sets of a deck made by a mesher
// (gmsh, Abaqus/CAE, ...), read into a Mesh; and a Mesh written back as an .inp that CalculiX accepts.
// Everything else in a deck (materials, steps, boundary conditions) is skipped and reported.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace nvh::condense {

struct MeshElement {
  std::string type;        ///< Abaqus element type as written, upper case: "C3D4", "C3D10", "C3D8", "C3D20"
  std::int64_t id = 0;     ///< element label in the file
  std::vector<int> nodes;  ///< 0-based indices into Mesh::nodes, in the file's order
  std::string elset;       ///< ELSET= of its *ELEMENT block, upper case ("" if none)
  int line = 0;            ///< line of the element in the file (in the included file for *INCLUDE)

  bool operator==(const MeshElement&) const = default;
};

struct Mesh {
  std::string file;                                   ///< for messages
  std::vector<Eigen::Vector3d> nodes;                 ///< coordinates (as in the file; SI meters assumed)
  std::vector<std::int64_t> node_ids;                 ///< label of each node
  std::vector<MeshElement> elements;                  ///< solid elements, in the file's order
  std::map<std::string, std::vector<int>> node_sets;  ///< NSET name (upper case) -> sorted node indices
  std::map<std::string, std::vector<int>>
      element_sets;  ///< ELSET name (upper case) -> sorted element indices

  /// Index of the node with label `id`, -1 if absent. O(1) for consecutive labels, O(log n) for sorted
  /// ones, O(n) otherwise (build an unordered_map for many look-ups in an unsorted mesh).
  int node_index(std::int64_t id) const;
};

/// Number of nodes of a solid element type this reader keeps (C3D4 4, C3D10 10, C3D8 8, C3D20 20); 0 for
/// any other type.
int abaqus_solid_node_count(const std::string& type);

/// Read *NODE (NSET=), *ELEMENT (TYPE=, ELSET=), *NSET and *ELSET (with and without GENERATE; members may
/// name other sets), *INCLUDE (INPUT=, relative to the including file) and *HEADING. Keywords and names are
/// case-insensitive (names are stored upper case); ** starts a comment; a data or keyword line that ends
/// with a comma goes on on the next line (C3D20 elements span two lines); a blank coordinate is 0.
/// Other keywords (*MATERIAL, *STEP, *BOUNDARY, ...) and their data are skipped: each distinct one is
/// appended once to `skipped` (optional) as written upper case, e.g. "*SOLID SECTION". Elements of
/// other types (gmsh's CPS6/S3/T3D2 boundary elements, C3D8R, ...) are skipped too, one entry per type:
/// "*ELEMENT, TYPE=CPS6 (120 elements)"; sets drop their members silently, and sets left empty are
/// dropped. Nodes may be defined after the elements that use them; sets are sorted and unique.
/// Errors (nvh::Error with file and line; the key is the keyword, e.g. "*ELEMENT"): a missing file, a node
/// referenced by an element or set but not defined, a duplicate node or element label, a wrong node
/// count for the type, a malformed number, data lines before any keyword (or element lines under
/// *NODE), an unknown set name in a set, *ELEMENT without TYPE=, *NODE with SYSTEM= other than R.
Mesh read_abaqus_mesh(const std::filesystem::path& file, std::vector<std::string>* skipped = nullptr);
/// The same from text; `name` stands for the file in messages, and *INCLUDE is relative to its folder.
Mesh parse_abaqus_mesh(const std::string& text, const std::string& name,
                       std::vector<std::string>* skipped = nullptr);

/// Write nodes, elements (one *ELEMENT block per run of equal type and elset, so the element order is
/// kept) and node and element sets as an .inp that CalculiX (ccx 2.20) accepts: at most 16 entries a
/// line (C3D20: label and 15 nodes, then 5), at most 132 characters a line for labels of up to 7 digits
/// (ccx reads longer lines too), coordinates in at most 20 characters as ccx reads them (Fortran f20.0;
/// the round trip is exact unless a coordinate needs more, else within 1e-13 relative). Element sets that are
/// just the elements of their ELSET= blocks are not repeated; empty sets are not written. nvh::Error if the
/// mesh is inconsistent (index out of range, unknown type, NaN).
void write_abaqus_mesh(const Mesh& mesh, std::ostream& out);

}  // namespace nvh::condense
