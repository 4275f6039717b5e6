#pragma once
// A 1-D table y(x), piecewise linear, strictly increasing abscissae; optionally periodic in x.
// Read from a TOML array of pairs or from a CSV file (two named or numbered columns).
#include <filesystem>
#include <string>
#include <vector>

namespace nvh::solve {

class Table1D {
 public:
  Table1D() = default;
  /// Throws nvh::Error naming `where` if x is not strictly increasing or sizes differ or fewer than 2 points.
  Table1D(std::vector<double> x, std::vector<double> y, const std::string& where, double period = 0.0);

  double operator()(double x) const;
  /// dy/dx of the piece containing x.
  double slope(double x) const;
  /// Integral of y from x[0]... to x (non-periodic tables; linear extrapolation by the end values beyond).
  double integral(double x) const;
  double x_min() const { return x_.front(); }
  double x_max() const { return x_.back(); }
  bool empty() const { return x_.empty(); }
  /// The table's points as given (abscissae strictly increasing).
  const std::vector<double>& xs() const { return x_; }
  const std::vector<double>& ys() const { return y_; }

 private:
  std::size_t piece(double& x) const;  // wraps x for periodic tables, returns the left index
  std::vector<double> x_, y_;
  double period_ = 0.0;
};

/// Read two columns of a CSV file (header row optional: columns by name if given, else by index 0 and 1).
/// Errors name the file and line.
Table1D read_csv_table(const std::filesystem::path& path, const std::string& x_column,
                       const std::string& y_column, double period = 0.0);

}  // namespace nvh::solve
