// Patch-mesh shadings (PDF / PostScript shading type 7, tensor-product patches) shared by the
// EPS and PDF writers; also their flat shapes as paths and linear gradients as axial shadings
// (type 2).
//
// Coordinates stay in canvas pixels with y down; each writer maps them to its page with a y
// flip. Every patch is written with edge flag 0 (16 points and 4 colours), so a mesh with holes
// needs no split: the hole is simply where no patch is. Patch colour in these formats is the
// bilinear interpolation of the corner colours, so each mesh patch is split ks×kt (exact Bézier
// subdivision, exactColorPieces) until that stays within WriteOptions::colorTolerance of the
// mesh's bicubic colour or the pieces are WriteOptions::minPiece pixels long.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "formats/registry.h"
#include "meshcore/bezier_patch.h"

namespace gm {

// The patches of one shading, in painting order.
struct MeshShading {
    std::vector<BezierPatch> patches;
    size_t source = 0;  // the document's mesh it comes from
};

// One shading per mesh, or per hole-free legacy piece when options.legacy; patches already
// subdivided for exact colour. Meshes without patches give no shading. The document must be
// valid (validateDocument).
std::vector<MeshShading> buildMeshShadings(const Document& doc, const WriteOptions& options);

// The binary data stream of a shading (before compression), for /BitsPerCoordinate
// 8·coordinateBytes /BitsPerComponent 16 /BitsPerFlag 8: per patch the flag byte 0, the 16
// points in the order of the PDF 1.7 reference, Table 4.36 (p00 p01 p02 p03 p13 p23 p33 p32 p31
// p30 p20 p10 p11 p12 p22 p21, p[a][b] with a along the patch's s), then the colours c00 c03 c33
// c30, all big-endian. Coordinates are quantised over the integer-bounded box `decode` =
// {xmin, xmax, ymin, ymax} in 16, 24 or 32 bits, the fewest that keep the step at 1/1024 px or
// finer (24 for any page narrower than 16384 px), which keeps files small; colours (clamped to
// 0–1) to 1/65535. (Edge flags 1–3, which leave out an edge shared with the patch before, would
// save more on split patches, but only by stating pieces turned or mirrored, and pdftocairo
// renders a mirrored patch measurably differently.)
struct BinaryShading {
    std::string data;
    double decode[4] = {0, 1, 0, 1};
    int coordinateBytes = 4;
};
BinaryShading encodeShadingBinary(const MeshShading& shading);

// The dictionary entries common to PostScript and PDF for a binary shading:
// "/ShadingType 7 /ColorSpace /DeviceRGB /BitsPerCoordinate 24 /BitsPerComponent 16 ...".
std::string binaryShadingEntries(const BinaryShading& shading);

// Patches [first, first+count) as PostScript array contents: per patch the flag 0, 16 points
// (x y, same order as the binary form), 4 colours (r g b); coordinates to 1e-4 px, colours to
// 1e-6; lines under 255 characters.
std::string encodeShadingText(const MeshShading& shading, size_t first, size_t count);

// `value` in fixed notation with at most `decimals` decimals, trailing zeros removed, never
// "-0"; independent of the C locale.
std::string formatDecimal(double value, int decimals);

// The operators of a page description language that fill or stroke a path.
struct PathOperators {
    const char* setColor;        // fill colour after "r g b": "rg" (PDF), "setrgbcolor" (PS)
    const char* moveTo;          // "m", "moveto"
    const char* lineTo;          // "l", "lineto"
    const char* curveTo;         // "c", "curveto"
    const char* close;           // "h", "closepath"
    const char* fill;            // nonzero fill: "f", "fill"
    const char* setStrokeColor;  // after "r g b": "RG", "setrgbcolor"
    const char* setLineWidth;    // after the width: "w", "setlinewidth"
    const char* roundCapsJoins;  // "1 J 1 j", "1 setlinecap 1 setlinejoin"
    const char* stroke;          // "S", "stroke"
    const char* clip;            // nonzero clip, the path then dropped: "W n", "clip newpath"
};
extern const PathOperators kPdfPathOperators;
extern const PathOperators kPostScriptPathOperators;

// A flat shape filled in its colour (opaque: opacity is the writer's matter), canvas
// coordinates to 1/1000 px, lines under 255 characters; cubics whose handles lie at a third and
// two thirds of their chord as lines.
std::string shapeFillOperators(const FlatShape& shape, const PathOperators& ops);

// A filled shape's outline made the clipping path (nonzero, the rule its fill uses), as above
// without colour or paint. The clip stays set: the caller brackets it (q and Q, gsave and
// grestore).
std::string shapeClipOperators(const FlatShape& shape, const PathOperators& ops);

// The dictionary entries common to PostScript and PDF for a linear gradient as an axial
// shading: "/ShadingType 2 /ColorSpace /DeviceRGB /Coords [x0 y0 x1 y1] /Extend [true true]"
// and on a line of its own the /Function: for two stops a type 2 (exponential, N 1) from the
// first stop's colour to the second's; for more a type 3 stitching such pieces, its /Bounds the
// inner offsets, its /Encode [0 1 0 1 ...]. Coordinates are canvas pixels (the writers' y flip
// applies) to 1/100 px, offsets to 1e-6, colours (clamped to 0–1) to 1e-4; a piece whose
// offsets round to one value is left out, so that the bounds increase strictly. Lines stay under
// 255 characters.
std::string axialShadingEntries(const LinearGradient& gradient);

// A stroked shape's centrelines stroked in its colour (opaque, as above), its width to 1/1000
// px, round caps and joins; closed centrelines closed (their last line left to the close),
// open ones not. The line width, caps and joins it sets stay set: the caller brackets it (q and
// Q, gsave and grestore).
std::string shapeStrokeOperators(const FlatShape& shape, const PathOperators& ops);

// zlib-format (RFC 1950) compression, what /FlateDecode reads.
std::string deflateBytes(const std::string& bytes);

// ASCII85 (btoa) encoding with `z` for zero groups and the `~>` end marker, in lines of at most
// `lineLength` characters, none starting with '%' (so DSC parsers never mistake data for
// comments).
std::string ascii85Encode(const std::string& bytes, size_t lineLength = 76);

}  // namespace gm
