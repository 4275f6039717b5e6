#include "postproc/signal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "postproc/uff58.hpp"

namespace nvh::postproc {
namespace {

constexpr std::int64_t kBlock = 1 << 20;  // samples per block when scanning a time dataset
// A time axis is uniform if every sample lies within this fraction of a step of t0 + i dt.
constexpr double kUniformTolerance = 1e-4;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n\"");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n\"");
  return s.substr(b, e - b + 1);
}

enum class Kind { kHdf5, kCsv, kUff };

struct ParsedAddress {
  std::filesystem::path file;
  Kind kind = Kind::kHdf5;
  std::string path;  // dataset path, CSV column, UFF record number ("" = default)
};

// "FILE.ext:rest": the file ends at the first ':' after a known extension (so a path may contain ':').
ParsedAddress parse_address(const std::string& address) {
  const std::vector<std::pair<std::string, Kind>> extensions = {{".h5", Kind::kHdf5}, {".hdf5", Kind::kHdf5},
                                                                {".csv", Kind::kCsv}, {".uff", Kind::kUff},
                                                                {".unv", Kind::kUff}, {".uff58", Kind::kUff}};
  const std::string low = lower(address);
  for (const auto& [ext, kind] : extensions) {
    std::size_t at = 0;
    while ((at = low.find(ext, at)) != std::string::npos) {
      const std::size_t end = at + ext.size();
      if (end == low.size() || low[end] == ':') {
        ParsedAddress parsed{address.substr(0, end), kind, end == low.size() ? "" : address.substr(end + 1)};
        if (kind != Kind::kUff && parsed.path.empty())
          throw Error("signal '" + address + "': no " + (kind == Kind::kCsv ? "column" : "dataset") +
                      " given; expected " +
                      (kind == Kind::kCsv ? "FILE.csv:COLUMN" : "FILE.h5:/path/to/dataset"));
        return parsed;
      }
      at = end;
    }
  }
  throw Error("signal '" + address +
              "': expected FILE.h5:/dataset[column], FILE.csv:column or FILE.uff[:N] (the file extension "
              "tells the format)");
}

// Samples above this magnitude are refused: every analysis sums squares (RMS, power spectra, levels), and the
// square of 1e155 overflows a double. No physical signal in SI units comes near it.
constexpr double kMaxSampleMagnitude = 1e150;

void check_finite(std::span<const double> values, std::int64_t offset, const std::string& address) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      std::ostringstream msg;
      msg << "signal '" << address << "': sample " << offset + static_cast<std::int64_t>(i) << " is "
          << values[i] << "; expected finite numbers (NaN or infinite samples cannot be analysed)";
      throw Error(msg.str());
    }
    if (std::abs(values[i]) > kMaxSampleMagnitude) {
      std::ostringstream msg;
      msg << "signal '" << address << "': sample " << offset + static_cast<std::int64_t>(i) << " is "
          << values[i] << "; expected a magnitude up to " << kMaxSampleMagnitude
          << " (its square, in every RMS, spectrum and level, would overflow)";
      throw Error(msg.str());
    }
  }
}

// Sample rate from equally spaced times; error naming `where` if they are not.
double rate_from_times(const std::string& where, std::int64_t n, double t0, double t_last,
                       const std::function<void(std::int64_t, std::span<double>)>& read_times) {
  if (n < 2)
    throw Error(where + ": needs at least 2 times to give a sample rate, found " + std::to_string(n));
  const double dt = (t_last - t0) / static_cast<double>(n - 1);
  if (!(dt > 0.0))
    throw Error(where + ": times must increase; first " + std::to_string(t0) + " s, last " +
                std::to_string(t_last) + " s");
  if (!std::isfinite(1.0 / dt))  // a subnormal step: the rate would be infinite
    throw Error(where + ": the time step " + std::to_string(dt) + " s gives no finite sample rate");
  std::vector<double> block;
  for (std::int64_t start = 0; start < n; start += kBlock) {
    const std::int64_t count = std::min(kBlock, n - start);
    block.resize(count);
    read_times(start, block);
    for (std::int64_t i = 0; i < count; ++i) {
      const double expected = t0 + static_cast<double>(start + i) * dt;
      if (std::abs(block[i] - expected) > kUniformTolerance * dt) {
        std::ostringstream msg;
        msg.precision(10);
        msg << where << ": times are not uniformly spaced: sample " << start + i << " is at " << block[i]
            << " s, expected " << expected << " s for a constant step of " << dt
            << " s; postproc needs uniformly sampled signals (resample first)";
        throw Error(msg.str());
      }
    }
  }
  return 1.0 / dt;
}

