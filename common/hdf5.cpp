#include "common/hdf5.hpp"

#include "common/interrupt.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <system_error>
#include <utility>

#include "common/error.hpp"

namespace nvh::h5 {
namespace {

// Arrays larger than this many values are stored chunked and compressed even when not asked for.
constexpr hsize_t kAutoChunkThreshold = 4096;
// Target number of values in one automatic chunk (128 KiB of doubles, well inside HDF5's 1 MiB
// default chunk cache, so appending row by row does not re-read and re-compress chunks).
constexpr hsize_t kChunkTargetValues = 16384;
constexpr int kDefaultDeflateLevel = 4;  // time histories: level 1 (Group::kTimeHistory, hdf5.hpp)

// No HDF5 exit handler. HDF5 1.10 keeps the id of an object whose close failed (a full disk: H5Fclose,
// H5Dclose cannot write what they hold) in its tables, pointing at memory it has already freed; its exit
// handler closes every id left and crashes on those. Every file is closed by its h5::File before exit,
// so the handler has nothing else to do. H5dont_atexit only acts before the library initializes, hence a
// static initializer (this file is linked into every tool that uses HDF5).
[[maybe_unused]] const bool kNoHdf5ExitHandler = H5dont_atexit() >= 0;

// ---------------------------------------------------------------------------------------------
// Errors

// The innermost description on HDF5's error stack (the stack of the last failed call), or "".
// Printing is silenced (silence_hdf5_errors), but the stack is still recorded and can be walked.
std::string hdf5_detail() {
  std::string detail;
  auto take_first = [](unsigned n, const H5E_error2_t* error, void* out) -> herr_t {
    if (n == 0 && error->desc != nullptr) *static_cast<std::string*>(out) = error->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take_first, &detail);
  H5Eclear2(H5E_DEFAULT);
  // A failed read or write of the file driver is a multi-line record (time, descriptor, buffer address,
  // offsets): keep its first words and the system's message, e.g. "file write failed: No space left on
  // device".
  const size_t system = detail.find("error message = '");
  if (system != std::string::npos) {
    const size_t begin = system + std::strlen("error message = '");
    const size_t end = detail.find('\'', begin);
    detail = detail.substr(0, detail.find(':')) + ": " + detail.substr(begin, end - begin);
  }
  return detail.empty() ? std::string() : " (HDF5: " + detail + ")";
}

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw Error(where + ": " + what);
}

hid_t check_id(hid_t id, const std::string& where, const std::string& what) {
  if (id < 0) fail(where, what + hdf5_detail());
  return id;
}

void check_status(herr_t status, const std::string& where, const std::string& what) {
  if (status < 0) fail(where, what + hdf5_detail());
}

// ---------------------------------------------------------------------------------------------
// Paths and descriptions for messages

// Path of `name` (relative to the group at `group_path`, or absolute) inside the file.
std::string join_path(const std::string& group_path, std::string_view name) {
  if (name.empty() || name == ".") return group_path;
  if (name.front() == '/') return std::string(name);
  if (group_path.empty() || group_path == "/") return "/" + std::string(name);
  return group_path + "/" + std::string(name);
}

std::string attribute_where(const std::string& object_where, std::string_view attr) {
  return object_where + ", attribute '" + std::string(attr) + "'";
}

hsize_t element_count(const std::vector<hsize_t>& dims) {
  return std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
}

// "(3, 4)", "(3,)" like numpy; "()" for a scalar.
std::string format_dims(const std::vector<hsize_t>& dims) {
  std::string text = "(";
  for (size_t i = 0; i < dims.size(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(dims[i]);
  }
  return text + (dims.size() == 1 ? ",)" : ")");
}

// What a datatype holds, as said after "found": "float64 data", "a string", ...
std::string describe_type(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type));
  switch (H5Tget_class(type)) {
    case H5T_FLOAT:
      return "float" + bits + " data";
    case H5T_INTEGER:
      return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits + " data";
    case H5T_STRING:
      return "a string";
    case H5T_COMPOUND:
      return "a compound type";
    case H5T_ENUM:
      return "an enum (e.g. booleans)";
    case H5T_ARRAY:
      return "an array type";
    case H5T_VLEN:
      return "a variable-length sequence";
    case H5T_REFERENCE:
      return "a reference";
    default:
      return "an unsupported type";
  }
}

// ---------------------------------------------------------------------------------------------
// Structure

// The successive prefixes of a path: "a/b/c" -> "a", "a/b", "a/b/c" ("/a/b" -> "/a", "/a/b").
std::vector<std::string> path_prefixes(std::string_view path) {
  std::vector<std::string> prefixes;
  std::string prefix = !path.empty() && path.front() == '/' ? "/" : "";
  for (size_t begin = path.find_first_not_of('/'); begin != std::string_view::npos;
       begin = path.find_first_not_of('/', begin)) {
    const size_t end = std::min(path.find('/', begin), path.size());
    const std::string_view component = path.substr(begin, end - begin);
    begin = end;
    if (component == ".") continue;  // "./a" is "a"
    if (!prefix.empty() && prefix.back() != '/') prefix += '/';
    prefix += component;
    prefixes.push_back(prefix);
  }
  return prefixes;
}

std::uint64_t little_endian(const unsigned char* p, int bytes);
std::string file_name_of(hid_t object);
bool read_only_with_default_sizes(hid_t object);

// ---------------------------------------------------------------------------------------------
// Object headers, read beside HDF5
//
// HDF5 1.10 trusts parts of the object headers it reads: a group's link storage addresses, the heap
// references of variable-length string attributes. In files opened read-only (on disk as HDF5 sees them,
// with its default 8-byte addresses and lengths: read_only_with_default_sizes), those are read here first
// and checked. Only version-1 object headers are walked: they carry no checksum. Version-2 headers ("OHDR")
// carry one, which HDF5 verifies itself when it loads them.

// Bytes of a file, read beside HDF5.
class FileBytes {
 public:
  explicit FileBytes(const std::string& file_name) : in_(file_name, std::ios::binary) {}
  // The `n` bytes at `at`, or none if they are not all in the file.
  std::vector<unsigned char> read(std::uint64_t at, std::size_t n) {
    std::vector<unsigned char> bytes(n);
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    if (!in_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(n))) bytes.clear();
    return bytes;
  }

 private:
  std::ifstream in_;
};

// The key under which a check of the object header at `address` is cached: the file's path, size and
// modification time (its contents, as far as a cache can tell) and the address.
std::string header_key(const std::string& file_name, std::uint64_t address) {
  std::error_code error;
  return file_name + "|" + std::to_string(std::filesystem::file_size(file_name, error)) + "|" +
         std::to_string(std::filesystem::last_write_time(file_name, error).time_since_epoch().count()) + "|" +
         std::to_string(address);
}

// Calls `message(type, flags, data, size)` for each message of the version-1 object header at `address`,
// in HDF5's order, until it returns false. HDF5 File Format Specification (version 0/1 superblocks),
// "Version 1 Data Object Header Prefix": version (1 byte, = 1), reserved (1), number of messages (2),
// reference count (4), size of the first message block (4), padding to 16 bytes; the first block follows.
// Each message: type (2 bytes), size of its data (2), flags (1), reserved (3), then the data (a multiple of
// 8 bytes). A continuation message (type 0x0010: address (8), length (8) of a further block) adds a block.
// Does nothing for a header of another version, and stops where HDF5 could not have written what it finds
// (a message running past its block, a block of more than 1 MiB, more than 64 blocks): HDF5 judges those.
void walk_v1_object_header(FileBytes& file, std::uint64_t address,
                           const std::function<bool(unsigned type, unsigned flags, const unsigned char* data,
                                                    std::size_t size)>& message) {
  const std::vector<unsigned char> prefix = file.read(address, 16);
  if (prefix.size() != 16 || prefix[0] != 1) return;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> blocks = {
      {address + 16, little_endian(&prefix[8], 4)}};
  for (std::size_t b = 0; b < blocks.size() && b < 64; ++b) {
    if (blocks[b].second > (1u << 20)) return;
    const std::vector<unsigned char> block =
        file.read(blocks[b].first, static_cast<std::size_t>(blocks[b].second));
    for (std::size_t at = 0; at + 8 <= block.size();) {
      const auto type = static_cast<unsigned>(little_endian(&block[at], 2));
      const auto size = static_cast<std::size_t>(little_endian(&block[at + 2], 2));
      if (at + 8 + size > block.size()) break;
      const unsigned char* data = &block[at + 8];
      if (type == 0x10 && size >= 16) blocks.emplace_back(little_endian(data, 8), little_endian(data + 8, 8));
      if (!message(type, block[at + 4], data, size)) return;
      at += 8 + size;
    }
  }
}

