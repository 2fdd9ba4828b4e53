// libFuzzer target for the .gmb reader: any input must either decode to a valid document or
// throw gm::Error — never crash, hang or allocate without bound. A decoded document must
// survive a lossless round trip exactly and a compact round trip without error.
//
// Random mutations almost never keep a section's CRC-32 right, which would stop the fuzzer at the
// checksum. So each input is decoded twice: as it is (exercising the checksum path), and with
// every section CRC it can frame recomputed (exercising everything behind it).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <zlib.h>

#include "formats/gmb.h"
#include "meshcore/error.h"

namespace {

gm::ReadLimits fuzzLimits() {
    gm::ReadLimits l;
    l.maxFileBytes = uint64_t(1) << 22;
    l.maxNodesPerMesh = uint64_t(1) << 16;
    l.maxGridSide = 1024;
    l.maxSlitsPerMesh = 256;
    l.maxMeshes = 64;
    l.maxCanvasSide = uint64_t(1) << 16;
    return l;
}

uint64_t le(const std::string& s, size_t at, int n) {
    uint64_t x = 0;
    for (int k = 0; k < n; ++k) x |= uint64_t(static_cast<unsigned char>(s[at + k])) << (8 * k);
    return x;
}

// Walks the section framing (layout: docs/formats.md) and rewrites each CRC.
std::string withFixedCrcs(std::string s) {
    size_t pos = 12;
    while (s.size() >= pos && s.size() - pos >= 28) {
        const uint64_t stored = le(s, pos + 8, 8);
        if (stored > s.size() - pos - 28) break;
        const size_t covered = 24 + static_cast<size_t>(stored);
        const uint32_t crc = static_cast<uint32_t>(
            crc32(0, reinterpret_cast<const Bytef*>(s.data() + pos), static_cast<uInt>(covered)));
        for (int k = 0; k < 4; ++k) s[pos + covered + k] = static_cast<char>((crc >> (8 * k)) & 0xff);
        pos += covered + 4;
    }
    return s;
}

[[noreturn]] void die(const char* what, const std::string& detail) {
    std::fprintf(stderr, "gmb_fuzzer: %s: %s\n", what, detail.c_str());
    std::abort();
}

void check(const std::string& input) {
    const gm::ReadLimits limits = fuzzLimits();
    gm::Document doc;
    try {
        doc = gm::decodeGmb(input, limits, "fuzz");
    } catch (const gm::Error&) {
        return;  // the expected outcome for nearly every input
    }
    // Re-encoded data may be larger than the input (it was compressed); same limits otherwise.
    gm::ReadLimits roomy = limits;
    roomy.maxFileBytes = uint64_t(1) << 30;
    std::string lossless;
    try {
        lossless = gm::encodeGmb(doc, false);
        const gm::Document back = gm::decodeGmb(lossless, roomy, "lossless");
        if (!(back == doc)) die("lossless round trip changed the document", "");
        if (gm::encodeGmb(back, false) != lossless) die("lossless re-encoding differs", "");
        gm::decodeGmb(gm::encodeGmb(doc, true), roomy, "compact");
    } catch (const gm::Error& e) {
        die("a decoded document failed to round-trip", e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string input(reinterpret_cast<const char*>(data), size);
    check(input);
    const std::string fixed = withFixedCrcs(input);
    if (fixed != input) check(fixed);
    return 0;
}