std::string column_suffix(const std::string& spec, hsize_t columns, const std::string& where,
                          hsize_t& column) {
  const std::string s = lower(trim(spec));
  if (s == "x" || s == "y" || s == "z") {
    column = static_cast<hsize_t>(s[0] - 'x');
  } else {
    char* end = nullptr;
    const long value = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || value < 0)
      throw Error(where + ": column '" + spec + "' is not a 0-based index or x, y, z");
    column = static_cast<hsize_t>(value);
  }
  if (column >= columns)
    throw Error(where + ": column " + std::to_string(column) + " out of range; the dataset has " +
                std::to_string(columns) + " columns (0-based)");
  if (columns == 3) return std::string(1, static_cast<char>('x' + column));
  std::string suffix = "c";
  suffix += std::to_string(column);
  return suffix;
}

}  // namespace

std::string sanitize_name(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    out += ok ? c : '_';
  }
  while (!out.empty() && out.front() == '_') out.erase(out.begin());
  return out.empty() ? "signal" : out;
}

std::pair<std::string, std::string> split_named_address(const std::string& text) {
  const auto eq = text.find('=');
  const auto colon = text.find(':');
  if (eq != std::string::npos && (colon == std::string::npos || eq < colon) && text.find('.') > eq)
    return {text.substr(0, eq), text.substr(eq + 1)};
  return {"", text};
}

std::string quantity_of_unit(const std::string& unit) {
  const std::string u = trim(unit);
  if (u == "m/s^2" || u == "m/s2" || u == "m s^-2") return "acceleration";
  if (u == "m/s" || u == "m s^-1") return "velocity";
  if (u == "m") return "displacement";
  if (u == "Pa") return "pressure";
  if (u == "N") return "force";
  if (u == "W") return "power";
  return "";
}

// ---------------------------------------------------------------------------------------------

struct SignalSource::Impl {
  // In memory (CSV, UFF, from_samples) ...
  std::vector<double> samples;
  // ... or an HDF5 dataset read by hyperslabs.
  std::unique_ptr<h5::File> file;
  h5::Handle dataset;
  int rank = 1;
  hsize_t column = 0;
};

SignalSource::SignalSource(SignalSource&&) noexcept = default;
SignalSource& SignalSource::operator=(SignalSource&&) noexcept = default;
SignalSource::~SignalSource() = default;

SignalSource SignalSource::from_samples(std::string name, std::vector<double> samples, double sample_rate_hz,
                                        std::string unit) {
  SignalSource s;
  s.impl_ = std::make_unique<Impl>();
  s.info_.name = sanitize_name(name);
  s.info_.address = name;
  s.info_.unit = std::move(unit);
  s.info_.sample_rate_hz = sample_rate_hz;
  s.info_.size = static_cast<std::int64_t>(samples.size());
  check_finite(samples, 0, name);
  s.impl_->samples = std::move(samples);
  return s;
}

