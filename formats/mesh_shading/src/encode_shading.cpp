#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

#include "formats/mesh_shading.h"

namespace gm {

namespace {
// Table 4.36 of the PDF 1.7 reference: the boundary anticlockwise in index space from p00, then
// the four interior points. {a, b} index BezierPatch::p[a][b].
constexpr int kPointOrder[16][2] = {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {1, 3}, {2, 3}, {3, 3}, {3, 2},
                                    {3, 1}, {3, 0}, {2, 0}, {1, 0}, {1, 1}, {1, 2}, {2, 2}, {2, 1}};
// The corners in the order of their points above.
constexpr int kColorOrder[4][2] = {{0, 0}, {0, 3}, {3, 3}, {3, 0}};

void putBigEndian(std::string& out, uint64_t value, int bytes) {
    for (int k = bytes - 1; k >= 0; --k)
        out.push_back(static_cast<char>((value >> (8 * k)) & 0xff));
}

uint64_t quantise(double value, double lo, double hi, uint64_t maxCode) {
    const double q = std::round((value - lo) / (hi - lo) * static_cast<double>(maxCode));
    if (!(q > 0)) return 0;
    if (q >= static_cast<double>(maxCode)) return maxCode;
    return static_cast<uint64_t>(q);
}

double clamp01(double c) { return std::min(1.0, std::max(0.0, c)); }
}  // namespace

BinaryShading encodeShadingBinary(const MeshShading& shading) {
    BinaryShading out;
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
    double ymin = xmin, ymax = -xmin;
    for (const BezierPatch& patch : shading.patches) {
        for (const auto& row : patch.p) {
            for (const Vec2& q : row) {
                xmin = std::min(xmin, q.x);
                xmax = std::max(xmax, q.x);
                ymin = std::min(ymin, q.y);
                ymax = std::max(ymax, q.y);
            }
        }
    }
    if (shading.patches.empty()) xmin = xmax = ymin = ymax = 0;
    // Integer bounds print exactly, so the reader decodes with the very range we encoded with.
    const double x0 = std::floor(xmin), y0 = std::floor(ymin);
    const double x1 = std::max(std::ceil(xmax), x0 + 1), y1 = std::max(std::ceil(ymax), y0 + 1);
    out.decode[0] = x0;
    out.decode[1] = x1;
    out.decode[2] = y0;
    out.decode[3] = y1;
    // The fewest coordinate bytes (2, 3 or 4) whose step range / (2^(8·bytes) − 1) is at most
    // 1/1024 px: 16 bits below 64 px, 24 below 16384 px, else 32.
    const double range = std::max(x1 - x0, y1 - y0);
    int cb = 2;
    while (cb < 4 && std::ldexp(1.0, 8 * cb) - 1 < range * 1024) ++cb;
    out.coordinateBytes = cb;
    const uint64_t maxCoordinate = (uint64_t(1) << (8 * cb)) - 1;
    constexpr uint64_t kMaxComponent = 0xffffu;

    out.data.reserve(shading.patches.size() * (1 + 16 * 2 * cb + 4 * 6));
    for (const BezierPatch& patch : shading.patches) {
        out.data.push_back('\0');  // edge flag 0: a patch of its own
        for (const auto& ab : kPointOrder) {
            const Vec2& q = patch.p[ab[0]][ab[1]];
            putBigEndian(out.data, quantise(q.x, x0, x1, maxCoordinate), cb);
            putBigEndian(out.data, quantise(q.y, y0, y1, maxCoordinate), cb);
        }
        for (const auto& ab : kColorOrder) {
            const Vec3& c = patch.c[ab[0]][ab[1]];
            for (int ch = 0; ch < 3; ++ch)
                putBigEndian(out.data, quantise(clamp01(c[ch]), 0, 1, kMaxComponent), 2);
        }
    }
    return out;
}

std::string binaryShadingEntries(const BinaryShading& shading) {
    std::string s = "/ShadingType 7 /ColorSpace /DeviceRGB /BitsPerCoordinate " +
                    std::to_string(8 * shading.coordinateBytes) +
                    " /BitsPerComponent 16 /BitsPerFlag 8 /Decode [";
    for (double d : shading.decode) s += formatDecimal(d, 0) + " ";
    s += "0 1 0 1 0 1]";
    return s;
}

std::string encodeShadingText(const MeshShading& shading, size_t first, size_t count) {
    std::string out;
    const size_t end = std::min(shading.patches.size(), first + count);
    std::string line;
    auto put = [&](const std::string& token) {
        if (line.size() + 1 + token.size() > 200) {
            out += line;
            out += '\n';
            line.clear();
        }
        if (!line.empty()) line += ' ';
        line += token;
    };
    for (size_t n = first; n < end; ++n) {
        const BezierPatch& patch = shading.patches[n];
        put("0");
        for (const auto& ab : kPointOrder) {
            const Vec2& q = patch.p[ab[0]][ab[1]];
            put(formatDecimal(q.x, 4));
            put(formatDecimal(q.y, 4));
        }
        for (const auto& ab : kColorOrder) {
            const Vec3& c = patch.c[ab[0]][ab[1]];
            for (int ch = 0; ch < 3; ++ch) put(formatDecimal(clamp01(c[ch]), 6));
        }
        out += line;
        out += '\n';
        line.clear();
    }
    return out;
}

std::string formatDecimal(double value, int decimals) {
    char buf[64];
    auto result = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
    std::string s(buf, result.ptr);
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

}  // namespace gm
