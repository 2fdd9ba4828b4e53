#include "converters/regions.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <set>

#include "meshcore/error.h"
#include "meshcore/geometry.h"

namespace gm {

std::vector<PixelComponent> labelComponents(int width, int height, const std::vector<int>& cls,
                                            std::vector<int>& compId) {
    compId.assign(cls.size(), -1);
    std::vector<PixelComponent> comps;
    std::vector<int> stack;
    for (int start = 0; start < width * height; ++start) {
        if (cls[start] < 0 || compId[start] >= 0) continue;
        const int id = static_cast<int>(comps.size());
        PixelComponent c;
        c.label = cls[start];
        c.x0 = c.x1 = start % width;
        c.y0 = c.y1 = start / width;
        compId[start] = id;
        stack.push_back(start);
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            const int x = p % width, y = p / width;
            ++c.size;
            c.x0 = std::min(c.x0, x), c.x1 = std::max(c.x1, x);
            c.y0 = std::min(c.y0, y), c.y1 = std::max(c.y1, y);
            for (int dy = -1; dy <= 1; ++dy) {
                const int ny = y + dy;
                if (ny < 0 || ny >= height) continue;
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx;
                    if (nx < 0 || nx >= width) continue;
                    const int q = ny * width + nx;
                    if (compId[q] < 0 && cls[q] == c.label) {
                        compId[q] = id;
                        stack.push_back(q);
                    }
                }
            }
        }
        comps.push_back(c);
    }
    return comps;
}

namespace {


// A grid of pixel samples around one component: the component's bounding box grown by `pad`.
struct LocalGrid {
    int x0 = 0, y0 = 0, w = 0, h = 0;  // image position of cell (0,0); size
    int index(int i, int j) const { return j * w + i; }
};

// Separable Gaussian blur in place (values outside the grid are never needed: the caller's
// margin covers the kernel).
void gaussianBlur(std::vector<float>& v, int w, int h, double sigma) {
    if (sigma <= 0) return;
    const int r = static_cast<int>(std::ceil(3 * sigma));
    std::vector<float> k(2 * r + 1);
    float sum = 0;
    for (int i = -r; i <= r; ++i) sum += k[i + r] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
    for (float& x : k) x /= sum;
    std::vector<float> tmp(v.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float acc = 0;
            for (int i = -r; i <= r; ++i) acc += k[i + r] * v[y * w + std::clamp(x + i, 0, w - 1)];
            tmp[y * w + x] = acc;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float acc = 0;
            for (int i = -r; i <= r; ++i) acc += k[i + r] * tmp[std::clamp(y + i, 0, h - 1) * w + x];
            v[y * w + x] = acc;
        }
}

// Marching squares over the sample grid `inside` (1 object): loops with the object on the right
// as seen on screen (y down), so outer loops have positive signed area and holes negative.
// Diagonal saddles join the inside pixels (8-connected object, 4-connected background), so loops
// never touch. `crossing(a, b)` gives the point between inside sample a and outside sample b.
std::vector<Polygon> marchingSquares(const LocalGrid& g, const std::vector<uint8_t>& inside,
                                     const std::function<Vec2(int, int)>& crossing) {
    const int W = g.w, H = g.h;
    // Edge ids: horizontal edge (i,j)-(i+1,j) is j*W+i; vertical edge (i,j)-(i,j+1) is W*H+j*W+i.
    std::vector<int> next(static_cast<size_t>(2) * W * H, -1);
    std::vector<int> starts;
    auto edgeEnds = [&](int e, int& a, int& b) {
        if (e < W * H) {
            a = e, b = e + 1;
        } else {
            a = e - W * H, b = a + W;
        }
    };
    for (int j = 0; j + 1 < H; ++j) {
        for (int i = 0; i + 1 < W; ++i) {
            // Corners in cyclic order: TL, TR, BR, BL; edge k joins corner k and k+1.
            const std::array<int, 4> corner = {g.index(i, j), g.index(i + 1, j),
                                               g.index(i + 1, j + 1), g.index(i, j + 1)};
            const std::array<bool, 4> in = {inside[corner[0]] != 0, inside[corner[1]] != 0,
                                            inside[corner[2]] != 0, inside[corner[3]] != 0};
            const int count = in[0] + in[1] + in[2] + in[3];
            if (count == 0 || count == 4) continue;
            const std::array<int, 4> edge = {j * W + i, W * H + j * W + i + 1, (j + 1) * W + i,
                                             W * H + j * W + i};
            const std::array<Vec2, 4> cornerPos = {Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}, Vec2{0, 1}};
            const std::array<Vec2, 4> edgeMid = {Vec2{.5, 0}, Vec2{1, .5}, Vec2{.5, 1}, Vec2{0, .5}};
            // Adds the segment joining edges e1 and e2, oriented so that the inside is on its right.
            auto addSegment = [&](int e1, int e2, int refCorner) {
                const Vec2 p = edgeMid[e1], q = edgeMid[e2];
                const bool rightOfRef = cross(q - p, cornerPos[refCorner] - p) > 0;
                const int from = rightOfRef == in[refCorner] ? edge[e1] : edge[e2];
                next[from] = from == edge[e1] ? edge[e2] : edge[e1];
                starts.push_back(from);
            };
            if (count == 1 || count == 3) {
                // Cut around the odd corner: its two edges are k-1 and k.
                int k = 0;
                while (in[k] != (count == 1)) ++k;
                addSegment((k + 3) % 4, k, k);
            } else if (in[0] == in[2]) {
                // Saddle: cut around each outside corner, keeping the inside diagonal connected.
                for (int k = 0; k < 4; ++k)
                    if (!in[k]) addSegment((k + 3) % 4, k, k);
            } else {
                // Two adjacent inside corners: the segment crosses the cell.
                const int k = in[0] == in[1] ? 1 : 0;  // edges k and k+2 have the crossings
                addSegment(k, k + 2, k);
            }
        }
    }
    std::vector<Polygon> loops;
    std::vector<uint8_t> visited(next.size(), 0);
    for (const int start : starts) {
        if (visited[start]) continue;
        Polygon poly;
        int e = start;
        do {
            visited[e] = 1;
            int a, b;
            edgeEnds(e, a, b);
            poly.points.push_back(inside[a] ? crossing(a, b) : crossing(b, a));
            e = next[e];
            assert(e >= 0);
        } while (e != start);
        loops.push_back(std::move(poly));
    }
    return loops;
}