namespace {

// The HDF5 part of open(): dataset, optional column, rate from attributes or a time dataset.
void open_hdf5(const ParsedAddress& a, const std::string& address, SignalInfo& info, SignalSource::Impl& impl,
               std::string& default_name) {
  impl.file = std::make_unique<h5::File>(h5::File::open_read(a.file));
  std::string path = a.path;
  std::string column_spec;
  bool has_column = false;
  if (!path.empty() && path.back() == ']') {
    const auto open = path.rfind('[');
    if (open == std::string::npos) throw Error("signal '" + address + "': ']' without '['");
    column_spec = path.substr(open + 1, path.size() - open - 2);
    path = path.substr(0, open);
    has_column = true;
  }
  if (path.empty() || path[0] != '/') path = "/" + path;
  const std::string where = a.file.string() + ":" + path;
  const h5::Group& root = impl.file->root();
  if (!root.exists(path)) throw Error(where + ": no such dataset in the file");
  const std::vector<hsize_t> dims = root.shape(path);
  // A corrupted shape can claim more samples than the file holds even compressed (deflate: at most about
  // 1032:1); refused here, before a reader sizes its buffers by it.
  hsize_t values = 1;
  for (const hsize_t d : dims) values = d == 0 || values <= ~hsize_t{0} / d ? values * d : ~hsize_t{0};
  std::error_code size_error;
  const auto file_bytes = static_cast<hsize_t>(std::filesystem::file_size(a.file, size_error));
  if (!size_error && values / 1100 > (file_bytes + (hsize_t{1} << 20)) / 8)
    throw Error(where + ": corrupt: its shape holds more values than the file (" +
                std::to_string(file_bytes) + " bytes) can hold");
  impl.rank = static_cast<int>(dims.size());
  default_name = path.substr(1);
  if (dims.size() == 1) {
    if (has_column) throw Error(where + ": a 1-D dataset has no columns; drop [" + column_spec + "]");
    info.size = static_cast<std::int64_t>(dims[0]);
  } else if (dims.size() == 2) {
    if (!has_column)
      throw Error(where + ": the dataset has shape (" + std::to_string(dims[0]) + ", " +
                  std::to_string(dims[1]) + "); choose a column, e.g. " + path + "[0]");
    default_name += '_';
    default_name += column_suffix(column_spec, dims[1], where, impl.column);
    info.size = static_cast<std::int64_t>(dims[0]);
  } else {
    throw Error(where + ": expected a 1-D dataset or a column of a 2-D one, found rank " +
                std::to_string(dims.size()));
  }
  impl.dataset = h5::Handle(H5Dopen2(root.id(), path.c_str(), H5P_DEFAULT));
  if (!impl.dataset.valid()) throw Error(where + ": cannot open the dataset");
  {
    const h5::Handle type(H5Dget_type(impl.dataset.get()));
    const H5T_class_t type_class = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
    if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
      throw Error(where + ": expected numeric data (float or integer samples)");
    if (const std::string fault = h5::numeric_type_fault(type.get()); !fault.empty())
      throw Error(where + ": " + fault);
  }
  std::string group_path = path.substr(0, path.rfind('/'));
  if (root.has_attribute("unit", path)) info.unit = root.string_attribute("unit", path);
  if (info.unit.empty() && root.has_attribute("units", path))
    info.unit = root.string_attribute("units", path);

  // Sample rate: attribute on the dataset, then on each group up to the root; else a `time` dataset in the
  // same group or a group above.
  if (root.has_attribute("sample_rate_hz", path)) {
    info.sample_rate_hz = root.double_attribute("sample_rate_hz", path);
  } else {
    std::string g = group_path;
    while (true) {
      const std::string here = g.empty() ? "/" : g;
      if (root.has_attribute("sample_rate_hz", here)) {
        info.sample_rate_hz = root.double_attribute("sample_rate_hz", here);
        break;
      }
      const std::string time_path = (g.empty() ? "" : g) + "/time";
      if (time_path != path && root.exists(time_path)) {
        const std::vector<hsize_t> tdims = root.shape(time_path);
        const std::string twhere = a.file.string() + ":" + time_path;
        if (tdims.size() != 1 || static_cast<std::int64_t>(tdims[0]) != info.size)
          throw Error(twhere + ": expected a 1-D time of " + std::to_string(info.size) + " samples beside " +
                      path);
        h5::Handle tset(H5Dopen2(root.id(), time_path.c_str(), H5P_DEFAULT));
        auto read_times = [&](std::int64_t start, std::span<double> out) {
          const hsize_t offset[1] = {static_cast<hsize_t>(start)};
          const hsize_t count[1] = {out.size()};
          h5::Handle file_space(H5Dget_space(tset.get()));
          H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, offset, nullptr, count, nullptr);
          h5::Handle mem_space(H5Screate_simple(1, count, nullptr));
          if (H5Dread(tset.get(), H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT,
                      out.data()) < 0)
            throw Error(twhere + ": cannot read");
        };
        double first = 0, last = 0;
        read_times(0, {&first, 1});
        read_times(info.size - 1, {&last, 1});
        info.start_time_s = first;
        info.sample_rate_hz = rate_from_times(twhere, info.size, first, last, read_times);
        break;
      }
      if (g.empty()) break;
      g = g.substr(0, g.rfind('/'));
    }
  }
  if (!(info.sample_rate_hz > 0.0))
    throw Error(where +
                ": no sample rate: expected a 'sample_rate_hz' attribute (> 0) on the dataset or a "
                "group above it, or a uniformly spaced 'time' dataset beside it");
}

