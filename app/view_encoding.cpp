#include "view_encoding.h"

#include "formats/base64.h"

#include <cmath>
#include <cstdio>

#include "formats/raster.h"

namespace gm {

std::string pngDataUri(const RgbaImage& image) {
    return "data:image/png;base64," + base64Encode(encodeImage(image, "page-image.png"));
}

std::string htmlEscape(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

}  // namespace gm
