// Byte-level helpers of the .gmb format: fixed-width little-endian fields, varints, CRC-32 and
// the two section codecs.
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>

#include "gmb_pvt.h"
#include "meshcore/error.h"

namespace gm::gmb {

void ByteWriter::f64(double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, 8);
    le(bits, 8);
}

void ByteWriter::varint(uint64_t x) {
    while (x >= 0x80) {
        out_.push_back(static_cast<char>((x & 0x7f) | 0x80));
        x >>= 7;
    }
    out_.push_back(static_cast<char>(x));
}

void ByteWriter::svarint(int64_t x) {
    const uint64_t ux = static_cast<uint64_t>(x);
    varint((ux << 1) ^ (x < 0 ? ~uint64_t(0) : 0));
}

std::string ByteReader::where() const {
    if (!origin_.decompressed) return "byte " + std::to_string(origin_.base + pos_);
    return "byte " + std::to_string(pos_) + " of the uncompressed payload of the section at byte " +
           std::to_string(origin_.sectionStart);
}

void ByteReader::fail(const std::string& what) const {
    const std::string in = origin_.section.empty() ? std::string() : " in section " + origin_.section;
    throw Error(what + in, origin_.file, where());
}

void ByteReader::need(uint64_t n, const std::string& what) const {
    if (n > remaining())
        fail("truncated: " + std::to_string(n) + " bytes needed for " + what + ", " +
             std::to_string(remaining()) + " remain");
}

uint64_t ByteReader::take(int n) {
    // The message is built only on failure: take() runs once per byte of a range-coded stream.
    if (static_cast<size_t>(n) > remaining())
        need(static_cast<uint64_t>(n), "a " + std::to_string(8 * n) + "-bit field");
    uint64_t x = 0;
    for (int k = 0; k < n; ++k)
        x |= static_cast<uint64_t>(static_cast<unsigned char>(data_[pos_ + k])) << (8 * k);
    pos_ += static_cast<size_t>(n);
    return x;
}

double ByteReader::f64() {
    const uint64_t bits = take(8);
    double x;
    std::memcpy(&x, &bits, 8);
    return x;
}

uint64_t ByteReader::varint() {
    uint64_t x = 0;
    for (int k = 0; k < 10; ++k) {
        if (remaining() == 0) need(1, "a varint");
        const auto byte = static_cast<unsigned char>(data_[pos_++]);
        // The tenth byte holds bit 63 only; anything more does not fit in 64 bits.
        if (k == 9 && byte > 1) fail("varint overflows 64 bits");
        x |= static_cast<uint64_t>(byte & 0x7f) << (7 * k);
        if (!(byte & 0x80)) return x;
    }
    fail("varint longer than 10 bytes");
}

int64_t ByteReader::svarint() {
    const uint64_t z = varint();
    return static_cast<int64_t>((z >> 1) ^ (~(z & 1) + 1));
}

void ByteReader::skip(uint64_t n) {
    need(n, "skipped data");
    pos_ += static_cast<size_t>(n);
}

uint32_t crc32Of(const char* data, size_t size) {
    uLong crc = crc32(0L, Z_NULL, 0);
    // zlib takes uInt lengths: feed large buffers in pieces.
    while (size > 0) {
        const uInt n = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
        crc = crc32(crc, reinterpret_cast<const Bytef*>(data), n);
        data += n;
        size -= n;
    }
    return static_cast<uint32_t>(crc);
}

