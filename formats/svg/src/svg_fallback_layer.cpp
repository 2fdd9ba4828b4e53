#include "svg_fallback_layer.h"

#include "formats/base64.h"
#include "meshcore/error.h"

namespace gm {

namespace {

std::string mediaType(const std::string& kind) {
    if (kind == "png") return "image/png";
    if (kind == "webp") return "image/webp";
    throw Error("unknown SVG fallback image kind '" + kind + "' (expected png or webp)");
}

}  // namespace

bool isSvgFallbackKind(const std::string& kind) {
    return kind == "png" || kind == "webp" || kind == "none";
}

const char* svgFallbackNamespaces() {
    return " xmlns:xlink=\"http://www.w3.org/1999/xlink\""
           " xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\""
           " xmlns:sodipodi=\"http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd\"";
}

void appendSvgFallbackLayer(std::string& out, const SvgFallbackImage& image, int width,
                            int height) {
    // The label tells an Inkscape user what the locked layer is and that editing the meshes
    // does not update it. xlink:href, not SVG 2's href: every viewer reads it.
    out +=
        "<g id=\"gradmesh-fallback\" inkscape:groupmode=\"layer\""
        " inkscape:label=\"Raster fallback (gradmesh render, not updated by edits)\""
        " sodipodi:insensitive=\"true\">\n<image width=\"" +
        std::to_string(width) + "\" height=\"" + std::to_string(height) +
        "\" preserveAspectRatio=\"none\" xlink:href=\"data:" + mediaType(image.kind) + ";base64,";
    out += base64Encode(image.bytes);
    out += "\"/>\n</g>\n";
}

}  // namespace gm
