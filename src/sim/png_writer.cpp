#include "sim/png_writer.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numeric>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/error.hpp"

namespace glmbslam::sim {
namespace {

/// CRC-32 (PNG chunks), table driven, eight bytes per step ("slicing by 8": the same CRC as the byte-wise
/// table loop, without its one-table-lookup-per-byte dependency chain).
class Crc32 {
 public:
  Crc32() {
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      table_[0][n] = c;
    }
    for (std::size_t t = 1; t < 8; ++t) {
      for (std::size_t n = 0; n < 256; ++n) {
        const std::uint32_t c = table_[t - 1][n];
        table_[t][n] = (c >> 8) ^ table_[0][c & 0xFFU];
      }
    }
  }
  std::uint32_t operator()(const std::uint8_t* data, std::size_t n) const {
    std::uint32_t c = 0xFFFFFFFFU;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint32_t lo, hi;
      std::memcpy(&lo, data + i, 4);  // little-endian byte order (x86-64, and every target we build for)
      std::memcpy(&hi, data + i + 4, 4);
      lo ^= c;
      c = table_[7][lo & 0xFFU] ^ table_[6][(lo >> 8) & 0xFFU] ^ table_[5][(lo >> 16) & 0xFFU] ^
          table_[4][lo >> 24] ^ table_[3][hi & 0xFFU] ^ table_[2][(hi >> 8) & 0xFFU] ^
          table_[1][(hi >> 16) & 0xFFU] ^ table_[0][hi >> 24];
    }
    for (; i < n; ++i) c = table_[0][(c ^ data[i]) & 0xFFU] ^ (c >> 8);
    return c ^ 0xFFFFFFFFU;
  }

 private:
  std::array<std::array<std::uint32_t, 256>, 8> table_{};
};

const Crc32& crc32() {
  static const Crc32 crc;
  return crc;
}

/// Adler-32 (zlib trailer). With SSE2, 16 bytes per step: over a run of n bytes x_1..x_n starting from
/// (a0, b0), a = a0 + Σ x_i and b = b0 + n·a0 + Σ (n − i + 1)·x_i; per 16-byte block j the weight splits
/// into 16·(blocks after j) + (16 − i), so b needs the running block sums and one weighted sum per block.
/// Exact integer arithmetic, reduced modulo 65521 once per run of at most kRun bytes.
std::uint32_t adler32(const std::uint8_t* data, std::size_t n) {
  constexpr std::uint64_t kMod = 65521U;
  std::uint64_t a = 1, b = 0;
  constexpr std::size_t kRun = 5552 / 16 * 16;  // keeps the 32-bit lane sums below 2^32
  while (n > 0) {
    const std::size_t run = std::min<std::size_t>(n, kRun);
    std::size_t i = 0;
    std::uint64_t sum = 0, weighted = 0, prefix = 0;  // Σx, Σ(16 − i)x per block, Σ_j (sums before j)
#if defined(__SSE2__)
    {
      const __m128i zero = _mm_setzero_si128();
      const __m128i w_lo = _mm_setr_epi16(16, 15, 14, 13, 12, 11, 10, 9);
      const __m128i w_hi = _mm_setr_epi16(8, 7, 6, 5, 4, 3, 2, 1);
      __m128i vsum = zero, vprefix = zero, vweighted = zero;
      for (; i + 16 <= run; i += 16) {
        const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(data + i));
        vprefix = _mm_add_epi32(vprefix, vsum);
        vsum = _mm_add_epi32(vsum, _mm_sad_epu8(x, zero));
        vweighted = _mm_add_epi32(vweighted, _mm_madd_epi16(_mm_unpacklo_epi8(x, zero), w_lo));
        vweighted = _mm_add_epi32(vweighted, _mm_madd_epi16(_mm_unpackhi_epi8(x, zero), w_hi));
      }
      alignas(16) std::uint32_t s[4], p[4], w[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(s), vsum);
      _mm_store_si128(reinterpret_cast<__m128i*>(p), vprefix);
      _mm_store_si128(reinterpret_cast<__m128i*>(w), vweighted);
      sum = static_cast<std::uint64_t>(s[0]) + s[2];  // sad_epu8: sums in lanes 0 and 2
      prefix = static_cast<std::uint64_t>(p[0]) + p[2];
      weighted = static_cast<std::uint64_t>(w[0]) + w[1] + w[2] + w[3];
    }
#endif
    // The blocks: b += i·a0 + 16·Σ_j prefix_j + Σ weighted, a += Σ x.
    b += static_cast<std::uint64_t>(i) * a + 16 * prefix + weighted;
    a += sum;
    for (; i < run; ++i) {
      a += data[i];
      b += a;
    }
    a %= kMod;
    b %= kMod;
    data += run;
    n -= run;
  }
  return static_cast<std::uint32_t>((b << 16) | a);
}