// A group's link storage, checked before HDF5 looks a name up in it. A group of the 1.8 format has a
// "link info" message (type 0x0002) in its object header; when a flipped byte makes its fractal-heap
// address look defined, HDF5 1.10 opens a B-tree at the (undefined or garbage) name-index address and
// crashes in its metadata accumulator. So dense link storage must point at a B-tree header ("BTHD") and a
// fractal heap ("FRHP"). Checked once per file contents and header address.
void check_group_links(hid_t group) {
  if (H5Iget_type(group) != H5I_GROUP || !read_only_with_default_sizes(group)) return;
  H5O_info_t info;
  if (H5Oget_info2(group, &info, H5O_INFO_BASIC) < 0) return;
  const std::string file_name = file_name_of(group);
  const std::string key = header_key(file_name, info.addr);
  static std::mutex mutex;
  static std::map<std::string, std::string> checked;  // "" if sound
  const std::lock_guard<std::mutex> lock(mutex);
  const auto known = checked.find(key);
  std::string fault;
  if (known != checked.end()) {
    fault = known->second;
  } else {
    FileBytes file(file_name);
    walk_v1_object_header(
        file, info.addr, [&](unsigned type, unsigned, const unsigned char* data, std::size_t size) {
          if (type != 0x02 || size < 18) return true;
          // Link info: version, flags, [maximum creation index (8) if flags bit 0], fractal heap address,
          // name index B-tree address, [creation order B-tree address].
          const std::size_t skip = (data[1] & 1) ? 8 : 0;
          if (2 + skip + 16 > size) return true;
          const std::uint64_t heap = little_endian(data + 2 + skip, 8);
          const std::uint64_t names = little_endian(data + 2 + skip + 8, 8);
          const std::uint64_t undefined = ~std::uint64_t{0};
          if (heap == undefined) return true;
          const std::vector<unsigned char> h = file.read(heap, 4), n = file.read(names, 4);
          if (names == undefined || h.size() != 4 || n.size() != 4 || std::memcmp(h.data(), "FRHP", 4) != 0 ||
              std::memcmp(n.data(), "BTHD", 4) != 0) {
            fault = "corrupt group (its link storage points at no B-tree or heap)";
          }
          return fault.empty();
        });
    checked[key] = fault;
  }
  if (!fault.empty()) throw Error(file_name + ": " + fault);
}

// A variable-length string attribute as an object header stores it (what H5Aread will follow).
struct StoredStringAttribute {
  std::string fault;                      // what would make HDF5 misread it, "" if nothing
  std::uint64_t count = 0;                // strings, as its dataspace says
  std::vector<unsigned char> references;  // 16 bytes per string
};

// One attribute message, as far as it is decoded here.
struct AttributeMessage {
  std::string name;
  std::string fault;     // a part of it that HDF5 1.10 would decode beyond the message, "" if none
  bool strings = false;  // it holds variable-length strings, described by `stored`
  StoredStringAttribute stored;
};

// Decodes an attribute message (type 0x000C) as HDF5 1.10 does (H5O__attr_decode), far enough to bound its
// parts and to take the references of variable-length strings. HDF5 File Format Specification, "Attribute
// Message": version (1), reserved (version 1) or flags (2, 3: bit 0 shared datatype, bit 1 shared
// dataspace), sizes of the name (with its terminating zero), datatype and dataspace (2 bytes each), the
// name's character set (version 3 only, 1 byte), then the name, datatype and dataspace, each padded to a
// multiple of 8 bytes in version 1 only, then the data. The datatype ("Datatype Message") starts with its
// class in the low 4 bits of byte 0 (9: variable-length), a class bit field (3 bytes; for class 9 the low 4
// bits say sequence (0) or string (1)) and the element size (4); a class 9 type then holds its base type, a
// datatype of the same form (class 0, fixed-point: then bit offset (2) and precision (2)). The dataspace
// ("Dataspace Message"): version (1), rank (1), flags (1), then in version 1 five reserved bytes, in version
// 2 a type (1: 0 scalar, 1 simple, 2 null); then the dimensions, 8 bytes each. HDF5 1.10.8 decodes the
// datatype and dataspace where the sizes put them, unbounded, and copies (elements x element size) bytes of
// data, bounded by the size of the whole message only: a flipped size makes it read beyond the message (and
// crash). What HDF5 refuses itself (unknown versions, a name size other than the name's) and shared
// datatypes or dataspaces (a reference elsewhere) are left undecoded.
AttributeMessage decode_attribute_message(const unsigned char* data, std::size_t size) {
  AttributeMessage message;
  if (size < 8 || data[0] < 1 || data[0] > 3) return message;
  const unsigned version = data[0];
  const auto padded = [version](std::uint64_t n) { return version == 1 ? (n + 7) / 8 * 8 : n; };
  const std::uint64_t name_at = version == 3 ? 9 : 8;
  const std::uint64_t type_at = name_at + padded(little_endian(data + 2, 2));
  const std::uint64_t space_at = type_at + padded(little_endian(data + 4, 2));
  const std::uint64_t data_at = space_at + padded(little_endian(data + 6, 2));
  if (name_at >= size) return message;
  const char* text = reinterpret_cast<const char*>(data + name_at);
  message.name.assign(text, strnlen(text, size - name_at));  // as HDF5: up to the terminating zero
  if (little_endian(data + 2, 2) != message.name.size() + 1) return message;  // HDF5 refuses it itself
  if (data_at > size) {
    message.fault = "its name, datatype and dataspace run past its message";
    return message;
  }
  if (version >= 2 && (data[1] & 3) != 0) return message;
  const unsigned char* type = type_at + 8 <= size ? data + type_at : nullptr;
  const unsigned char* space = space_at + 4 <= size ? data + space_at : nullptr;
  const std::uint64_t dims_at = space != nullptr && space[0] == 1 ? 8 : 4;
  if (type == nullptr || space == nullptr || (space[0] != 1 && space[0] != 2) || space[1] > 32)
    return message;
  if (space_at + dims_at + 8 * std::uint64_t{space[1]} > size) {
    message.fault = "its dataspace runs past its message";
    return message;
  }
  std::uint64_t count = space[0] == 2 && space[3] == 2 ? 0 : 1;  // a null dataspace has no elements
  const std::uint64_t too_many = size + 1;  // more elements than fit in the message: a bound, not overflowing
  for (unsigned d = 0; d < space[1]; ++d) {
    const std::uint64_t dim = little_endian(space + dims_at + 8 * d, 8);
    count = std::min(count * std::min(dim, too_many), too_many);
  }
  const std::uint64_t element = little_endian(type + 4, 4);
  if (count * element > size - data_at) {
    message.fault = "its data runs past its message";
    return message;
  }
  if ((type[0] & 0x0f) != 9 || (type[1] & 0x0f) != 1) return message;  // not variable-length strings
  message.strings = true;
  StoredStringAttribute& stored = message.stored;
  // HDF5 copies elements of the size the datatype says, then H5Aread takes them as 16-byte references.
  if (element != 16) {
    stored.fault = "its string type has elements of " + std::to_string(element) + " bytes, not 16";
    return message;
  }
  // Its characters: the 1-byte unsigned integer type HDF5 gives every string (class 0, size 1, bit offset 0,
  // precision 8). Other values make HDF5 convert each string with another character size (wrong strings,
  // or gigabytes for a size of 2^29).
  const unsigned char* base = type_at + 20 <= size ? type + 8 : nullptr;
  if (base == nullptr || (base[0] & 0x0f) != 0 || little_endian(base + 4, 4) != 1 ||
      little_endian(base + 8, 2) != 0 || little_endian(base + 10, 2) != 8) {
    stored.fault = "its strings are not of 8-bit characters";
    return message;
  }
  stored.count = count;
  stored.references.assign(data + data_at, data + data_at + 16 * count);
  return message;
}

// The attribute messages of one object header, as read beside HDF5.
struct StoredAttributes {
  std::string fault;  // the first message HDF5 would decode beyond, "" if none
  std::map<std::string, StoredStringAttribute> strings;  // variable-length string attributes, by name
};

// The attribute messages of the version-1 object header at `address` (HDF5 opens the first message of a
// name); none for headers of another version (checksummed; their attributes may also be in dense storage,
// a fractal heap, not read here). Read once per file contents and header address.
const StoredAttributes& stored_attributes(const std::string& file_name, std::uint64_t address) {
  static std::mutex mutex;
  static std::map<std::string, StoredAttributes> known;
  const std::string key = header_key(file_name, address);
  const std::lock_guard<std::mutex> lock(mutex);
  const auto found = known.find(key);
  if (found != known.end()) return found->second;
  StoredAttributes& attributes = known[key];
  std::set<std::string> names;  // of every attribute message, strings or not
  const auto take = [&](unsigned type, unsigned flags, const unsigned char* data, std::size_t size) {
    // Attribute messages (0x000C), unless shared (message flags bit 1: the data is a reference to them).
    if (type != 0x0c || (flags & 2) != 0) return true;
    AttributeMessage message = decode_attribute_message(data, size);
    if (attributes.fault.empty() && !message.fault.empty())
      attributes.fault = "corrupt attribute '" + message.name + "' (" + message.fault + ")";
    if (message.strings && names.count(message.name) == 0)
      attributes.strings.emplace(message.name, std::move(message.stored));
    names.insert(message.name);
    return true;
  };
  FileBytes file(file_name);
  walk_v1_object_header(file, address, take);
  return attributes;
}

