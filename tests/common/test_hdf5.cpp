// Round trips through nvh::h5, checked against the raw HDF5 C API (an independent reader), and the
// error messages of every failed read.
#include "common/hdf5.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace nvh::h5 {
namespace {

namespace fs = std::filesystem;

// The message of the nvh::Error thrown by `action` ("" and a test failure if none is thrown).
std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const nvh::Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected an nvh::Error";
  return "";
}

// ---- an independent reader: the raw HDF5 C API ----

struct RawFile {
  explicit RawFile(const fs::path& path) : id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~RawFile() {
    if (id >= 0) H5Fclose(id);
  }
  hid_t id;
};

struct RawDataset {
  std::vector<hsize_t> dims;
  std::vector<hsize_t> max_dims;
  std::vector<double> values;
  H5D_layout_t layout = H5D_LAYOUT_ERROR;
  std::vector<hsize_t> chunk;
  bool deflate = false;
  H5T_class_t type_class = H5T_NO_CLASS;
  size_t type_size = 0;
};

RawDataset raw_read(const fs::path& file_path, const std::string& dataset_path, bool read_values = true) {
  RawDataset raw;
  RawFile file(file_path);
  EXPECT_GE(file.id, 0) << file_path;
  const hid_t dataset = H5Dopen2(file.id, dataset_path.c_str(), H5P_DEFAULT);
  EXPECT_GE(dataset, 0) << dataset_path;
  if (dataset < 0) return raw;

  const hid_t space = H5Dget_space(dataset);
  const int rank = H5Sget_simple_extent_ndims(space);
  raw.dims.resize(rank);
  raw.max_dims.resize(rank);
  H5Sget_simple_extent_dims(space, raw.dims.data(), raw.max_dims.data());
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  H5Sclose(space);

  const hid_t type = H5Dget_type(dataset);
  raw.type_class = H5Tget_class(type);
  raw.type_size = H5Tget_size(type);
  H5Tclose(type);

  const hid_t dcpl = H5Dget_create_plist(dataset);
  raw.layout = H5Pget_layout(dcpl);
  if (raw.layout == H5D_CHUNKED) {
    raw.chunk.resize(rank);
    H5Pget_chunk(dcpl, rank, raw.chunk.data());
    for (int i = 0; i < H5Pget_nfilters(dcpl); ++i) {
      unsigned flags = 0;
      size_t n_values = 0;
      unsigned filter_config = 0;
      if (H5Pget_filter2(dcpl, i, &flags, &n_values, nullptr, 0, nullptr, &filter_config) ==
          H5Z_FILTER_DEFLATE) {
        raw.deflate = true;
      }
    }
  }
  H5Pclose(dcpl);

  if (read_values && count > 0) {
    raw.values.resize(count);
    EXPECT_GE(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.values.data()), 0);
  }
  H5Dclose(dataset);
  return raw;
}

// ---- fixture: a private temporary directory ----

class Hdf5Test : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    directory_ = fs::temp_directory_path() /
                 ("nvh_test_hdf5_" + std::to_string(::getpid()) + "_" + std::to_string(random()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    // Every handle was closed: no file, group, dataset, ... is left open in the library.
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
    std::error_code ignored;
    fs::remove_all(directory_, ignored);
  }
  fs::path file(const std::string& name) const { return directory_ / name; }
  static fs::path temporary_of(const fs::path& path) {
    return path.string() + ".tmp-" + std::to_string(::getpid());
  }

  fs::path directory_;
};

// A 3x4 matrix whose entry (i, j) is 10 i + j + 0.5, so a transposed layout cannot go unnoticed.
Eigen::MatrixXd test_matrix(int rows = 3, int cols = 4) {
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) m(i, j) = 10.0 * i + j + 0.5;
  }
  return m;
}

// ============================== round trips ==============================