/// Huffman code lengths (at most `limit` bits) for the frequencies `freq`; zero frequency → length 0.
/// At least two symbols get a code (a one-symbol deflate code would be incomplete).
std::vector<int> huffman_lengths(std::vector<std::uint64_t> freq, int limit) {
  const std::size_t n = freq.size();
  std::size_t used = 0;
  for (std::uint64_t f : freq) used += f > 0 ? 1 : 0;
  for (std::size_t i = 0; i < n && used < 2; ++i) {
    if (freq[i] == 0) {
      freq[i] = 1;
      ++used;
    }
  }
  std::vector<int> length(n, 0);
  for (;;) {
    // Nodes: leaves 0..n−1, internal nodes appended; a deterministic (weight, id) order.
    std::vector<std::uint64_t> weight(freq.begin(), freq.end());
    std::vector<int> parent(n, -1);
    std::vector<std::pair<std::uint64_t, int>> heap;
    for (std::size_t i = 0; i < n; ++i) {
      if (freq[i] > 0) heap.emplace_back(freq[i], static_cast<int>(i));
    }
    auto greater = [](const auto& x, const auto& y) { return x > y; };
    std::make_heap(heap.begin(), heap.end(), greater);
    while (heap.size() > 1) {
      std::pop_heap(heap.begin(), heap.end(), greater);
      const auto a = heap.back();
      heap.pop_back();
      std::pop_heap(heap.begin(), heap.end(), greater);
      const auto b = heap.back();
      heap.pop_back();
      const int id = static_cast<int>(weight.size());
      weight.push_back(a.first + b.first);
      parent.push_back(-1);
      parent[static_cast<std::size_t>(a.second)] = id;
      parent[static_cast<std::size_t>(b.second)] = id;
      heap.emplace_back(a.first + b.first, id);
      std::push_heap(heap.begin(), heap.end(), greater);
    }
    int longest = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (freq[i] == 0) {
        length[i] = 0;
        continue;
      }
      int d = 0;
      for (int p = parent[i]; p >= 0; p = parent[static_cast<std::size_t>(p)]) ++d;
      length[i] = d;
      longest = std::max(longest, d);
    }
    if (longest <= limit) return length;
    for (std::uint64_t& f : freq) {
      if (f > 0) f = (f + 1) / 2;  // flatten the distribution and retry
    }
  }
}

/// Canonical codes (RFC 1951 §3.2.2), bit-reversed for LSB-first output.
std::vector<std::uint32_t> canonical_codes(const std::vector<int>& length) {
  std::array<std::uint32_t, 16> count{}, next{};
  for (int l : length) count[static_cast<std::size_t>(l)] += l > 0 ? 1U : 0U;
  std::uint32_t code = 0;
  for (std::size_t bits = 1; bits < 16; ++bits) {
    next[bits] = code;
    code = (code + count[bits]) << 1;
  }
  std::vector<std::uint32_t> codes(length.size(), 0);
  for (std::size_t i = 0; i < length.size(); ++i) {
    const int l = length[i];
    if (l == 0) continue;
    std::uint32_t c = next[static_cast<std::size_t>(l)]++;
    std::uint32_t r = 0;
    for (int k = 0; k < l; ++k, c >>= 1) r = (r << 1) | (c & 1U);
    codes[i] = r;
  }
  return codes;
}

