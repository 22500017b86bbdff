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
// Array flag bits (the second byte of the flags' first word).
constexpr std::uint32_t kComplex = 0x0800, kGlobal = 0x0400, kLogical = 0x0200;
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

  /// The element at `pos` of a buffer of `len` bytes (small-element format included), which must end, padding
  /// included, within `len`: libmatio reads an array's parts one after the other, so a part overrunning its
  /// array would be read from the bytes that follow.
  Element part(const std::uint8_t* buf, std::uint64_t len, std::uint64_t pos, const char* what) const {
    if (len - pos < 8) fail(std::string("a data element tag in ") + what + " is cut off");
    Element e;
    const std::uint32_t word = u32(buf + pos);
    if ((word >> 16) != 0) {  // small data element: 2-byte size, 2-byte type, 4 bytes of data
      e.type = word & 0xFFFFu;
      e.size = word >> 16;
      if (e.size > 4) fail(std::string("a small data element in ") + what + " declares more than 4 bytes");
      e.data = buf + pos + 4;
      e.next = pos + 8;
      return e;
    }
    e.type = word;
    e.size = u32(buf + pos + 4);
    if (e.size > len - pos - 8) {
      fail(std::string("a data element in ") + what + " declares " + std::to_string(e.size) + " bytes, " +
           std::to_string(len - pos - 8) + " remain");
    }
    // padded to 8 bytes, but for a compressed element
    const std::uint64_t padded = e.type == kMiCompressed ? e.size : (e.size + 7) / 8 * 8;
    if (padded > len - pos - 8) fail(std::string(what) + " overruns what contains it");
    e.data = buf + pos + 8;
    e.next = pos + 8 + padded;
    return e;
  }

  /// Bytes per value of a numeric data type; 0 for a type that holds no values (miMATRIX, miCOMPRESSED,
  /// the reserved 8, 10, 11, or unknown).
  static std::uint64_t value_size(std::uint32_t type) {
    switch (type) {
      case 1:
      case 2:
      case 16:
        return 1;  // miINT8, miUINT8, miUTF8
      case 3:
      case 4:
      case 17:
        return 2;  // miINT16, miUINT16, miUTF16
      case 5:
      case 6:
      case 7:
      case 18:
        return 4;  // miINT32, miUINT32, miSINGLE, miUTF32
      case 9:
      case 12:
      case 13:
        return 8;  // miDOUBLE, miINT64, miUINT64
      default:
        return 0;
    }
  }

  enum class Count { kExactly, kAtMost };

  /// A numeric part holding exactly (or at most) `count` values; a UTF-8 char array holds at least `count`
  /// bytes, as a character may take several.
  void values(const Element& e, std::uint64_t count, Count bound, const char* what) const {
    const std::uint64_t size = value_size(e.type);
    if (size == 0)
      fail(std::string(what) + " has the data type " + std::to_string(e.type) + ", not a number type");
    if (e.size % size != 0) fail(std::string(what) + " is not a whole number of values");
    const std::uint64_t n = e.size / size;
    const bool fits = bound == Count::kAtMost ? n <= count : e.type == 16 ? n >= count : n == count;
    if (!fits) {
      fail(std::string(what) + " stores " + std::to_string(n) + " values for " +
           (bound == Count::kAtMost ? "at most " : "") + std::to_string(count) + " elements");
    }
  }

  /// An array's real data, then its imaginary data if it is complex; returns the offset after them.
  std::uint64_t data_parts(const std::uint8_t* buf, std::uint64_t len, std::uint64_t pos, bool complex,
                           std::uint64_t count, Count bound) const {
    const Element real = part(buf, len, pos, "an array's data");
    values(real, count, bound, "an array's data");
    if (!complex) return real.next;
    const Element imaginary = part(buf, len, real.next, "an array's imaginary data");
    values(imaginary, count, bound, "an array's imaginary data");
    return imaginary.next;
  }

  /// An miMATRIX element's contents (MAT-File Format, "miMATRIX Format"): array flags, dimensions, name,
  /// then exactly the parts its class has — real (and imaginary) data; sparse row indices, column starts
  /// and data; a cell's or struct's nested arrays — and nothing more. libmatio reads these parts in
  /// sequence and allocates from their sizes, so only this exact layout is handed to it.
  void matrix(const std::uint8_t* buf, std::uint64_t len, int depth) const {
    if (len == 0) {
      if (depth == 0) fail("an array is empty (no flags, dimensions or name)");
      return;  // an empty nested array (e.g. an empty cell)
    }
    if (depth > kMaxDepth) fail("arrays nested more than " + std::to_string(kMaxDepth) + " deep");
    const Element flags = part(buf, len, 0, "an array's flags");
    if (flags.type != kMiUint32 || flags.size != 8) fail("an array's flags are not two miUINT32 values");
    const std::uint32_t flag_word = u32(flags.data);
    const std::uint32_t array_class = flag_word & 0xFFu;
    if (array_class == 0 || array_class > 17)
      fail("an array has the unknown class " + std::to_string(array_class));
    // objects, function handles and opaque values have other layouts, which libmatio cannot bound either
    if (array_class == kObject || array_class > 15)
      fail("an array is a MATLAB object, function handle or opaque value, which glmbslam does not read");
    if ((flag_word & ~(0xFFu | kComplex | kGlobal | kLogical)) != 0)
      fail("an array's flags have unknown bits set");
    const bool complex = (flag_word & kComplex) != 0;
    const std::uint64_t nzmax = u32(flags.data + 4);
    const Element dims = part(buf, len, flags.next, "an array's dimensions");
    if (dims.type != kMiInt32 || dims.size < 8 || dims.size % 4 != 0)
      fail("an array's dimensions are not at least two miINT32 values");
    std::uint64_t count = 1;
    for (std::uint64_t i = 0; i < dims.size / 4; ++i) {
      const auto d = static_cast<std::int32_t>(u32(dims.data + 4 * i));
      if (d < 0) fail("an array has a negative dimension");
      const auto ud = static_cast<std::uint64_t>(d);
      count = ud != 0 && count > kSaturated / ud ? kSaturated : count * ud;
    }
    const Element name = part(buf, len, dims.next, "an array's name");
    if (name.type != kMiInt8) fail("an array's name is not an miINT8 element");
    if (depth == 0) {
      variable_.assign(reinterpret_cast<const char*>(name.data), name.size);
      if (name.size == 0) fail("a variable has no name");
    }
    std::uint64_t pos = name.next;
    if (array_class == kCell || array_class == kStruct) {
      std::uint64_t children = count;
      if (array_class == kStruct) {
        const Element field_length = part(buf, len, pos, "a struct's field name length");
        if (field_length.type != kMiInt32 || field_length.size != 4)
          fail("a struct's field name length is not one miINT32 value");
        const std::uint32_t length = u32(field_length.data);
        const Element field_names = part(buf, len, field_length.next, "a struct's field names");
        if (field_names.type != kMiInt8) fail("a struct's field names are not an miINT8 element");
        if (length == 0 ? field_names.size != 0 : field_names.size % length != 0)
          fail("a struct's field names are not a whole number of names");
        const std::uint64_t fields = length == 0 ? 0 : field_names.size / length;
        children = fields != 0 && count > kSaturated / fields ? kSaturated : count * fields;
        pos = field_names.next;
      }
      std::uint64_t nested = 0;
      while (pos < len) {
        const Element e = part(buf, len, pos, "a nested array");
        if (e.type != kMiMatrix) fail("a cell or struct holds a data element that is not an array");
        matrix(e.data, e.size, depth + 1);
        ++nested;
        pos = e.next;
      }
      if (nested != children) {
        fail("a cell or struct array declares " + std::to_string(children) + " elements and holds " +
             std::to_string(nested));
      }
      return;
    }
    if (array_class == kSparse) {
      if (dims.size != 8) fail("a sparse array is not two-dimensional");
      const Element rows = part(buf, len, pos, "a sparse array's row indices");
      const Element starts = part(buf, len, rows.next, "a sparse array's column starts");
      for (const Element* e : {&rows, &starts}) {
        if (e->type != kMiInt32 && e->type != kMiUint32)
          fail("a sparse array's indices are not 32-bit integers");
        if (e->size % 4 != 0) fail("a sparse array's indices are not a whole number of values");
      }
      const std::uint64_t columns = static_cast<std::uint32_t>(u32(dims.data + 4));
      if (starts.size / 4 != columns + 1) fail("a sparse array's column starts do not match its columns");
      if (nzmax > rows.size / 4) fail("a sparse array declares more non-zeros than its row indices hold");
      // its data holds at most one value per row index
      pos = data_parts(buf, len, starts.next, complex, rows.size / 4, Count::kAtMost);
    } else {  // char, logical and numeric arrays
      pos = data_parts(buf, len, pos, complex, count, Count::kExactly);
    }
    if (pos < len) fail("an array holds data beyond its parts");
  }

  /// The top-level element at `pos`: an array, or a compressed array (inflated, then checked); returns the
  /// offset of the next. libmatio reads one variable per top-level element, so nothing else may stand there.
  std::uint64_t top_level(const std::uint8_t* buf, std::uint64_t len, std::uint64_t pos) const {
    variable_.clear();
    const Element e = part(buf, len, pos, "a variable");
    if (e.type == kMiMatrix) {
      matrix(e.data, e.size, 0);
    } else if (e.type == kMiCompressed) {
      const std::vector<std::uint8_t> inflated = inflate(e.data, e.size);
      const std::uint64_t n = inflated.size();
      if (n < 8 || u32(inflated.data()) != kMiMatrix) fail("a compressed variable does not hold an array");
      // libmatio's own writer declares a compressed char array's size for two bytes per character and
      // stores one, so the declared size may exceed what inflates; libmatio reads the parts, which must fit
      // in what does inflate
      matrix(inflated.data() + 8, std::min<std::uint64_t>(u32(inflated.data() + 4), n - 8), 0);
    } else {
      fail("the data element of type " + std::to_string(e.type) +
           " stands between the variables (only arrays and compressed arrays belong there)");
    }
    return e.next;
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
  while (pos < len) pos = walker.top_level(bytes.data(), len, pos);
}

}  // namespace glmbslam::io