// Douglas–Peucker on a closed loop; marks kept points in `keep`.
void simplifyLoop(const std::vector<Vec2>& p, double tol, std::vector<uint8_t>& keep) {
    const int n = static_cast<int>(p.size());
    if (n <= 8) {
        std::fill(keep.begin(), keep.end(), 1);
        return;
    }
    // Anchor at 0 and the point farthest from it.
    int far = 1;
    for (int k = 1; k < n; ++k)
        if (norm(p[k] - p[0]) > norm(p[far] - p[0])) far = k;
    keep[0] = keep[far] = 1;
    std::vector<std::pair<int, int>> stack = {{0, far}, {far, n}};
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        if (j - i < 2) continue;
        const Vec2 a = p[i % n], b = p[j % n];
        int best = -1;
        double bestDist = -1;
        for (int m = i + 1; m < j; ++m) {
            const double d = pointSegmentDistance(p[m % n], a, b);
            if (d > bestDist) bestDist = d, best = m;
        }
        int split = -1;
        for (int m = i + 1; m < j; ++m)
            if (keep[m % n]) { split = m; break; }
        if (split < 0 && bestDist > tol) split = best;
        if (split < 0) continue;
        keep[split % n] = 1;
        stack.push_back({i, split});
        stack.push_back({split, j});
    }
    int kept = 0;
    for (uint8_t k : keep) kept += k;
    if (kept < 4) std::fill(keep.begin(), keep.end(), 1);
}

double orient(Vec2 a, Vec2 b, Vec2 c) { return cross(b - a, c - a); }

bool segmentsTouch(Vec2 p1, Vec2 p2, Vec2 p3, Vec2 p4) {
    if (std::max(p1.x, p2.x) < std::min(p3.x, p4.x) || std::max(p3.x, p4.x) < std::min(p1.x, p2.x) ||
        std::max(p1.y, p2.y) < std::min(p3.y, p4.y) || std::max(p3.y, p4.y) < std::min(p1.y, p2.y))
        return false;
    const double o1 = orient(p1, p2, p3), o2 = orient(p1, p2, p4);
    const double o3 = orient(p3, p4, p1), o4 = orient(p3, p4, p2);
    return o1 * o2 <= 0 && o3 * o4 <= 0;
}