/// LSB-first bit writer into a preallocated buffer (the caller reserves enough room).
class BitWriter {
 public:
  explicit BitWriter(std::uint8_t* out) : out_(out), start_(out) {}
  void put(std::uint32_t bits, int n) {
    acc_ |= static_cast<std::uint64_t>(bits) << count_;
    count_ += n;
    if (count_ >= 32) {
      const auto word = static_cast<std::uint32_t>(acc_);
      std::memcpy(out_, &word, 4);  // little-endian: LSB first
      out_ += 4;
      acc_ >>= 32;
      count_ -= 32;
    }
  }
  /// Writes the codes table[data[i]] (code in the low 16 bits, ≤ 15 bits long, length above) for i < n: the
  /// same bits as put(code, length) per byte, three codes (≤ 45 bits) per unaligned 8-byte store.
  void put_literals(const std::uint8_t* data, std::size_t n, const std::uint32_t* table) {
    std::uint64_t acc = acc_;
    int count = count_;
    std::uint8_t* out = out_;
    while (count >= 8) {
      *out++ = static_cast<std::uint8_t>(acc & 0xFFU);
      acc >>= 8;
      count -= 8;
    }
    std::size_t i = 0;
    for (; i + 3 <= n; i += 3) {
      const std::uint32_t e0 = table[data[i]], e1 = table[data[i + 1]], e2 = table[data[i + 2]];
      acc |= static_cast<std::uint64_t>(e0 & 0xFFFFU) << count;
      count += static_cast<int>(e0 >> 16);
      acc |= static_cast<std::uint64_t>(e1 & 0xFFFFU) << count;
      count += static_cast<int>(e1 >> 16);
      acc |= static_cast<std::uint64_t>(e2 & 0xFFFFU) << count;
      count += static_cast<int>(e2 >> 16);  // ≤ 7 + 45
      std::memcpy(out, &acc, 8);            // little-endian: LSB first; the bytes past count are rewritten
      const int bytes = count >> 3;
      out += bytes;
      acc >>= 8 * bytes;
      count -= 8 * bytes;
    }
    acc_ = acc;
    count_ = count;
    out_ = out;
    for (; i < n; ++i) put(table[data[i]] & 0xFFFFU, static_cast<int>(table[data[i]] >> 16));
  }
  /// Flushes the partial byte; returns the number of bytes written.
  std::size_t finish() {
    while (count_ > 0) {
      *out_++ = static_cast<std::uint8_t>(acc_ & 0xFFU);
      acc_ >>= 8;
      count_ = std::max(0, count_ - 8);
    }
    return static_cast<std::size_t>(out_ - start_);
  }

 private:
  std::uint8_t* out_;
  std::uint8_t* start_;
  std::uint64_t acc_ = 0;
  int count_ = 0;
};

void put_u32_be(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

/// Appends a chunk: length, type, data, CRC of type and data.
void put_chunk(std::vector<std::uint8_t>& out, const char* type, const std::uint8_t* data, std::size_t n) {
  put_u32_be(out, static_cast<std::uint32_t>(n));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + n);
  put_u32_be(out, crc32()(out.data() + start, n + 4));
}

}  // namespace

