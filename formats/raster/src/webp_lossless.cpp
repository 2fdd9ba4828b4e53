#include <webp/encode.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "formats/raster.h"
#include "meshcore/error.h"

namespace gm {

namespace {

// 8-bit straight RGBA, rounded as the PNG writer rounds.
std::vector<uint8_t> rgba8(const RgbaImage& image) {
    std::vector<uint8_t> out(image.pixels.size());
    for (size_t k = 0; k < out.size(); ++k)
        out[k] = static_cast<uint8_t>(std::lround(std::clamp(image.pixels[k], 0.f, 1.f) * 255.f));
    return out;
}

}  // namespace

std::string encodeWebpLossless(const RgbaImage& image) {
    WebPConfig config;
    // Level 6 of 0-9: near the smallest files at a fraction of level 9's time.
    if (!WebPConfigInit(&config) || !WebPConfigLosslessPreset(&config, 6))
        throw Error("libwebp could not set up lossless encoding");
    WebPPicture picture;
    if (!WebPPictureInit(&picture)) throw Error("libwebp could not set up a picture");
    picture.use_argb = 1;  // keeps the pixels as they are (no YUV)
    picture.width = image.width;
    picture.height = image.height;
    const std::vector<uint8_t> pixels = rgba8(image);
    WebPMemoryWriter memory;
    WebPMemoryWriterInit(&memory);
    picture.writer = WebPMemoryWrite;
    picture.custom_ptr = &memory;
    const bool ok = WebPPictureImportRGBA(&picture, pixels.data(), image.width * 4) &&
                    WebPEncode(&config, &picture);
    const int code = picture.error_code;
    WebPPictureFree(&picture);
    std::string bytes(reinterpret_cast<const char*>(memory.mem), memory.size);
    WebPMemoryWriterClear(&memory);
    if (!ok) throw Error("WebP encoding failed (libwebp error " + std::to_string(code) + ")");
    return bytes;
}

}  // namespace gm
