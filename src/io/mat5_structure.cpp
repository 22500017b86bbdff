#include "io/mat5_structure.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <zlib.h>

#include "core/error.hpp"

namespace glmbslam::io {

namespace {

// Data types and array classes of the level-5 format.
constexpr std::uint32_t kMiInt8 = 1, kMiInt32 = 5, kMiUint32 = 6, kMiMatrix = 14, kMiCompressed = 15;
constexpr std::uint32_t kCell = 1, kStruct = 2, kObject = 3, kSparse = 5;
constexpr int kMaxDepth = 32;  // nesting of cells / structs
// zlib's largest expansion is about 1032:1; an element inflating to more is corrupt.
constexpr std::uint64_t kMaxInflation = 1032;
constexpr std::uint64_t kSaturated = UINT64_MAX;

class Walker {
 public:
  Walker(std::string file, bool swap) : file_(std::move(file)), swap_(swap) {}

  [[noreturn]] void fail(const std::string& what) const {
    const std::string in = variable_.empty() ? std::string() : "variable '" + variable_ + "': ";
    throw InputError(file_, in + what + ": the .mat file is corrupt or truncated");
  }

  std::uint32_t u32(const std::uint8_t* p) const {
    std::uint32_t v = static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
                      static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
    if (swap_) v = (v >> 24) | ((v >> 8) & 0xFF00u) | ((v << 8) & 0xFF0000u) | (v << 24);
    return v;
  }

  struct Element {
    std::uint32_t type = 0;
    std::uint64_t size = 0;  // bytes of data
    const std::uint8_t* data = nullptr;
    std::uint64_t next = 0;  // offset of the following element
  };

  /// The element at `pos` of a buffer of `len` bytes (small-element format included).
  Element element(const std::uint8_t* buf, std::uint64_t len, std::uint64_t pos, const char* where) const {
    if (len - pos < 8) fail(std::string("a data element tag in ") + where + " is cut off");
    Element e;
    const std::uint32_t word = u32(buf + pos);
    if ((word >> 16) != 0) {  // small data element: 2-byte size, 2-byte type, 4 bytes of data
      e.type = word & 0xFFFFu;
      e.size = word >> 16;
      if (e.size > 4) fail(std::string("a small data element in ") + where + " declares more than 4 bytes");
      e.data = buf + pos + 4;
      e.next = pos + 8;
      return e;
    }
    e.type = word;
    e.size = u32(buf + pos + 4);
    if (e.size > len - pos - 8) {
      fail(std::string("a data element in ") + where + " declares " + std::to_string(e.size) + " bytes, " +
           std::to_string(len - pos - 8) + " remain");
    }
    e.data = buf + pos + 8;
    const std::uint64_t padded = e.type == kMiCompressed ? e.size : (e.size + 7) / 8 * 8;
    e.next = std::min(len, pos + 8 + padded);
    return e;
  }

  /// An miMATRIX element's contents: array flags, dimensions, name, then data or nested arrays.
  void matrix(const std::uint8_t* buf, std::uint64_t len, int depth) const {
    if (len == 0) return;  // an empty array (e.g. an empty cell)
    if (depth > kMaxDepth) fail("arrays nested more than " + std::to_string(kMaxDepth) + " deep");
    const Element flags = element(buf, len, 0, "an array");
    if (flags.type != kMiUint32 || flags.size != 8) fail("an array's flags are not two miUINT32 values");
    const std::uint32_t array_class = u32(flags.data) & 0xFFu;
    if (array_class == 0 || array_class > 17)
      fail("an array has the unknown class " + std::to_string(array_class));
    // function handles and classdef objects have another layout, which libmatio cannot bound either
    if (array_class > 15)
      fail("an array is a MATLAB function handle or object, which glmbslam does not read");
    const std::uint64_t nzmax = u32(flags.data + 4);
    const Element dims = element(buf, len, flags.next, "an array");
    if (dims.type != kMiInt32 || dims.size < 8 || dims.size % 4 != 0)
      fail("an array's dimensions are not at least two miINT32 values");
    std::uint64_t count = 1;
    for (std::uint64_t i = 0; i < dims.size / 4; ++i) {
      const auto d = static_cast<std::int32_t>(u32(dims.data + 4 * i));
      if (d < 0) fail("an array has a negative dimension");
      const auto ud = static_cast<std::uint64_t>(d);
      count = ud != 0 && count > kSaturated / ud ? kSaturated : count * ud;
    }
    const Element name = element(buf, len, dims.next, "an array");
    if (name.type != kMiInt8) fail("an array's name is not an miINT8 element");
    if (depth == 0) variable_.assign(reinterpret_cast<const char*>(name.data), name.size);
    std::uint64_t pos = name.next, data_bytes = 0, nested = 0;
    std::uint64_t fields = 1;
    if (array_class == kStruct || array_class == kObject) {
      if (array_class == kObject) {
        const Element class_name = element(buf, len, pos, "an object");
        pos = class_name.next;
      }
      const Element field_length = element(buf, len, pos, "a struct");
      const Element field_names = element(buf, len, field_length.next, "a struct");
      const std::uint32_t length = field_length.size >= 4 ? u32(field_length.data) : 0;
      fields = length == 0 ? 0 : field_names.size / length;
      pos = field_names.next;
    }
    while (pos < len) {
      const Element e = element(buf, len, pos, "an array");
      if (e.type == kMiMatrix) {
        matrix(e.data, e.size, depth + 1);
        ++nested;
      } else {
        data_bytes += e.size;
      }
      pos = e.next;
    }
    const std::uint64_t elements =
        array_class == kStruct || array_class == kObject
            ? (fields != 0 && count > kSaturated / fields ? kSaturated : count * fields)
            : count;
    if (array_class == kCell || array_class == kStruct || array_class == kObject) {
      if (elements > nested) {
        fail("a cell or struct array declares " + std::to_string(elements) + " elements and holds " +
             std::to_string(nested));
      }
    } else if (array_class == kSparse) {
      if (nzmax > data_bytes) fail("a sparse array declares more non-zeros than its data holds");
    } else if (count > data_bytes) {
      fail("an array declares " + std::to_string(count) + " elements and stores " +
           std::to_string(data_bytes) + " bytes");
    }
  }