// One edge of a simplified loop: the span of original points it replaces.
struct LoopSpan {
    int loop, from, to;  // original point indices of the span
};

// The simplified loops' edges (between consecutive kept points), and the kept points' bounds.
std::vector<LoopSpan> keptSpans(const std::vector<Polygon*>& loops,
                                const std::vector<std::vector<uint8_t>>& keep, Vec2& lo, Vec2& hi) {
    std::vector<LoopSpan> spans;
    double minX = std::numeric_limits<double>::max(), minY = minX;
    double maxX = -minX, maxY = -minX;
    for (size_t l = 0; l < loops.size(); ++l) {
        const auto& p = loops[l]->points;
        const int n = static_cast<int>(p.size());
        int first = -1, prev = -1;
        for (int k = 0; k < n; ++k) {
            if (!keep[l][k]) continue;
            minX = std::min(minX, p[k].x), maxX = std::max(maxX, p[k].x);
            minY = std::min(minY, p[k].y), maxY = std::max(maxY, p[k].y);
            if (prev >= 0)
                spans.push_back({static_cast<int>(l), prev, k});
            else
                first = k;
            prev = k;
        }
        spans.push_back({static_cast<int>(l), prev, first});
    }
    lo = {minX, minY};
    hi = {maxX, maxY};
    return spans;
}

// Marks the edges that cross or touch another edge (other than their neighbours on the same
// loop), through a uniform grid of the edges' bounding boxes; false when none does.
bool markTouchingSpans(const std::vector<Polygon*>& loops, const std::vector<LoopSpan>& spans,
                       Vec2 lo, Vec2 hi, std::vector<uint8_t>& bad) {
    const double cell = 4.0;
    const int gw = static_cast<int>((hi.x - lo.x) / cell) + 1;
    const int gh = static_cast<int>((hi.y - lo.y) / cell) + 1;
    std::vector<std::vector<int>> grid(static_cast<size_t>(gw) * gh);
    auto P = [&](int l, int k) { return loops[l]->points[k]; };
    for (size_t s = 0; s < spans.size(); ++s) {
        const Vec2 a = P(spans[s].loop, spans[s].from), b = P(spans[s].loop, spans[s].to);
        const int cx0 = static_cast<int>((std::min(a.x, b.x) - lo.x) / cell);
        const int cx1 = static_cast<int>((std::max(a.x, b.x) - lo.x) / cell);
        const int cy0 = static_cast<int>((std::min(a.y, b.y) - lo.y) / cell);
        const int cy1 = static_cast<int>((std::max(a.y, b.y) - lo.y) / cell);
        for (int cy = cy0; cy <= cy1; ++cy)
            for (int cx = cx0; cx <= cx1; ++cx) grid[cy * gw + cx].push_back(static_cast<int>(s));
    }
    bad.assign(spans.size(), 0);
    bool any = false;
    for (const auto& bucket : grid) {
        for (size_t u = 0; u < bucket.size(); ++u) {
            for (size_t v = u + 1; v < bucket.size(); ++v) {
                const LoopSpan& s = spans[bucket[u]];
                const LoopSpan& t = spans[bucket[v]];
                if (s.loop == t.loop && (s.to == t.from || t.to == s.from)) continue;
                if (segmentsTouch(P(s.loop, s.from), P(s.loop, s.to), P(t.loop, t.from),
                                  P(t.loop, t.to))) {
                    bad[bucket[u]] = bad[bucket[v]] = 1;
                    any = true;
                }
            }
        }
    }
    return any;
}

// Splits the kept edges of one loop longer than maxSegment evenly: the shape stays, the
// spacing is bounded. Returns the loop's new points.
std::vector<Vec2> splitLongEdges(const std::vector<Vec2>& p, const std::vector<uint8_t>& keep,
                                 double maxSegment) {
    std::vector<int> kept;
    for (size_t k = 0; k < keep.size(); ++k)
        if (keep[k]) kept.push_back(static_cast<int>(k));
    std::vector<Vec2> out;
    for (size_t k = 0; k < kept.size(); ++k) {
        const Vec2 a = p[kept[k]], b = p[kept[(k + 1) % kept.size()]];
        const int pieces =
            maxSegment > 0 ? std::max(1, static_cast<int>(std::ceil(norm(b - a) / maxSegment))) : 1;
        for (int q = 0; q < pieces; ++q)
            out.push_back(a + (static_cast<double>(q) / pieces) * (b - a));
    }
    return out;
}