// CSV: a header row of names (optionally "name [unit]"), comma- or semicolon-separated numbers below.
void open_csv(const ParsedAddress& a, SignalInfo& info, SignalSource::Impl& impl, std::string& default_name) {
  std::ifstream in(a.file);
  if (!in) throw Error(a.file.string() + ": cannot open the CSV file");
  std::string line;
  int line_number = 0;
  std::vector<std::string> names, units;
  char separator = ',';
  while (std::getline(in, line)) {
    ++line_number;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    if (line.find(',') == std::string::npos && line.find(';') != std::string::npos) separator = ';';
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, separator)) {
      std::string name = trim(field), unit;
      const auto bracket = name.find('[');
      if (bracket != std::string::npos && name.back() == ']') {
        unit = trim(name.substr(bracket + 1, name.size() - bracket - 2));
        name = trim(name.substr(0, bracket));
      }
      names.push_back(name);
      units.push_back(unit);
    }
    break;
  }
  if (names.empty()) throw Error(a.file.string() + ": empty CSV file; expected a header row of column names");
  auto find_column = [&](const std::string& wanted) -> int {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == wanted) return static_cast<int>(i);
    return -1;
  };
  int column = find_column(a.path);
  if (column < 0) {
    char* end = nullptr;
    const long index = std::strtol(a.path.c_str(), &end, 10);
    if (*end == '\0' && index >= 0 && index < static_cast<long>(names.size()))
      column = static_cast<int>(index);
  }
  if (column < 0) {
    std::ostringstream msg;
    msg << a.file.string() << ":" << line_number << ": no column '" << a.path << "'; the header has:";
    for (const auto& n : names) msg << " " << n;
    throw Error(msg.str());
  }
  int time_column = -1;
  for (const char* t : {"time", "time_s", "t"})
    if (time_column < 0) time_column = find_column(t);
  std::vector<double> times;
  while (std::getline(in, line)) {
    ++line_number;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    std::stringstream ss(line);
    std::string field;
    int c = 0;
    bool found = false;
    while (std::getline(ss, field, separator)) {
      if (c == column || c == time_column) {
        const std::string text = trim(field);
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(value)) {
          std::ostringstream msg;
          msg << a.file.string() << ":" << line_number << ": column '" << names[c] << "': '" << text
              << "' is not a finite number";
          throw Error(msg.str());
        }
        if (c == column) {
          impl.samples.push_back(value);
          found = true;
        }
        if (c == time_column) times.push_back(value);
      }
      ++c;
    }
    if (!found) {
      std::ostringstream msg;
      msg << a.file.string() << ":" << line_number << ": the row has no column " << column << " ('"
          << names[column] << "')";
      throw Error(msg.str());
    }
  }
  info.size = static_cast<std::int64_t>(impl.samples.size());
  info.unit = units[column];
  default_name = names[column];
  if (time_column < 0)
    throw Error(a.file.string() + ": no time column; expected a column named time, time_s or t (s)");
  info.start_time_s = times.empty() ? 0.0 : times.front();
  std::ostringstream time_where;
  time_where << a.file.string() << ": column '" << names[time_column] << "'";
  info.sample_rate_hz =
      rate_from_times(time_where.str(), info.size, times.empty() ? 0.0 : times.front(),
                      times.empty() ? 0.0 : times.back(), [&](std::int64_t start, std::span<double> out) {
                        std::copy_n(times.begin() + start, out.size(), out.begin());
                      });
}

void open_uff(const ParsedAddress& a, SignalInfo& info, SignalSource::Impl& impl, std::string& default_name) {
  std::vector<Uff58Record> records = read_uff58(a.file);
  int index = 1;
  if (!a.path.empty()) {
    char* end = nullptr;
    index = static_cast<int>(std::strtol(a.path.c_str(), &end, 10));
    if (*end != '\0' || index < 1)
      throw Error(a.file.string() + ": record '" + a.path + "': expected a 1-based dataset 58 number");
  }
  if (index > static_cast<int>(records.size()))
    throw Error(a.file.string() + ": asked for dataset 58 number " + std::to_string(index) +
                ", the file has " + std::to_string(records.size()));
  Uff58Record& r = records[index - 1];
  if (!(r.abscissa_increment > 0.0))
    throw Error(a.file.string() + ": dataset 58 number " + std::to_string(index) +
                ": abscissa increment must be > 0 s");
  info.sample_rate_hz = 1.0 / r.abscissa_increment;
  info.start_time_s = r.abscissa_min;
  info.unit = r.ordinate_unit == "NONE" ? "" : r.ordinate_unit;
  info.size = static_cast<std::int64_t>(r.values.size());
  default_name = trim(r.id1).empty() || trim(r.id1) == "NONE"
                     ? a.file.stem().string() + "_" + std::to_string(index)
                     : trim(r.id1);
  impl.samples = std::move(r.values);
}

}  // namespace

