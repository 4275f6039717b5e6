#pragma once
// Universal File Format, dataset 58 (function at a nodal DOF), ASCII and binary ("58b"): the exchange
// format of measured time histories in test labs, so that measured and simulated signals meet in one plot.
//
// Layout (SDRC/I-DEAS "Universal Dataset Number 58", University of Cincinnati SDRL description):
//   "    -1" / "    58" (binary: "    58b" + byte order, float format, 11 ASCII lines, byte count)
//   records 1-5: ID lines (80A); record 6: function type, response node and direction (I5,I10,...)
//   record 7: ordinate data type (2 real single, 4 real double), number of points, even spacing (1),
//             abscissa minimum and increment (3I10,3E13.5)
//   records 8-11: abscissa, ordinate, denominator and z-axis data characteristics (I10,3I5,2(1X,A20))
//   record 12: the ordinates (ASCII: 6E13.5 single, 4E20.12 double; binary: raw IEEE 754)
//   "    -1"
// Only real, evenly spaced time histories (function type 1) are written; reading also accepts uneven
// abscissae if they are uniform within 1e-6 of the step.
#include <filesystem>
#include <string>
#include <vector>

namespace nvh::postproc {

struct Uff58Record {
  std::string id1;                      ///< record 1: free text (we write the signal name)
  std::string id2;                      ///< record 2: free text
  std::string ordinate_label = "NONE";  ///< record 9 axis label
  std::string ordinate_unit = "NONE";   ///< record 9 axis unit label (e.g. "m/s^2")
  int response_node = 1;
  int response_direction = 0;       ///< 1..3 = +X..+Z, -1..-3 = -X..-Z, 0 scalar
  double abscissa_min = 0.0;        ///< start time, s
  double abscissa_increment = 0.0;  ///< sample interval, s
  std::vector<double> values;
};

/// All dataset-58 records of a file (other datasets are skipped). Errors name the file, the line and what
/// was expected.
std::vector<Uff58Record> read_uff58(const std::filesystem::path& path);

/// Write the records as ASCII (4E20.12 double precision) or binary (58b, little-endian IEEE double).
/// Written under a temporary name and renamed when complete.
void write_uff58(const std::filesystem::path& path, const std::vector<Uff58Record>& records, bool binary);

}  // namespace nvh::postproc