// Simplifies every loop of a region; where a simplified edge would cross or touch another, the
// original points of that span come back, until the loops are again disjoint simple polygons.
// Then splits edges longer than maxSegment evenly.
void simplifyLoops(std::vector<Polygon*> loops, double tol, double maxSegment) {
    if (tol <= 0) return;
    std::vector<std::vector<uint8_t>> keep(loops.size());
    for (size_t l = 0; l < loops.size(); ++l) {
        keep[l].assign(loops[l]->points.size(), 0);
        simplifyLoop(loops[l]->points, tol, keep[l]);
    }
    std::vector<uint8_t> bad;
    for (int round = 0; round < 64; ++round) {
        Vec2 lo, hi;
        const std::vector<LoopSpan> spans = keptSpans(loops, keep, lo, hi);
        if (!markTouchingSpans(loops, spans, lo, hi, bad)) break;
        bool changed = false;
        for (size_t s = 0; s < spans.size(); ++s) {
            if (!bad[s]) continue;
            const int n = static_cast<int>(loops[spans[s].loop]->points.size());
            for (int k = (spans[s].from + 1) % n; k != spans[s].to; k = (k + 1) % n) {
                if (!keep[spans[s].loop][k]) changed = true;
                keep[spans[s].loop][k] = 1;
            }
        }
        if (!changed) break;  // already at full resolution: the traced loops are simple
    }
    for (size_t l = 0; l < loops.size(); ++l)
        loops[l]->points = splitLongEdges(loops[l]->points, keep[l], maxSegment);
}

// Fills the holes (background not 4-connected to the grid's border) smaller than minHole
// pixels into `inside`.
void fillSmallHoles(const LocalGrid& g, std::vector<uint8_t>& inside, int minHole) {
    std::vector<int> holeId(inside.size(), -2);  // -2 unvisited background, -1 outside
    std::vector<int> stack;
    auto flood = [&](int seed, int id, std::vector<int>* members) {
        holeId[seed] = id;
        stack.push_back(seed);
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            if (members) members->push_back(p);
            const int i = p % g.w, j = p / g.w;
            const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
            for (const auto& q : nb) {
                if (q[0] < 0 || q[1] < 0 || q[0] >= g.w || q[1] >= g.h) continue;
                const int k = g.index(q[0], q[1]);
                if (!inside[k] && holeId[k] == -2) {
                    holeId[k] = id;
                    stack.push_back(k);
                }
            }
        }
    };
    flood(0, -1, nullptr);
    int holeCount = 0;
    for (size_t k = 0; k < inside.size(); ++k) {
        if (inside[k] || holeId[k] != -2) continue;
        std::vector<int> members;
        flood(static_cast<int>(k), holeCount++, &members);
        if (static_cast<int>(members.size()) < minHole)
            for (int m : members) inside[m] = 1;
    }
}

// The sub-pixel field the loops are traced in: the source coverage, lightly blurred, over the
// trace grid plus `margin` samples on every side; beyond the image the border value is repeated.
struct CoverageField {
    int margin = 0, w = 0, h = 0;
    std::vector<float> values;

    CoverageField(const LocalGrid& g, int width, int height,
                  const std::function<float(int, int)>& source, double smoothing)
        : margin(smoothing > 0 ? static_cast<int>(std::ceil(3 * smoothing)) : 0),
          w(g.w + 2 * margin),
          h(g.h + 2 * margin),
          values(static_cast<size_t>(w) * h) {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const int x = std::clamp(g.x0 - margin + i, 0, width - 1);
                const int y = std::clamp(g.y0 - margin + j, 0, height - 1);
                values[j * w + i] = source(x, y);
            }
        gaussianBlur(values, w, h, smoothing);
    }
    // The value at trace-grid sample k.
    float at(const LocalGrid& g, int k) const {
        return values[(k / g.w + margin) * w + k % g.w + margin];
    }
};