std::filesystem::path SignalSource::file_of(const std::string& text) {
  return parse_address(split_named_address(text).second).file;
}

SignalSource SignalSource::open(const std::string& text) {
  const auto [name, address] = split_named_address(text);
  const ParsedAddress parsed = parse_address(address);
  if (!std::filesystem::exists(parsed.file))
    throw Error("signal '" + address + "': file " + parsed.file.string() + " not found");
  SignalSource s;
  s.impl_ = std::make_unique<Impl>();
  s.info_.address = address;
  s.info_.file = parsed.file;
  std::string default_name;
  switch (parsed.kind) {
    case Kind::kHdf5:
      open_hdf5(parsed, address, s.info_, *s.impl_, default_name);
      break;
    case Kind::kCsv:
      open_csv(parsed, s.info_, *s.impl_, default_name);
      break;
    case Kind::kUff:
      open_uff(parsed, s.info_, *s.impl_, default_name);
      break;
  }
  s.info_.name = sanitize_name(name.empty() ? default_name : name);
  if (s.info_.size < 1) throw Error("signal '" + address + "': no samples");
  if (!s.impl_->samples.empty()) check_finite(s.impl_->samples, 0, address);
  return s;
}

void SignalSource::read(std::int64_t window_offset, std::span<double> out) const {
  const auto count = static_cast<std::int64_t>(out.size());
  if (window_offset < 0 || window_offset + count > info_.size)
    throw Error("signal '" + info_.address + "': read of samples [" + std::to_string(window_offset) + ", " +
                std::to_string(window_offset + count) + ") beyond its " + std::to_string(info_.size) +
                " samples");
  const std::int64_t offset = first_ + window_offset;  // in the file
  if (count == 0) return;
  if (!impl_->dataset.valid()) {
    std::copy_n(impl_->samples.begin() + offset, count, out.begin());
    return;
  }
  h5::Handle file_space(H5Dget_space(impl_->dataset.get()));
  const hsize_t mem_count[1] = {static_cast<hsize_t>(count)};
  h5::Handle mem_space(H5Screate_simple(1, mem_count, nullptr));
  herr_t status;
  if (impl_->rank == 1) {
    const hsize_t start[1] = {static_cast<hsize_t>(offset)};
    status = H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, mem_count, nullptr);
  } else {
    const hsize_t start[2] = {static_cast<hsize_t>(offset), impl_->column};
    const hsize_t block[2] = {static_cast<hsize_t>(count), 1};
    status = H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, block, nullptr);
  }
  if (status < 0 || H5Dread(impl_->dataset.get(), H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(),
                            H5P_DEFAULT, out.data()) < 0)
    throw Error("signal '" + info_.address + "': cannot read samples " + std::to_string(offset) + " to " +
                std::to_string(offset + count - 1) + " (is the dataset numeric?)");
  check_finite(out, offset, info_.address);
}

void SignalSource::restrict_to(std::int64_t first, std::int64_t count) {
  if (file_size_ < 0) {
    file_size_ = info_.size;
    file_start_s_ = info_.start_time_s;
  }
  if (first < 0 || count < 1 || first + count > file_size_)
    throw Error("signal '" + info_.address + "': window of samples [" + std::to_string(first) + ", " +
                std::to_string(first + count) + ") is not inside its " + std::to_string(file_size_) +
                " samples");
  first_ = first;
  info_.size = count;
  info_.start_time_s = file_start_s_ + static_cast<double>(first) / info_.sample_rate_hz;
}

std::vector<double> SignalSource::read_all() const {
  std::vector<double> all(static_cast<std::size_t>(info_.size));
  read(0, all);
  return all;
}

}  // namespace nvh::postproc