  /// A top-level element: an array, or a compressed array (inflated, then checked).
  void top_level(const Element& e) const {
    variable_.clear();
    if (e.type == kMiMatrix) {
      matrix(e.data, e.size, 0);
    } else if (e.type == kMiCompressed) {
      const std::vector<std::uint8_t> inflated = inflate(e.data, e.size);
      const std::uint64_t n = inflated.size();
      std::uint64_t pos = 0;
      while (pos < n) {
        const Element inner = element(inflated.data(), n, pos, "a compressed variable");
        if (inner.type == kMiMatrix) matrix(inner.data, inner.size, 0);
        pos = inner.next;
      }
    }
  }

  std::vector<std::uint8_t> inflate(const std::uint8_t* data, std::uint64_t size) const {
    std::vector<std::uint8_t> out;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) fail("zlib cannot start");
    z.next_in = const_cast<Bytef*>(data);
    z.avail_in = static_cast<uInt>(size);
    const std::uint64_t limit = size * kMaxInflation + 4096;
    std::uint8_t chunk[16384];
    int status = Z_OK;
    while (status == Z_OK) {
      z.next_out = chunk;
      z.avail_out = sizeof(chunk);
      status = ::inflate(&z, Z_NO_FLUSH);
      if (status != Z_OK && status != Z_STREAM_END) break;
      out.insert(out.end(), chunk, chunk + (sizeof(chunk) - z.avail_out));
      if (out.size() > limit) break;
      if (status == Z_OK && z.avail_in == 0 && z.avail_out != 0) break;  // input exhausted before the end
    }
    inflateEnd(&z);
    if (out.size() > limit) fail("a compressed variable inflates beyond zlib's largest ratio");
    // a damaged or cut stream: libmatio reads what inflates; the walk below checks it for consistency
    return out;
  }

 private:
  std::string file_;
  bool swap_;
  mutable std::string variable_;  ///< the top-level variable being checked, for messages
};

}  // namespace

void check_mat5_structure(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot be opened");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  // Only level-5 and 7.3 files are read: libmatio's level-4 fallback trusts a header without any signature
  // and allocates from it.
  const bool little = bytes.size() >= 128 && bytes[126] == 'I' && bytes[127] == 'M';
  const bool big = bytes.size() >= 128 && bytes[126] == 'M' && bytes[127] == 'I';
  if (!little && !big) {
    throw InputError(path.string(), "not a MATLAB level-5 or 7.3 .mat file (no 128-byte header)");
  }
  const std::uint32_t version = little ? (bytes[124] | bytes[125] << 8) : (bytes[125] | bytes[124] << 8);
  if (version == 0x0200) return;  // 7.3: HDF5, read by libmatio through the HDF5 library
  if (version != 0x0100) {
    throw InputError(path.string(), "not a MATLAB level-5 or 7.3 .mat file (header version " +
                                        std::to_string(version) + ")");
  }
  const Walker walker(path.string(), big);
  const std::uint64_t len = bytes.size();
  std::uint64_t pos = 128;
  while (pos < len) {
    const auto e = walker.element(bytes.data(), len, pos, "the file");
    walker.top_level(e);
    pos = e.next;
  }
}

}  // namespace glmbslam::io