// The region's loops from marching squares over `inside`, each crossing placed on the field's
// iso-line: 0.5 for the holes, options.outerLevel for the outer loop.
std::vector<Polygon> traceLoops(const LocalGrid& g, const std::vector<uint8_t>& inside,
                                const CoverageField& field, int width, int height,
                                const RegionOptions& options) {
    auto pixelCentre = [&](int k) {
        return Vec2{g.x0 + k % g.w + 0.5, g.y0 + k / g.w + 0.5};
    };
    auto outsideImage = [&](int k) {
        const int x = g.x0 + k % g.w, y = g.y0 + k / g.w;
        return x < 0 || y < 0 || x >= width || y >= height;
    };
    // The crossing of the field's iso-line `level` between an inside pixel centre a and an
    // outside one b, never nearer either centre than 0.1 px (loops through a saddle stay apart)
    // and, with `minT`, never nearer a than that.
    auto crossingAt = [&](double level, double minT) {
        return [&, level, minT](int a, int b) {
            const Vec2 pa = pixelCentre(a), pb = pixelCentre(b);
            double t = 0.5;  // the image border, between a border pixel and the padding beyond
            if (!outsideImage(b)) {
                // Each sample forced to its side of the level, so the crossing lies between.
                const double fa = std::max<double>(field.at(g, a), level + 0.05);
                const double fb = std::min<double>(field.at(g, b), level - 0.05);
                t = std::clamp((fa - level) / (fa - fb), minT, 0.9);
            }
            return pa + t * (pb - pa);
        };
    };
    std::vector<Polygon> loops = marchingSquares(g, inside, crossingAt(0.5, 0.1));
    if (options.outerLevel != 0.5) {
        // The outer loop again, from the lower iso-line and never inside a pixel edge; the
        // holes keep the 0.5 iso-line. The outer loop only moves away from the holes.
        std::vector<Polygon> grown = marchingSquares(g, inside, crossingAt(options.outerLevel, 0.5));
        for (auto& l : loops)
            if (polygonSignedArea(l) > 0)
                for (auto& o : grown)
                    if (polygonSignedArea(o) > 0) l = std::move(o);
    }
    return loops;
}

// Builds one region from a component. `source(x, y)` is the coverage to trace at an image pixel
// (only its sub-pixel position matters: which pixels are inside comes from the component).
Region buildRegion(int width, int height, const PixelComponent& comp, int compIndex,
                   const std::vector<int>& compId, const std::function<float(int, int)>& source,
                   const RegionOptions& options) {
    Region region;
    region.width = width;
    region.height = height;
    region.label = comp.label;
    // Trace grid: bounding box plus one background sample on every side.
    LocalGrid g;
    g.x0 = comp.x0 - 1, g.y0 = comp.y0 - 1;
    g.w = comp.x1 - comp.x0 + 3, g.h = comp.y1 - comp.y0 + 3;
    std::vector<uint8_t> inside(static_cast<size_t>(g.w) * g.h, 0);
    for (int j = 1; j + 1 < g.h; ++j)
        for (int i = 1; i + 1 < g.w; ++i)
            inside[g.index(i, j)] = compId[(g.y0 + j) * width + g.x0 + i] == compIndex;
    fillSmallHoles(g, inside, options.minHole);

    region.mask.assign(static_cast<size_t>(width) * height, 0);
    for (int j = 1; j + 1 < g.h; ++j)
        for (int i = 1; i + 1 < g.w; ++i)
            if (inside[g.index(i, j)]) {
                region.mask[(g.y0 + j) * width + g.x0 + i] = 1;
                ++region.pixelCount;
            }

    const CoverageField field(g, width, height, source, options.smoothing);
    std::vector<Polygon> loops = traceLoops(g, inside, field, width, height, options);
    std::vector<Polygon*> loopPtrs;
    for (auto& l : loops) loopPtrs.push_back(&l);
    simplifyLoops(loopPtrs, options.simplifyTolerance, options.maxSegment);

    int outerCount = 0;
    for (auto& l : loops) {
        if (polygonSignedArea(l) > 0) {
            region.outer = std::move(l);
            ++outerCount;
        } else {
            region.holes.push_back(std::move(l));
        }
    }
    assert(outerCount == 1);
    (void)outerCount;
    return region;
}

