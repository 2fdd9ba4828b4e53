// Private to the .gmb reader and writer: format constants (the layout itself is specified in
// docs/formats.md), little-endian byte buffers and section framing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "meshcore/gradient_mesh.h"

namespace gm {
struct ReadLimits;
}

namespace gm::gmb {

// PNG's trick: the high byte catches 7-bit transfers, CR LF and LF catch line-ending
// conversion, Ctrl-Z stops `type` on DOS.
constexpr char kMagic[8] = {'\x89', 'G', 'M', 'B', '\r', '\n', '\x1a', '\n'};
constexpr uint16_t kMajor = 1;
constexpr uint16_t kMinor = 4;             // the newest 1.x minor this code reads and writes
constexpr uint16_t kMinorCms2 = 3;         // a file whose newest sections are CMS2
constexpr uint16_t kMajorShort = 2;        // version 2: 1.4 with short section framing
constexpr uint16_t kMinorShort = 0;        // the newest 2.x minor this code reads and writes
constexpr size_t kFileHeaderSize = 12;     // magic, major, minor
constexpr size_t kSectionHeaderSize = 24;  // 1.x: tag, flags, codec, reserved, stored, raw
constexpr size_t kCrcSize = 4;
constexpr size_t kSectionOverhead = kSectionHeaderSize + kCrcSize;
// 2.x: tag, flags, codec and a varint S of one byte at least, then the CRC.
constexpr size_t kShortSectionHeaderMin = 7;
constexpr size_t kShortSectionOverheadMin = kShortSectionHeaderMin + kCrcSize;

constexpr uint8_t kSectionOptional = 0x01;  // a reader that does not know the tag skips it

enum class Codec : uint8_t { Stored = 0, Deflate = 1, Zstd = 2 };

// MESH section: how KNOT, NODE, SLIT and TANG of that mesh are encoded. The writer's compact
// mode writes Coded meshes in CMS2 or CMS3 sections (since 1.3 and 1.4); Quantized (1.0), Coded
// in MESH (1.1) and CMSH records (1.2) are only read.
enum class Encoding : uint8_t { Float64 = 0, Quantized = 1, Coded = 2 };
constexpr uint8_t kMeshColorByRule = 0x01;  // colour derivatives omitted, recomputed by the rule
// The mesh is in the Bicubic colour model (ColorModel::Bicubic). Coded meshes then store no
// colour derivatives (as with kMeshColorByRule); float64 meshes store them as zeros.
constexpr uint8_t kMeshColorBicubic = 0x02;
constexpr uint8_t kMeshFlagsKnown = kMeshColorByRule | kMeshColorBicubic;

constexpr size_t kDocPayloadSize = 12;   // DOCU in version 1.0
constexpr size_t kMeshPayloadSize = 32;  // MESH in version 1.0

// Order of the per-mesh quantisation exponents in MESH (a field is stored as q · 2^exponent).
enum Field { kKnot = 0, kPos, kPosU, kPosV, kCol, kColU, kColV, kFieldCount };
// Quantised values are integers of at most this magnitude, so q · 2^e is exact in a double.
constexpr int64_t kMaxQuantized = int64_t(1) << 53;
constexpr int kMaxExponent = 960;  // |exponent|: keeps q · 2^e finite and normal

// A node record lists 15 components in this order: pos.x pos.y posU.x posU.y posV.x posV.y
// col.r col.g col.b colU.r colU.g colU.b colV.r colV.g colV.b; the last six are left out when
// colour derivatives are omitted.
constexpr int kNodeComponents = 15;
constexpr int kNodeComponentsByRule = 9;

inline double& nodeComponent(Node& n, int k) {
    switch (k) {
        case 0: return n.pos.x;
        case 1: return n.pos.y;
        case 2: return n.posU.x;
        case 3: return n.posU.y;
        case 4: return n.posV.x;
        case 5: return n.posV.y;
        case 6: case 7: case 8: return n.col[k - 6];
        case 9: case 10: case 11: return n.colU[k - 9];
        default: return n.colV[k - 12];
    }
}
inline double nodeComponent(const Node& n, int k) { return nodeComponent(const_cast<Node&>(n), k); }

// The quantisation exponent that applies to node-record component k.
inline Field fieldOfComponent(int k) {
    static constexpr Field fields[kNodeComponents] = {kPos,  kPos,  kPosU, kPosU, kPosV,
                                                      kPosV, kCol,  kCol,  kCol,  kColU,
                                                      kColU, kColU, kColV, kColV, kColV};
    return fields[k];
}

// Appends little-endian fixed-width fields and LEB128 varints.
class ByteWriter {
public:
    void u8(uint8_t x) { out_.push_back(static_cast<char>(x)); }
    void u16(uint16_t x) { le(x, 2); }
    void u32(uint32_t x) { le(x, 4); }
    void u64(uint64_t x) { le(x, 8); }
    void i16(int16_t x) { le(static_cast<uint16_t>(x), 2); }
    void f64(double x);
    void varint(uint64_t x);
    void svarint(int64_t x);  // zigzag, so small negative numbers stay short
    void bytes(const std::string& s) { out_ += s; }
    std::string& str() { return out_; }

private:
    void le(uint64_t x, int n) {
        for (int k = 0; k < n; ++k) out_.push_back(static_cast<char>((x >> (8 * k)) & 0xff));
    }
    std::string out_;
};

// Where a reader's bytes came from, for error messages: a section's payload as stored in the
// file (offsets are file offsets) or after decompression (offsets within the payload).
struct Origin {
    std::string file;
    std::string section;        // tag, e.g. "NODE"; empty for the file header
    uint64_t base = 0;          // file offset of byte 0 of this buffer when not decompressed
    bool decompressed = false;  // then `sectionStart` is where the section begins in the file
    uint64_t sectionStart = 0;
};

// Reads little-endian fields with bounds checks; every failure is a gm::Error naming the file,
// the section and the byte.
class ByteReader {
public:
    ByteReader(const char* data, size_t size, Origin origin)
        : data_(data), size_(size), origin_(std::move(origin)) {}

