#pragma once
// A small RAII layer over the HDF5 C API: files, groups, datasets and attributes.
//
// Conventions (documented in docs/hdf5-format.md):
// - Eigen matrices are written as 2-D datasets of shape (rows, cols) in HDF5's row-major order, so h5py's
//   `f[path][i, j]` is the matrix entry (i, j).
// - N-D arrays are written from a flat buffer in row-major (C) order with the given dims.
// - Strings are variable-length UTF-8.
// - Outputs are created under a temporary name beside the final path and renamed onto it by commit():
//   a reader never sees a half-written file, and a File destroyed without commit() removes its temporary.
// - Every read checks rank, shape (where asked) and type, and a failure names the file and the path.
#include <hdf5.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace nvh::h5 {

/// Owns one HDF5 identifier (file, group, dataset, dataspace, datatype, attribute, property list)
/// and closes it with the right H5*close on destruction. Move-only.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(other.id_) { other.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle();

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Give up the id without closing it. For a file about to be closed by hand: HDF5 1.10 keeps the id of a
  /// file whose H5Fclose failed (a full disk) pointing at a half-freed file, and a second close crashes.
  hid_t release() noexcept {
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

/// Options of a chunked, compressed dataset.
struct Chunking {
  std::vector<hsize_t> chunk;  ///< chunk dims; empty: chosen automatically
  int deflate_level = 4;       ///< gzip level 0..9 (0: no compression)
};

class Group;

/// A dataset that grows along its first dimension (time histories, sweep tables).
/// Created by Group::create_appendable; each append() adds rows and extends the dataset on disk.
class AppendableDataset {
 public:
  AppendableDataset() = default;
  /// Append `rows` x columns() values given row-major.
  void append(std::span<const double> row_major_values);
  hsize_t rows() const { return rows_; }
  hsize_t columns() const { return columns_; }
  /// Write pending data to disk (H5Dflush) so a killed run keeps it.
  void flush();
  /// A string attribute on this dataset (replaced if present), written through the open handle: no lookup of
  /// its path (a results file's ~200 `unit` attributes cost 0.17 M instructions each by path).
  void set_attribute(std::string_view attr, const std::string& value);
  /// Shrink to the first `rows` rows (a restart drops the rows written after its checkpoint).
  void truncate(hsize_t rows);

 private:
  friend class Group;
  Handle dataset_;
  std::string path_;  // for error messages: "file.h5:/group/name"
  hsize_t rows_ = 0;
  hsize_t columns_ = 0;
  int rank_ = 2;  // 1 for a growing vector (create_appendable_vector)
};

/// An HDF5 group (the root group "/" included). Paths are relative to this group; "a/b/c" is allowed.
class Group {
 public:
  Group() = default;

  // --- structure ---
  /// Create a group (and missing intermediate groups); error if it exists as a dataset.
  Group create_group(std::string_view path);
  /// Open an existing group; error naming the file and path if it is missing.
  Group open_group(std::string_view path) const;
  /// True if a link (group or dataset) exists at `path` (intermediate groups checked too).
  bool exists(std::string_view path) const;
  /// Names of the direct members (groups and datasets), in creation/name order.
  std::vector<std::string> members() const;
  /// Full path of this group inside its file, e.g. "/invariants".
  const std::string& path() const { return path_; }

  // --- writing datasets (error if the name exists) ---
  void write(std::string_view name, double value);
  void write(std::string_view name, std::int64_t value);
  void write(std::string_view name, int value);  // as int64 (a bare `3` would otherwise be ambiguous)
  void write(std::string_view name, const Eigen::VectorXd& values);
  void write(std::string_view name, const Eigen::MatrixXd& values);  // shape (rows, cols)
  /// Any other Eigen expression (e.g. `A * x`, `VectorXd::Zero(n)`, which would be ambiguous between the two
  /// above): a vector if it has one column at compile time, else a matrix.
  template <typename Derived>
  void write(std::string_view name, const Eigen::MatrixBase<Derived>& values) {
    if constexpr (Derived::ColsAtCompileTime == 1) {
      write(name, Eigen::VectorXd(values));
    } else {
      write(name, Eigen::MatrixXd(values));
    }
  }
  void write(std::string_view name, std::span<const double> row_major, const std::vector<hsize_t>& dims,
             const Chunking& chunking = {});
  void write(std::string_view name, std::span<const std::int64_t> values);
  void write(std::string_view name, const std::vector<std::string>& values);
  void write(std::string_view name, const std::string& value);

  /// An extendible, chunked, compressed 2-D dataset (unlimited rows, fixed columns).
  /// Time histories are compressed at gzip level 1 (kTimeHistory): measured on the valvetrain at 40 kHz output
  /// (18 MB of doubles per 0.1 s simulated), level 4 spent 0.23 s of a 0.48 s run compressing, level 1 0.13 s,
  /// for a file 3.5 % larger. Shuffle does most of the work on doubles.
  static inline const Chunking kTimeHistory{{}, 1};
  AppendableDataset create_appendable(std::string_view name, hsize_t columns, const Chunking& chunking = kTimeHistory);
  /// An extendible 1-D dataset (a time history of one scalar): shape (n,), one value per row.
  AppendableDataset create_appendable_vector(std::string_view name, const Chunking& chunking = kTimeHistory);
  /// Reopen a dataset made by create_appendable(_vector) to append more rows (restart with File::open_append).
  AppendableDataset open_appendable(std::string_view name);

  // --- attributes on this group (or, with `object`, on a member dataset/group) ---
  void set_attribute(std::string_view attr, const std::string& value, std::string_view object = ".");
  void set_attribute(std::string_view attr, const char* value, std::string_view object = ".");
  void set_attribute(std::string_view attr, double value, std::string_view object = ".");
  void set_attribute(std::string_view attr, std::int64_t value, std::string_view object = ".");
  void set_attribute(std::string_view attr, int value, std::string_view object = ".");
  void set_attribute(std::string_view attr, const std::vector<double>& value, std::string_view object = ".");
  void set_attribute(std::string_view attr, const std::vector<std::string>& value,
                     std::string_view object = ".");

  bool has_attribute(std::string_view attr, std::string_view object = ".") const;
  std::string string_attribute(std::string_view attr, std::string_view object = ".") const;
  double double_attribute(std::string_view attr, std::string_view object = ".") const;
  std::int64_t int_attribute(std::string_view attr, std::string_view object = ".") const;
  std::vector<std::string> strings_attribute(std::string_view attr, std::string_view object = ".") const;
  std::vector<double> doubles_attribute(std::string_view attr, std::string_view object = ".") const;

  // --- reading datasets; errors name file and path, and what was expected against what was found ---
  /// Dims of a dataset.
  std::vector<hsize_t> shape(std::string_view name) const;
  double read_double(std::string_view name) const;
  std::int64_t read_int(std::string_view name) const;
  /// 1-D double dataset; `expected_size` checked when given.
  Eigen::VectorXd read_vector(std::string_view name, std::optional<hsize_t> expected_size = {}) const;
  /// 2-D double dataset; expected rows/cols checked when given.
  Eigen::MatrixXd read_matrix(std::string_view name, std::optional<hsize_t> expected_rows = {},
                              std::optional<hsize_t> expected_cols = {}) const;
  /// Any-rank double dataset, row-major; its dims returned through `dims`.
  std::vector<double> read_array(std::string_view name, std::vector<hsize_t>& dims) const;
  std::vector<std::int64_t> read_ints(std::string_view name) const;
  std::vector<std::string> read_strings(std::string_view name) const;
  std::string read_string(std::string_view name) const;

  hid_t id() const { return handle_.get(); }

 private:
  friend class File;
  Group(Handle handle, std::string path, std::string file_name)
      : handle_(std::move(handle)), path_(std::move(path)), file_name_(std::move(file_name)) {}
  std::string where(std::string_view name) const;  // "file.h5:/group/name" for messages
  Handle handle_;
  std::string path_;
  std::string file_name_;
};

/// An HDF5 file. Created files live under a temporary name until commit().
class File {
 public:
  /// Create a new output: writes to "<path>.tmp-<pid>" in the same directory; commit() renames it onto
  /// `path` (replacing an older file). Missing parent directories are an error naming them.
  static File create(const std::filesystem::path& path);
  /// Open an existing file read-only; error naming the file if it is missing or not HDF5.
  static File open_read(const std::filesystem::path& path);
  /// Open an existing file for appending (restart of a killed run); no temporary, no rename.
  static File open_append(const std::filesystem::path& path);

  File(File&&) noexcept;
  File& operator=(File&&) noexcept;
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  /// Without commit(), a created file's temporary is closed and removed.
  ~File();

  Group root();
  const Group& root() const;
  /// Write everything HDF5 still holds in memory to disk (a checkpoint); error naming the file if it cannot.
  void flush();
  /// Flush and close, then rename the temporary onto the final path. Only for created files.
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  File() = default;
  void close_and_discard() noexcept;  // close all handles; remove an uncommitted temporary

  std::filesystem::path path_;       // final path
  std::filesystem::path temporary_;  // empty unless created and not yet committed
  Handle file_;                      // declared before root_ so that root_ is closed first
  Group root_;
};

/// "" if `type` is a numeric type HDF5 can convert to a native double or int64 safely (an integer of 1, 2, 4 or
/// 8 bytes, a float of 4 or 8 with its bits inside its size), else what it is ("float460864 data ..."): a
/// corrupted type size made HDF5 1.10's conversion copy beyond its buffers.
std::string numeric_type_fault(hid_t type);

/// Turn HDF5's own error stack printing off for this process (our errors say what went wrong).
/// Called once by File::create/open; safe to call again.
void silence_hdf5_errors();

}  // namespace nvh::h5
