#pragma once
// In-process meshing with the gmsh C++ API (Debian libgmsh-dev 4.8.4, OpenCASCADE 7.6): a geometry (a .geo
// script or a CAD file) is meshed into tetrahedra, or an existing .msh is read, and the result is returned
// as the same Mesh that read_abaqus_mesh gives, in Abaqus/CalculiX node order, so volume_model.cpp builds
// it unchanged.
#include <filesystem>

#include "condense/abaqus_mesh.hpp"

namespace nvh::condense {

struct GmshRequest {
  /// .geo script; .step/.stp/.iges/.igs (OpenCASCADE, converted to metres from the file's own length
  /// unit); .brep (no unit: coordinates taken as metres); or an existing .msh (any version gmsh reads;
  /// then nothing is meshed and `order` and `size` are ignored: the elements are taken as in the file).
  /// A .geo's coordinates are taken as metres as written. Extensions are case-insensitive.
  std::filesystem::path geometry;
  int order = 2;      ///< 1: C3D4, 2: C3D10 (mid-edge nodes on the geometry for curved boundaries)
  double size = 0.0;  ///< target element size, m (Mesh.MeshSizeMax); 0: gmsh's default or the .geo's sizes
  int threads = 1;    ///< General.NumThreads (>= 1)
};

/// Mesh the geometry's volumes (or read the .msh) in-process and return its tetrahedra:
///  - elements: C3D4 (gmsh type 4) or C3D10 (type 11, gmsh's nodes 9 and 10 swapped into Abaqus order),
///    volume by volume; id = gmsh's element tag; elset = the upper-case name of the first 3D physical
///    group that holds its volume ("" if none); line = 0.
///  - nodes: only those used by the tetrahedra, by ascending gmsh node tag (node_ids = the tags).
///  - node_sets: one per physical group of dimension 2 and 3, named by its physical name in upper case or
///    "PG<dim>_<tag>" when unnamed (groups of equal name are merged); the nodes of the group's elements
///    (for a surface: its triangles, mid-edge nodes included), sorted; nodes not on a tetrahedron are
///    left out and sets left empty are dropped.
///  - element_sets: one per 3D physical group, named likewise: the elements of its volumes, sorted.
///  - file: the geometry path.
/// Every volume must get tetrahedra. gmsh is a process-wide singleton: each call initializes and finalizes
/// it (serialized by a mutex); the caller must not have a gmsh session of its own open meanwhile, and a
/// .geo must not end the process (no "Exit;"). gmsh's own configuration files are not read.
/// nvh::Error naming the file for: an unsupported extension, a missing or unreadable file, a script or
/// CAD file gmsh cannot read, a geometry with no volume, a failed mesh (gmsh's error message, or a volume
/// left without tetrahedra), 3D elements other than tetrahedra (hexahedra, prisms, pyramids, ...), a .msh
/// without tetrahedra; and for order not 1 or 2, size < 0 or not finite, threads < 1.
Mesh mesh_with_gmsh(const GmshRequest& request);

}  // namespace nvh::condense
