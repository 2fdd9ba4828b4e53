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

// The outer loop's points every `step` of arc length, their arc positions and prefix shoelace
// sums (for the area on one side of any chord in O(1)).
struct SampledLoop {
    std::vector<Vec2> q;
    std::vector<double> s;       // arc position of q[t]
    std::vector<double> prefix;  // prefix[t] = Σ_{u<t} cross(q_u, q_{u+1})
    double perimeter = 0;
    double step = 0;
    double total = 0;  // the sampled polygon's area

    // The area of the polygon q_i .. q_j closed by the chord.
    double areaBetween(size_t i, size_t j) const {
        return std::fabs(prefix[j] - prefix[i] + cross(q[j], q[i])) / 2;
    }
};

std::optional<SampledLoop> sampleLoop(const std::vector<Vec2>& loop, const NeckOptions& options) {
    SampledLoop L;
    for (size_t i = 0; i < loop.size(); ++i)
        L.perimeter += norm(loop[(i + 1) % loop.size()] - loop[i]);
    L.step = std::max(options.step, L.perimeter / std::max(8, options.maxPoints));
    double acc = 0, next = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
        if (i > 0) acc += norm(loop[i] - loop[i - 1]);
        if (acc >= next) {
            L.q.push_back(loop[i]);
            L.s.push_back(acc);
            next = acc + L.step;
        }
    }
    const size_t n = L.q.size();
    if (n < 8) return std::nullopt;
    L.prefix.assign(n, 0);
    for (size_t t = 1; t < n; ++t) L.prefix[t] = L.prefix[t - 1] + cross(L.q[t - 1], L.q[t]);
    L.total = std::fabs(L.prefix[n - 1] + cross(L.q[n - 1], L.q[0])) / 2;
    if (L.total <= 0) return std::nullopt;
    return L;
}

// How many of the chord's samples, 1 px apart with the ends left out (they lie on the outline,
// half a pixel from either side's pixel centres), fall in region pixels; `samples` gets their
// count + 1.
int samplesInside(const Region& region, Vec2 a, Vec2 b, double length, int& samples) {
    const int w = region.width, h = region.height;
    auto inside = [&](double x, double y) {
        const int px = static_cast<int>(std::floor(x)), py = static_cast<int>(std::floor(y));
        return px >= 0 && py >= 0 && px < w && py < h && region.mask[static_cast<size_t>(py) * w + px];
    };
    samples = std::max(2, static_cast<int>(std::ceil(length)));
    int in = 0;
    for (int k = 1; k < samples; ++k) {
        const double t = double(k) / samples;
        in += inside(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
    }
    return in;
}

struct Chord {
    size_t i = 0, j = 0;  // indices into SampledLoop::q, i < j
    double ratio = 0;     // length / shorter arc
};

// The qualifying chord (NeckOptions) with the smallest ratio.
std::optional<Chord> narrowestChord(const Region& region, const SampledLoop& L,
                                    const NeckOptions& options) {
    std::optional<Chord> best;
    double bestRatio = options.maxRatio;
    const double minArc = 8 * L.step;
    const size_t n = L.q.size();
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
            const double along = L.s[j] - L.s[i];
            const double arc = std::min(along, L.perimeter - along);
            if (arc < minArc) continue;
            const double d = norm(L.q[j] - L.q[i]);
            if (d >= bestRatio * arc) continue;
            const double a = L.areaBetween(i, j);
            if (std::min(a, L.total - a) < options.minShare * L.total) continue;
            int samples = 0;
            const int in = samplesInside(region, L.q[i], L.q[j], d, samples);
            if (in < options.minInside * (samples - 1)) continue;
            bestRatio = d / arc;
            best = Chord{i, j, bestRatio};
        }
    return best;
}

// Side 1: the region's pixels whose centres lie inside the polygon q_i .. q_j (closed by the
// chord), by scanlines over the region's bounding box; side 2 the rest. False when the region
// has no pixel.
bool splitAtChord(const Region& region, const SampledLoop& L, const Chord& chord,
                  std::vector<uint8_t>& side) {
    const int w = region.width, h = region.height;
    side.assign(region.mask.size(), 0);
    const PixelBox box = maskBounds(region.mask, w, h);
    if (box.empty()) return false;
    const std::vector<Vec2>& q = L.q;
    std::vector<double> xs;
    for (int y = box.y0; y <= box.y1; ++y) {
        const double yc = y + 0.5;
        xs.clear();
        for (size_t t = chord.i; t <= chord.j; ++t) {
            const Vec2 p = q[t], r = t == chord.j ? q[chord.i] : q[t + 1];
            if ((p.y > yc) != (r.y > yc)) xs.push_back(p.x + (yc - p.y) * (r.x - p.x) / (r.y - p.y));
        }
        std::sort(xs.begin(), xs.end());
        size_t c = 0;
        for (int x = box.x0; x <= box.x1; ++x) {
            const double xc = x + 0.5;
            while (c < xs.size() && xs[c] <= xc) ++c;
            const size_t k = static_cast<size_t>(y) * w + x;
            if (region.mask[k]) side[k] = (c % 2 == 1) ? 1 : 2;
        }
    }
    return true;
}

}  // namespace

std::optional<NeckCut> findNeck(const Region& region, const NeckOptions& options) {
    const std::vector<Vec2>& loop = region.outer.points;
    const int w = region.width, h = region.height;
    if (loop.size() < 8 || w <= 0 || h <= 0) return std::nullopt;
    const std::optional<SampledLoop> sampled = sampleLoop(loop, options);
    if (!sampled) return std::nullopt;
    const std::optional<Chord> chord = narrowestChord(region, *sampled, options);
    if (!chord) return std::nullopt;

    NeckCut cut;
    cut.a = sampled->q[chord->i];
    cut.b = sampled->q[chord->j];
    cut.ratio = chord->ratio;
    if (!splitAtChord(region, *sampled, *chord, cut.side)) return std::nullopt;
    // Specks on the wrong side (the sampled polygon cuts the outline's corners by a fraction
    // of a pixel) go to the other side.
    keepLargest(cut.side, w, h);
    bool has1 = false, has2 = false;
    for (uint8_t v : cut.side) has1 |= v == 1, has2 |= v == 2;
    if (!has1 || !has2) return std::nullopt;
    return cut;
}

}  // namespace gm