TEST_F(Hdf5Test, ScalarsRoundTrip) {
  const fs::path path = file("scalars.h5");
  {
    File out = File::create(path);
    Group root = out.root();
    root.write("pi", 3.141592653589793);
    root.write("big", std::int64_t{9007199254740993});  // 2^53 + 1: not representable as a double
    root.write("small", -7);
    root.write("name", std::string("Kurbelwelle ü"));
    out.commit();
  }
  File in = File::open_read(path);
  const Group& root = in.root();
  EXPECT_EQ(root.read_double("pi"), 3.141592653589793);
  EXPECT_EQ(root.read_int("big"), 9007199254740993);
  EXPECT_EQ(root.read_int("small"), -7);
  EXPECT_EQ(root.read_string("name"), "Kurbelwelle ü");
  EXPECT_EQ(root.read_double("small"), -7.0);  // integers convert to double
  EXPECT_TRUE(root.shape("pi").empty());

  const RawDataset raw = raw_read(path, "/pi");
  EXPECT_TRUE(raw.dims.empty());
  ASSERT_EQ(raw.values.size(), 1u);
  EXPECT_EQ(raw.values[0], 3.141592653589793);
  EXPECT_EQ(raw.type_class, H5T_FLOAT);
  EXPECT_EQ(raw.type_size, 8u);
  const RawDataset raw_int = raw_read(path, "/big", false);
  EXPECT_EQ(raw_int.type_class, H5T_INTEGER);
  EXPECT_EQ(raw_int.type_size, 8u);
}

TEST_F(Hdf5Test, VectorsRoundTrip) {
  const fs::path path = file("vectors.h5");
  Eigen::VectorXd v(5);
  v << 1.5, -2.25, 0.0, 1e300, -1e-300;
  {
    File out = File::create(path);
    Group root = out.root();
    root.write("v", v);
    root.write("empty", Eigen::VectorXd());
    out.commit();
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_vector("v"), v);
  EXPECT_EQ(in.root().read_vector("v", 5).size(), 5);
  EXPECT_EQ(in.root().read_vector("empty").size(), 0);
  EXPECT_EQ(in.root().shape("v"), std::vector<hsize_t>{5});

  const RawDataset raw = raw_read(path, "/v");
  EXPECT_EQ(raw.dims, std::vector<hsize_t>{5});
  EXPECT_EQ(raw.values, std::vector<double>(v.data(), v.data() + 5));
  EXPECT_EQ(raw_read(path, "/empty").dims, std::vector<hsize_t>{0});
}

TEST_F(Hdf5Test, MatrixEntryLandsAtRowAndColumn) {
  const fs::path path = file("matrix.h5");
  const Eigen::MatrixXd m = test_matrix();
  {
    File out = File::create(path);
    out.root().write("m", m);
    out.commit();
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_matrix("m"), m);
  EXPECT_EQ(in.root().read_matrix("m", 3, 4), m);
  EXPECT_EQ(in.root().shape("m"), (std::vector<hsize_t>{3, 4}));

  // Raw check: shape (rows, cols) and row-major order, i.e. element [i, j] at i * cols + j.
  const RawDataset raw = raw_read(path, "/m");
  ASSERT_EQ(raw.dims, (std::vector<hsize_t>{3, 4}));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_EQ(raw.values[i * 4 + j], 10.0 * i + j + 0.5) << i << ", " << j;
  }
}

TEST_F(Hdf5Test, NdArrayRoundTrip) {
  const fs::path path = file("array.h5");
  std::vector<double> values(2 * 3 * 4);
  for (size_t k = 0; k < values.size(); ++k) values[k] = 0.25 * static_cast<double>(k);
  {
    File out = File::create(path);
    out.root().write("a", values, {2, 3, 4});
    out.root().write("s", std::vector<double>{42.0}, {});  // rank 0: a scalar
    out.commit();
  }
  File in = File::open_read(path);
  std::vector<hsize_t> dims;
  EXPECT_EQ(in.root().read_array("a", dims), values);
  EXPECT_EQ(dims, (std::vector<hsize_t>{2, 3, 4}));
  EXPECT_EQ(in.root().read_array("s", dims), std::vector<double>{42.0});
  EXPECT_TRUE(dims.empty());

  const RawDataset raw = raw_read(path, "/a");
  ASSERT_EQ(raw.dims, (std::vector<hsize_t>{2, 3, 4}));
  EXPECT_EQ(raw.values[1 * 12 + 2 * 4 + 3], 0.25 * 23);  // element [1, 2, 3] in C order
  EXPECT_EQ(raw.values, values);
}

