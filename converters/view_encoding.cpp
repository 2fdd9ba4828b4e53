#include "view_encoding.h"

#include <cmath>
#include <cstdio>

#include "formats/raster.h"

namespace gm {

std::string base64(const std::string& bytes) {
    static const char* const kDigits =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t k = 0;
    for (; k + 2 < bytes.size(); k += 3) {
        const unsigned v = static_cast<unsigned char>(bytes[k]) << 16 |
                           static_cast<unsigned char>(bytes[k + 1]) << 8 |
                           static_cast<unsigned char>(bytes[k + 2]);
        for (int shift = 18; shift >= 0; shift -= 6) out += kDigits[(v >> shift) & 63];
    }
    if (k < bytes.size()) {
        const bool two = k + 1 < bytes.size();
        const unsigned v = static_cast<unsigned char>(bytes[k]) << 16 |
                           (two ? static_cast<unsigned char>(bytes[k + 1]) << 8 : 0);
        out += kDigits[(v >> 18) & 63];
        out += kDigits[(v >> 12) & 63];
        out += two ? kDigits[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string pngDataUri(const RgbaImage& image) {
    return "data:image/png;base64," + base64(encodeImage(image, "page-image.png"));
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

std::string jsonQuote(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '<' || static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string jsonNumber(double value) {
    if (std::isnan(value)) return "null";
    if (std::isinf(value)) return value > 0 ? "1.7976931348623157e308" : "-1.7976931348623157e308";
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

}  // namespace gm
