// The compact .gmb of a converted image, and the choice of its level: what `gradmesh convert
// IMAGE -o OUT.gmb --compact [--compact-level L|auto]` writes. The file's colours are refitted to
// its own grids (visible_colors.h), and its figures are measured on its decoded re-render over
// the pixels the conversion's error is measured on, so that its size is weighed against its own
// quality. The .gmb codec is passed in (this library does not depend on the formats).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "converters/colors.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct CompactFile {
    int level = 0;
    Document doc;       // what the file holds (encoding it again gives the same bytes)
    std::string bytes;  // the file
    FitError error;     // its figures over the measured pixels
    std::string refit;  // QuantisedColors::how: "as is", "refit" or "bicubic refit"
};

struct CompactCodec {
    std::function<std::string(const Document&, int level)> encode;  // a compact .gmb
    std::function<Document(const std::string&)> decode;
};

// What to measure against: the image, the measured pixels (width·height, non-zero = measured),
// the conversion's colour mode and threads, and the mesh's own error over those pixels.
struct CompactTarget {
    const RgbaImage& image;
    const std::vector<uint8_t>& measured;
    ColorMode colors;
    int threads = 0;
    FitError meshError;
};

// The compact file of `doc` at `level`.
CompactFile compactFileAt(const Document& doc, int level, const CompactTarget& target,
                          const CompactCodec& codec);

// The coarsest level whose file adds at most 5 % (and 0.02) to the mesh's E. Each level is first
// measured as it quantises (one encode and render); only a level within 25 % of the bound gets
// the colour refit, which can bring it under. Level 0 when none is within the bound.
CompactFile coarsestCompactFile(const Document& doc, int maxLevel, const CompactTarget& target,
                                const CompactCodec& codec);

}  // namespace gm