TEST_F(Hdf5Test, IntsAndStringsRoundTrip) {
  const fs::path path = file("ints_strings.h5");
  const std::vector<std::int64_t> ints = {0, -1, 42, INT64_MAX, INT64_MIN};
  const std::vector<std::string> strings = {"crankshaft", "", "Zylinder ü ß", "a longer string with spaces"};
  {
    File out = File::create(path);
    out.root().write("ints", ints);
    out.root().write("strings", strings);
    out.root().write("no_strings", std::vector<std::string>{});
    out.commit();
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_ints("ints"), ints);
  EXPECT_EQ(in.root().read_strings("strings"), strings);
  EXPECT_TRUE(in.root().read_strings("no_strings").empty());

  // Raw check: variable-length UTF-8 strings.
  RawFile raw(path);
  const hid_t dataset = H5Dopen2(raw.id, "/strings", H5P_DEFAULT);
  const hid_t type = H5Dget_type(dataset);
  EXPECT_EQ(H5Tget_class(type), H5T_STRING);
  EXPECT_GT(H5Tis_variable_str(type), 0);
  EXPECT_EQ(H5Tget_cset(type), H5T_CSET_UTF8);
  H5Tclose(type);
  H5Dclose(dataset);
}

TEST_F(Hdf5Test, ChunkedAndCompressedStorage) {
  const fs::path path = file("chunked.h5");
  std::vector<double> values(100 * 50);
  for (size_t k = 0; k < values.size(); ++k) values[k] = std::sin(0.01 * static_cast<double>(k));
  {
    File out = File::create(path);
    out.root().write("explicit", values, {100, 50}, Chunking{{10, 64}, 6});
    out.root().write("large", Eigen::VectorXd::LinSpaced(10000, 0.0, 1.0));
    out.root().write("small", Eigen::VectorXd::LinSpaced(10, 0.0, 1.0));
    out.commit();
  }
  const RawDataset explicit_chunk = raw_read(path, "/explicit");
  EXPECT_EQ(explicit_chunk.layout, H5D_CHUNKED);
  EXPECT_EQ(explicit_chunk.chunk, (std::vector<hsize_t>{10, 50}));  // clamped to the data
  EXPECT_TRUE(explicit_chunk.deflate);
  EXPECT_EQ(explicit_chunk.values, values);

  const RawDataset large = raw_read(path, "/large");
  EXPECT_EQ(large.layout, H5D_CHUNKED);
  EXPECT_TRUE(large.deflate);
  ASSERT_EQ(large.values.size(), 10000u);
  EXPECT_EQ(large.values[9999], 1.0);
  EXPECT_EQ(raw_read(path, "/small", false).layout, H5D_CONTIGUOUS);

  File in = File::open_read(path);
  std::vector<hsize_t> dims;
  EXPECT_EQ(in.root().read_array("explicit", dims), values);
}

TEST_F(Hdf5Test, AppendableGrowsAndReopens) {
  const fs::path path = file("history.h5");
  Eigen::MatrixXd expected(7, 3);
  for (int i = 0; i < 7; ++i) expected.row(i) << i, 10.0 * i, -0.5 * i;
  auto row_major = [&](int first, int count) {
    std::vector<double> values;
    for (int i = first; i < first + count; ++i) {
      for (int j = 0; j < 3; ++j) values.push_back(expected(i, j));
    }
    return values;
  };
  {
    File out = File::create(path);
    AppendableDataset history = out.root().create_appendable("time/history", 3);
    EXPECT_EQ(history.rows(), 0u);
    EXPECT_EQ(history.columns(), 3u);
    history.append(row_major(0, 1));
    history.append(row_major(1, 4));
    history.flush();
    EXPECT_EQ(history.rows(), 5u);
    EXPECT_NE(error_of([&] {
                history.append(std::vector<double>{1.0, 2.0});
              }).find(path.string() + ":/time/history: cannot append 2 values"),
              std::string::npos);
    EXPECT_EQ(history.rows(), 5u);
    out.commit();
  }
  const RawDataset raw = raw_read(path, "/time/history");
  EXPECT_EQ(raw.dims, (std::vector<hsize_t>{5, 3}));
  EXPECT_EQ(raw.max_dims[0], H5S_UNLIMITED);
  EXPECT_EQ(raw.max_dims[1], 3u);
  EXPECT_EQ(raw.layout, H5D_CHUNKED);
  EXPECT_TRUE(raw.deflate);
  EXPECT_EQ(raw.values, row_major(0, 5));

  {  // restart: reopen and append two more rows
    File again = File::open_append(path);
    AppendableDataset history = again.root().open_appendable("time/history");
    EXPECT_EQ(history.rows(), 5u);
    history.append(row_major(5, 2));
    EXPECT_EQ(history.rows(), 7u);
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_matrix("time/history", 7, 3), expected);
}

