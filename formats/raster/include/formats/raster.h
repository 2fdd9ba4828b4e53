// Raster images through OpenImageIO: reading inputs and writing re-renders.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "formats/registry.h"
#include "meshcore/image.h"

namespace gm {

// What an image file's header says, read without decoding its pixels.
struct ImageProbe {
    int width = 0, height = 0, channels = 0;
    std::string format;  // by content, as OpenImageIO names it: "png", "jpeg", "tiff", "openexr"
    int pages = 1;       // subimages (pages of a TIFF); only the first is read
};

// Throws gm::Error naming the file when it cannot be opened or its content is not one of the
// formats readImage takes (whatever its extension says).
ImageProbe probeImage(const std::string& path);

// Reads PNG, JPEG, TIFF or OpenEXR, decided by content (8/16-bit, half/float; grey,
// grey+alpha, RGB, RGBA) into straight-alpha float RGBA, sRGB-encoded: linear inputs (EXR,
// float TIFF marked linear) are encoded on read. Refuses images over maxPixels before
// allocating their pixels, files of other formats (a GIF named .png) naming their real format,
// and files the decoder reports damaged (a truncated JPEG). Reads the first page only.
RgbaImage readImage(const std::string& path, uint64_t maxPixels = uint64_t(64) << 20);

// The file content for `path`, by its extension (.png .jpg .jpeg .tif .tiff .exr); linear
// formats (EXR) get decoded values. Encoded in memory; nothing is written.
std::string encodeImage(const RgbaImage& image, const std::string& path);

// encodeImage, written atomically (atomic_file.h): no partial file is left behind.
void writeImage(const RgbaImage& image, const std::string& path);

// Lossless WebP of `image` (8-bit straight RGBA), through libwebp: OpenImageIO's WebP writer
// turns pixels into subsampled YUV first, even when asked for lossless.
std::string encodeWebpLossless(const RgbaImage& image);

// The image beneath an SVG's meshes (SvgFallbackEncoder, formats/svg.h): `doc` rendered as
// `gradmesh render` does, 1 pixel per canvas pixel, transparent where nothing is painted,
// encoded as "png" or "webp" (lossless).
std::string encodeFallbackImage(const Document& doc, const std::string& kind);

// Composites straight-alpha `image` over an RGBA background (alpha 0 leaves it unchanged).
void compositeOver(RgbaImage& image, const std::array<float, 4>& background);

// The raster "mesh format": writing renders the document (WriteOptions::rasterScale,
// ::background); it cannot be read as a mesh.
std::unique_ptr<MeshFormat> makeRasterFormat();

}  // namespace gm