// Before HDF5 decodes the attribute messages of `object` (H5Aexists_by_name and H5Aopen_by_name decode them
// in turn until the one named): in a file opened read-only, none may have a part HDF5 would decode beyond
// its message. Returns the address of the object's header, HADDR_UNDEF if it was not read (other files).
haddr_t check_attribute_messages(hid_t loc, const std::string& object, const std::string& object_where) {
  if (!read_only_with_default_sizes(loc)) return HADDR_UNDEF;
  H5O_info_t info;
  if (H5Oget_info_by_name2(loc, object.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) return HADDR_UNDEF;
  const StoredAttributes& attributes = stored_attributes(file_name_of(loc), info.addr);
  if (!attributes.fault.empty()) fail(object_where, attributes.fault);
  return info.addr;
}

// The group at `path` (opened, checked by check_group_links), or an invalid handle if it is not a group.
Handle open_if_group(hid_t loc, const std::string& path) {
  Handle object(H5Oopen(loc, path.c_str(), H5P_DEFAULT));
  if (!object.valid() || H5Iget_type(object.get()) != H5I_GROUP) return Handle();
  check_group_links(object.get());
  return object;
}

bool is_group(hid_t loc, const std::string& path) {
  return open_if_group(loc, path).valid();
}

// True if every component of `path` exists and all but the last are groups. H5Lexists itself fails
// (rather than returning false) when an intermediate component is missing, hence the walk. Each group is
// checked before a name is looked up in it.
bool link_exists(hid_t loc, std::string_view path) {
  const std::vector<std::string> prefixes = path_prefixes(path);
  if (!prefixes.empty()) check_group_links(loc);
  for (size_t i = 0; i < prefixes.size(); ++i) {
    if (H5Lexists(loc, prefixes[i].c_str(), H5P_DEFAULT) <= 0) return false;
    if (i + 1 < prefixes.size() && !is_group(loc, prefixes[i])) return false;
  }
  return true;  // also for "", "." and "/": the group itself
}

// Before creating `path`: each existing parent component must be a group (missing ones get created).
void require_parent_groups(hid_t loc, std::string_view path, const std::string& where) {
  const std::vector<std::string> prefixes = path_prefixes(path);
  for (size_t i = 0; i + 1 < prefixes.size(); ++i) {
    if (H5Lexists(loc, prefixes[i].c_str(), H5P_DEFAULT) <= 0) return;
    if (!is_group(loc, prefixes[i])) fail(where, "cannot create: '" + prefixes[i] + "' is not a group");
  }
}

// Link creation properties that create missing intermediate groups ("a/b/c" with no "a").
Handle intermediate_groups_lcpl() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  return lcpl;
}

// Group creation properties that remember the creation order of members, so members() lists them
// in the order they were written. Intermediate groups inherit this from their parent.
Handle creation_order_gcpl() {
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE));
  H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  return gcpl;
}

Handle make_dataspace(const std::vector<hsize_t>& dims, const std::string& where) {
  if (dims.empty()) return Handle(check_id(H5Screate(H5S_SCALAR), where, "cannot create a dataspace"));
  return Handle(check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), where,
                         "cannot create a dataspace of shape " + format_dims(dims)));
}

// Variable-length UTF-8 strings, used both in the file and in memory (as const char* / char*).
Handle vlen_string_type() {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

// ---------------------------------------------------------------------------------------------
// Chunking

void check_deflate_level(int level, const std::string& where) {
  if (level < 0 || level > 9) fail(where, "deflate level must be 0..9, got " + std::to_string(level));
}

// An automatic chunk shape: halve the largest dimension until the chunk holds at most
// kChunkTargetValues values.
std::vector<hsize_t> automatic_chunk(const std::vector<hsize_t>& dims) {
  std::vector<hsize_t> chunk = dims;
  for (hsize_t& c : chunk) c = std::max<hsize_t>(c, 1);
  while (element_count(chunk) > kChunkTargetValues) {
    hsize_t& largest = *std::max_element(chunk.begin(), chunk.end());
    if (largest == 1) break;
    largest = (largest + 1) / 2;
  }
  return chunk;
}

// Chunk dims for a fixed-size dataset, or empty for contiguous storage: the caller's chunk when
// given (clamped to the dataset: HDF5 rejects fixed-size chunks larger than the data), else an
// automatic one for arrays of more than kAutoChunkThreshold values.
std::vector<hsize_t> chunk_for(const std::vector<hsize_t>& dims, const Chunking& chunking,
                               const std::string& where) {
  const hsize_t count = element_count(dims);
  if (dims.empty() || count == 0) return {};  // scalars and empty arrays cannot be chunked
  if (chunking.chunk.empty())
    return count > kAutoChunkThreshold ? automatic_chunk(dims) : std::vector<hsize_t>{};
  if (chunking.chunk.size() != dims.size()) {
    fail(where, "chunk shape " + format_dims(chunking.chunk) + " does not have the rank of the data shape " +
                    format_dims(dims));
  }
  std::vector<hsize_t> chunk(dims.size());
  for (size_t i = 0; i < dims.size(); ++i) {
    if (chunking.chunk[i] == 0) fail(where, "chunk shape " + format_dims(chunking.chunk) + " has a zero");
    chunk[i] = std::min(chunking.chunk[i], dims[i]);
  }
  return chunk;
}

// Dataset creation properties: chunked with shuffle + deflate when `chunk` is given, else defaults.
Handle dataset_creation_plist(const std::vector<hsize_t>& chunk, int deflate_level,
                              const std::string& where) {
  Handle dcpl(check_id(H5Pcreate(H5P_DATASET_CREATE), where, "cannot create a property list"));
  if (chunk.empty()) return dcpl;
  check_deflate_level(deflate_level, where);
  check_status(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), where,
               "cannot set chunk shape " + format_dims(chunk));
  if (deflate_level > 0) {
    // Byte shuffling before deflate groups the exponent bytes of doubles: much better compression.
    check_status(H5Pset_shuffle(dcpl.get()), where, "cannot set the shuffle filter");
    check_status(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate_level)), where,
                 "cannot set deflate compression");
  }
  return dcpl;
}

// ---------------------------------------------------------------------------------------------
// Writing

// Before creating `name`: it must not exist, and its existing parents must be groups.
void require_new(hid_t loc, std::string_view name, const std::string& where) {
  if (link_exists(loc, name)) fail(where, "already exists");
  require_parent_groups(loc, name, where);
}

// Create dataset `name` with the given shape and storage, and write `data` (in memory type `mem_type`).
void create_dataset(hid_t loc, std::string_view name, const std::string& where, hid_t file_type,
                    hid_t mem_type, const std::vector<hsize_t>& dims, const void* data,
                    const std::vector<hsize_t>& chunk = {}, int deflate_level = kDefaultDeflateLevel) {
  require_new(loc, name, where);
  const Handle space = make_dataspace(dims, where);
  const Handle dcpl = dataset_creation_plist(chunk, deflate_level, where);
  const Handle lcpl = intermediate_groups_lcpl();
  Handle dataset(check_id(
      H5Dcreate2(loc, std::string(name).c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
      where, "cannot create dataset"));
  // HDF5 rejects a null buffer even for zero values, and an empty std::vector may have one.
  if (element_count(dims) == 0) return;
  check_status(H5Dwrite(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), where,
               "cannot write dataset");
  // The data may still be in HDF5's chunk cache or sieve buffer: the close writes it, and on a full disk
  // fails there. A silent close would lose the data and commit a file without it.
  check_status(H5Dclose(dataset.release()), where, "cannot write dataset");
}

void create_double_dataset(hid_t loc, std::string_view name, const std::string& where, const double* data,
                           const std::vector<hsize_t>& dims, const Chunking& chunking = {}) {
  create_dataset(loc, name, where, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims, data,
                 chunk_for(dims, chunking, where), chunking.deflate_level);
}

std::vector<const char*> c_strings(const std::vector<std::string>& values) {
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const std::string& value : values) pointers.push_back(value.c_str());
  return pointers;
}