TEST_F(Hdf5Test, AppendableVectorGrowsTruncatesAndReopens) {
  // The 1-D time histories of solve's results: shape (n,), truncated to a checkpoint on restart.
  const fs::path path = file("vector.h5");
  {
    File out = File::create(path);
    AppendableDataset t = out.root().create_appendable_vector("time");
    t.append(std::vector<double>{0.0, 0.1, 0.2});
    t.append(std::vector<double>{0.3, 0.4});
    EXPECT_EQ(t.rows(), 5u);
    EXPECT_EQ(t.columns(), 1u);
    out.commit();
  }
  const RawDataset raw = raw_read(path, "/time");
  EXPECT_EQ(raw.dims, (std::vector<hsize_t>{5}));
  EXPECT_EQ(raw.max_dims[0], H5S_UNLIMITED);
  EXPECT_EQ(raw.values, (std::vector<double>{0.0, 0.1, 0.2, 0.3, 0.4}));
  {  // restart from a checkpoint after 3 samples: the rows after it go, new ones follow
    File again = File::open_append(path);
    AppendableDataset t = again.root().open_appendable("time");
    EXPECT_EQ(t.rows(), 5u);
    t.truncate(3);
    t.append(std::vector<double>{0.35});
    EXPECT_EQ(t.rows(), 4u);
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_vector("time", 4), (Eigen::VectorXd(4) << 0.0, 0.1, 0.2, 0.35).finished());
}

TEST_F(Hdf5Test, AppendableDatasetCarriesItsOwnAttribute) {
  // solve's time histories get their unit through the open handle (no path lookup); setting it again replaces
  // it.
  const fs::path path = file("unit.h5");
  {
    File out = File::create(path);
    AppendableDataset v = out.root().create_appendable("markers/a/velocity", 3);
    v.set_attribute("unit", "m");
    v.set_attribute("unit", "m/s");
    AppendableDataset t = out.root().create_appendable_vector("time");
    t.set_attribute("unit", "s");
    out.commit();
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().string_attribute("unit", "markers/a/velocity"), "m/s");
  EXPECT_EQ(in.root().string_attribute("unit", "time"), "s");
  EXPECT_NE(error_of([] {
              AppendableDataset().set_attribute("unit", "m");
            }).find("not made by Group::create_appendable"),
            std::string::npos);
}