void requireValidSize(int width, int height, size_t count, const char* what) {
    if (width <= 0 || height <= 0)
        throw Error("the " + std::string(what) + " has no pixels (" + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
    if (count != static_cast<size_t>(width) * height)
        throw Error("the " + std::string(what) + " holds " + std::to_string(count) +
                    " values for " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels");
}

std::vector<Region> regionsFromClasses(int width, int height, const std::vector<int>& cls,
                                       const std::function<float(int, int, bool)>& source,
                                       const RegionOptions& options, const char* what) {
    std::vector<int> compId;
    std::vector<PixelComponent> comps = labelComponents(width, height, cls, compId);
    if (comps.empty()) throw Error("the " + std::string(what) + " is empty: no object pixel");
    std::vector<int> order;
    for (size_t c = 0; c < comps.size(); ++c)
        if (comps[c].size >= std::max(1, options.minArea)) order.push_back(static_cast<int>(c));
    if (order.empty()) {
        int largest = 0;
        for (const auto& c : comps) largest = std::max(largest, c.size);
        throw Error("no region of the " + std::string(what) + " has the minimum area of " +
                    std::to_string(options.minArea) + " pixels (largest: " +
                    std::to_string(largest) + ")");
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return comps[a].size > comps[b].size; });
    std::vector<Region> regions;
    for (int c : order) {
        auto src = [&](int x, int y) {
            return source(x, y, compId[static_cast<size_t>(y) * width + x] == c);
        };
        regions.push_back(buildRegion(width, height, comps[c], c, compId, src, options));
    }
    return regions;
}

}  // namespace

Coverage coverageFromAlpha(const RgbaImage& image) {
    requireValidSize(image.width, image.height, image.pixels.size() / 4, "image");
    Coverage c{image.width, image.height, {}};
    c.values.resize(static_cast<size_t>(image.width) * image.height);
    for (size_t k = 0; k < c.values.size(); ++k) c.values[k] = image.pixels[4 * k + 3];
    return c;
}

Coverage coverageFromMaskImage(const RgbaImage& mask) {
    requireValidSize(mask.width, mask.height, mask.pixels.size() / 4, "mask image");
    Coverage c{mask.width, mask.height, {}};
    c.values.resize(static_cast<size_t>(mask.width) * mask.height);
    for (size_t k = 0; k < c.values.size(); ++k) {
        const float* p = &mask.pixels[4 * k];
        c.values[k] = (0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2]) * p[3];
    }
    return c;
}

Coverage coverageFromBits(int width, int height, const std::vector<uint8_t>& bits) {
    requireValidSize(width, height, bits.size(), "mask");
    Coverage c{width, height, std::vector<float>(bits.size())};
    for (size_t k = 0; k < bits.size(); ++k) c.values[k] = bits[k] ? 1.f : 0.f;
    return c;
}

void requireMaskMatchesImage(const RgbaImage& image, const RgbaImage& mask,
                             const std::string& maskName) {
    if (image.width != mask.width || image.height != mask.height)
        throw Error("the mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                        " pixels but the image is " + std::to_string(image.width) + "x" +
                        std::to_string(image.height),
                    maskName);
}

std::vector<Region> extractRegions(const Coverage& coverage, const RegionOptions& options) {
    requireValidSize(coverage.width, coverage.height, coverage.values.size(), "mask");
    std::vector<int> cls(coverage.values.size());
    for (size_t k = 0; k < cls.size(); ++k)
        cls[k] = std::isfinite(coverage.values[k]) && coverage.values[k] >= 0.5f ? 1 : -1;
    const int w = coverage.width;
    auto source = [&](int x, int y, bool inComponent) {
        float v = coverage.values[static_cast<size_t>(y) * w + x];
        if (!std::isfinite(v)) v = 0;
        // Other components' pixels are background for this one.
        return inComponent || v < 0.5f ? std::clamp(v, 0.f, 1.f) : 0.f;
    };
    return regionsFromClasses(coverage.width, coverage.height, cls, source, options, "mask");
}

std::vector<Region> extractRegionsFromLabels(int width, int height, const std::vector<int>& labels,
                                             const RegionOptions& options) {
    requireValidSize(width, height, labels.size(), "label map");
    std::vector<int> cls(labels.size());
    for (size_t k = 0; k < cls.size(); ++k) cls[k] = labels[k] < 0 ? -1 : labels[k];
    auto source = [](int, int, bool inComponent) { return inComponent ? 1.f : 0.f; };
    return regionsFromClasses(width, height, cls, source, options, "label map");
}

