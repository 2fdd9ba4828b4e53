// The JSON report of one image conversion (`gradmesh convert IMAGE -o OUT --report R.json`):
// what was asked, seconds per stage, patches, errors, bytes per format, the compact file, the
// segmentation's figures and every region's, with its refinement sequence. docs/design.md §6
// lists the keys.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "converters/compact_file.h"
#include "converters/convert_segments.h"

namespace gm {

// What the report says besides the conversion's own figures.
struct ReportFacts {
    std::string input, output;
    int width = 0, height = 0;
    bool segment = false;
    ColorMode colors = ColorMode::FitBicubic;
    double maxError = 0;
    int maxPatches = 0, totalPatches = 0;
    double readSeconds = 0, maskSeconds = 0, writeSeconds = 0, endToEndSeconds = 0;
    size_t meshes = 0;
    uint64_t outputBytes = 0, gmbLosslessBytes = 0;
    std::optional<uint64_t> exactSvgBytes;  // left out (null) for large meshes
    bool compactAuto = false;
};

// `report` is the conversion's (for an object, only its `convert` part is filled).
std::string conversionReportJson(const ReportFacts& facts, const SegmentConvertReport& report,
                                 const CompactFile& compact);

// --colors' name of a colour mode: "bicubic", "hermite" or "sampled".
const char* colorModeName(ColorMode mode);

// A JSON string literal, safe inside an HTML <script> element as well ('<' is written \u003c,
// so no "</script>" can close it).
std::string jsonString(const std::string& text);

// A JSON number: finite values as they are (%.6g), infinity (the PSNR of a perfect fit) as
// ±1e308, NaN as null.
std::string jsonNumber(double v);

}  // namespace gm