    uint8_t u8() { return static_cast<uint8_t>(take(1)); }
    uint16_t u16() { return static_cast<uint16_t>(take(2)); }
    uint32_t u32() { return static_cast<uint32_t>(take(4)); }
    uint64_t u64() { return take(8); }
    int16_t i16() { return static_cast<int16_t>(static_cast<uint16_t>(take(2))); }
    double f64();
    uint64_t varint();
    int64_t svarint();
    void skip(uint64_t n);

    size_t position() const { return pos_; }
    // What error messages call the section from now on (a CMS2 section names each mesh in it).
    void rename(const std::string& section) { origin_.section = section; }
    size_t remaining() const { return size_ - pos_; }
    // Throws "truncated" unless `n` bytes remain (n in 64 bits: callers pass products of counts).
    void need(uint64_t n, const std::string& what) const;
    // "byte 1234" in the file, or where in a decompressed payload.
    std::string where() const;
    [[noreturn]] void fail(const std::string& what) const;

private:
    uint64_t take(int n);
    const char* data_;
    size_t size_;
    size_t pos_ = 0;
    Origin origin_;
};

// CRC-32 (zlib's) of a byte range.
uint32_t crc32Of(const char* data, size_t size);

// Compresses with `codec`; returns false (leaving `out` unspecified) if the result would not be
// smaller than the input.
bool compressPayload(Codec codec, const std::string& raw, std::string& out);

// Inflates exactly `rawSize` bytes; the output grows with the data actually produced, so a lying
// declaration costs no memory up front. Throws via `origin` if the stream is corrupt, ends early,
// produces more than `rawSize` bytes or has data after its end.
std::string decompressPayload(Codec codec, const char* data, size_t size, uint64_t rawSize,
                              const Origin& origin);

// Saturating 64-bit arithmetic for size bounds computed from untrusted counts.
inline uint64_t satMul(uint64_t a, uint64_t b) {
    uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? UINT64_MAX : r;
}
inline uint64_t satAdd(uint64_t a, uint64_t b) {
    uint64_t r;
    return __builtin_add_overflow(a, b, &r) ? UINT64_MAX : r;
}

}  // namespace gm::gmb