TEST_F(Hdf5Test, Attributes) {
  const fs::path path = file("attributes.h5");
  {
    File out = File::create(path);
    Group root = out.root();
    root.write("m", test_matrix());
    root.set_attribute("title", std::string("Motor 4"));
    root.set_attribute("c_string", "literal");
    root.set_attribute("speed_rpm", 2500.5);
    root.set_attribute("cylinders", 4);
    root.set_attribute("big", std::int64_t{1} << 40);
    root.set_attribute("weights", std::vector<double>{0.5, 0.25});
    root.set_attribute("names", std::vector<std::string>{"x", "y ü"});
    root.set_attribute("unit", "mm", "m");    // on a member dataset
    root.set_attribute("speed_rpm", 3000.0);  // setting again replaces
    root.set_attribute("empty", std::vector<std::string>{});
    out.commit();
  }
  File in = File::open_read(path);
  const Group& root = in.root();
  EXPECT_EQ(root.string_attribute("title"), "Motor 4");
  EXPECT_EQ(root.string_attribute("c_string"), "literal");
  EXPECT_EQ(root.double_attribute("speed_rpm"), 3000.0);
  EXPECT_EQ(root.int_attribute("cylinders"), 4);
  EXPECT_EQ(root.int_attribute("big"), std::int64_t{1} << 40);
  EXPECT_EQ(root.doubles_attribute("weights"), (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(root.strings_attribute("names"), (std::vector<std::string>{"x", "y ü"}));
  EXPECT_TRUE(root.strings_attribute("empty").empty());
  EXPECT_EQ(root.string_attribute("unit", "m"), "mm");
  EXPECT_TRUE(root.has_attribute("unit", "m"));
  EXPECT_FALSE(root.has_attribute("unit"));
  EXPECT_FALSE(root.has_attribute("unit", "no/such/object"));

  // Raw check of a double attribute on the root group.
  RawFile raw(path);
  const hid_t attribute = H5Aopen_by_name(raw.id, "/", "speed_rpm", H5P_DEFAULT, H5P_DEFAULT);
  double speed = 0.0;
  EXPECT_GE(H5Aread(attribute, H5T_NATIVE_DOUBLE, &speed), 0);
  EXPECT_EQ(speed, 3000.0);
  H5Aclose(attribute);

  const std::string file_name = path.string();
  EXPECT_EQ(error_of([&] { root.string_attribute("nope"); }), file_name + ":/: no attribute 'nope'");
  EXPECT_EQ(error_of([&] { root.double_attribute("title"); }),
            file_name + ":/, attribute 'title': expected float64 data, found a string");
  EXPECT_EQ(error_of([&] { root.int_attribute("speed_rpm"); }),
            file_name + ":/, attribute 'speed_rpm': expected integer data, found float64 data");
  EXPECT_EQ(error_of([&] { root.double_attribute("weights"); }),
            file_name + ":/, attribute 'weights': expected a single value, found shape (2,)");
  EXPECT_EQ(error_of([&] { root.string_attribute("unit", "nothing"); }),
            file_name + ":/nothing: no such group or dataset");
}

TEST_F(Hdf5Test, GroupsAndMembers) {
  const fs::path path = file("groups.h5");
  {
    File out = File::create(path);
    Group root = out.root();
    Group deep = root.create_group("a/b/c");
    EXPECT_EQ(deep.path(), "/a/b/c");
    deep.write("x", 1.0);
    root.write("zeta", 1.0);
    root.write("alpha", 2.0);
    root.write("a/b/mid", 3.0);             // nested write
    root.write("new/intermediate/y", 4.0);  // creates intermediate groups
    Group b = root.open_group("a/b");
    EXPECT_EQ(b.path(), "/a/b");
    EXPECT_EQ(b.open_group("c").path(), "/a/b/c");
    EXPECT_EQ(root.create_group("a/b").path(), "/a/b");  // existing group: opened
    EXPECT_EQ(error_of([&] { root.create_group("zeta"); }),
              path.string() + ":/zeta: expected a group, found a dataset");
    b.write("late", 5.0);
    out.commit();
  }
  File in = File::open_read(path);
  const Group& root = in.root();
  EXPECT_EQ(root.path(), "/");
  // Creation order, not name order.
  EXPECT_EQ(root.members(), (std::vector<std::string>{"a", "zeta", "alpha", "new"}));
  EXPECT_EQ(root.open_group("a/b").members(), (std::vector<std::string>{"c", "mid", "late"}));
  EXPECT_TRUE(root.exists("a/b/c/x"));
  EXPECT_TRUE(root.exists("/a/b"));
  EXPECT_TRUE(root.exists("./a/b"));
  EXPECT_TRUE(root.exists("."));
  EXPECT_TRUE(root.exists("new/intermediate/y"));
  EXPECT_FALSE(root.exists("a/x/y"));   // missing intermediate: false, no error
  EXPECT_FALSE(root.exists("zeta/x"));  // a dataset is no group
  EXPECT_FALSE(root.exists("nothing"));
  EXPECT_EQ(root.read_double("a/b/c/x"), 1.0);
  EXPECT_EQ(root.open_group("a").read_double("b/mid"), 3.0);
  EXPECT_EQ(error_of([&] { root.open_group("a/missing"); }), path.string() + ":/a/missing: no such group");
  EXPECT_EQ(error_of([&] { root.open_group("alpha"); }),
            path.string() + ":/alpha: expected a group, found a dataset");
}

TEST_F(Hdf5Test, ReadsFilesOfOtherWriters) {
  // A file as h5py would write it: float32, int32 and fixed-length strings, no creation order.
  const fs::path path = file("foreign.h5");
  {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 3;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const float floats[3] = {0.5f, 1.5f, -2.0f};
    hid_t d = H5Dcreate2(f, "floats", H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, floats);
    H5Dclose(d);
    const std::int32_t ints[3] = {7, -8, 9};
    d = H5Dcreate2(f, "ints", H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, ints);
    H5Dclose(d);
    const hid_t fixed = H5Tcopy(H5T_C_S1);
    H5Tset_size(fixed, 4);
    H5Tset_strpad(fixed, H5T_STR_NULLPAD);
    const char text[12] = {'a', 'b', 'c', 'd', 'x', 0, 0, 0, 'y', 'z', 0, 0};
    d = H5Dcreate2(f, "fixed", fixed, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, fixed, H5S_ALL, H5S_ALL, H5P_DEFAULT, text);
    H5Dclose(d);
    H5Tclose(fixed);
    H5Sclose(space);
    H5Fclose(f);
  }
  File in = File::open_read(path);
  EXPECT_EQ(in.root().read_vector("floats"), Eigen::Vector3d(0.5, 1.5, -2.0));
  EXPECT_EQ(in.root().read_ints("ints"), (std::vector<std::int64_t>{7, -8, 9}));
  EXPECT_EQ(in.root().read_vector("ints"), Eigen::Vector3d(7, -8, 9));
  EXPECT_EQ(in.root().read_strings("fixed"), (std::vector<std::string>{"abcd", "x", "yz"}));
  EXPECT_EQ(in.root().members(), (std::vector<std::string>{"fixed", "floats", "ints"}));  // name order
}

// ============================== temporary file, commit, lifetime ==============================

TEST_F(Hdf5Test, WritesUnderTemporaryNameUntilCommit) {
  const fs::path path = file("results.h5");
  const fs::path temporary = temporary_of(path);
  File out = File::create(path);
  out.root().write("x", 1.0);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::exists(temporary));
  EXPECT_EQ(out.path(), path);
  out.commit();
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(temporary));
  EXPECT_EQ(File::open_read(path).root().read_double("x"), 1.0);
  EXPECT_NE(error_of([&] { out.commit(); }).find(path.string() + ": commit()"), std::string::npos);
}

