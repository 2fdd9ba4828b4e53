// Linear gradients as axial shadings (PDF / PostScript shading type 2), see mesh_shading.h.
#include <algorithm>
#include <vector>

#include "formats/mesh_shading.h"

namespace gm {

namespace {

// One interval of the gradient: its offsets as written, and the colours at its ends.
struct Piece {
    std::string lo, hi;
    Vec3 c0, c1;
};

std::vector<Piece> pieces(const LinearGradient& g) {
    std::vector<Piece> out;
    for (size_t k = 1; k < g.stops.size(); ++k) {
        const GradientStop &a = g.stops[k - 1], &b = g.stops[k];
        Piece p{formatDecimal(a.offset, 6), formatDecimal(b.offset, 6), a.col, b.col};
        if (p.lo != p.hi) out.push_back(std::move(p));
    }
    return out;
}

std::string colourArray(Vec3 c) {
    std::string s = "[";
    for (int k = 0; k < 3; ++k) s += (k ? " " : "") + formatDecimal(std::clamp(c[k], 0.0, 1.0), 4);
    return s + "]";
}

std::string exponential(const Piece& p) {
    return "<< /FunctionType 2 /Domain [0 1] /C0 " + colourArray(p.c0) + " /C1 " +
           colourArray(p.c1) + " /N 1 >>";
}

// Type 3 over the pieces: each one's type 2 function gets its interval mapped to [0 1].
std::string stitching(const std::vector<Piece>& ps) {
    std::string functions, bounds, encode;
    for (size_t k = 0; k < ps.size(); ++k) {
        functions += exponential(ps[k]) + "\n";
        if (k > 0) bounds += (k > 1 ? " " : "") + ps[k].lo;
        encode += k > 0 ? " 0 1" : "0 1";
    }
    return "<< /FunctionType 3 /Domain [0 1] /Functions [\n" + functions + "]\n/Bounds [" + bounds +
           "] /Encode [" + encode + "] >>";
}

}  // namespace

std::string axialShadingEntries(const LinearGradient& g) {
    const std::string coords = formatDecimal(g.from.x, 2) + " " + formatDecimal(g.from.y, 2) + " " +
                               formatDecimal(g.to.x, 2) + " " + formatDecimal(g.to.y, 2);
    const std::vector<Piece> ps = pieces(g);  // never empty: offsets run from 0 to 1
    return "/ShadingType 2 /ColorSpace /DeviceRGB /Coords [" + coords +
           "] /Extend [true true]\n/Function " +
           (ps.size() == 1 ? exponential(ps.front()) : stitching(ps));
}

}  // namespace gm