namespace {
// One separable pass of dilateMask: out(x, y) = any of `in` within `radius` along x (alongX)
// or along y.
std::vector<uint8_t> dilatePass(const std::vector<uint8_t>& in, int w, int h, int radius,
                                bool alongX) {
    std::vector<uint8_t> out(in.size(), 0);
    const int len = alongX ? w : h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int at = alongX ? x : y;
            uint8_t v = 0;
            for (int d = -radius; d <= radius && !v; ++d) {
                const int q = at + d;
                if (q >= 0 && q < len)
                    v = in[alongX ? static_cast<size_t>(y) * w + q : static_cast<size_t>(q) * w + x];
            }
            out[static_cast<size_t>(y) * w + x] = v;
        }
    return out;
}
}  // namespace

std::vector<uint8_t> dilateMask(const std::vector<uint8_t>& mask, int w, int h, int radius) {
    return dilatePass(dilatePass(mask, w, h, radius, true), w, h, radius, false);
}

Region growRegionInto(const Region& own, int overlap, int minHole, const std::vector<uint8_t>& under,
                      double outerLevel) {
    if (overlap <= 0 && minHole <= 0) return own;
    RegionOptions regionOptions;
    regionOptions.minArea = 1;
    regionOptions.minHole = minHole;
    regionOptions.outerLevel = outerLevel;
    std::vector<uint8_t> grown = own.mask;
    if (overlap > 0) {
        const std::vector<uint8_t> d = dilateMask(own.mask, own.width, own.height, overlap);
        for (size_t k = 0; k < grown.size(); ++k) grown[k] = grown[k] || (d[k] && under[k]);
    }
    std::vector<Region> grownRegions =
        extractRegions(coverageFromBits(own.width, own.height, grown), regionOptions);
    if (grownRegions.empty()) throw Error("the grown region vanished");
    Region region =
        std::move(grownRegions.front());  // the largest: grown from one component, it is one
    region.label = own.label;
    region.mask = own.mask;
    region.pixelCount = own.pixelCount;
    return region;
}

std::vector<int> firstRegionAt(const std::vector<Region>& regions) {
    if (regions.empty()) return {};
    std::vector<int> at(regions.front().mask.size(), -1);
    for (size_t k = regions.size(); k-- > 0;)
        for (size_t p = 0; p < at.size(); ++p)
            if (regions[k].mask[p]) at[p] = static_cast<int>(k);
    return at;
}

std::vector<std::set<int>> touchingRegions(const std::vector<Region>& regions) {
    const std::vector<int> at = firstRegionAt(regions);
    const int w = regions.front().width, h = regions.front().height;
    std::vector<std::set<int>> out(regions.size());
    auto link = [&](int a, int b) {
        if (a < 0 || b < 0 || a == b) return;
        out[static_cast<size_t>(a)].insert(b);
        out[static_cast<size_t>(b)].insert(a);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p = static_cast<size_t>(y) * w + x;
            if (x + 1 < w) link(at[p], at[p + 1]);
            if (y + 1 < h) link(at[p], at[p + static_cast<size_t>(w)]);
        }
    return out;
}

PixelBox maskBounds(const std::vector<uint8_t>& mask, int w, int h) {
    PixelBox b{w, h, -1, -1};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (mask[static_cast<size_t>(y) * w + x]) {
                b.x0 = std::min(b.x0, x), b.x1 = std::max(b.x1, x);
                b.y0 = std::min(b.y0, y), b.y1 = std::max(b.y1, y);
            }
    return b.x1 < 0 ? PixelBox{} : b;
}

std::vector<uint8_t> openMask(const std::vector<uint8_t>& mask, int w, int h, int radius) {
    std::vector<uint8_t> inv(mask.size());
    for (size_t k = 0; k < mask.size(); ++k) inv[k] = !mask[k];
    std::vector<uint8_t> eroded = dilateMask(inv, w, h, radius);
    for (auto& v : eroded) v = !v;
    std::vector<uint8_t> out = dilateMask(eroded, w, h, radius);
    for (size_t k = 0; k < out.size(); ++k) out[k] = out[k] && mask[k];
    return out;
}

}  // namespace gm
