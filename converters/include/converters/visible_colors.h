// Colours refitted to what the viewer sees. Two cases where a mesh's own fit (colors.h, over
// its region's pixels) is not the best one:
//  - Overlap. A whole image's meshes overlap (convert_segments.h: each region's mesh reaches
//    about a pixel under its neighbours, and the base mesh lies under all of them), and a pixel
//    shows only the topmost mesh. A mesh's colours are best fitted to the pixels where it is on
//    top, not to its region's.
//  - Quantisation. A compact file moves the geometry and the colour slopes onto grids (gmb.h).
//    The colours fitted to the moved geometry, with the moved slopes held, win back much of
//    what the grids cost, for a few per cent more bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "converters/colors.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

// Per pixel (row-major, the document's canvas) the index of the topmost mesh of `doc` that
// covers its centre, -1 where none does or where `mask` is 0. One render.
std::vector<int> topmostMeshes(const Document& doc, const std::vector<uint8_t>& mask,
                               int threads = 0);

// `doc` with every mesh's colours refitted (computeColors in `mode`) over the pixels of `mask`
// where that mesh is topmost. In Fit and FitValues modes a mesh whose slopes follow the colour
// rule is refitted by the rule, so that a file still leaves its slopes out. A mesh
// topmost on fewer than 4 pixels keeps its colours, as does every mesh in Sampled mode. The
// geometry is unchanged. Meshes are fitted in parallel (threads 0: all hardware threads).
// Throws gm::Error when the image's or the mask's size differs from the canvas.
Document refitVisibleColors(const Document& doc, const RgbaImage& image,
                            const std::vector<uint8_t>& mask, ColorMode mode, int threads = 0);

// Colours for a document that is to be quantised: `quantise` maps a document to what its file
// holds (for a compact .gmb: written at its level and read back). The candidates are
// quantise(doc) and, when quantisation raised the squared error over `mask` by more than 1 %:
//  - Fit: all colours refitted to the quantised geometry, quantised, then the values refitted
//    with those quantised slopes held (FitValues);
//  - FitBicubic: colours refitted in the Bicubic model to the quantised geometry;
//  - Sampled: none (the paper's colours stay the paper's).
// each quantised again. The one with the least squared error over `mask` is returned.
struct QuantisedColors {
    Document doc;          // quantise(...) of the candidate kept
    FitError error;        // its figures over `mask` (compareOverMask)
    FitError unquantised;  // `doc`'s own
    // "as is", "refit" (Fit) or "bicubic refit" (FitBicubic); when a refit threw gm::Error,
    // "as is; the refit failed: " and its reason.
    std::string how;
};
// `unquantised`, when given, is `doc`'s error over `mask` (compareOverMask), known to the
// caller: it saves a render.
QuantisedColors colorsForQuantisation(const Document& doc, const RgbaImage& image,
                                      const std::vector<uint8_t>& mask, ColorMode mode,
                                      const std::function<Document(const Document&)>& quantise,
                                      int threads = 0, const FitError* unquantised = nullptr);

}  // namespace gm
