// Test support for the SHAP section: decoding errors, header fields and hand-made payloads.
#pragma once

#include <catch2/catch.hpp>
#include <string>

#include "formats/gmb.h"
#include "gmb_test_support.h"
#include "meshcore/error.h"
#include "meshcore/synthetic_meshes.h"

namespace gmbtest {

// The message a decode of `bytes` (as "t.gmb") fails with; empty if it reads.
inline std::string decodeError(const std::string& bytes) {
    try {
        gm::decodeGmb(bytes, gm::ReadLimits{}, "t.gmb");
    } catch (const gm::Error& e) {
        return e.what();
    }
    return "";
}

// The version in a file's header: major * 100 + minor.
inline int versionOf(const std::string& bytes) {
    return static_cast<int>(getLE(bytes, 8, 2) * 100 + getLE(bytes, 10, 2));
}

// A lossless 1.5 file whose SHAP payload is replaced by `payload` (sizes and CRC fixed).
inline std::string withShapePayload(const std::string& payload) {
    const std::string file = gm::encodeGmb(gm::makeFlatDocument(), false);
    const size_t at = file.find("SHAP");
    REQUIRE(at != std::string::npos);
    const uint64_t stored = getLE(file, at + 8, 8);
    std::string out = file.substr(0, at + 8);
    putLE(out, payload.size(), 8);
    putLE(out, payload.size(), 8);
    out += payload;
    putLE(out, crc32(out, at, out.size()), 4);
    out += file.substr(at + 24 + stored + 4);
    return out;
}

// The SHAP payload's encoding byte of a lossless file (its payload is stored as it is).
inline int shapeEncodingOf(const std::string& file) {
    const size_t at = file.find("SHAP");
    REQUIRE(at != std::string::npos);
    return static_cast<unsigned char>(file[at + 24 + 1]);  // after a one-byte shape count
}

}  // namespace gmbtest