// Create (or replace) attribute `attr` on `object` and write `data` into it.
void write_attribute(hid_t loc, std::string_view object, std::string_view attr,
                     const std::string& object_where, hid_t file_type, hid_t mem_type,
                     const std::vector<hsize_t>& dims, const void* data) {
  const std::string where = attribute_where(object_where, attr);
  if (!link_exists(loc, object)) fail(object_where, "no such group or dataset");
  const std::string object_name(object);
  const std::string attr_name(attr);
  // Attributes cannot be resized or retyped in place: setting one again replaces it.
  const htri_t exists = H5Aexists_by_name(loc, object_name.c_str(), attr_name.c_str(), H5P_DEFAULT);
  check_status(exists < 0 ? -1 : 0, where, "cannot check for the attribute");
  if (exists > 0) {
    check_status(H5Adelete_by_name(loc, object_name.c_str(), attr_name.c_str(), H5P_DEFAULT), where,
                 "cannot replace the attribute");
  }
  const Handle space = make_dataspace(dims, where);
  const Handle attribute(check_id(H5Acreate_by_name(loc, object_name.c_str(), attr_name.c_str(), file_type,
                                                    space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                  where, "cannot create the attribute"));
  if (element_count(dims) == 0) return;
  check_status(H5Awrite(attribute.get(), mem_type, data), where, "cannot write the attribute");
}

// ---------------------------------------------------------------------------------------------
// Reading: a dataset and an attribute both have a dataspace, a datatype and a read call.

struct Source {
  Handle object;  // a dataset or an attribute
  std::string where;
  // An attribute's: the address of the object header it is stored in (H5Oget_info2 on an attribute gives
  // the object it was opened from, not the one it is attached to).
  haddr_t owner_header = HADDR_UNDEF;
  bool is_attribute() const { return H5Iget_type(object.get()) == H5I_ATTR; }
};

struct Extent {
  bool null = false;          // H5S_NULL: a dataspace with no elements at all (h5py's Empty)
  std::vector<hsize_t> dims;  // empty for a scalar
  std::vector<hsize_t> max_dims;
  hsize_t count() const { return null ? 0 : element_count(dims); }
  std::string describe() const {
    return null ? "an empty (null) dataspace" : dims.empty() ? "a scalar" : "shape " + format_dims(dims);
  }
};

Extent extent_of(const Source& source) {
  const Handle space(
      check_id(source.is_attribute() ? H5Aget_space(source.object.get()) : H5Dget_space(source.object.get()),
               source.where, "cannot get the dataspace"));
  Extent extent;
  if (H5Sget_simple_extent_type(space.get()) == H5S_NULL) {
    extent.null = true;
    return extent;
  }
  const int rank = H5Sget_simple_extent_ndims(space.get());
  check_status(rank, source.where, "cannot get the rank");
  extent.dims.resize(static_cast<size_t>(rank));
  extent.max_dims.resize(static_cast<size_t>(rank));
  check_status(H5Sget_simple_extent_dims(space.get(), extent.dims.data(), extent.max_dims.data()),
               source.where, "cannot get the shape");
  return extent;
}

Handle type_of(const Source& source) {
  return Handle(
      check_id(source.is_attribute() ? H5Aget_type(source.object.get()) : H5Dget_type(source.object.get()),
               source.where, "cannot get the datatype"));
}

// Read all elements, converted by HDF5 to `mem_type`.
void read_raw(const Source& source, hid_t mem_type, void* buffer) {
  const herr_t status = source.is_attribute()
                            ? H5Aread(source.object.get(), mem_type, buffer)
                            : H5Dread(source.object.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
  check_status(status, source.where, "cannot read");
}

Source open_dataset(hid_t loc, std::string_view name, const std::string& where) {
  if (!link_exists(loc, name)) fail(where, "no such dataset");
  Handle object(check_id(H5Oopen(loc, std::string(name).c_str(), H5P_DEFAULT), where, "cannot open"));
  if (H5Iget_type(object.get()) == H5I_GROUP) fail(where, "expected a dataset, found a group");
  if (H5Iget_type(object.get()) != H5I_DATASET) fail(where, "expected a dataset, found a named datatype");
  return Source{std::move(object), where};
}

Source open_attribute(hid_t loc, std::string_view object, std::string_view attr,
                      const std::string& object_where) {
  const std::string where = attribute_where(object_where, attr);
  if (!link_exists(loc, object)) fail(object_where, "no such group or dataset");
  const std::string object_name(object);
  const std::string attr_name(attr);
  const haddr_t header = check_attribute_messages(loc, object_name, object_where);
  if (H5Aexists_by_name(loc, object_name.c_str(), attr_name.c_str(), H5P_DEFAULT) <= 0) {
    fail(object_where, "no attribute '" + attr_name + "'");
  }
  Handle attribute(
      check_id(H5Aopen_by_name(loc, object_name.c_str(), attr_name.c_str(), H5P_DEFAULT, H5P_DEFAULT), where,
               "cannot open the attribute"));
  return Source{std::move(attribute), where, header};
}

// Shape checks. Each returns the extent, or throws "expected ..., found shape (...)".

Extent require_single_value(const Source& source) {
  const Extent extent = extent_of(source);
  if (extent.count() != 1) fail(source.where, "expected a single value, found " + extent.describe());
  return extent;
}

Extent require_1d(const Source& source, std::optional<hsize_t> expected_size = {}) {
  const Extent extent = extent_of(source);
  const bool ok =
      !extent.null && extent.dims.size() == 1 && (!expected_size || extent.dims[0] == *expected_size);
  if (!ok) {
    const std::string expected =
        expected_size ? "a 1-D dataset of " + std::to_string(*expected_size) + " values" : "a 1-D dataset";
    fail(source.where, "expected " + expected + ", found " + extent.describe());
  }
  return extent;
}

// Element type checks: doubles accept any float or integer data (HDF5 converts), integers only
// integer data (no silent truncation of floats), strings only strings.

void require_numeric(const Source& source, const Handle& type, bool integer_only) {
  const H5T_class_t type_class = H5Tget_class(type.get());
  const bool ok = type_class == H5T_INTEGER || (!integer_only && type_class == H5T_FLOAT);
  if (!ok) {
    fail(source.where, std::string("expected ") + (integer_only ? "integer" : "float64") + " data, found " +
                           describe_type(type.get()));
  }
  if (const std::string fault = numeric_type_fault(type.get()); !fault.empty()) fail(source.where, fault);
}

// A corrupted shape can claim more values than the file could hold even compressed (deflate's ratio is at
// most about 1032:1): refuse it before allocating, rather than failing in the allocator.
void require_plausible_size(const Source& source, hsize_t count, hsize_t value_size) {
  const Handle file(H5Iget_file_id(source.object.get()));
  hsize_t file_size = 0;
  if (!file.valid() || H5Fget_filesize(file.get(), &file_size) < 0) return;
  const hsize_t limit = (file_size + (hsize_t{1} << 20)) * 1100 / std::max<hsize_t>(value_size, 1);
  if (count > limit) {
    fail(source.where, "corrupt: its shape holds " + std::to_string(count) + " values, more than the file (" +
                           std::to_string(file_size) + " bytes) can hold");
  }
}

std::vector<double> read_doubles(const Source& source, hsize_t count) {
  require_numeric(source, type_of(source), false);
  require_plausible_size(source, count, 8);
  std::vector<double> values(count);
  if (count > 0) read_raw(source, H5T_NATIVE_DOUBLE, values.data());
  return values;
}

std::vector<std::int64_t> read_int64s(const Source& source, hsize_t count) {
  require_numeric(source, type_of(source), true);
  require_plausible_size(source, count, 8);
  std::vector<std::int64_t> values(count);
  if (count > 0) read_raw(source, H5T_NATIVE_INT64, values.data());
  return values;
}

// ---------------------------------------------------------------------------------------------
// Variable-length strings: HDF5 1.10 reads them from "global heap collections" and trusts what it finds
// there: a corrupted collection (an object size running past its end), or a corrupted reference (an
// object index the collection does not have, a length shorter than the object), makes it read or copy
// out of bounds and crash. So before the first variable-length read of a file, every collection in it
// (found by its "GCOL" signature) is checked the way HDF5 will walk it; and before reading a
// variable-length dataset or attribute, each of its references (raw bytes, read beside HDF5: a dataset's
// from its contiguous storage, an attribute's from its owner's object header) is checked against the
// collection it points into (docs/cli.md, "corrupted input files"). A collection's fault counts when a
// string refers into it: HDF5 loads a collection only for a reference, and the four bytes "GCOL" also turn up
// by chance in compressed raw data (a results file of 5 MB had them), which is no collection at all. Strings
// whose references cannot be read beside HDF5 (chunked or compact datasets, attributes of headers not walked)
// are refused if any collection with a sound header (version 1, reserved bytes 0: what chance bytes almost
// never spell) is faulty, as HDF5 might load that one.
// The checks assume HDF5's default 8-byte addresses and lengths and no user block; other files are read
// unchecked.

struct HeapCollection {
  std::uint64_t size = 0;
  std::map<std::uint16_t, std::uint64_t> objects;  // index -> object size
  std::string fault;                               // what is wrong with it, "" if sound
};

struct HeapCheck {
  std::map<std::uint64_t, HeapCollection> collections;  // by file address (every "GCOL" found)
  std::string error;  // the first fault of a collection with a sound header, "" if none
};

// The message of a faulty collection at `offset` of the file.
std::string collection_fault_text(std::uint64_t offset, const std::string& fault) {
  return "corrupt variable-length string storage (global heap collection at byte " + std::to_string(offset) +
         ": " + fault + ")";
}

std::uint64_t little_endian(const unsigned char* p, int bytes) {
  std::uint64_t value = 0;
  for (int i = bytes - 1; i >= 0; --i) value = (value << 8) | p[i];
  return value;
}

// Walk one collection as HDF5's loader does (header: "GCOL", version 1, 3 reserved bytes, 8-byte size;
// objects: 2-byte index, 2-byte reference count, 4 reserved, 8-byte size, data padded to 8 bytes;
// index 0 is the free space). "" if sound, else what is wrong.
std::string check_collection(const std::vector<unsigned char>& bytes, HeapCollection& collection) {
  if (bytes[4] != 1) return "unknown version " + std::to_string(bytes[4]);
  collection.size = little_endian(bytes.data() + 8, 8);
  if (collection.size < 4096 || collection.size != bytes.size()) return "impossible size";
  std::size_t at = 16;
  while (at < bytes.size()) {
    if (at + 16 > bytes.size()) break;  // a tail too short for an object header is free space
    const auto index = static_cast<std::uint16_t>(little_endian(bytes.data() + at, 2));
    const std::uint64_t size = little_endian(bytes.data() + at + 8, 8);
    const std::uint64_t need = index == 0 ? size : 16 + (size + 7) / 8 * 8;
    if (size > bytes.size() || need == 0 || need > bytes.size() - at) {
      return "object " + std::to_string(index) + " runs past the end of the collection";
    }
    if (index != 0 && !collection.objects.emplace(index, size).second) {
      return "object " + std::to_string(index) + " appears twice";
    }
    at += static_cast<std::size_t>(need);
  }
  return "";
}

// Files opened read-only, with HDF5's default 8-byte addresses and lengths and no user block: the ones whose
// bytes on disk are what HDF5 reads (a file being written has metadata in HDF5's cache, not yet on disk).
bool read_only_with_default_sizes(hid_t object) {
  const Handle file(H5Iget_file_id(object));
  unsigned intent = 0;
  if (!file.valid() || H5Fget_intent(file.get(), &intent) < 0 || intent != H5F_ACC_RDONLY) return false;
  const Handle fcpl(H5Fget_create_plist(file.get()));
  size_t address_size = 0, length_size = 0;
  hsize_t userblock = 1;
  if (!fcpl.valid() || H5Pget_sizes(fcpl.get(), &address_size, &length_size) < 0 ||
      H5Pget_userblock(fcpl.get(), &userblock) < 0) {
    return false;
  }
  return address_size == 8 && length_size == 8 && userblock == 0;
}

std::string file_name_of(hid_t object) {
  const ssize_t length = H5Fget_name(object, nullptr, 0);
  if (length <= 0) return "";
  std::string name(static_cast<size_t>(length) + 1, '\0');
  H5Fget_name(object, name.data(), name.size());
  name.resize(static_cast<size_t>(length));
  return name;
}

// The check of every collection of a file, made once per file and contents (path, size, time).
const HeapCheck& heap_check(const std::string& file_name) {
  static std::mutex mutex;
  static std::map<std::string, std::pair<std::string, HeapCheck>> checked;
  std::error_code error;
  const auto size = std::filesystem::file_size(file_name, error);
  const auto time = std::filesystem::last_write_time(file_name, error);
  const std::string stamp = std::to_string(size) + "@" + std::to_string(time.time_since_epoch().count());
  const std::lock_guard<std::mutex> lock(mutex);
  auto& [known_stamp, check] = checked[file_name];
  if (known_stamp == stamp) return check;
  known_stamp = stamp;
  check = HeapCheck();
  std::ifstream in(file_name, std::ios::binary);
  constexpr std::size_t kBlock = 1 << 20;
  std::vector<char> block(kBlock + 3);
  std::size_t carried = 0;  // bytes kept from the previous block (a signature split across blocks)
  std::uint64_t block_start = 0;
  std::vector<std::uint64_t> found;
  while (in) {
    in.read(block.data() + carried, static_cast<std::streamsize>(kBlock));
    const std::size_t valid = carried + static_cast<std::size_t>(in.gcount());
    if (valid < 4) break;
    for (std::size_t i = 0; i + 4 <= valid; ++i) {
      const void* hit = std::memchr(block.data() + i, 'G', valid - 3 - i);
      if (hit == nullptr) break;
      i = static_cast<std::size_t>(static_cast<const char*>(hit) - block.data());
      if (std::memcmp(block.data() + i, "GCOL", 4) == 0) found.push_back(block_start + i);
    }
    std::memmove(block.data(), block.data() + valid - 3, 3);
    block_start += valid - 3;
    carried = 3;
  }
  for (const std::uint64_t offset : found) {
    std::ifstream file(file_name, std::ios::binary);
    unsigned char header[16] = {};
    file.seekg(static_cast<std::streamoff>(offset));
    if (!file.read(reinterpret_cast<char*>(header), 16)) continue;
    const std::uint64_t collection_size = little_endian(header + 8, 8);
    HeapCollection collection;
    std::string fault;
    if (collection_size < 16 || collection_size > size - offset) {
      fault = "impossible size";
    } else {
      std::vector<unsigned char> bytes(static_cast<std::size_t>(collection_size));
      file.seekg(static_cast<std::streamoff>(offset));
      file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      fault = file ? check_collection(bytes, collection) : "cannot read it";
    }
    const bool sound_header = header[4] == 1 && header[5] == 0 && header[6] == 0 && header[7] == 0;
    if (!fault.empty() && sound_header && check.error.empty()) {
      check.error = collection_fault_text(offset, fault);
    }
    collection.fault = fault;
    check.collections.emplace(offset, std::move(collection));
  }
  return check;
}

// One stored variable-length string's reference (16 bytes: length (4), collection address (8), object
// index (4)) checked against the collections of `check`: "" if it refers to a stored string of its length in
// a sound collection (the object H5HG_read will copy into a buffer of that length, plus a terminator), else
// what is wrong.
std::string reference_fault(const HeapCheck& check, const unsigned char* reference) {
  const std::uint64_t length = little_endian(reference, 4);
  const std::uint64_t address = little_endian(reference + 4, 8);
  const std::uint64_t index = little_endian(reference + 12, 4);
  if (length == 0 && address == 0) return "";  // an empty string: nothing stored
  const std::string no_string = "refers to no stored string of its length";
  const auto collection = check.collections.find(address);
  if (collection == check.collections.end() || index > 0xffff) return no_string;
  if (!collection->second.fault.empty()) {
    return "refers into " + collection_fault_text(address, collection->second.fault);
  }
  const auto object = collection->second.objects.find(static_cast<std::uint16_t>(index));
  return object != collection->second.objects.end() && object->second == length ? "" : no_string;
}

// The references of a variable-length string dataset of `count` strings, read from its contiguous
// storage; none (unchecked) for chunked or compact storage, which is not reachable beside HDF5.
std::vector<unsigned char> dataset_references(const Source& source, const std::string& file_name,
                                              hsize_t count) {
  const hid_t object = source.object.get();
  const haddr_t offset = H5Dget_offset(object);
  if (offset == HADDR_UNDEF) return {};
  if (H5Dget_storage_size(object) != 16 * count)
    fail(source.where, "corrupt: storage size does not match its shape");
  std::vector<unsigned char> references =
      FileBytes(file_name).read(offset, static_cast<std::size_t>(16 * count));
  if (references.empty()) fail(source.where, "corrupt: its data lies beyond the end of the file");
  return references;
}

// The references of a variable-length string attribute of `count` strings, read from the object header of
// the object it is attached to; none (unchecked) if that header was not read (stored_attributes).
std::vector<unsigned char> attribute_references(const Source& source, const std::string& file_name,
                                                hsize_t count) {
  const hid_t attribute = source.object.get();
  if (source.owner_header == HADDR_UNDEF) return {};
  const ssize_t length = H5Aget_name(attribute, 0, nullptr);
  if (length < 0) return {};
  std::string name(static_cast<std::size_t>(length) + 1, '\0');
  H5Aget_name(attribute, name.size(), name.data());
  name.resize(static_cast<std::size_t>(length));
  const auto& strings = stored_attributes(file_name, source.owner_header).strings;
  const auto found = strings.find(name);
  if (found == strings.end()) return {};
  const StoredStringAttribute& stored = found->second;
  if (!stored.fault.empty()) fail(source.where, "corrupt: " + stored.fault);
  if (stored.count != count) {
    fail(source.where, "corrupt: its object header holds " + std::to_string(stored.count) + " strings, not " +
                           std::to_string(count));
  }
  return stored.references;
}

// Before HDF5 reads `count` variable-length strings from `source`: the checks above; throws naming the file.
void check_variable_length_strings(const Source& source, hsize_t count) {
  const hid_t object = source.object.get();
  if (!read_only_with_default_sizes(object)) return;
  const std::string file_name = file_name_of(object);
  if (file_name.empty()) return;
  const HeapCheck& check = heap_check(file_name);
  const std::vector<unsigned char> references = source.is_attribute()
                                                    ? attribute_references(source, file_name, count)
                                                    : dataset_references(source, file_name, count);
  if (references.empty() && !check.error.empty()) fail(source.where, check.error);  // unchecked references
  for (std::size_t i = 0; i < references.size() / 16; ++i) {
    const std::string fault = reference_fault(check, references.data() + 16 * i);
    if (!fault.empty()) fail(source.where, "corrupt: string " + std::to_string(i) + " " + fault);
  }
}

// Strings: variable-length (ours, and h5py's str) or fixed-length (h5py's numpy bytes). HDF5 cannot
// convert between the two, so each is read in its own memory type.
std::vector<std::string> read_strings_from(const Source& source, hsize_t count) {
  const Handle type = type_of(source);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    fail(source.where, "expected string data, found " + describe_type(type.get()));
  }
  const bool variable = H5Tis_variable_str(type.get()) > 0;
  require_plausible_size(source, count, variable ? 16 : std::max<size_t>(H5Tget_size(type.get()), 1));
  std::vector<std::string> values;
  values.reserve(count);
  if (count == 0) return values;
  if (variable) {
    check_variable_length_strings(source, count);
    // HDF5 allocates each string; we copy and free them.
    const Handle mem_type = vlen_string_type();
    std::vector<char*> pointers(count, nullptr);
    read_raw(source, mem_type.get(), pointers.data());
    for (char* pointer : pointers) {
      values.emplace_back(pointer != nullptr ? pointer : "");
      H5free_memory(pointer);
    }
    return values;
  }
  // Fixed length: read the raw bytes in the file's own string type and strip the padding.
  const size_t size = H5Tget_size(type.get());
  const H5T_str_t padding = H5Tget_strpad(type.get());
  std::vector<char> bytes(count * size);
  read_raw(source, type.get(), bytes.data());
  for (hsize_t i = 0; i < count; ++i) {
    std::string value(bytes.data() + i * size, size);
    if (padding == H5T_STR_SPACEPAD) {
      value.erase(value.find_last_not_of(' ') + 1);
    } else {
      value.erase(std::min(value.find('\0'), value.size()));
    }
    values.push_back(std::move(value));
  }
  return values;
}

}  // namespace

