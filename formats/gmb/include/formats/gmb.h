// .gmb — the native binary format (FORMATS.md): the whole representation, exactly.
#pragma once

#include <memory>
#include <string>

#include "formats/registry.h"

namespace gm {

std::unique_ptr<MeshFormat> makeGmbFormat();

// In-memory encode/decode (the format object reads/writes files through these).
// `compact`: quantised + compressed, within the bounds below; otherwise lossless (bit-exact).
std::string encodeGmb(const Document& doc, bool compact);
// Throws gm::Error naming `fileName` and the byte offset on any malformed input; checks every
// count against the bytes that remain and against `limits` before allocating.
Document decodeGmb(const std::string& bytes, const ReadLimits& limits,
                   const std::string& fileName = "<memory>");

// Stated maximum errors of compact mode.
struct GmbCompactBounds {
    static constexpr double position = 1.0 / 64.0;  // pixels, node positions
    static constexpr double color = 0.5 / 255.0;    // 0–1 units, node colours
};

}  // namespace gm
