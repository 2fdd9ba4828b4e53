#include "meshcore/printable_text.h"

#include <cstdio>
#include <string>
#include <vector>

namespace gm {

namespace {

std::string hexEscape(const char* format, unsigned value) {
    char b[8];
    std::snprintf(b, sizeof b, format, value);
    return b;
}

// What a UTF-8 lead byte announces: the sequence's length (0: not a lead byte), the smallest
// code point that needs it (shorter forms are overlong), and the code point's bits it carries.
struct Utf8Lead {
    size_t length;
    unsigned minimum;
    unsigned bits;
};

Utf8Lead utf8Lead(unsigned char c) {
    if (c >= 0xC2 && c <= 0xDF) return {2, 0x80, c & 0x1Fu};
    if (c >= 0xE0 && c <= 0xEF) return {3, 0x800, c & 0x0Fu};
    if (c >= 0xF0 && c <= 0xF4) return {4, 0x10000, c & 0x07u};
    return {0, 0, 0};
}

// Length of the well-formed UTF-8 sequence starting at s[at] (2 to 4), 0 when there is none.
size_t utf8SequenceLength(const std::string& s, size_t at) {
    const Utf8Lead lead = utf8Lead(static_cast<unsigned char>(s[at]));
    if (lead.length == 0 || at + lead.length > s.size()) return 0;
    unsigned code = lead.bits;
    for (size_t k = 1; k < lead.length; ++k) {
        const unsigned char c = static_cast<unsigned char>(s[at + k]);
        if ((c & 0xC0) != 0x80) return 0;
        code = (code << 6) | (c & 0x3Fu);
    }
    const bool surrogate = code >= 0xD800 && code <= 0xDFFF;
    if (code < lead.minimum || code > 0x10FFFF || surrogate) return 0;
    return lead.length;
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

std::string oneLine(const std::string& message) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (start <= message.size()) {
        size_t end = message.find_first_of("\r\n", start);
        if (end == std::string::npos) end = message.size();
        std::string part = message.substr(start, end - start);
        const size_t a = part.find_first_not_of(" \t"), b = part.find_last_not_of(" \t");
        part = a == std::string::npos ? std::string() : part.substr(a, b - a + 1);
        bool seen = part.empty();
        for (const std::string& p : parts) seen = seen || p.find(part) != std::string::npos;
        if (!seen) parts.push_back(part);
        start = end + 1;
    }
    std::string line;
    for (const std::string& p : parts) line += (line.empty() ? "" : "; ") + p;
    return line;
}

}  // namespace gm
