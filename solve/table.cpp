#include "solve/table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "solve/element_registry.hpp"

namespace nvh::solve {

Table1D::Table1D(std::vector<double> x, std::vector<double> y, const std::string& where, double period)
    : x_(std::move(x)), y_(std::move(y)), period_(period) {
  if (x_.size() != y_.size())
    throw Error(where + ": the table has " + std::to_string(x_.size()) + " abscissae but " +
                std::to_string(y_.size()) + " values");
  if (x_.size() < 2) throw Error(where + ": a table needs at least 2 points");
  // Finite first: NaN would otherwise be reported as an abscissa that does not increase.
  for (std::size_t k = 0; k < x_.size(); ++k)
    if (!std::isfinite(x_[k]) || !std::isfinite(y_[k]))
      throw Error(where + ": point " + std::to_string(k + 1) + " is not a finite number");
  for (std::size_t k = 1; k < x_.size(); ++k)
    if (!(x_[k] > x_[k - 1]))
      throw Error(where + ": the abscissa must increase strictly, but point " + std::to_string(k + 1) + " (" +
                  std::to_string(x_[k]) + ") does not exceed point " + std::to_string(k) + " (" +
                  std::to_string(x_[k - 1]) + ")");
}

std::size_t Table1D::piece(double& x) const {
  if (period_ > 0) {
    x = x_.front() + std::fmod(x - x_.front(), period_);
    if (x < x_.front()) x += period_;
  }
  if (x <= x_.front()) return 0;
  if (x >= x_.back()) return x_.size() - 2;
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  return static_cast<std::size_t>(it - x_.begin()) - 1;
}

double Table1D::operator()(double x) const {
  if (period_ > 0) {  // periodic: interpolate across the wrap between the last and the first point
    double xw = x;
    piece(xw);
    if (xw > x_.back()) {
      const double x1 = x_.front() + period_;
      return y_.back() + (y_.front() - y_.back()) * (xw - x_.back()) / (x1 - x_.back());
    }
    x = xw;
  } else {
    x = std::clamp(x, x_.front(), x_.back());  // constant beyond the ends
  }
  double xx = x;
  const std::size_t k = piece(xx);
  const double s = (y_[k + 1] - y_[k]) / (x_[k + 1] - x_[k]);
  return y_[k] + s * (xx - x_[k]);
}

double Table1D::slope(double x) const {
  if (period_ <= 0 && (x < x_.front() || x > x_.back())) return 0.0;
  double xx = x;
  const std::size_t k = piece(xx);
  if (period_ > 0 && xx > x_.back())  // the periodic wrap from the last point to the first, as operator()
    return (y_.front() - y_.back()) / (x_.front() + period_ - x_.back());
  return (y_[k + 1] - y_[k]) / (x_[k + 1] - x_[k]);
}

double Table1D::integral(double x) const {
  double sum = 0;
  if (x <= x_.front()) return y_.front() * (x - x_.front());
  for (std::size_t k = 0; k + 1 < x_.size(); ++k) {
    if (x <= x_[k]) break;
    const double b = std::min(x, x_[k + 1]);
    const double yb = y_[k] + (y_[k + 1] - y_[k]) * (b - x_[k]) / (x_[k + 1] - x_[k]);
    sum += 0.5 * (y_[k] + yb) * (b - x_[k]);
  }
  if (x > x_.back()) sum += y_.back() * (x - x_.back());
  return sum;
}

namespace {
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r\"");
    const auto e = cell.find_last_not_of(" \t\r\"");
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return out;
}
bool parse_double(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0';
}
/// A table's numbers must be finite and no larger than the scene's other coefficients (element_registry.hpp):
/// strtod reads "inf", "nan" and overflows such as 1e999 (as inf) without complaint.
bool usable(double v) {
  return std::isfinite(v) && std::abs(v) <= bounds::kCoefficient &&
         (v == 0 || std::abs(v) >= std::numeric_limits<double>::min());
}
}  // namespace

Table1D read_csv_table(const std::filesystem::path& path, const std::string& x_column,
                       const std::string& y_column, double period) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open the table file");
  std::string line;
  int line_no = 0, xi = 0, yi = 1;
  bool header_seen = false;
  std::vector<double> x, y;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const auto cells = split_csv(line);
    double a = 0;
    if (!header_seen && x.empty() && !parse_double(cells[0], a)) {  // a header row
      header_seen = true;
      auto find = [&](const std::string& name, int fallback) {
        if (name.empty()) return fallback;
        for (std::size_t k = 0; k < cells.size(); ++k)
          if (cells[k] == name) return static_cast<int>(k);
        std::string have;
        for (const auto& c : cells) have += (have.empty() ? "" : ", ") + c;
        throw Error(path.string() + ":" + std::to_string(line_no) + ": no column '" + name +
                    "' (the header has: " + have + ")");
      };
      xi = find(x_column, 0);
      yi = find(y_column, 1);
      continue;
    }
    double vx = 0, vy = 0;
    if (static_cast<int>(cells.size()) <= std::max(xi, yi) || !parse_double(cells[xi], vx) ||
        !parse_double(cells[yi], vy))
      throw Error(path.string() + ":" + std::to_string(line_no) + ": expected numbers in columns " +
                  std::to_string(xi + 1) + " and " + std::to_string(yi + 1) + ", got '" + line + "'");
    for (const int column : {xi, yi}) {
      if (!usable(column == xi ? vx : vy))
        throw Error(path.string() + ":" + std::to_string(line_no) + ": column " + std::to_string(column + 1) +
                    ": '" + cells[column] +
                    "' is not a finite number of magnitude <= 1e20 (and not subnormal)");
    }
    x.push_back(vx);
    y.push_back(vy);
  }
  return Table1D(std::move(x), std::move(y), path.string(), period);
}

}  // namespace nvh::solve
