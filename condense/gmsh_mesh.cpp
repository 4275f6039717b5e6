#include "condense/gmsh_mesh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/error.hpp"

namespace nvh::condense {

namespace {

constexpr int kTet4 = 4;    // gmsh element type of the 4-node tetrahedron
constexpr int kTet10 = 11;  // ... of the 10-node tetrahedron

std::mutex& gmsh_mutex() {
  static std::mutex mutex;
  return mutex;
}

/// One gmsh session: gmsh::initialize in the constructor, gmsh::finalize in the destructor, one at a time
/// in the process (gmsh keeps its model and options in globals; initialize resets the options).
class GmshSession {
 public:
  explicit GmshSession(int threads) : lock_(gmsh_mutex()) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.NumThreads", threads);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // NOLINT(bugprone-empty-catch): nothing to do if gmsh fails to shut down
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
};

enum class Input { kGeo, kCad, kBrep, kMsh };

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string last_gmsh_error() {
  std::string error;
  try {
    gmsh::logger::getLastError(error);
  } catch (...) {
    error.clear();
  }
  return error;
}

/// gmsh node tag -> index into the kept nodes: a dense table when the tags are (nearly) contiguous, as
/// gmsh numbers them, else a hash map.
class TagIndex {
 public:
  explicit TagIndex(const std::vector<std::size_t>& sorted_tags) {
    const std::size_t max_tag = sorted_tags.empty() ? 0 : sorted_tags.back();
    if (max_tag <= 4 * sorted_tags.size() + 1024) {
      dense_.assign(max_tag + 1, -1);
      for (std::size_t i = 0; i < sorted_tags.size(); ++i) dense_[sorted_tags[i]] = static_cast<int>(i);
    } else {
      for (std::size_t i = 0; i < sorted_tags.size(); ++i) sparse_[sorted_tags[i]] = static_cast<int>(i);
    }
  }
  /// -1 if the tag is not kept.
  int operator()(std::size_t tag) const {
    if (!sparse_.empty()) {
      const auto it = sparse_.find(tag);
      return it == sparse_.end() ? -1 : it->second;
    }
    return tag < dense_.size() ? dense_[tag] : -1;
  }

 private:
  std::vector<int> dense_;
  std::unordered_map<std::size_t, int> sparse_;
};

/// The gmsh model (meshed or read) -> Mesh. Throws nvh::Error via `fail`.
template <class Fail>
Mesh extract_tetrahedra(const std::string& file, Input input, const Fail& fail) {
  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);

  // The tetrahedra of each volume, in gmsh's node order for now; elements_of[v] = [begin, end) of volume v.
  struct Raw {
    std::size_t tag;
    int type;
    std::size_t first;  // offset into raw_nodes
  };
  std::vector<Raw> raw;
  std::vector<std::size_t> raw_nodes;
  std::map<int, std::pair<int, int>> elements_of;
  for (const auto& [dim, tag] : volumes) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, dim, tag);
    const int begin = static_cast<int>(raw.size());
    for (int type : types) {
      if (type != kTet4 && type != kTet10) {
        std::string name;
        int edim = 0, eorder = 0, nn = 0, primary = 0;
        std::vector<double> local;
        gmsh::model::mesh::getElementProperties(type, name, edim, eorder, nn, local, primary);
        fail("volume " + std::to_string(tag) + " has elements of gmsh type " + std::to_string(type) + " (" +
             name + "); only tetrahedra (C3D4, C3D10) are supported");
      }
      std::vector<std::size_t> element_tags, node_tags;
      gmsh::model::mesh::getElementsByType(type, element_tags, node_tags, tag);
      const std::size_t n = type == kTet4 ? 4 : 10;
      for (std::size_t e = 0; e < element_tags.size(); ++e)
        raw.push_back(Raw{element_tags[e], type, raw_nodes.size() + e * n});
      raw_nodes.insert(raw_nodes.end(), node_tags.begin(), node_tags.end());
    }
    const int end = static_cast<int>(raw.size());
    if (begin == end && input != Input::kMsh) {
      const std::string error = last_gmsh_error();
      fail("volume " + std::to_string(tag) + " was not meshed" +
           (error.empty() ? "" : " (gmsh: " + error + ")"));
    }
    elements_of[tag] = {begin, end};
  }
  if (raw.empty()) {
    fail(input == Input::kMsh ? "the mesh has no tetrahedra (gmsh saves only the elements of physical groups "
                                "when there are any: a Physical Volume is needed, or Mesh.SaveAll = 1)"
                              : "no tetrahedra were made");
  }

  // Keep the nodes of the tetrahedra, by ascending tag.
  std::vector<std::size_t> kept = raw_nodes;
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  const TagIndex index(kept);

  Mesh mesh;
  mesh.file = file;
  mesh.nodes.resize(kept.size());
  mesh.node_ids.assign(kept.begin(), kept.end());
  {
    std::vector<std::size_t> tags;
    std::vector<double> coord, parametric;
    gmsh::model::mesh::getNodes(tags, coord, parametric, -1, -1, /*includeBoundary=*/false,
                                /*returnParametricCoord=*/false);
    std::vector<bool> seen(kept.size(), false);
    for (std::size_t i = 0; i < tags.size(); ++i) {
      const int k = index(tags[i]);
      if (k < 0) continue;
      mesh.nodes[k] = Eigen::Vector3d(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]);
      seen[k] = true;
    }
    for (std::size_t k = 0; k < kept.size(); ++k)
      if (!seen[k]) fail("node " + std::to_string(kept[k]) + " of a tetrahedron has no coordinates");
  }

  // The element set name of each volume: the first 3D physical group that holds it.
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  std::vector<std::pair<std::pair<int, int>, std::string>> named;  // (dim, tag) -> set name
  for (const auto& [dim, tag] : groups) {
    if (dim != 2 && dim != 3) continue;
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    named.push_back(
        {{dim, tag}, name.empty() ? "PG" + std::to_string(dim) + "_" + std::to_string(tag) : upper(name)});
  }
  std::map<int, std::string> elset_of_volume;
  std::map<std::string, std::vector<int>> element_sets;
  for (const auto& [group, name] : named) {
    if (group.first != 3) continue;
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(group.first, group.second, entities);
    for (int v : entities) {
      elset_of_volume.emplace(v, name);
      const auto it = elements_of.find(v);
      if (it == elements_of.end()) continue;
      for (int e = it->second.first; e < it->second.second; ++e) element_sets[name].push_back(e);
    }
  }

  // Elements in Abaqus order: gmsh's 10-node tetrahedron has nodes 9 and 10 on edges 3-4 and 2-4,
  // Abaqus/CalculiX's on 2-4 and 3-4.
  static constexpr int kTet10Order[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
  mesh.elements.resize(raw.size());
  for (const auto& [volume, range] : elements_of) {
    const auto set = elset_of_volume.find(volume);
    for (int e = range.first; e < range.second; ++e) {
      const Raw& r = raw[e];
      MeshElement& out = mesh.elements[e];
      const int n = r.type == kTet4 ? 4 : 10;
      out.type = r.type == kTet4 ? "C3D4" : "C3D10";
      out.id = static_cast<std::int64_t>(r.tag);
      out.nodes.resize(n);
      for (int j = 0; j < n; ++j) out.nodes[j] = index(raw_nodes[r.first + (n == 4 ? j : kTet10Order[j])]);
      out.elset = set == elset_of_volume.end() ? "" : set->second;
    }
  }

  for (auto& [name, members] : element_sets) {
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    if (!members.empty()) mesh.element_sets[name] = std::move(members);
  }

  for (const auto& [group, name] : named) {
    std::vector<std::size_t> tags;
    std::vector<double> coord;
    gmsh::model::mesh::getNodesForPhysicalGroup(group.first, group.second, tags, coord);
    std::vector<int>& set = mesh.node_sets[name];
    for (std::size_t tag : tags) {
      const int k = index(tag);
      if (k >= 0) set.push_back(k);
    }
  }
  for (auto it = mesh.node_sets.begin(); it != mesh.node_sets.end();) {
    std::vector<int>& set = it->second;
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    it = set.empty() ? mesh.node_sets.erase(it) : std::next(it);
  }
  return mesh;
}

}  // namespace

