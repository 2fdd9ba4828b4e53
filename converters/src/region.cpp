#include "converters/region.h"

namespace gm {

double polygonSignedArea(const Polygon& poly) {
    const auto& p = poly.points;
    const size_t n = p.size();
    double twice = 0;
    for (size_t k = 0; k < n; ++k) {
        const Vec2 a = p[k], b = p[(k + 1) % n];
        twice += a.x * b.y - b.x * a.y;
    }
    return twice / 2;
}

}  // namespace gm
