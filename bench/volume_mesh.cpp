// bench_volume_mesh: mesh a geometry with gmsh exactly as condense does (second-order tetrahedra, the
// given size) and write it as an Abaqus/CalculiX .inp, so that condense and CalculiX solve the very same
// mesh in bench/run_volume_bench.sh. Prints the node, element and DOF counts.
//
// usage: bench_volume_mesh GEOMETRY SIZE_M OUT.inp
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>

#include "condense/abaqus_mesh.hpp"
#include "condense/gmsh_mesh.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: bench_volume_mesh GEOMETRY SIZE_M OUT.inp\n");
    return 2;
  }
  try {
    using namespace nvh::condense;
    const Mesh mesh = mesh_with_gmsh(GmshRequest{argv[1], 2, std::atof(argv[2]), 1});
    std::ofstream out(argv[3]);
    write_abaqus_mesh(mesh, out);
    out.close();
    if (!out) throw std::runtime_error(std::string("cannot write ") + argv[3]);
    std::printf("%zu nodes, %zu elements, %zu DOF\n", mesh.nodes.size(), mesh.elements.size(),
                3 * mesh.nodes.size());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_volume_mesh: %s\n", e.what());
    return 1;
  }
}
