#include "formats/base64.h"

#include <cstdint>

namespace gm {

std::string base64Encode(const std::string& bytes) {
    static const char* alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t k = 0;
    // Whole groups of three bytes become four characters.
    for (; k + 3 <= bytes.size(); k += 3) {
        const uint32_t v = uint32_t(uint8_t(bytes[k])) << 16 |
                           uint32_t(uint8_t(bytes[k + 1])) << 8 | uint8_t(bytes[k + 2]);
        for (int shift : {18, 12, 6, 0}) out += alphabet[(v >> shift) & 63];
    }
    // One or two bytes left: two or three characters, padded with '='.
    const size_t rest = bytes.size() - k;
    if (rest > 0) {
        uint32_t v = uint32_t(uint8_t(bytes[k])) << 16;
        if (rest == 2) v |= uint32_t(uint8_t(bytes[k + 1])) << 8;
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += rest == 2 ? alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

}  // namespace gm
