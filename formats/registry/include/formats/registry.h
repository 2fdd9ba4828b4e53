// The format registry: one reader/writer per format, found by name or file extension.
// Nothing outside formats/builtin_formats.cpp and formats/mesh_readers.cpp names a format.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

// Limits a reader enforces before it allocates; a caller may raise them.
struct ReadLimits {
    uint64_t maxFileBytes = uint64_t(1) << 30;   // 1 GiB
    uint64_t maxNodesPerMesh = uint64_t(1) << 24; // 16 M nodes
    uint64_t maxGridSide = uint64_t(1) << 16;     // columns or rows of one mesh
    uint64_t maxSlitsPerMesh = uint64_t(1) << 16;
    uint64_t maxMeshes = uint64_t(1) << 20;
    uint64_t maxShapes = uint64_t(1) << 20;       // flat shapes
    uint64_t maxCanvasSide = uint64_t(1) << 20;   // pixels
    // Patches of all meshes together, counted before they are built: a small file can name
    // many (an SVG painting one mesh with thousands of shapes, a compact .gmb of flat patches).
    uint64_t maxPatches = uint64_t(1) << 20;
};

// The message of a document over ReadLimits::maxPatches (or a conversion over its limit).
std::string tooManyPatchesMessage(uint64_t patches, uint64_t limit);

struct ReadOptions {
    ReadLimits limits;
};

// WriteOptions::compactLevel of `convert IMAGE --compact-level auto`: the image conversion
// resolves it, measuring each level's file against the image, before anything is written.
constexpr int kCompactLevelAuto = -1;

struct WriteOptions {
    bool compact = false;             // .gmb: quantised + compressed
    int compactLevel = 0;             // .gmb compact: coarser grids, 0 to kGmbMaxCompactLevel
                                      // (gmb.h), or kCompactLevelAuto (image conversions only)
    bool legacy = false;              // write every mesh as its hole-free pieces
    // SVG: "bicubic" (one SVG patch per mesh patch, type="bicubic", compact syntax; alias
    // "editable") or "exact" (each patch subdivided until bilinear colour is within
    // colorTolerance, at most maxSvgPatches SVG patches in all).
    std::string svgColors = "bicubic";
    int64_t maxSvgPatches = 2'000'000;
    // SVG: "embed" (default) puts the mesh script for browsers without mesh support at the end
    // of every SVG that holds meshes (docs/browsers.md); "none" leaves it out.
    std::string svgScript = "embed";
    double colorTolerance = 1.0 / 255.0;  // exact-colour subdivision tolerance (0–1 units)
    double minPiece = 1.0;  // exact colours: no sub-patch shorter than this along s or t,
                            // canvas pixels (exactColorPieces); 0: no limit
    // SVG: our render of the document embedded beneath the meshes, for viewers that draw no
    // meshes (browsers' <img>, librsvg): "png", "webp" (lossless) or "none".
    std::string svgFallback = "none";
    bool textShading = false;         // EPS/PDF: text DataSource instead of the binary stream
    double rasterScale = 1.0;         // raster outputs: pixels per canvas pixel
    std::array<float, 4> background = {0, 0, 0, 0};  // raster outputs: RGBA 0–1, alpha 0 = none
    std::array<float, 4> meshLines = {0, 0, 0, 0};   // raster outputs: patch edges drawn in
                                                     // this colour; alpha 0 = none
    // SVG/EPS/PDF: refuse, before encoding, a document whose output would be larger (by
    // MeshFormat::leastBytes, a lower bound).
    uint64_t maxOutputBytes = uint64_t(1) << 30;  // 1 GiB
};

// Patches of all the document's meshes.
uint64_t documentPatches(const Document& doc);

// Throws gm::Error naming `path` when `leastBytes` is over options.maxOutputBytes.
void requireOutputWithinLimit(uint64_t leastBytes, const WriteOptions& options,
                              const std::string& path);

class MeshFormat {
public:
    virtual ~MeshFormat() = default;
    virtual std::string name() const = 0;                     // e.g. "gmb"
    virtual std::vector<std::string> extensions() const = 0;  // lower case, with dot: ".gmb"
    virtual bool canRead() const { return false; }
    virtual bool canWrite() const { return false; }
    // A cheap check of the first bytes of a file (may be fewer than asked for).
    virtual bool sniff(const std::string& /*head*/) const { return false; }
    // Throw gm::Error naming the file on any problem.
    virtual Document read(const std::string& path, const ReadOptions& options) const;
    // The whole file in memory. `path` is the file it is meant for: named in errors, and its
    // extension picks the encoding of formats with several (raster).
    virtual std::string encode(const Document& doc, const std::string& path,
                               const WriteOptions& options) const;
    // encode(), then written atomically (atomic_file.h): never a partial file at `path`, and an
    // existing file there stays as it was when anything fails.
    void write(const Document& doc, const std::string& path, const WriteOptions& options) const;
    // A lower bound of the bytes encode() would produce (or build in memory) for `doc`, cheap
    // to compute; 0 when the format does not say.
    virtual uint64_t leastBytes(const Document& /*doc*/, const WriteOptions& /*options*/) const {
        return 0;
    }
};

class FormatRegistry {
public:
    // The registry with every built-in format (formats/builtin_formats.cpp).
    static const FormatRegistry& builtin();
    // The built-in formats that read meshes (.gmb, SVG), as in builtin(), for programs that
    // must not load the raster library (formats/mesh_readers.cpp, target formats_mesh_readers).
    // Only these formats read, so forReading() finds here the format builtin() finds for any
    // file that builtin() can read.
    static const FormatRegistry& meshReaders();

    void add(std::unique_ptr<MeshFormat> format);
    const MeshFormat* byName(const std::string& name) const;
    // By extension of `path` (case-insensitive); nullptr when none.
    const MeshFormat* forPath(const std::string& path) const;
    // By extension, confirmed by sniffing the file's first bytes when the file exists.
    const MeshFormat* forReading(const std::string& path) const;
    std::vector<const MeshFormat*> all() const;
    // The writer for `path`'s extension; throws Error naming the path and the extensions
    // written when there is none.
    const MeshFormat& writerFor(const std::string& path) const;

private:
    std::vector<std::unique_ptr<MeshFormat>> formats_;
};

// Lower-cased extension of a path including the dot ("" when none).
std::string lowerExtension(const std::string& path);

}  // namespace gm
