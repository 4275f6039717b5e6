#pragma once
// XDMF 3 (XML, http://xdmf.org/index.php/XDMF_Model_and_Format) for a triangulated surface over time: a
// Temporal collection of Uniform grids, one per frame, each with a Triangle topology, an XYZ geometry and
// node-centred attributes, all of them HDF5 datasets referred to as "FILE.h5:/path" (the file by its name
// only: keep the .xdmf and the .h5 in the same folder). ParaView opens it with its Xdmf3 readers.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/xml.hpp"

namespace nvh::postproc {

/// An HDF5 dataset of float64 values, (rows) or (rows, columns).
struct XdmfField {
  std::string name;  ///< attribute name shown by ParaView (empty for a geometry)
  std::string path;  ///< dataset path in the HDF5 file
  int columns = 1;   ///< 1: Scalar, 3: Vector
};

struct XdmfFrame {
  double time = 0.0;              ///< s
  std::string geometry;           ///< dataset of the node positions (nodes, 3)
  std::vector<XdmfField> fields;  ///< node-centred attributes
};

struct XdmfSurfaceSeries {
  std::string h5_file;     ///< the HDF5 file's name, as the DataItems refer to it
  std::string name;        ///< the collection's name
  std::int64_t nodes = 0;  ///< rows of every geometry and field
  std::int64_t triangles = 0;
  std::string topology;  ///< dataset of the triangles (triangles, 3) int64, 0-based node indices
  std::vector<std::pair<std::string, std::string>> information;  ///< Domain <Information Name= Value=>
  std::vector<XdmfFrame> frames;
};

/// The XML text.
std::string xdmf_text(const XdmfSurfaceSeries& series);

/// `text` with &, <, >, " and ' escaped for XML (common/xml.hpp).
using nvh::xml_escape;

}  // namespace nvh::postproc
