#include "condense/mesh_export.hpp"

#include <unistd.h>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/xml.hpp"

namespace nvh::condense {

namespace {

/// XDMF 3 topology names of the Abaqus solid types (same node order).
std::string xdmf_topology(const std::string& type) {
  if (type == "C3D4") return "Tetrahedron";
  if (type == "C3D10") return "Tetrahedron_10";
  if (type == "C3D8") return "Hexahedron";
  if (type == "C3D20") return "Hexahedron_20";
  throw Error("no XDMF topology for element type " + type);
}

std::string shape_name(int j) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "shape_%04d", j + 1);
  return buffer;
}

/// A coordinate's name for ParaView: "001 mode 1 (123.4 Hz)".
std::string vector_name(const MeshExport& e, int j) {
  std::ostringstream s;
  s.precision(6);
  char index[16];
  std::snprintf(index, sizeof index, "%03d", j + 1);
  s << index << " " << e.coordinates[j];
  if (j < e.frequency_hz.size()) s << " (" << e.frequency_hz(j) << " Hz)";
  return s.str();
}

/// A 2-D int64 dataset (the HDF5 layer writes 1-D integer arrays only).
void write_int_matrix(h5::Group& group, const std::string& name,
                      const Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& m) {
  const hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  const h5::Handle space(H5Screate_simple(2, dims, nullptr));
  h5::Handle set(H5Dcreate2(group.id(), name.c_str(), H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                            H5P_DEFAULT));
  // The close writes what HDF5 still buffers (a full disk fails there): checked, not left to the Handle.
  if (!set.valid() || H5Dwrite(set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data()) < 0 ||
      H5Dclose(set.release()) < 0) {
    throw Error("cannot write the dataset " + group.path() + "/" + name);
  }
}

}  // namespace

MeshExport make_mesh_export(const Mesh& mesh, const Eigen::MatrixXd& shapes,
                            const std::vector<std::string>& coordinates,
                            const Eigen::VectorXd& frequency_hz) {
  // Only the nodes that elements use, renumbered densely.
  const int count = static_cast<int>(mesh.nodes.size());
  std::vector<int> index(count, -1);
  int used = 0;
  for (const MeshElement& e : mesh.elements)
    for (int n : e.nodes)
      if (index[n] < 0) index[n] = 0;
  std::vector<int> nodes;
  for (int n = 0; n < count; ++n) {
    if (index[n] < 0) continue;
    index[n] = used++;
    nodes.push_back(n);
  }
  MeshExport e;
  e.position.resize(used, 3);
  for (int i = 0; i < used; ++i) {
    e.position.row(i) = mesh.nodes[nodes[i]].transpose();
    e.labels.push_back(mesh.node_ids[nodes[i]]);
  }
  std::map<std::string, std::vector<const MeshElement*>> by_type;
  for (const MeshElement& el : mesh.elements) by_type[el.type].push_back(&el);
  for (const auto& [type, elements] : by_type) {
    const int k = static_cast<int>(elements.front()->nodes.size());
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> block(elements.size(), k);
    for (std::size_t r = 0; r < elements.size(); ++r)
      for (int j = 0; j < k; ++j) block(static_cast<Eigen::Index>(r), j) = index[elements[r]->nodes[j]];
    e.block_types.push_back(type);
    e.blocks.push_back(std::move(block));
  }
  e.coordinates = coordinates;
  e.frequency_hz = frequency_hz;
  for (Eigen::Index j = 0; j < shapes.cols(); ++j) {
    Eigen::MatrixXd s(used, 3);
    for (int i = 0; i < used; ++i)
      for (int a = 0; a < 3; ++a) s(i, a) = shapes(6 * nodes[i] + a, j);
    e.shapes.push_back(std::move(s));
  }
  return e;
}

std::filesystem::path mesh_export_h5_path(const std::filesystem::path& superelement) {
  std::filesystem::path p = superelement;
  return p.replace_extension(".mesh.h5");
}