// =============================================================================================
// Handle

namespace {
// Close `id` with the H5*close of its kind. Ids already closed (e.g. by a strong file close) are skipped;
// HDF5 does not reuse ids, so a stale id never names another object.
void close_id(hid_t id) noexcept {
  if (id < 0 || H5Iis_valid(id) <= 0) return;
  switch (H5Iget_type(id)) {
    case H5I_FILE:
      H5Fclose(id);
      break;
    case H5I_GROUP:
      H5Gclose(id);
      break;
    case H5I_DATASET:
      H5Dclose(id);
      break;
    case H5I_DATASPACE:
      H5Sclose(id);
      break;
    case H5I_DATATYPE:
      H5Tclose(id);
      break;
    case H5I_ATTR:
      H5Aclose(id);
      break;
    case H5I_GENPROP_LST:
      H5Pclose(id);
      break;
    default:
      break;
  }
}
}  // namespace

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    close_id(id_);
    id_ = other.id_;
    other.id_ = H5I_INVALID_HID;
  }
  return *this;
}

Handle::~Handle() {
  close_id(id_);
}

// =============================================================================================
// AppendableDataset

void AppendableDataset::append(std::span<const double> row_major_values) {
  if (!dataset_.valid()) throw Error("append() on an AppendableDataset not made by Group::create_appendable");
  if (row_major_values.size() % columns_ != 0) {
    fail(path_, "cannot append " + std::to_string(row_major_values.size()) +
                    " values: not a whole number of rows of " + std::to_string(columns_) + " columns");
  }
  const hsize_t new_rows = row_major_values.size() / columns_;
  if (new_rows == 0) return;
  if (rank_ == 1) {
    const hsize_t extent1[1] = {rows_ + new_rows};
    check_status(H5Dset_extent(dataset_.get(), extent1), path_, "cannot extend");
    const Handle space1(check_id(H5Dget_space(dataset_.get()), path_, "cannot get the dataspace"));
    const hsize_t start1[1] = {rows_};
    const hsize_t count1[1] = {new_rows};
    check_status(H5Sselect_hyperslab(space1.get(), H5S_SELECT_SET, start1, nullptr, count1, nullptr), path_,
                 "cannot select the new rows");
    const Handle memory1(check_id(H5Screate_simple(1, count1, nullptr), path_, "cannot create a dataspace"));
    check_status(H5Dwrite(dataset_.get(), H5T_NATIVE_DOUBLE, memory1.get(), space1.get(), H5P_DEFAULT,
                          row_major_values.data()),
                 path_, "cannot append rows");
    rows_ += new_rows;
    return;
  }
  // Grow the dataset, then write into the new rows: a hyperslab of the file's dataspace.
  const hsize_t extent[2] = {rows_ + new_rows, columns_};
  check_status(H5Dset_extent(dataset_.get(), extent), path_, "cannot extend");
  const Handle file_space(check_id(H5Dget_space(dataset_.get()), path_, "cannot get the dataspace"));
  const hsize_t start[2] = {rows_, 0};
  const hsize_t count[2] = {new_rows, columns_};
  check_status(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), path_,
               "cannot select the new rows");
  const Handle memory_space(
      check_id(H5Screate_simple(2, count, nullptr), path_, "cannot create a dataspace"));
  check_status(H5Dwrite(dataset_.get(), H5T_NATIVE_DOUBLE, memory_space.get(), file_space.get(), H5P_DEFAULT,
                        row_major_values.data()),
               path_, "cannot append rows");
  rows_ += new_rows;
}

