#include "postproc/xdmf.hpp"

#include <sstream>

#include "common/xml.hpp"

namespace nvh::postproc {

namespace {

void data_item(std::ostringstream& x, const std::string& indent, std::int64_t rows, int columns,
               const char* number_type, const std::string& h5, const std::string& path) {
  x << indent << "<DataItem Dimensions=\"" << rows;
  if (columns > 1) x << " " << columns;
  x << "\" NumberType=\"" << number_type << "\" Precision=\"8\" Format=\"HDF\">" << xml_escape(h5) << ":"
    << xml_escape(path) << "</DataItem>\n";
}

}  // namespace

std::string xdmf_text(const XdmfSurfaceSeries& s) {
  std::ostringstream x;
  x.precision(17);
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  for (const auto& [name, value] : s.information)
    x << "  <Information Name=\"" << xml_escape(name) << "\" Value=\"" << xml_escape(value) << "\"/>\n";
  x << "  <Grid Name=\"" << xml_escape(s.name) << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < s.frames.size(); ++f) {
    const XdmfFrame& frame = s.frames[f];
    x << "   <Grid Name=\"frame " << f << "\" GridType=\"Uniform\">\n";
    x << "    <Time Value=\"" << frame.time << "\"/>\n";
    x << "    <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << s.triangles << "\">\n";
    data_item(x, "     ", s.triangles, 3, "Int", s.h5_file, s.topology);
    x << "    </Topology>\n    <Geometry GeometryType=\"XYZ\">\n";
    data_item(x, "     ", s.nodes, 3, "Float", s.h5_file, frame.geometry);
    x << "    </Geometry>\n";
    for (const XdmfField& field : frame.fields) {
      x << "    <Attribute Name=\"" << xml_escape(field.name) << "\" AttributeType=\""
        << (field.columns == 3 ? "Vector" : "Scalar") << "\" Center=\"Node\">\n";
      data_item(x, "     ", s.nodes, field.columns, "Float", s.h5_file, field.path);
      x << "    </Attribute>\n";
    }
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return x.str();
}

}  // namespace nvh::postproc
