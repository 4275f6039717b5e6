#include "postproc/uff58.hpp"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "postproc/signal.hpp"

namespace nvh::postproc {
namespace {

// Specific data type codes of records 8-11 (SDRL dataset 58 description).
int spec_data_type(const std::string& unit) {
  const std::string q = quantity_of_unit(unit);
  if (q == "displacement") return 8;
  if (q == "velocity") return 11;
  if (q == "acceleration") return 12;
  if (q == "force") return 13;
  if (q == "pressure") return 15;
  return 0;  // unknown
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// Reads a file line by line while keeping the byte position (binary blocks sit between ASCII lines).
class LineReader {
 public:
  LineReader(std::string bytes, std::string file) : bytes_(std::move(bytes)), file_(std::move(file)) {}
  bool next(std::string& line) {
    if (pos_ >= bytes_.size()) return false;
    const std::size_t end = bytes_.find('\n', pos_);
    const std::size_t stop = end == std::string::npos ? bytes_.size() : end;
    line = bytes_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos_ = stop + 1;
    ++line_;
    return true;
  }
  std::string require(const char* what) {
    std::string line;
    if (!next(line)) fail(std::string("file ends where ") + what + " was expected");
    return line;
  }
  /// Raw bytes (a binary block); lines are not counted inside it.
  std::string take(std::size_t n) {
    if (pos_ + n > bytes_.size())
      fail("binary block of " + std::to_string(n) + " bytes runs past the end of the file");
    std::string out = bytes_.substr(pos_, n);
    pos_ += n;
    return out;
  }
  [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }
  [[noreturn]] void fail_at(int line, const std::string& what) const {
    throw Error(file_ + ":" + std::to_string(line) + ": dataset 58: " + what);
  }
  int line() const { return line_; }

 private:
  std::string bytes_;
  std::string file_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

/// Finite and not subnormal: what a sample or an abscissa may be.
bool usable(double v) {
  return std::isfinite(v) && (v == 0 || std::abs(v) >= std::numeric_limits<double>::min());
}

double fixed_double(const std::string& line, std::size_t at, std::size_t width, LineReader& r,
                    const char* field) {
  const std::string text = trim(line.size() > at ? line.substr(at, width) : "");
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0')
    r.fail(std::string("record 7: ") + field + ": '" + text + "' is not a number");
  // strtod reads "inf", "nan" and overflows (1e999 as inf); a subnormal increment gives an infinite rate.
  if (!usable(v)) r.fail(std::string("record 7: ") + field + ": '" + text + "' is not a finite number");
  return v;
}

/// An integer field of record 7 within [lo, hi], checked before the conversion (undefined beyond the type).
std::int64_t fixed_integer(const std::string& line, std::size_t at, std::size_t width, LineReader& r,
                           const char* field, double lo, double hi) {
  const double v = fixed_double(line, at, width, r, field);
  if (!(v >= lo && v <= hi) || v != std::floor(v)) {
    std::ostringstream msg;
    msg << "record 7: " << field << ": " << v << " is not an integer in [" << lo << ", " << hi << "]";
    r.fail(msg.str());
  }
  return static_cast<std::int64_t>(v);
}

std::string fixed_text(const std::string& line, std::size_t at, std::size_t width) {
  return trim(line.size() > at ? line.substr(at, width) : "");
}

Uff58Record read_record(LineReader& r, bool binary, int byte_order, std::size_t n_bytes) {
  Uff58Record rec;
  rec.id1 = trim(r.require("record 1 (ID line 1)"));
  rec.id2 = trim(r.require("record 2 (ID line 2)"));
  for (int i = 3; i <= 5; ++i) r.require("records 3-5 (ID lines)");
  const std::string r6 = r.require("record 6 (function type and DOF)");
  {
    std::istringstream in(r6);
    int function_type = 0, function_id = 0, version = 0, load_case = 0;
    std::string entity;
    in >> function_type >> function_id >> version >> load_case >> entity >> rec.response_node >>
        rec.response_direction;
  }
  const std::string r7 = r.require("record 7 (data form)");
  const int r7_line = r.line();
  const int data_type = static_cast<int>(fixed_integer(r7, 0, 10, r, "ordinate data type", 0, 99));
  // At most 2^31 points (16 GB of doubles): a larger count is a corrupt record, not a measurement.
  const std::int64_t points = fixed_integer(r7, 10, 10, r, "number of points", 1, 2147483648.0);
  const int even = static_cast<int>(fixed_integer(r7, 20, 10, r, "abscissa spacing", 0, 1));
  rec.abscissa_min = fixed_double(r7, 30, 13, r, "abscissa minimum");
  rec.abscissa_increment = fixed_double(r7, 43, 13, r, "abscissa increment");
  if (data_type != 2 && data_type != 4)
    r.fail("ordinate data type " + std::to_string(data_type) +
           " not supported; expected 2 (real single) or 4 (real double) - a time history is real");
  if (points < 1) r.fail("record 7: number of points must be >= 1");
  r.require("record 8 (abscissa characteristics)");
  const std::string r9 = r.require("record 9 (ordinate characteristics)");
  rec.ordinate_label = fixed_text(r9, 26, 20);
  rec.ordinate_unit = fixed_text(r9, 47, 20);
  r.require("record 10 (denominator characteristics)");
  r.require("record 11 (z-axis characteristics)");

  const std::int64_t per_point = even ? 1 : 2;
  const std::int64_t count = points * per_point;
  std::vector<double> raw;
  raw.reserve(static_cast<std::size_t>(count));
  if (binary) {
    const std::size_t width = data_type == 2 ? 4 : 8;
    const std::size_t need = static_cast<std::size_t>(count) * width;
    if (n_bytes != 0 && n_bytes != need)
      r.fail("binary header says " + std::to_string(n_bytes) + " bytes, record 7 implies " +
             std::to_string(need));
    const std::string block = r.take(need);
    const bool swap = (byte_order == 2) != (std::endian::native == std::endian::big);
    for (std::int64_t i = 0; i < count; ++i) {
      unsigned char b[8];
      std::memcpy(b, block.data() + i * width, width);
      if (swap) std::reverse(b, b + width);
      if (width == 4) {
        float f;
        std::memcpy(&f, b, 4);
        raw.push_back(f);
      } else {
        double d;
        std::memcpy(&d, b, 8);
        raw.push_back(d);
      }
    }
    for (std::size_t i = 0; i < raw.size(); ++i)
      if (!usable(raw[i]))
        r.fail_at(r7_line,
                  "binary value " + std::to_string(i) + " (0-based) of the record is not a finite number");
    std::string end;
    while (r.next(end) && trim(end).empty()) {
    }
    if (trim(end) != "-1") r.fail("expected '    -1' after the binary data, found '" + end + "'");
  } else {
    std::string line;
    while (true) {
      line = r.require("data or the closing '    -1'");
      if (trim(line) == "-1") break;
      const char* p = line.c_str();
      char* end = nullptr;
      while (true) {
        const double v = std::strtod(p, &end);
        if (end == p) break;
        if (!usable(v)) {
          const char* first = p;
          while (first < end && std::isspace(static_cast<unsigned char>(*first))) ++first;
          std::ostringstream msg;
          msg << "'" << std::string_view(first, static_cast<std::size_t>(end - first))
              << "' is not a finite number (sample " << raw.size() / per_point << ", 0-based)";
          r.fail(msg.str());
        }
        raw.push_back(v);
        p = end;
      }
      if (trim(std::string(p)).size() > 0) r.fail("'" + trim(std::string(p)) + "' is not a number");
    }
    if (static_cast<std::int64_t>(raw.size()) != count)
      r.fail_at(r7_line, "record 7 announces " + std::to_string(points) + " points, found " +
                             std::to_string(raw.size() / per_point) + " (data ends at line " +
                             std::to_string(r.line()) + ")");
  }
  if (even) {
    rec.values = std::move(raw);
  } else {
    // Uneven abscissa: (x, y) pairs; accepted only if x is uniform (postproc needs a sample rate).
    const double x0 = raw[0], x1 = raw[2 * (points - 1)];
    rec.abscissa_min = x0;
    rec.abscissa_increment = points > 1 ? (x1 - x0) / static_cast<double>(points - 1) : 0.0;
    for (std::int64_t i = 0; i < points; ++i) {
      const double expected = x0 + static_cast<double>(i) * rec.abscissa_increment;
      if (std::abs(raw[2 * i] - expected) > 1e-6 * std::abs(rec.abscissa_increment))
        r.fail("uneven abscissa is not uniform at point " + std::to_string(i) +
               "; postproc needs uniformly sampled signals");
      rec.values.push_back(raw[2 * i + 1]);
    }
  }
  return rec;
}

std::string fixed(const std::string& s, std::size_t width) {
  std::string out = s.substr(0, width);
  out.resize(width, ' ');
  return out;
}

}  // namespace

std::vector<Uff58Record> read_uff58(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open the universal file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LineReader r(std::move(bytes), path.string());
  std::vector<Uff58Record> records;
  std::string line;
  while (r.next(line)) {
    if (trim(line) != "-1") continue;
    std::string header;
    if (!r.next(header)) break;
    const int number = std::atoi(header.substr(0, 6).c_str());
    const bool binary = header.size() > 6 && (header[6] == 'b' || header[6] == 'B');
    if (number != 58) {
      // Skip an ASCII dataset of another type up to its closing "-1".
      while (r.next(line) && trim(line) != "-1") {
      }
      continue;
    }
    int byte_order = 1;
    std::size_t n_bytes = 0;
    if (binary) {
      std::istringstream fields(header.substr(7));
      int fp_format = 0, ascii_lines = 0;
      fields >> byte_order >> fp_format >> ascii_lines >> n_bytes;
      if (fp_format != 2 && fp_format != 0)
        r.fail("binary floating-point format " + std::to_string(fp_format) +
               " not supported; expected 2 (IEEE 754)");
    }
    records.push_back(read_record(r, binary, byte_order, n_bytes));
  }
  if (records.empty())
    throw Error(path.string() + ": no dataset 58 found (a universal file of time histories was expected)");
  return records;
}

void write_uff58(const std::filesystem::path& path, const std::vector<Uff58Record>& records, bool binary) {
  const std::filesystem::path temporary = path.string() + ".tmp-" + std::to_string(::getpid());
  register_temporary(temporary);
  {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw Error(path.string() + ": cannot create the file (does its directory exist?)");
    char buf[256];
    for (const Uff58Record& rec : records) {
      const std::size_t n = rec.values.size();
      out << "    -1\n";
      if (binary) {
        std::snprintf(buf, sizeof buf, "%6i%c%6i%6i%12i%12lu%6i%6i%12i%12i\n", 58, 'b', 1, 2, 11,
                      static_cast<unsigned long>(n * 8), 0, 0, 0, 0);
        out << buf;
      } else {
        out << "    58\n";
      }
      out << fixed(rec.id1.empty() ? "NONE" : rec.id1, 80) << "\n"
          << fixed(rec.id2.empty() ? "NONE" : rec.id2, 80) << "\n"
          << fixed("NONE", 80) << "\n"
          << fixed("NONE", 80) << "\n"
          << fixed("NONE", 80) << "\n";
      std::snprintf(buf, sizeof buf, "%5i%10i%5i%10i %-10s%10i%4i %-10s%10i%4i\n", 1, 0, 0, 0, "NONE",
                    rec.response_node, rec.response_direction, "NONE", 0, 0);
      out << buf;
      // E13.6 keeps seven digits of the sample interval (E13.5 would lose the sample rate's sixth digit).
      std::snprintf(buf, sizeof buf, "%10i%10lu%10i%13.6E%13.6E%13.5E\n", 4, static_cast<unsigned long>(n), 1,
                    rec.abscissa_min, rec.abscissa_increment, 0.0);
      out << buf;
      std::snprintf(buf, sizeof buf, "%10i%5i%5i%5i %-20s %-20s\n", 17, 0, 0, 0, "Time", "s");
      out << buf;
      std::snprintf(buf, sizeof buf, "%10i%5i%5i%5i %-20s %-20s\n", spec_data_type(rec.ordinate_unit), 0, 0,
                    0, fixed(rec.ordinate_label, 20).c_str(), fixed(rec.ordinate_unit, 20).c_str());
      out << buf;
      std::snprintf(buf, sizeof buf, "%10i%5i%5i%5i %-20s %-20s\n", 0, 0, 0, 0, "NONE", "NONE");
      out << buf << buf;
      if (binary) {
        // Little-endian IEEE double, as announced in the header (byte order 1).
        std::string block(n * 8, '\0');
        for (std::size_t i = 0; i < n; ++i) {
          unsigned char b[8];
          std::memcpy(b, &rec.values[i], 8);
          if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + 8);
          std::memcpy(block.data() + i * 8, b, 8);
        }
        out.write(block.data(), static_cast<std::streamsize>(block.size()));
        out << "    -1\n";
      } else {
        for (std::size_t i = 0; i < n; ++i) {
          std::snprintf(buf, sizeof buf, "%20.12E", rec.values[i]);
          out << buf;
          if (i % 4 == 3 || i + 1 == n) out << "\n";
        }
        out << "    -1\n";
      }
    }
    if (!out) throw Error(path.string() + ": write failed (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  unregister_temporary(temporary);
  if (ec) {
    std::filesystem::remove(temporary);
    throw Error(path.string() + ": cannot rename the finished file into place: " + ec.message());
  }
}

}  // namespace nvh::postproc