void AppendableDataset::truncate(hsize_t rows) {
  if (!dataset_.valid())
    throw Error("truncate() on an AppendableDataset not made by Group::create_appendable");
  if (rows >= rows_) return;
  const hsize_t extent[2] = {rows, columns_};
  check_status(H5Dset_extent(dataset_.get(), extent), path_, "cannot shrink");
  rows_ = rows;
}

void AppendableDataset::set_attribute(std::string_view attr, const std::string& value) {
  if (!dataset_.valid())
    throw Error("set_attribute() on an AppendableDataset not made by Group::create_appendable");
  const Handle type = vlen_string_type();
  const char* pointer = value.c_str();
  write_attribute(dataset_.get(), ".", attr, path_, type.get(), type.get(), {}, &pointer);
}

void AppendableDataset::flush() {
  if (!dataset_.valid()) throw Error("flush() on an AppendableDataset not made by Group::create_appendable");
  check_status(H5Dflush(dataset_.get()), path_, "cannot write the appended rows to disk");
}

// =============================================================================================
// Group: structure

std::string Group::where(std::string_view name) const {
  return file_name_ + ":" + join_path(path_, name);
}

Group Group::create_group(std::string_view path) {
  const std::string location = where(path);
  if (link_exists(handle_.get(), path)) return open_group(path);  // open_group rejects a dataset
  require_parent_groups(handle_.get(), path, location);
  const Handle lcpl = intermediate_groups_lcpl();
  const Handle gcpl = creation_order_gcpl();
  Handle group(
      check_id(H5Gcreate2(handle_.get(), std::string(path).c_str(), lcpl.get(), gcpl.get(), H5P_DEFAULT),
               location, "cannot create group"));
  return Group(std::move(group), join_path(path_, path), file_name_);
}

Group Group::open_group(std::string_view path) const {
  const std::string location = where(path);
  if (!link_exists(handle_.get(), path)) fail(location, "no such group");
  Handle object(
      check_id(H5Oopen(handle_.get(), std::string(path).c_str(), H5P_DEFAULT), location, "cannot open"));
  if (H5Iget_type(object.get()) != H5I_GROUP) fail(location, "expected a group, found a dataset");
  return Group(std::move(object), join_path(path_, path), file_name_);
}

bool Group::exists(std::string_view path) const {
  return link_exists(handle_.get(), path);
}