void encode_png_gray8(const cv::Mat& image, PngScratch& scratch) {
  if (image.type() != CV_8UC1 || image.empty())
    throw ConfigError("PNG writer: needs a non-empty 8-bit image");
  const auto W = static_cast<std::size_t>(image.cols);
  const auto H = static_cast<std::size_t>(image.rows);
  // Sub filter: each byte minus its left neighbour (mod 256), filter type 1 at the start of every row.
  std::vector<std::uint8_t>& f = scratch.filtered;
  f.resize(H * (W + 1));
  std::array<std::uint64_t, 257> hist{};
  for (std::size_t r = 0; r < H; ++r) {
    const std::uint8_t* src = image.ptr<std::uint8_t>(static_cast<int>(r));
    std::uint8_t* dst = f.data() + r * (W + 1);
    dst[0] = 1;
    dst[1] = src[0];
    for (std::size_t c = 1; c < W; ++c) dst[c + 1] = static_cast<std::uint8_t>(src[c] - src[c - 1]);
  }
  {
    // Four partial histograms (breaks the store-to-load dependency on repeated bytes).
    std::array<std::array<std::uint32_t, 256>, 4> part{};
    const std::size_t n = f.size();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
      ++part[0][f[i]];
      ++part[1][f[i + 1]];
      ++part[2][f[i + 2]];
      ++part[3][f[i + 3]];
    }
    for (; i < n; ++i) ++part[0][f[i]];
    for (std::size_t s = 0; s < 256; ++s) hist[s] = part[0][s] + part[1][s] + part[2][s] + part[3][s];
  }
  hist[256] = 1;  // end of block
  const std::vector<int> lit_len = huffman_lengths(std::vector<std::uint64_t>(hist.begin(), hist.end()), 15);
  const std::vector<std::uint32_t> lit_code = canonical_codes(lit_len);

  // Code lengths of the literal/length alphabet (257 codes) and one distance code of length 1, written with
  // the code-length alphabet (literal lengths 0–15 only, no run-length codes).
  std::vector<int> all_lengths(lit_len.begin(), lit_len.end());
  all_lengths.push_back(1);
  std::vector<std::uint64_t> cl_freq(19, 0);
  for (int l : all_lengths) ++cl_freq[static_cast<std::size_t>(l)];
  const std::vector<int> cl_len = huffman_lengths(cl_freq, 7);
  const std::vector<std::uint32_t> cl_code = canonical_codes(cl_len);
  static constexpr std::array<int, 19> kOrder = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                                 11, 4,  12, 3, 13, 2, 14, 1, 15};
  int hclen = 19;
  while (hclen > 4 && cl_len[static_cast<std::size_t>(kOrder[static_cast<std::size_t>(hclen - 1)])] == 0)
    --hclen;

  std::vector<std::uint8_t>& out = scratch.encoded;
  out.clear();
  out.reserve(2 * f.size() + 2048);
  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  out.insert(out.end(), kSignature, kSignature + 8);
  std::uint8_t ihdr[13];
  for (int k = 0; k < 4; ++k) {
    ihdr[k] = static_cast<std::uint8_t>(W >> (24 - 8 * k));
    ihdr[4 + k] = static_cast<std::uint8_t>(H >> (24 - 8 * k));
  }
  ihdr[8] = 8;  // bit depth
  ihdr[9] = 0;  // grayscale
  ihdr[10] = ihdr[11] = ihdr[12] = 0;
  put_chunk(out, "IHDR", ihdr, 13);

  // IDAT: written in place (length patched afterwards) to avoid a copy.
  const std::size_t idat_start = out.size();
  put_u32_be(out, 0);
  out.insert(out.end(), {'I', 'D', 'A', 'T'});
  out.push_back(0x78);  // zlib: deflate, 32 KiB window
  out.push_back(0x01);  // no dictionary, fastest; (0x78·256 + 0x01) % 31 == 0
  {
    // Worst case: 15 bits per byte plus the header (< 300 bytes).
    const std::size_t at = out.size();
    out.resize(at + 2 * f.size() + 1024);
    BitWriter bits(out.data() + at);
    bits.put(1, 1);  // BFINAL
    bits.put(2, 2);  // dynamic Huffman
    bits.put(0, 5);  // HLIT = 257 − 257
    bits.put(0, 5);  // HDIST = 1 − 1
    bits.put(static_cast<std::uint32_t>(hclen - 4), 4);
    for (int k = 0; k < hclen; ++k) {
      bits.put(
          static_cast<std::uint32_t>(cl_len[static_cast<std::size_t>(kOrder[static_cast<std::size_t>(k)])]),
          3);
    }
    for (int l : all_lengths) {
      bits.put(cl_code[static_cast<std::size_t>(l)], cl_len[static_cast<std::size_t>(l)]);
    }
    // Literal codes (≤ 15 bits) with their lengths in the top bits: three per 64-bit flush.
    std::array<std::uint32_t, 256> table{};
    for (std::size_t s = 0; s < 256; ++s) {
      table[s] = lit_code[s] | (static_cast<std::uint32_t>(lit_len[s]) << 16);
    }
    bits.put_literals(f.data(), f.size(), table.data());
    bits.put(lit_code[256], lit_len[256]);
    out.resize(at + bits.finish());
  }
  put_u32_be(out, adler32(f.data(), f.size()));
  const std::size_t idat_len = out.size() - idat_start - 8;
  for (int k = 0; k < 4; ++k)
    out[idat_start + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(idat_len >> (24 - 8 * k));
  put_u32_be(out, crc32()(out.data() + idat_start + 4, idat_len + 4));
  put_chunk(out, "IEND", nullptr, 0);
}

void write_png_gray8(const std::filesystem::path& path, const cv::Mat& image, PngScratch& scratch) {
  encode_png_gray8(image, scratch);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!file) throw InputError(path.string(), "cannot write image");
  const std::size_t n = scratch.encoded.size();
  const bool ok = std::fwrite(scratch.encoded.data(), 1, n, file.get()) == n;
  if (std::fclose(file.release()) != 0 || !ok) throw InputError(path.string(), "cannot write image");
}

}  // namespace glmbslam::sim
