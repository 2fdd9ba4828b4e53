// .gmb — the native binary format (docs/formats.md): the whole representation, exactly.
#pragma once

#include <memory>
#include <string>

#include "formats/registry.h"

namespace gm {

std::unique_ptr<MeshFormat> makeGmbFormat();

// In-memory encode/decode (the format object reads/writes files through these). The layout,
// versions 1.4 and 2.0, is specified in docs/formats.md; the reader
// also reads every 1.0 to 1.3 file (CMSH sections included), a lossless file is still a 1.0
// file and a compact one 2.0 (see GmbFraming). A document with flat shapes is written as 1.5
// (lossless) or 2.1 (compact): a SHAP section after the meshes.
// `compact`: quantised, predicted and range-coded (encoding 2), within the bounds below, in
// CMS2 or CMS3 sections (versions 1.3 and 1.4: each run of meshes is one range-coded stream
// whose models learn from mesh to mesh, so many small meshes cost little more than one);
// otherwise lossless: every double stored bit for bit. Throws gm::Error (without a file name)
// for a document that fails validateDocument.
// compactLevel: see GmbCompactShifts (0 unless compact).
// streams: how each run is coded. CMS3's models start from priors taken from converted images:
// on those it is usually smaller than CMS2, but on meshes unlike them it can be larger. By
// default (Smaller) the writer codes each run both ways and keeps the smaller, so a file is 1.4
// only when that pays; Cms2 keeps every file readable by 1.3 readers.
enum class GmbStreams { Smaller, Cms2, Cms3 };
// framing (compact files only; lossless files are always 1.0): Short writes version 2.0, 1.4's
// sections with shorter headers (varint sizes: 11 bytes for an empty section instead of 28, and
// a varint DOCU), which matters for small files; Long writes 1.3 or 1.4, for readers that know
// only 1.x.
enum class GmbFraming { Short, Long };
std::string encodeGmb(const Document& doc, bool compact, int compactLevel = 0,
                      GmbStreams streams = GmbStreams::Smaller,
                      GmbFraming framing = GmbFraming::Short);
// Throws gm::Error naming `fileName` and the byte offset on any malformed input; checks every
// count against the bytes that remain and against `limits` before allocating. The decoded
// (uncompressed) data may not exceed limits.maxFileBytes either, so a small compressed file
// cannot expand without bound (a decoded value counts as the 8 bytes of its binary64). The result
// always passes validateDocument.
Document decodeGmb(const std::string& bytes, const ReadLimits& limits,
                   const std::string& fileName = "<memory>");

// Stated maximum errors of compact mode, per value, between a mesh and its compact round trip
// (positions are rounded to a 1/32 px grid, colours to 1/256: at most 1/512 off).
// Derivative bounds are stated for the derivative times the larger knot interval next to its
// node in its direction (for x_u and c_u of a node in column i, max(u_i - u_{i-1},
// u_{i+1} - u_i); for x_v and c_v of row j likewise with v), which is what the patches using
// it scale it by (gradient_mesh.h): the tangent of every patch edge is within the bound,
// whatever the knot scale. They apply to node derivatives, slit-copy derivatives (the column
// and row of their node), slit-end tangents (column i0 or i1) and corner tangent breaks (the
// column of the corner). The ±d structure of slit ends holds exactly (d is stored once), and
// knots stay strictly increasing.
// A mesh whose values do not fit the quantisation grid (coordinates beyond ±2^47 px,
// knots larger than about 2^30 times the smallest knot interval) is stored as float64, exactly.
struct GmbCompactBounds {
    static constexpr double position = 1.0 / 64.0;         // pixels, node positions
    static constexpr double color = 0.5 / 255.0;           // 0–1 units, node colours
    static constexpr double positionTangent = 1.0 / 16.0;  // pixels: |error of x_u| · Δu
    static constexpr double colorTangent = 1.0 / 256.0;    // 0–1 units: |error of c_u| · Δu
    // Each knot is within this fraction of the mesh's smallest knot interval.
    static constexpr double knotRelative = 1.0 / (1 << 22);
};
// Coarser compact files, for size: at level L (0 to kGmbMaxCompactLevel; 0 is the default and
// the bounds above) each quantity's grid, and with it its bound, is 2^k times level 0's, with k
// from gmbCompactShifts(L). Every file states its grids, so any reader of its version reads
// every level. Each level trades error for bytes (bench/README.md has the figures); 4 and 5 suit
// small, coarse meshes, where they cost little. 6 is 5 with colours and colour slopes on grids
// twice as coarse: for flat-coloured drawings; on photos it costs more.
constexpr int kGmbMaxCompactLevel = 6;
// Knots too (GmbCompactBounds::knotRelative × 2^knot): levels 1 to 4 keep each knot within
// 2^-10 of the smallest interval, which moves a patch edge's tangent by at most 0.2 %; levels 5
// and 6 within 2^-5, at most 6 % (on the smallest patches; less on larger ones). Small meshes
// pay most for their knots, so the coarse levels save most there.
struct GmbCompactShifts {
    int position = 0, color = 0, positionTangent = 0, colorTangent = 0, knot = 0;
};
// Throws gm::Error for a level outside 0..kGmbMaxCompactLevel.
GmbCompactShifts gmbCompactShifts(int level);
// Colour derivatives that follow the colour rule (meshcore/color_rule.h, followsColorRule) are
// not stored in compact mode: the reader recomputes them with applyColorRule from the decoded
// colours, knots and positions. They then follow the rule exactly, and differ from the written
// ones only by what the colour and position quantisation changes in the rule's inputs.

}  // namespace gm