std::vector<std::string> Group::members() const {
  const std::string location = where(".");
  H5G_info_t info;
  check_status(H5Gget_info(handle_.get(), &info), location, "cannot list members");
  // Groups we create track creation order; others (e.g. written by h5py) are listed by name.
  unsigned order_flags = 0;
  const Handle gcpl(H5Gget_create_plist(handle_.get()));
  if (gcpl.valid()) H5Pget_link_creation_order(gcpl.get(), &order_flags);
  const H5_index_t index = (order_flags & H5P_CRT_ORDER_INDEXED) ? H5_INDEX_CRT_ORDER : H5_INDEX_NAME;

  std::vector<std::string> names;
  names.reserve(info.nlinks);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    // First call: the name's length; second: the name (plus its terminating NUL).
    const ssize_t length =
        H5Lget_name_by_idx(handle_.get(), ".", index, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    check_status(length < 0 ? -1 : 0, location, "cannot list members");
    std::string name(static_cast<size_t>(length) + 1, '\0');
    H5Lget_name_by_idx(handle_.get(), ".", index, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<size_t>(length));
    names.push_back(std::move(name));
  }
  return names;
}

// =============================================================================================
// Group: writing datasets

void Group::write(std::string_view name, double value) {
  create_double_dataset(handle_.get(), name, where(name), &value, {});
}

void Group::write(std::string_view name, std::int64_t value) {
  create_dataset(handle_.get(), name, where(name), H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &value);
}

void Group::write(std::string_view name, int value) {
  write(name, static_cast<std::int64_t>(value));
}

void Group::write(std::string_view name, const Eigen::VectorXd& values) {
  create_double_dataset(handle_.get(), name, where(name), values.data(),
                        {static_cast<hsize_t>(values.size())});
}

void Group::write(std::string_view name, const Eigen::MatrixXd& values) {
  // Eigen stores columns contiguously; HDF5 datasets are row-major. Transpose the buffer so that
  // dataset element [i, j] is the matrix entry (i, j).
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> row_major = values;
  create_double_dataset(handle_.get(), name, where(name), row_major.data(),
                        {static_cast<hsize_t>(values.rows()), static_cast<hsize_t>(values.cols())});
}

void Group::write(std::string_view name, std::span<const double> row_major, const std::vector<hsize_t>& dims,
                  const Chunking& chunking) {
  if (element_count(dims) != row_major.size()) {
    fail(where(name), "shape " + format_dims(dims) + " needs " + std::to_string(element_count(dims)) +
                          " values, got " + std::to_string(row_major.size()));
  }
  create_double_dataset(handle_.get(), name, where(name), row_major.data(), dims, chunking);
}

void Group::write(std::string_view name, std::span<const std::int64_t> values) {
  const std::vector<hsize_t> dims = {values.size()};
  create_dataset(handle_.get(), name, where(name), H5T_STD_I64LE, H5T_NATIVE_INT64, dims, values.data(),
                 chunk_for(dims, {}, where(name)));
}

void Group::write(std::string_view name, const std::vector<std::string>& values) {
  const Handle type = vlen_string_type();
  const std::vector<const char*> pointers = c_strings(values);
  create_dataset(handle_.get(), name, where(name), type.get(), type.get(), {values.size()}, pointers.data());
}

void Group::write(std::string_view name, const std::string& value) {
  const Handle type = vlen_string_type();
  const char* pointer = value.c_str();
  create_dataset(handle_.get(), name, where(name), type.get(), type.get(), {}, &pointer);
}

AppendableDataset Group::create_appendable(std::string_view name, hsize_t columns, const Chunking& chunking) {
  const std::string location = where(name);
  if (columns == 0) fail(location, "an appendable dataset needs at least one column");
  require_new(handle_.get(), name, location);
  // Rows are unlimited (H5S_UNLIMITED), which HDF5 only allows for chunked datasets.
  std::vector<hsize_t> chunk = chunking.chunk;
  if (chunk.empty()) {
    const hsize_t chunk_columns = std::min(columns, kChunkTargetValues);
    chunk = {std::max<hsize_t>(1, kChunkTargetValues / chunk_columns), chunk_columns};
  } else if (chunk.size() != 2 || chunk[0] == 0 || chunk[1] == 0) {
    fail(location,
         "chunk shape " + format_dims(chunk) + " of an appendable dataset must be (rows, columns) > 0");
  }
  chunk[1] = std::min(chunk[1], columns);

  const hsize_t dims[2] = {0, columns};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, columns};
  const Handle space(check_id(H5Screate_simple(2, dims, max_dims), location, "cannot create a dataspace"));
  const Handle dcpl = dataset_creation_plist(chunk, chunking.deflate_level, location);
  const Handle lcpl = intermediate_groups_lcpl();
  AppendableDataset appendable;
  appendable.dataset_ = Handle(check_id(H5Dcreate2(handle_.get(), std::string(name).c_str(), H5T_IEEE_F64LE,
                                                   space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                                        location, "cannot create dataset"));
  appendable.path_ = location;
  appendable.columns_ = columns;
  return appendable;
}

AppendableDataset Group::open_appendable(std::string_view name) {
  Source source = open_dataset(handle_.get(), name, where(name));
  const Extent extent = extent_of(source);
  if (extent.null || extent.dims.empty() || extent.dims.size() > 2 || extent.max_dims[0] != H5S_UNLIMITED) {
    fail(source.where, "expected an appendable dataset (unlimited rows), found " + extent.describe());
  }
  require_numeric(source, type_of(source), false);
  AppendableDataset appendable;
  appendable.dataset_ = std::move(source.object);
  appendable.path_ = source.where;
  appendable.rows_ = extent.dims[0];
  appendable.rank_ = static_cast<int>(extent.dims.size());
  appendable.columns_ = appendable.rank_ == 2 ? extent.dims[1] : 1;
  return appendable;
}

AppendableDataset Group::create_appendable_vector(std::string_view name, const Chunking& chunking) {
  const std::string location = where(name);
  require_new(handle_.get(), name, location);
  std::vector<hsize_t> chunk = chunking.chunk;
  if (chunk.empty()) chunk = {kChunkTargetValues};
  if (chunk.size() != 1 || chunk[0] == 0)
    fail(location, "the chunk of a 1-D appendable dataset is (rows) > 0");
  const hsize_t dims[1] = {0};
  const hsize_t max_dims[1] = {H5S_UNLIMITED};
  const Handle space(check_id(H5Screate_simple(1, dims, max_dims), location, "cannot create a dataspace"));
  const Handle dcpl = dataset_creation_plist(chunk, chunking.deflate_level, location);
  const Handle lcpl = intermediate_groups_lcpl();
  AppendableDataset appendable;
  appendable.dataset_ = Handle(check_id(H5Dcreate2(handle_.get(), std::string(name).c_str(), H5T_IEEE_F64LE,
                                                   space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                                        location, "cannot create dataset"));
  appendable.path_ = location;
  appendable.columns_ = 1;
  appendable.rank_ = 1;
  return appendable;
}

// =============================================================================================
// Group: attributes

void Group::set_attribute(std::string_view attr, const std::string& value, std::string_view object) {
  const Handle type = vlen_string_type();
  const char* pointer = value.c_str();
  write_attribute(handle_.get(), object, attr, where(object), type.get(), type.get(), {}, &pointer);
}

void Group::set_attribute(std::string_view attr, const char* value, std::string_view object) {
  set_attribute(attr, std::string(value != nullptr ? value : ""), object);
}

void Group::set_attribute(std::string_view attr, double value, std::string_view object) {
  write_attribute(handle_.get(), object, attr, where(object), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value);
}

void Group::set_attribute(std::string_view attr, std::int64_t value, std::string_view object) {
  write_attribute(handle_.get(), object, attr, where(object), H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &value);
}

void Group::set_attribute(std::string_view attr, int value, std::string_view object) {
  set_attribute(attr, static_cast<std::int64_t>(value), object);
}

void Group::set_attribute(std::string_view attr, const std::vector<double>& value, std::string_view object) {
  write_attribute(handle_.get(), object, attr, where(object), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                  {value.size()}, value.data());
}

void Group::set_attribute(std::string_view attr, const std::vector<std::string>& value,
                          std::string_view object) {
  const Handle type = vlen_string_type();
  const std::vector<const char*> pointers = c_strings(value);
  write_attribute(handle_.get(), object, attr, where(object), type.get(), type.get(), {value.size()},
                  pointers.data());
}

bool Group::has_attribute(std::string_view attr, std::string_view object) const {
  if (!link_exists(handle_.get(), object)) return false;
  check_attribute_messages(handle_.get(), std::string(object), where(object));
  return H5Aexists_by_name(handle_.get(), std::string(object).c_str(), std::string(attr).c_str(),
                           H5P_DEFAULT) > 0;
}

std::string Group::string_attribute(std::string_view attr, std::string_view object) const {
  const Source source = open_attribute(handle_.get(), object, attr, where(object));
  require_single_value(source);
  return read_strings_from(source, 1).front();
}

double Group::double_attribute(std::string_view attr, std::string_view object) const {
  const Source source = open_attribute(handle_.get(), object, attr, where(object));
  require_single_value(source);
  return read_doubles(source, 1).front();
}

std::int64_t Group::int_attribute(std::string_view attr, std::string_view object) const {
  const Source source = open_attribute(handle_.get(), object, attr, where(object));
  require_single_value(source);
  return read_int64s(source, 1).front();
}

std::vector<std::string> Group::strings_attribute(std::string_view attr, std::string_view object) const {
  const Source source = open_attribute(handle_.get(), object, attr, where(object));
  return read_strings_from(source, require_1d(source).count());
}

std::vector<double> Group::doubles_attribute(std::string_view attr, std::string_view object) const {
  const Source source = open_attribute(handle_.get(), object, attr, where(object));
  return read_doubles(source, require_1d(source).count());
}

// =============================================================================================
// Group: reading datasets

std::vector<hsize_t> Group::shape(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  return extent_of(source).dims;
}

double Group::read_double(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  require_single_value(source);
  return read_doubles(source, 1).front();
}

std::int64_t Group::read_int(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  require_single_value(source);
  return read_int64s(source, 1).front();
}

Eigen::VectorXd Group::read_vector(std::string_view name, std::optional<hsize_t> expected_size) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  const std::vector<double> values = read_doubles(source, require_1d(source, expected_size).count());
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

Eigen::MatrixXd Group::read_matrix(std::string_view name, std::optional<hsize_t> expected_rows,
                                   std::optional<hsize_t> expected_cols) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  const Extent extent = extent_of(source);
  const bool ok = !extent.null && extent.dims.size() == 2 &&
                  (!expected_rows || extent.dims[0] == *expected_rows) &&
                  (!expected_cols || extent.dims[1] == *expected_cols);
  if (!ok) {
    std::string expected = "a 2-D dataset";
    if (expected_rows && expected_cols) {
      expected += " of shape " + format_dims({*expected_rows, *expected_cols});
    } else if (expected_rows) {
      expected += " with " + std::to_string(*expected_rows) + " rows";
    } else if (expected_cols) {
      expected += " with " + std::to_string(*expected_cols) + " columns";
    }
    fail(source.where, "expected " + expected + ", found " + extent.describe());
  }
  const std::vector<double> values = read_doubles(source, extent.count());
  // The dataset is row-major: map it as such, and let Eigen copy it into column-major storage.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(values.data(), static_cast<Eigen::Index>(extent.dims[0]),
                                    static_cast<Eigen::Index>(extent.dims[1]));
}