TEST_F(Hdf5Test, CommitReplacesAnOlderFile) {
  const fs::path path = file("results.h5");
  {
    File first = File::create(path);
    first.root().write("version", 1);
    first.commit();
  }
  {
    File second = File::create(path);
    second.root().write("version", 2);
    EXPECT_EQ(File::open_read(path).root().read_int("version"), 1);  // old file intact until commit
    second.commit();
  }
  EXPECT_EQ(File::open_read(path).root().read_int("version"), 2);
}

TEST_F(Hdf5Test, UncommittedFileLeavesNothing) {
  const fs::path path = file("abandoned.h5");
  {
    File out = File::create(path);
    out.root().write("x", Eigen::VectorXd::Ones(100));
    EXPECT_TRUE(fs::exists(temporary_of(path)));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(temporary_of(path)));
  EXPECT_TRUE(fs::is_empty(directory_));
}

TEST_F(Hdf5Test, MovedFileKeepsItsTemporary) {
  const fs::path path_a = file("a.h5");
  const fs::path path_b = file("b.h5");
  File a = File::create(path_a);
  File moved(std::move(a));
  moved.root().write("x", 1.0);
  File b = File::create(path_b);
  b = std::move(moved);  // b's own uncommitted temporary is discarded
  EXPECT_FALSE(fs::exists(temporary_of(path_b)));
  EXPECT_TRUE(fs::exists(temporary_of(path_a)));
  b.commit();
  EXPECT_TRUE(fs::exists(path_a));
  EXPECT_FALSE(fs::exists(path_b));
  EXPECT_EQ(File::open_read(path_a).root().read_double("x"), 1.0);
}

TEST_F(Hdf5Test, HandlesOutlivingTheFileFailCleanly) {
  const fs::path path = file("closed.h5");
  File out = File::create(path);
  Group group = out.root().create_group("g");
  out.commit();  // closes everything, including `group`
  EXPECT_THROW(group.write("y", 1.0), nvh::Error);
  EXPECT_THROW(out.root(), nvh::Error);
  EXPECT_FALSE(File::open_read(path).root().exists("g/y"));
}

TEST_F(Hdf5Test, MissingParentDirectoryIsNamed) {
  const fs::path path = directory_ / "no" / "such" / "dir" / "out.h5";
  EXPECT_EQ(error_of([&] { File::create(path); }), path.string() + ": cannot create: directory '" +
                                                       (directory_ / "no/such/dir").string() +
                                                       "' does not exist");
}

// ============================== read errors name the file and the path ==============================

