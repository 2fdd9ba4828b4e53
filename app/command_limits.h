// The resource limits of `convert` and `render` (docs/limits.md): the memory budget
// (--max-memory), the canvas of a render (--max-canvas-pixels) and the patches of a document
// (--max-document-patches). What a step will need is estimated from sizes known before it
// allocates (an image's header, a canvas, a patch budget) and checked against them, so that a
// too-large input is a clear error instead of the kernel's out-of-memory kill.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "formats/registry.h"

namespace gm {

struct CommandLimits {
    uint64_t maxMemory = uint64_t(4) << 30;                 // bytes
    uint64_t maxCanvasPixels = uint64_t(1) << 28;           // of a raster output (16384²)
    uint64_t maxDocumentPatches = ReadLimits{}.maxPatches;  // read or converted
};

// The limits given among a command's option values (the defaults for those not given).
// Throws std::invalid_argument naming the option on a bad value.
CommandLimits commandLimits(const std::map<std::string, std::string>& values);

// The valued options commandLimits reads.
extern const char* const kLimitOptions[3];

// Peak bytes per image pixel of a conversion, from the peak RSS of 4096² photos (87 B/pixel
// for an object, 104 for a whole image in two regions) with room for more regions and meshes:
// image, mask, regions, triangulation and fit; with --segment also the labels, one mask per
// region and the regions' fits side by side.
constexpr uint64_t kObjectBytesPerPixel = 120;
constexpr uint64_t kSegmentBytesPerPixel = 200;
// A render to a raster file: the float RGBA canvas, its coverage, and the writer's copy.
constexpr uint64_t kRenderBytesPerPixel = 48;

// Parses "4G", "512M", "1.5GiB", "100000" (bytes; K, M, G, T are powers of 1024).
// Throws std::invalid_argument naming `option` on anything else or on zero.
uint64_t parseByteCount(const std::string& option, const std::string& text);

// "3.9 GiB", "512 MiB", "900 B".
std::string byteText(double bytes);

// Throws gm::Error naming `file`: "<what> is too large for the memory budget (needs ~X, limit
// Y; raise with --max-memory)" when `needed` is over `limit`.
void requireMemoryBudget(double needed, uint64_t limit, const std::string& what,
                         const std::string& file);

// Before rendering a width × height canvas at `scale` into `file`: its pixels within
// maxCanvasPixels and their memory within maxMemory (gm::Error naming `file` otherwise).
void requireRenderWithinLimits(int width, int height, double scale, const CommandLimits& limits,
                               const std::string& file);

}  // namespace gm