std::vector<double> Group::read_array(std::string_view name, std::vector<hsize_t>& dims) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  const Extent extent = extent_of(source);
  if (extent.null) fail(source.where, "expected an array, found " + extent.describe());
  std::vector<double> values = read_doubles(source, extent.count());
  dims = extent.dims;
  return values;
}

std::vector<std::int64_t> Group::read_ints(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  return read_int64s(source, require_1d(source).count());
}

std::vector<std::string> Group::read_strings(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  return read_strings_from(source, require_1d(source).count());
}

std::string Group::read_string(std::string_view name) const {
  const Source source = open_dataset(handle_.get(), name, where(name));
  require_single_value(source);
  return read_strings_from(source, 1).front();
}

// =============================================================================================
// File

namespace {

// File access properties of created files: a "strong" close, so closing the file also closes every
// group and dataset the caller still holds in it. commit() and the destructor then really release the
// temporary, and a stale Group fails instead of writing into the committed file.
// Files opened by open_read/open_append keep HDF5's default ("weak") close instead: HDF5 refuses to
// open one file twice with different close degrees, and the raw C API (or another library) in the same
// process uses the default.
Handle strong_close_fapl() {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG);
  return fapl;
}

Handle open_root(hid_t file, const std::string& file_name) {
  return Handle(check_id(H5Gopen2(file, "/", H5P_DEFAULT), file_name, "cannot open the root group"));
}

// Open an existing file; `flags` is H5F_ACC_RDONLY or H5F_ACC_RDWR.
Handle open_existing(const std::filesystem::path& path, unsigned flags) {
  silence_hdf5_errors();
  std::error_code error;
  if (!std::filesystem::exists(path, error)) fail(path.string(), "no such file");
  if (std::filesystem::is_directory(path, error))
    fail(path.string(), "is a directory, expected an HDF5 file");
  const hid_t id = H5Fopen(path.c_str(), flags, H5P_DEFAULT);
  const std::string mode = flags == H5F_ACC_RDWR ? "for appending" : "for reading";
  return Handle(
      check_id(id, path.string(), "cannot open " + mode + " (not an HDF5 file, or not accessible)"));
}

}  // namespace

File File::create(const std::filesystem::path& path) {
  silence_hdf5_errors();
  const std::string name = path.string();
  std::error_code error;
  const std::filesystem::path parent = path.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, error)) {
    fail(name, "cannot create: directory '" + parent.string() + "' does not exist");
  }
  File file;
  file.path_ = path;
  file.temporary_ = path;
  file.temporary_ += ".tmp-" + std::to_string(::getpid());
  register_temporary(file.temporary_);  // removed if a signal stops the run

  // Track link creation order in the root group (a file creation list carries group properties).
  const Handle fcpl(H5Pcreate(H5P_FILE_CREATE));
  H5Pset_link_creation_order(fcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  const Handle fapl = strong_close_fapl();
  file.file_ = Handle(check_id(H5Fcreate(file.temporary_.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()),
                               name, "cannot create temporary file '" + file.temporary_.string() + "'"));
  file.root_ = Group(open_root(file.file_.get(), name), "/", name);
  return file;
}

File File::open_read(const std::filesystem::path& path) {
  File file;
  file.path_ = path;
  file.file_ = open_existing(path, H5F_ACC_RDONLY);
  file.root_ = Group(open_root(file.file_.get(), path.string()), "/", path.string());
  return file;
}

File File::open_append(const std::filesystem::path& path) {
  File file;
  file.path_ = path;
  file.file_ = open_existing(path, H5F_ACC_RDWR);
  file.root_ = Group(open_root(file.file_.get(), path.string()), "/", path.string());
  return file;
}

File::File(File&& other) noexcept
    : path_(std::move(other.path_)),
      temporary_(std::move(other.temporary_)),
      file_(std::move(other.file_)),
      root_(std::move(other.root_)) {
  other.temporary_.clear();
}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    close_and_discard();
    path_ = std::move(other.path_);
    temporary_ = std::move(other.temporary_);
    file_ = std::move(other.file_);
    root_ = std::move(other.root_);
    other.temporary_.clear();
  }
  return *this;
}

File::~File() {
  close_and_discard();
}

void File::close_and_discard() noexcept {
  root_ = Group();
  file_ = Handle();  // a created file: strong close, also closes whatever the caller still holds
  if (!temporary_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
    unregister_temporary(temporary_);
    temporary_.clear();
  }
}

Group File::root() {
  if (!file_.valid()) throw Error(path_.string() + ": the file is closed (committed or moved from)");
  return root_.open_group(".");
}

const Group& File::root() const {
  return root_;
}

void File::flush() {
  if (!file_.valid()) throw Error(path_.string() + ": the file is closed (committed or moved from)");
  check_status(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), path_.string(), "cannot write to disk");
}

void File::commit() {
  const std::string name = path_.string();
  if (temporary_.empty()) fail(name, "commit() of a file not made by File::create, or committed already");
  // Close explicitly to see errors (a full disk shows up here); the strong close degree closes every
  // object still open in the file first. The Handle then finds its id invalid and does nothing.
  root_ = Group();
  // The id is released before the close: after a failed H5Fclose it must never be closed again.
  check_status(H5Fclose(file_.release()), name,
               "cannot write the file (its temporary '" + temporary_.string() + "' is removed)");
  std::error_code error;
  std::filesystem::rename(temporary_, path_, error);
  if (error) fail(name, "cannot rename '" + temporary_.string() + "' onto it: " + error.message());
  unregister_temporary(temporary_);
  temporary_.clear();
}

void silence_hdf5_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

std::string numeric_type_fault(hid_t type) {
  const H5T_class_t type_class = H5Tget_class(type);
  const size_t size = H5Tget_size(type);
  const size_t precision = H5Tget_precision(type);
  const int offset = H5Tget_offset(type);
  const bool integer = type_class == H5T_INTEGER && (size == 1 || size == 2 || size == 4 || size == 8);
  const bool real = type_class == H5T_FLOAT && (size == 4 || size == 8);
  const bool bits_inside =
      precision > 0 && offset >= 0 && precision + static_cast<size_t>(offset) <= 8 * size;
  if ((integer || real) && bits_inside) return "";
  return "corrupt or unsupported type: " + describe_type(type) + " of " + std::to_string(precision) +
         " bits at bit " + std::to_string(offset);
}

}  // namespace nvh::h5
