#include "meshcore/printable_text.h"

#include <cstdio>

namespace gm {

namespace {

std::string hexEscape(const char* format, unsigned value) {
    char b[8];
    std::snprintf(b, sizeof b, format, value);
    return b;
}

// Length of the well-formed UTF-8 sequence starting at s[at] (2 to 4), 0 when there is none.
size_t utf8SequenceLength(const std::string& s, size_t at) {
    const unsigned char lead = static_cast<unsigned char>(s[at]);
    size_t n = 0;
    unsigned minimum = 0, code = 0;
    if (lead >= 0xC2 && lead <= 0xDF) n = 2, minimum = 0x80, code = lead & 0x1F;
    else if (lead >= 0xE0 && lead <= 0xEF) n = 3, minimum = 0x800, code = lead & 0x0F;
    else if (lead >= 0xF0 && lead <= 0xF4) n = 4, minimum = 0x10000, code = lead & 0x07;
    else return 0;
    if (at + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k) {
        const unsigned char c = static_cast<unsigned char>(s[at + k]);
        if ((c & 0xC0) != 0x80) return 0;
        code = (code << 6) | (c & 0x3F);
    }
    if (code < minimum || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
    return n;
}

}  // namespace

std::string printableText(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (size_t k = 0; k < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[k]);
        if (c < 0x20 || c == 0x7F) {
            out += hexEscape("\\x%02x", c);
            ++k;
        } else if (c < 0x80) {
            out += static_cast<char>(c);
            ++k;
        } else if (const size_t n = utf8SequenceLength(text, k); n == 0) {
            out += hexEscape("\\x%02x", c);
            ++k;
        } else if (c == 0xC2 && static_cast<unsigned char>(text[k + 1]) < 0xA0) {
            out += hexEscape("\\u%04x", static_cast<unsigned char>(text[k + 1]));  // C1
            k += n;
        } else {
            out.append(text, k, n);
            k += n;
        }
    }
    return out;
}

}  // namespace gm
