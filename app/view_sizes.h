// The view page's "bytes per format": the document encoded by each writer in memory (nothing
// is written), within the output limits the writers enforce.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "formats/registry.h"

namespace gm {

struct FormatSize {
    std::string format;  // ".gmb", ".gmb compact", ".svg", ".svgz", ".pdf", ".eps"
    int64_t bytes = -1;  // -1: not encoded (see note)
    std::string note;    // why not (over --max-output-bytes, a writer's refusal), or a remark
};

// Above this many patches the PDF and EPS are not encoded (their size is noted as not
// measured): each takes about 1 KB and 0.1 ms per patch, so a document at the patch limit would
// cost gigabytes and minutes for two figures.
constexpr uint64_t kMaxPostScriptPatches = 50000;

struct ViewEncodings {
    std::vector<FormatSize> sizes;
    std::string svg;  // the SVG as `convert` writes it (empty when it could not be written)
};

// Encodes `doc` as each format with `options` (its maxOutputBytes included; the SVG is always
// the default, bicubic one). A Hermite mesh's
// SVG is refitted to the bicubic rule first, as `convert` does (a line on standard error says
// how far that is from the Hermite render). A writer's refusal is recorded, not thrown.
ViewEncodings encodeForView(const Document& doc, const WriteOptions& options);

}  // namespace gm
