// .svg — SVG 2 <meshgradient> (docs/formats.md): written for Inkscape, read back from our own files
// and from what Inkscape saves after opening them.
//
// The canvas maps 1:1 to the SVG user space: viewBox "0 0 W H", pixels, y down. Every hole-free
// mesh (a mesh with slits is written as its legacy pieces) becomes one <meshgradient> painted on
// a <path> of its own outline.
//
// Colour modes (WriteOptions::svgColors):
//  - "bicubic" (the default): one SVG patch per mesh patch, type="bicubic", in a compact syntax
//    (positions to 1/100 px, relative, separators only where needed; colours 8-bit). A
//    ColorModel::Bicubic mesh is then drawn by Inkscape as we draw it; a Hermite mesh gets
//    Inkscape's slopes instead of its own (svgEditableDeviation says how far that is; the
//    `gradmesh` command refits such meshes to the bicubic model before writing).
//  - "exact": each patch is split into exact Bézier sub-patches until the bilinear colour that
//    meshgradient patches interpolate is within WriteOptions::colorTolerance of ours, or the
//    pieces are WriteOptions::minPiece pixels long (exactColorPieces); the `tensor` attribute
//    carries the exact interior control points. A meshgradient is a regular grid, so patch
//    column i is split ku_i times and patch row j kv_j times, with ku_i / kv_j the largest
//    per-patch count along s / t over that column / row. Refused over
//    WriteOptions::maxSvgPatches SVG patches.
// Browsers implement no meshgradient: unless WriteOptions::svgScript is "none", the document
// ends with a <script> (formats/svg/script/mesh_polyfill.js, minified) that draws the meshes
// where the browser cannot (docs/browsers.md). Inkscape and our reader ignore it.
// A path ending in ".svgz" is written gzip-compressed; gzip input is read either way.
//
// Flat shapes (Document::shapes) are plain paths between the meshes' paths: filled in one
// colour, stroked with round caps and joins, or filled with a <linearGradient> written just
// before the path (userSpaceOnUse, pad, sRGB; its id a hash of its text, so that SVGs inlined
// in one page never share an id for different gradients). Browsers draw them natively.
//
// Reading gives one GradientMesh per painted meshgradient (see decodeSvg for what is read and
// how the Ferguson data is recovered from Bézier handles), and one FlatShape per path filled
// with a colour or a linearGradient (href chains, bounding-box units and any invertible
// transform followed; radial gradients, per-stop opacities and gradient strokes refused by
// name) or stroked in one colour (docs/formats.md).
//
// Mesh shapes are painted with style="fill:url(#mN) none": viewers without meshes paint
// nothing there (the fallback paint), and mesh polyfills (Inkscape's, ours) find the paint in
// the style attribute. With WriteOptions::svgFallback "png" or "webp" our render of the
// document lies beneath the shapes as an image in a locked Inkscape layer (svgz too).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "formats/registry.h"

namespace gm {

// Renders `doc` and encodes it as `kind` ("png" or "webp"), 1 image pixel per canvas pixel.
// The SVG library links no image codec: its caller supplies this (builtin_formats.cpp).
using SvgFallbackEncoder = std::function<std::string(const Document& doc, const std::string& kind)>;

// Without an encoder, writing with WriteOptions::svgFallback other than "none" fails.
std::unique_ptr<MeshFormat> makeSvgFormat(SvgFallbackEncoder fallback = {});

// WriteOptions::svgFallback values: "png", "webp" or "none".
bool isSvgFallbackKind(const std::string& kind);

// An encoded image of the whole canvas, drawn beneath the meshes.
struct SvgFallbackImage {
    std::string kind;   // "png" or "webp"
    std::string bytes;  // the image file's bytes
};

// In-memory encode. Throws gm::Error for an unknown colour mode or an invalid document.
std::string encodeSvg(const Document& doc, const WriteOptions& options);

// In-memory decode; throws gm::Error naming `fileName` and the element on anything it cannot
// read. Besides `limits` (file size, grid sizes, mesh count), it refuses: DTDs declaring
// entities, more than SvgReadLimits::maxElements elements, nesting deeper than tinyxml2's limit,
// numbers that are not finite or exceed SvgReadLimits::maxCoordinate (each number as written,
// and every mesh point once its transforms are applied), href chains with a cycle
// or longer than SvgReadLimits::maxHrefChain.
//
// Recovery of the Ferguson data (a meshgradient stores Bézier handles, not derivatives):
//  - knots: uniform up to the ratio of handle lengths on the two sides of each grid line
//    (weighted median over the line), so that a mesh subdivided non-uniformly, as the exact
//    mode writes it, gets back derivatives that agree on both sides;
//  - posU / posV = 3·(handle − corner) / Δknot, averaged over the two sides; where the two
//    u-handles of a node disagree (a kink, as at former slit ends) the left patches get a
//    CornerTangent break. v-handles cannot break in our representation: they are averaged;
//  - tensor points (and the Coons interior) are not representable with zero twists: the
//    interior becomes the zero-twist one of the recovered edges;
//  - colours from the stops (8-bit in our files); colour derivatives: type="bicubic" gives a
//    ColorModel::Bicubic mesh (Inkscape's own rule, exactly); otherwise (bilinear patches) the derivative of the parabola through the
//    node and its two neighbours along the grid line, one-sided at the mesh border and at
//    u-breaks. Corner colours are exact; inside, a Coons patch's bilinear colour differs from the
//    zero-twist interpolant by its twist.
Document decodeSvg(const std::string& bytes, const ReadLimits& limits,
                   const std::string& fileName = "<memory>");

struct SvgReadLimits {
    static constexpr uint64_t maxFileBytes = uint64_t(256) << 20;  // also capped by ReadLimits
    static constexpr uint64_t maxElements = uint64_t(8) << 20;
    static constexpr double maxCoordinate = 1e7;  // |number| in paths, positions, transforms
    static constexpr int maxHrefChain = 64;
};

// How far Inkscape's bicubic colour rule is from the mesh's own colour derivatives: what a
// bicubic SVG of a Hermite mesh written without a refit loses. Max over the document's Hermite
// meshes (a Bicubic mesh loses nothing: 0).
struct SvgEditableDeviation {
    // colorRuleDeviation: 0–1 colour per unit of our global parameters.
    double ruleDeviation = 0;
    // bicubicExportDeviation: 0–1 colour per unit of patch parameter, between the local slopes
    // our patches use and those Inkscape computes for the written pieces.
    double slopeDeviation = 0;
    // An upper bound (0–1 colour units) of the colour difference inside a patch that follows:
    // half the slope deviation.
    double maxColorDifference = 0;
};
SvgEditableDeviation svgEditableDeviation(const Document& doc);

// Figures of one encode, for reports: patches written (after subdivision) and meshgradients.
struct SvgEncodeStats {
    int64_t svgPatches = 0;
    int64_t meshGradients = 0;
    int maxSubdivision = 1;  // largest ku or kv used in exact mode
};
// `fallback` is the image of WriteOptions::svgFallback, required unless that is "none".
std::string encodeSvg(const Document& doc, const WriteOptions& options, SvgEncodeStats* stats,
                      const SvgFallbackImage* fallback = nullptr);

}  // namespace gm