namespace {

// Compression level and window: the window is capped so that any file we write decodes with
// the reader's window limit below.
constexpr int kZstdLevel = 19;
constexpr int kZstdWindowLog = 23;
constexpr int kDeflateLevel = 9;

[[noreturn]] void failCodec(const Origin& origin, const std::string& what) {
    throw Error(what + " in section " + origin.section, origin.file,
                "byte " + std::to_string(origin.sectionStart));
}

// The output grows in steps as data arrives, never past `rawSize`.
void growOutput(std::string& out, size_t used, uint64_t rawSize) {
    if (used < out.size()) return;
    const uint64_t next = std::min<uint64_t>(rawSize, std::max<uint64_t>(uint64_t(1) << 16, 2 * used));
    out.resize(static_cast<size_t>(next));
}

std::string inflateZstd(const char* data, size_t size, uint64_t rawSize, const Origin& origin) {
    ZSTD_DCtx* ctx = ZSTD_createDCtx();
    if (!ctx) failCodec(origin, "out of memory for zstd");
    struct Free {
        ZSTD_DCtx* c;
        ~Free() { ZSTD_freeDCtx(c); }
    } guard{ctx};
    // A hostile frame may ask for a window of up to 2 GiB; ours never need more than 2^23.
    ZSTD_DCtx_setParameter(ctx, ZSTD_d_windowLogMax, kZstdWindowLog + 1);
    std::string out;
    ZSTD_inBuffer in{data, size, 0};
    size_t used = 0;
    for (;;) {
        // Once everything declared has arrived, a one-byte probe catches a stream that is longer.
        char probe;
        const bool full = used == rawSize;
        if (!full) growOutput(out, used, rawSize);
        ZSTD_outBuffer o = full ? ZSTD_outBuffer{&probe, 1, 0} : ZSTD_outBuffer{&out[0], out.size(), used};
        const size_t inBefore = in.pos;
        const size_t r = ZSTD_decompressStream(ctx, &o, &in);
        if (ZSTD_isError(r))
            failCodec(origin, std::string("corrupt zstd data (") + ZSTD_getErrorName(r) + ")");
        if (full && o.pos > 0)
            failCodec(origin, "compressed data is larger than its declared size " + std::to_string(rawSize));
        bool progressed = in.pos != inBefore;
        if (!full) {
            progressed = progressed || o.pos != used;
            used = o.pos;
        }
        if (r == 0) {  // the frame is complete
            if (in.pos != in.size) failCodec(origin, "data after the end of the compressed stream");
            if (used != rawSize)
                failCodec(origin, "compressed data ends after " + std::to_string(used) +
                                      " bytes; its declared size is " + std::to_string(rawSize));
            out.resize(used);
            return out;
        }
        if (!progressed)
            failCodec(origin, "compressed stream is incomplete after " + std::to_string(used) +
                                  " of its declared " + std::to_string(rawSize) + " bytes");
    }
}

std::string inflateDeflate(const char* data, size_t size, uint64_t rawSize, const Origin& origin) {
    z_stream zs{};
    if (inflateInit(&zs) != Z_OK) failCodec(origin, "cannot start inflate");
    struct End {
        z_stream* z;
        ~End() { inflateEnd(z); }
    } guard{&zs};
    std::string out;
    size_t used = 0;
    size_t consumed = 0;
    for (;;) {
        growOutput(out, used, rawSize);
        // One byte of slack past the declared size detects a stream that is too long.
        char slack;
        const bool full = used == rawSize;
        zs.next_out = reinterpret_cast<Bytef*>(full ? &slack : &out[used]);
        zs.avail_out = full ? 1u : static_cast<uInt>(std::min<size_t>(out.size() - used, 1u << 30));
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data + consumed));
        zs.avail_in = static_cast<uInt>(std::min<size_t>(size - consumed, 1u << 30));
        const uInt outBefore = zs.avail_out, inBefore = zs.avail_in;
        const int r = inflate(&zs, Z_NO_FLUSH);
        const size_t produced = outBefore - zs.avail_out;
        consumed += inBefore - zs.avail_in;
        if (full && produced > 0)
            failCodec(origin, "compressed data is larger than its declared size " + std::to_string(rawSize));
        used += full ? 0 : produced;
        if (r == Z_STREAM_END) {
            if (used != rawSize)
                failCodec(origin, "compressed data ends after " + std::to_string(used) +
                                      " bytes; its declared size is " + std::to_string(rawSize));
            if (consumed != size) failCodec(origin, "data after the end of the compressed stream");
            out.resize(used);
            return out;
        }
        if (r == Z_NEED_DICT || r == Z_DATA_ERROR || r == Z_MEM_ERROR || r == Z_STREAM_ERROR)
            failCodec(origin, std::string("corrupt deflate data (") + (zs.msg ? zs.msg : "error") + ")");
        if (r == Z_BUF_ERROR && consumed == size)
            failCodec(origin, "compressed data ends after " + std::to_string(used) +
                                  " bytes; its declared size is " + std::to_string(rawSize));
    }
}

}  // namespace

bool compressPayload(Codec codec, const std::string& raw, std::string& out) {
    if (codec == Codec::Zstd) {
        ZSTD_CCtx* ctx = ZSTD_createCCtx();
        if (!ctx) return false;
        ZSTD_CCtx_setParameter(ctx, ZSTD_c_compressionLevel, kZstdLevel);
        ZSTD_CCtx_setParameter(ctx, ZSTD_c_windowLog, kZstdWindowLog);
        out.resize(ZSTD_compressBound(raw.size()));
        const size_t n = ZSTD_compress2(ctx, &out[0], out.size(), raw.data(), raw.size());
        ZSTD_freeCCtx(ctx);
        if (ZSTD_isError(n)) return false;
        out.resize(n);
    } else if (codec == Codec::Deflate) {
        if (raw.size() > (1u << 30)) return false;  // compress2 takes 32-bit lengths
        uLongf n = compressBound(static_cast<uLong>(raw.size()));
        out.resize(n);
        if (compress2(reinterpret_cast<Bytef*>(&out[0]), &n,
                      reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                      kDeflateLevel) != Z_OK)
            return false;
        out.resize(n);
    } else {
        return false;
    }
    return out.size() < raw.size();
}

std::string decompressPayload(Codec codec, const char* data, size_t size, uint64_t rawSize,
                              const Origin& origin) {
    if (codec == Codec::Zstd) return inflateZstd(data, size, rawSize, origin);
    if (codec == Codec::Deflate) return inflateDeflate(data, size, rawSize, origin);
    failCodec(origin, "unknown compression method " + std::to_string(static_cast<int>(codec)));
}

}  // namespace gm::gmb