std::filesystem::path mesh_export_xdmf_path(const std::filesystem::path& superelement) {
  std::filesystem::path p = superelement;
  return p.replace_extension(".xdmf");
}

void write_mesh_export(const std::filesystem::path& superelement, const MeshExport& e,
                       const Provenance& provenance) {
  const std::filesystem::path h5_path = mesh_export_h5_path(superelement);
  const std::filesystem::path xdmf_path = mesh_export_xdmf_path(superelement);
  const auto nodes = static_cast<hsize_t>(e.position.rows());
  {
    h5::File file = h5::File::create(h5_path);
    h5::Group root = file.root();
    root.set_attribute("format", kMeshExportFormat);
    root.set_attribute("format_version", kMeshExportFormatVersion);
    root.set_attribute("units", "SI (m)");
    write_provenance(root, provenance);
    h5::Group mesh = root.create_group("mesh");
    mesh.write("position", e.position);
    mesh.set_attribute("units", "m", "position");
    mesh.write("labels", std::span<const std::int64_t>(e.labels));
    for (std::size_t b = 0; b < e.blocks.size(); ++b) {
      const auto& block = e.blocks[b];
      h5::Group group = mesh.create_group(e.block_types[b]);
      write_int_matrix(group, "connectivity", block);
      group.set_attribute("description",
                          "(elements, nodes per element): 0-based indices into /mesh/position, in Abaqus (= "
                          "XDMF and VTK) node order",
                          "connectivity");
      group.set_attribute("elements", static_cast<std::int64_t>(block.rows()));
    }
    h5::Group modes = root.create_group("shapes");
    modes.write("coordinates", e.coordinates);
    if (e.frequency_hz.size() > 0) {
      modes.write("frequency_hz", e.frequency_hz);
      modes.set_attribute("units", "Hz", "frequency_hz");
    }
    for (std::size_t j = 0; j < e.shapes.size(); ++j) {
      const std::string name = shape_name(static_cast<int>(j));
      modes.write(name, e.shapes[j]);
      modes.set_attribute("units", "m per unit coordinate", name);
    }
    file.commit();
  }

  // The XDMF refers to the .h5 by its file name (both lie in the same folder).
  const std::string h5 = h5_path.filename().string();
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  const bool several = e.blocks.size() > 1;
  if (several) x << "  <Grid Name=\"component\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
  for (std::size_t b = 0; b < e.blocks.size(); ++b) {
    const auto& block = e.blocks[b];
    const std::string type = e.block_types[b];
    x << "  <Grid Name=\"" << type << "\" GridType=\"Uniform\">\n";
    x << "   <Topology TopologyType=\"" << xdmf_topology(type) << "\" NumberOfElements=\"" << block.rows()
      << "\">\n    <DataItem Dimensions=\"" << block.rows() << " " << block.cols()
      << "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/mesh/" << type
      << "/connectivity</DataItem>\n   </Topology>\n";
    x << "   <Geometry GeometryType=\"XYZ\">\n    <DataItem Dimensions=\"" << nodes
      << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
      << ":/mesh/position</DataItem>\n   </Geometry>\n";
    for (std::size_t j = 0; j < e.shapes.size(); ++j) {
      x << "   <Attribute Name=\"" << xml_escape(vector_name(e, static_cast<int>(j)))
        << "\" AttributeType=\"Vector\" Center=\"Node\">\n    <DataItem Dimensions=\"" << nodes
        << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/shapes/"
        << shape_name(static_cast<int>(j)) << "</DataItem>\n   </Attribute>\n";
    }
    x << "  </Grid>\n";
  }
  if (several) x << "  </Grid>\n";
  x << " </Domain>\n</Xdmf>\n";

  const std::filesystem::path temporary = xdmf_path.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary);
    out << x.str();
    out.close();
    if (!out) {
      std::filesystem::remove(temporary);
      throw Error("cannot write " + xdmf_path.string());
    }
  }
  std::filesystem::rename(temporary, xdmf_path);
}

}  // namespace nvh::condense