class Hdf5ErrorTest : public Hdf5Test {
 protected:
  void SetUp() override {
    Hdf5Test::SetUp();
    path_ = file("results.h5");
    File out = File::create(path_);
    Group modes = out.root().create_group("modes");
    modes.write("frequency_hz", test_matrix());  // (3, 4) where a vector of 12 is expected
    modes.write("count", 12);
    modes.write("label", std::string("first bending"));
    modes.write("damping", Eigen::VectorXd::Constant(4, 0.02));
    out.commit();
    file_name_ = path_.string();
  }
  std::string at(const std::string& dataset) const { return file_name_ + ":" + dataset + ": "; }

  fs::path path_;
  std::string file_name_;
};

TEST_F(Hdf5ErrorTest, WrongRank) {
  File in = File::open_read(path_);
  EXPECT_EQ(error_of([&] { in.root().read_vector("modes/frequency_hz", 12); }),
            at("/modes/frequency_hz") + "expected a 1-D dataset of 12 values, found shape (3, 4)");
  EXPECT_EQ(error_of([&] { in.root().open_group("modes").read_matrix("damping"); }),
            at("/modes/damping") + "expected a 2-D dataset, found shape (4,)");
  EXPECT_EQ(error_of([&] { in.root().read_double("modes/damping"); }),
            at("/modes/damping") + "expected a single value, found shape (4,)");
  EXPECT_EQ(error_of([&] { in.root().read_ints("modes/count"); }),
            at("/modes/count") + "expected a 1-D dataset, found a scalar");
}

TEST_F(Hdf5ErrorTest, WrongSize) {
  File in = File::open_read(path_);
  EXPECT_EQ(error_of([&] { in.root().read_vector("modes/damping", 6); }),
            at("/modes/damping") + "expected a 1-D dataset of 6 values, found shape (4,)");
  EXPECT_EQ(error_of([&] { in.root().read_matrix("modes/frequency_hz", 3, 5); }),
            at("/modes/frequency_hz") + "expected a 2-D dataset of shape (3, 5), found shape (3, 4)");
  EXPECT_EQ(error_of([&] { in.root().read_matrix("modes/frequency_hz", 4); }),
            at("/modes/frequency_hz") + "expected a 2-D dataset with 4 rows, found shape (3, 4)");
  EXPECT_EQ(error_of([&] { in.root().read_matrix("modes/frequency_hz", {}, 2); }),
            at("/modes/frequency_hz") + "expected a 2-D dataset with 2 columns, found shape (3, 4)");
}

TEST_F(Hdf5ErrorTest, MissingPath) {
  File in = File::open_read(path_);
  EXPECT_EQ(error_of([&] { in.root().read_vector("modes/shape"); }), at("/modes/shape") + "no such dataset");
  EXPECT_EQ(error_of([&] { in.root().read_double("solution/x"); }), at("/solution/x") + "no such dataset");
  EXPECT_EQ(error_of([&] { in.root().shape("modes/count/x"); }), at("/modes/count/x") + "no such dataset");
  EXPECT_EQ(error_of([&] { in.root().read_vector("modes"); }),
            at("/modes") + "expected a dataset, found a group");
}

TEST_F(Hdf5ErrorTest, WrongType) {
  File in = File::open_read(path_);
  EXPECT_EQ(error_of([&] { in.root().read_double("modes/label"); }),
            at("/modes/label") + "expected float64 data, found a string");
  EXPECT_EQ(error_of([&] { in.root().read_int("modes/label"); }),
            at("/modes/label") + "expected integer data, found a string");
  EXPECT_EQ(error_of([&] { in.root().read_int("modes/damping"); }),
            at("/modes/damping") + "expected a single value, found shape (4,)");
  EXPECT_EQ(error_of([&] { in.root().read_ints("modes/damping"); }),
            at("/modes/damping") + "expected integer data, found float64 data");
  EXPECT_EQ(error_of([&] { in.root().read_string("modes/count"); }),
            at("/modes/count") + "expected string data, found int64 data");
}

