#include "converters/neck.h"

#include <algorithm>
#include <cmath>

#include "converters/regions.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {


// Each side keeps only its largest 8-connected component; the pixels of its other components
// go to the other side.
void keepLargest(std::vector<uint8_t>& side, int w, int h) {
    std::vector<int> cls(side.size()), compId;
    for (size_t k = 0; k < side.size(); ++k) cls[k] = side[k] ? side[k] : -1;
    const std::vector<PixelComponent> comps = labelComponents(w, h, cls, compId);
    int largest[3] = {-1, -1, -1};
    for (int c = 0; c < static_cast<int>(comps.size()); ++c) {
        int& best = largest[comps[c].label];
        if (best < 0 || comps[c].size > comps[best].size) best = c;
    }
    for (size_t k = 0; k < side.size(); ++k)
        if (side[k] && compId[k] != largest[side[k]]) side[k] = side[k] == 1 ? 2 : 1;
}

}  // namespace

std::optional<NeckCut> findNeck(const Region& region, const NeckOptions& options) {
    const std::vector<Vec2>& loop = region.outer.points;
    const int w = region.width, h = region.height;
    if (loop.size() < 8 || w <= 0 || h <= 0) return std::nullopt;
    double perimeter = 0;
    for (size_t i = 0; i < loop.size(); ++i) perimeter += norm(loop[(i + 1) % loop.size()] - loop[i]);
    const double step = std::max(options.step, perimeter / std::max(8, options.maxPoints));

    // Loop points every `step` of arc length, their arc positions and prefix shoelace sums.
    std::vector<Vec2> q;
    std::vector<double> s;
    double acc = 0, next = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
        if (i > 0) acc += norm(loop[i] - loop[i - 1]);
        if (acc >= next) {
            q.push_back(loop[i]);
            s.push_back(acc);
            next = acc + step;
        }
    }
    const size_t n = q.size();
    if (n < 8) return std::nullopt;
    std::vector<double> prefix(n, 0);  // prefix[t] = Σ_{u<t} cross(q_u, q_{u+1})
    for (size_t t = 1; t < n; ++t) prefix[t] = prefix[t - 1] + cross(q[t - 1], q[t]);
    const double total = std::fabs(prefix[n - 1] + cross(q[n - 1], q[0])) / 2;
    if (total <= 0) return std::nullopt;

    auto inside = [&](double x, double y) {
        const int px = static_cast<int>(std::floor(x)), py = static_cast<int>(std::floor(y));
        return px >= 0 && py >= 0 && px < w && py < h && region.mask[static_cast<size_t>(py) * w + px];
    };
    double best = options.maxRatio;
    size_t bi = 0, bj = 0;
    bool found = false;
    const double minArc = 8 * step;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
            const double along = s[j] - s[i];
            const double arc = std::min(along, perimeter - along);
            if (arc < minArc) continue;
            const double d = norm(q[j] - q[i]);
            if (d >= best * arc) continue;
            const double a = std::fabs(prefix[j] - prefix[i] + cross(q[j], q[i])) / 2;
            if (std::min(a, total - a) < options.minShare * total) continue;
            // Samples 1 px apart, the ends left out (they lie on the outline, half a pixel
            // from either side's pixel centres).
            const int samples = std::max(2, static_cast<int>(std::ceil(d)));
            int in = 0;
            for (int k = 1; k < samples; ++k) {
                const double t = double(k) / samples;
                in += inside(q[i].x + t * (q[j].x - q[i].x), q[i].y + t * (q[j].y - q[i].y));
            }
            if (in < options.minInside * (samples - 1)) continue;
            best = d / arc;
            bi = i, bj = j;
            found = true;
        }
    if (!found) return std::nullopt;

    // Side 1: the region's pixels whose centres lie inside the polygon q_bi .. q_bj (closed by
    // the chord), by scanlines; side 2 the rest. Specks on the wrong side (the sampled polygon
    // cuts the outline's corners by a fraction of a pixel) go to the other side.
    NeckCut cut;
    cut.a = q[bi];
    cut.b = q[bj];
    cut.ratio = best;
    cut.side.assign(region.mask.size(), 0);
    const PixelBox box = maskBounds(region.mask, w, h);
    if (box.empty()) return std::nullopt;
    const int x0 = box.x0, y0 = box.y0, x1 = box.x1, y1 = box.y1;
    std::vector<double> xs;
    for (int y = y0; y <= y1; ++y) {
        const double yc = y + 0.5;
        xs.clear();
        for (size_t t = bi; t <= bj; ++t) {
            const Vec2 p = q[t], r = t == bj ? q[bi] : q[t + 1];
            if ((p.y > yc) != (r.y > yc)) xs.push_back(p.x + (yc - p.y) * (r.x - p.x) / (r.y - p.y));
        }
        std::sort(xs.begin(), xs.end());
        size_t c = 0;
        for (int x = x0; x <= x1; ++x) {
            const double xc = x + 0.5;
            while (c < xs.size() && xs[c] <= xc) ++c;
            const size_t k = static_cast<size_t>(y) * w + x;
            if (region.mask[k]) cut.side[k] = (c % 2 == 1) ? 1 : 2;
        }
    }
    keepLargest(cut.side, w, h);
    bool has1 = false, has2 = false;
    for (uint8_t v : cut.side) has1 |= v == 1, has2 |= v == 2;
    if (!has1 || !has2) return std::nullopt;
    return cut;
}

}  // namespace gm