Mesh mesh_with_gmsh(const GmshRequest& request) {
  const std::string file = request.geometry.string();
  const auto fail = [&file](const std::string& message) {
    throw Error(message, SourceLocation{file, 0, 0}, "");
  };

  const std::string extension = lower(request.geometry.extension().string());
  Input input = Input::kGeo;
  if (extension == ".geo") {
    input = Input::kGeo;
  } else if (extension == ".step" || extension == ".stp" || extension == ".iges" || extension == ".igs") {
    input = Input::kCad;
  } else if (extension == ".brep") {
    input = Input::kBrep;
  } else if (extension == ".msh") {
    input = Input::kMsh;
  } else {
    fail("unsupported extension \"" + request.geometry.extension().string() +
         "\" for gmsh (expected .geo, .step, .stp, .iges, .igs, .brep or .msh)");
  }
  if (request.order != 1 && request.order != 2)
    fail("element order " + std::to_string(request.order) + " is not supported (1: C3D4, 2: C3D10)");
  if (!std::isfinite(request.size) || request.size < 0)
    fail("the element size must be >= 0 m (0: gmsh's default), not " + std::to_string(request.size));
  if (request.threads < 1) fail("threads must be >= 1, not " + std::to_string(request.threads));
  {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(request.geometry, ec)) fail("no such file");
    std::ifstream probe(request.geometry);
    if (!probe) fail("cannot read the file");
  }

  GmshSession session(request.threads);
  std::string stage = "reading";
  try {
    if (input == Input::kCad) {
      // OpenCASCADE converts the file's length unit to its session unit ("xstep.cascade.unit", a process
      // global that outlives gmsh::finalize and that later STEP writes use too); keep it at OCC's default,
      // millimetres, and scale the shapes to metres.
      gmsh::option::setString("Geometry.OCCTargetUnit", "MM");
      gmsh::option::setNumber("Geometry.OCCScaling", 1e-3);
    }
    gmsh::open(file);  // a missing file is silent in gmsh 4.8: checked above
    gmsh::vectorpair volumes;
    gmsh::model::getEntities(volumes, 3);
    if (volumes.empty())
      fail(input == Input::kMsh ? "the mesh has no volume" : "the geometry has no volume to mesh");
    if (input != Input::kMsh) {
      stage = "meshing";
      gmsh::model::mesh::clear();  // a .geo may have meshed already ("Mesh 3;")
      gmsh::option::setNumber("Mesh.ElementOrder", request.order);
      if (request.size > 0) gmsh::option::setNumber("Mesh.MeshSizeMax", request.size);
      gmsh::model::mesh::generate(3);
    }
    stage = "reading the mesh";
    return extract_tetrahedra(file, input, fail);
  } catch (const Error&) {
    throw;
  } catch (const std::string& message) {  // gmsh 4.8 throws its error message (General.AbortOnError = 2)
    fail("gmsh failed " + stage + ": " + message);
  } catch (const std::exception& e) {
    fail("gmsh failed " + stage + ": " + e.what());
  } catch (...) {
    const std::string error = last_gmsh_error();
    fail("gmsh failed " + stage + (error.empty() ? "" : ": " + error));
  }
  return {};  // not reached
}

}  // namespace nvh::condense