TEST_F(Hdf5ErrorTest, WritingErrors) {
  File out = File::open_append(path_);
  Group root = out.root();
  EXPECT_EQ(error_of([&] { root.write("modes/count", 1.0); }), at("/modes/count") + "already exists");
  EXPECT_EQ(error_of([&] { root.write("modes/count/x", 1.0); }),
            at("/modes/count/x") + "cannot create: 'modes/count' is not a group");
  EXPECT_EQ(error_of([&] { root.create_group("modes/label/sub/group"); }),
            at("/modes/label/sub/group") + "cannot create: 'modes/label' is not a group");
  EXPECT_EQ(error_of([&] {
              root.write("bad", std::vector<double>(5), {2, 3});
            }),
            at("/bad") + "shape (2, 3) needs 6 values, got 5");
  EXPECT_EQ(error_of([&] {
              root.write("bad", std::vector<double>(6), {2, 3}, Chunking{{2}, 4});
            }),
            at("/bad") + "chunk shape (2,) does not have the rank of the data shape (2, 3)");
  EXPECT_EQ(error_of([&] { root.create_appendable("bad", 0); }),
            at("/bad") + "an appendable dataset needs at least one column");
  EXPECT_EQ(error_of([&] { root.open_appendable("modes/damping"); }),
            at("/modes/damping") + "expected an appendable dataset (unlimited rows), found shape (4,)");
  EXPECT_FALSE(root.exists("bad"));
}

TEST_F(Hdf5ErrorTest, OpeningErrors) {
  const fs::path missing = file("missing.h5");
  EXPECT_EQ(error_of([&] { File::open_read(missing); }), missing.string() + ": no such file");
  EXPECT_EQ(error_of([&] { File::open_append(missing); }), missing.string() + ": no such file");
  const fs::path text = file("not_hdf5.h5");
  std::ofstream(text) << "just text\n";
  EXPECT_EQ(error_of([&] {
              File::open_read(text);
            }).rfind(text.string() + ": cannot open for reading (not an HDF5 file, or not accessible)", 0),
            0u);
  EXPECT_EQ(error_of([&] { File::open_read(directory_); }),
            directory_.string() + ": is a directory, expected an HDF5 file");
}

// ---- a full disk (issue 18): a clean error naming the file, no temporary left, no crash ----

// A 16 KiB tmpfs, when this process may mount one (root); the test is skipped otherwise.
class Hdf5FullDiskTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_h5_full_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    if (::geteuid() != 0) GTEST_SKIP() << "mounting a small tmpfs needs root";
    const std::string mount = "mount -t tmpfs -o size=16k tmpfs " + dir_.string() + " 2>/dev/null";
    if (std::system(mount.c_str()) != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here (a container without it?)";
    mounted_ = true;
  }
  void TearDown() override {
    if (mounted_) {
      EXPECT_EQ(std::system(("umount " + dir_.string()).c_str()), 0);
    }
    fs::remove_all(dir_);
  }
  bool empty() const { return fs::is_empty(dir_); }
  fs::path dir_;
  bool mounted_ = false;
};

TEST_F(Hdf5FullDiskTest, CommitOfAFileLargerThanTheDiskFailsCleanly) {
  const fs::path path = dir_ / "big.h5";
  const std::string message = error_of([&] {
    File file = File::create(path);
    Group root = file.root();
    root.write("values", Eigen::VectorXd::Random(100000));  // 800 kB that do not compress, in 16 kB
    file.commit();
  });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_TRUE(empty()) << "the temporary is left behind";
  // HDF5 still works in this process (its state was not left corrupt by the failed close).
  const fs::path elsewhere =
      fs::temp_directory_path() / ("nvh_h5_after_full_" + std::to_string(::getpid()) + ".h5");
  {
    File file = File::create(elsewhere);
    file.root().write("x", 1.0);
    file.commit();
  }
  EXPECT_EQ(File::open_read(elsewhere).root().read_double("x"), 1.0);
  fs::remove(elsewhere);
}

TEST_F(Hdf5FullDiskTest, FlushOfAppendedRowsFailsCleanly) {
  const fs::path path = dir_ / "rows.h5";
  {
    File file = File::create(path);
    file.root().create_appendable("rows", 100);
    file.commit();
  }
  File file = File::open_append(path);
  AppendableDataset rows = file.root().open_appendable("rows");
  std::vector<double> values(100 * 1000);  // 800 kB of rows that do not compress
  std::mt19937 random(7);
  for (double& v : values) v = std::uniform_real_distribution<double>(0.0, 1.0)(random);
  const std::string message = error_of([&] {
    rows.append(values);
    rows.flush();
    file.flush();
  });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
}

}  // namespace
}  // namespace nvh::h5
