#include "formats/raster.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

namespace gm {

std::string encodeFallbackImage(const Document& doc, const std::string& kind) {
    if (kind != "png" && kind != "webp")
        throw Error("unknown fallback image kind '" + kind + "' (expected png or webp)");
    const RgbaImage image = renderDocument(doc).image;
    if (kind == "webp") return encodeWebpLossless(image);
    return encodeImage(image, "fallback.png");  // the name only picks the encoder
}

}  // namespace gm
