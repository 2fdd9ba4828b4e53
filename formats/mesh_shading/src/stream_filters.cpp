#include <zlib.h>

#include <algorithm>
#include <cstdint>

#include "formats/mesh_shading.h"
#include "meshcore/error.h"

namespace gm {

std::string deflateBytes(const std::string& bytes) {
    uLongf size = compressBound(static_cast<uLong>(bytes.size()));
    std::string out(size, '\0');
    const int rc = compress2(reinterpret_cast<Bytef*>(&out[0]), &size,
                             reinterpret_cast<const Bytef*>(bytes.data()),
                             static_cast<uLong>(bytes.size()), Z_BEST_COMPRESSION);
    if (rc != Z_OK) throw Error("zlib compression failed (code " + std::to_string(rc) + ")");
    out.resize(size);
    return out;
}

std::string ascii85Encode(const std::string& bytes, size_t lineLength) {
    std::string out;
    out.reserve(bytes.size() * 5 / 4 + bytes.size() / lineLength + 8);
    size_t column = 0;
    auto put = [&](const char* chars, size_t n) {
        for (size_t k = 0; k < n; ++k) {
            if (column >= lineLength) {
                out += '\n';
                column = 0;
            }
            if (column == 0 && chars[k] == '%') {
                out += ' ';  // ignored by the decoder
                ++column;
            }
            out += chars[k];
            ++column;
        }
    };
    const size_t n = bytes.size();
    for (size_t i = 0; i < n; i += 4) {
        const size_t len = std::min<size_t>(4, n - i);
        uint32_t word = 0;
        for (size_t k = 0; k < 4; ++k)
            word = (word << 8) | (k < len ? static_cast<unsigned char>(bytes[i + k]) : 0u);
        if (word == 0 && len == 4) {
            put("z", 1);
            continue;
        }
        char group[5];
        for (int k = 4; k >= 0; --k) {
            group[k] = static_cast<char>('!' + word % 85);
            word /= 85;
        }
        put(group, len + 1);  // a final partial group of m bytes is written as m+1 characters
    }
    // The end marker stays on one line: some decoders do not allow whitespace inside it.
    if (column + 2 > lineLength) out += '\n';
    out += "~>\n";
    return out;
}

}  // namespace gm
