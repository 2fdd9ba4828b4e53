#include "converters/triangulate.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <deque>
#include <set>
#include <functional>
#include <string>
#include <utility>

#include "meshcore/error.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
    int nesting = -1;  // constraint crossings from the infinite face; odd means in the region
};
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Loops are simple and disjoint, so any intersection is a bug upstream: let CGAL report it
// instead of silently splitting a constraint.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
using CdtPoint = Cdt::Point;

bool inDomain(Cdt::Face_handle f) { return f->info().nesting % 2 == 1; }

// Nesting levels by breadth-first search from the infinite face, one level per constraint
// crossed (the way CGAL's polygon-with-holes example marks its domain).
void markDomain(Cdt& cdt) {
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting = -1;
    std::deque<std::pair<Cdt::Face_handle, int>> border = {{cdt.infinite_face(), 0}};
    std::deque<Cdt::Face_handle> queue;
    while (!border.empty()) {
        const auto [start, level] = border.front();
        border.pop_front();
        if (start->info().nesting != -1) continue;
        start->info().nesting = level;
        queue.push_back(start);
        while (!queue.empty()) {
            const Cdt::Face_handle f = queue.front();
            queue.pop_front();
            for (int i = 0; i < 3; ++i) {
                const Cdt::Face_handle g = f->neighbor(i);
                if (g->info().nesting != -1) continue;
                if (cdt.is_constrained(Cdt::Edge(f, i))) {
                    border.push_back({g, level + 1});
                } else {
                    g->info().nesting = level;
                    queue.push_back(g);
                }
            }
        }
    }
}

// Appends loop `src` to `out`, splitting edges longer than `spacing` evenly; returns the output
// position of each source point.
std::vector<int> appendResampledLoop(const std::vector<Vec2>& src, int start, double spacing,
                                     std::vector<Vec2>& out) {
    const int n = static_cast<int>(src.size());
    std::vector<int> position(n);
    for (int s = 0; s < n; ++s) {
        const int k = (start + s) % n;
        const Vec2 a = src[k], b = src[(k + 1) % n];
        position[k] = static_cast<int>(out.size());
        out.push_back(a);
        const int pieces = static_cast<int>(std::ceil(norm(b - a) / spacing));
        for (int q = 1; q < pieces; ++q) out.push_back(a + (static_cast<double>(q) / pieces) * (b - a));
    }
    return position;
}

// Error diffusion over the pixels of `allowed` (a subset of the region's mask).
std::vector<Vec2> diffuseSamples(const Region& region, const std::vector<uint8_t>& allowed,
                                 const std::vector<float>& saliency,
                                 const TriangulateOptions& options) {
    const int w = region.width, h = region.height;
    assert(saliency.size() == allowed.size());
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    double salSum = 0;
    int count = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (!allowed[k]) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
            salSum += saliency[k];
            ++count;
        }
    std::vector<Vec2> samples;
    if (count == 0 || options.sampleFraction <= 0) return samples;
    const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
    auto inRegion = [&](int i, int j) {
        return i >= 0 && j >= 0 && i < bw && j < bh &&
               allowed[static_cast<size_t>(j + y0) * w + i + x0];
    };
    // Density per pixel, at most one sample per pixel: scale, cap at 1, rescale the rest.
    const double salMean = salSum / count;
    std::vector<double> density(static_cast<size_t>(bw) * bh, 0.0);
    for (int j = 0; j < bh; ++j)
        for (int i = 0; i < bw; ++i)
            if (inRegion(i, j)) {
                const double s = saliency[static_cast<size_t>(j + y0) * w + i + x0];
                const double relative = salMean > 0 ? std::min(s / salMean, options.saliencyCap) : 0;
                density[j * bw + i] = 1 + options.saliencyWeight * relative;
            }
    const double target = std::min(1.0, options.sampleFraction) * count;
    double weightSum = 0;
    for (double d : density) weightSum += d;
    for (double& d : density) d *= target / weightSum;
    for (int pass = 0; pass < 8; ++pass) {
        double capped = 0, free = 0;
        for (double d : density)
            if (d >= 1) capped += 1;
            else free += d;
        if (free <= 0 || capped + free <= target * (1 + 1e-9)) break;
        const double scale = (target - capped) / free;
        for (double& d : density)
            if (d < 1) d = std::min(1.0, d * scale);
    }
    // Error diffusion is biased along any border it meets: no error arrives at the upstream side
    // (a gap) and error stopped at the downstream side piles samples up. So the diffusion runs
    // over the bounding box grown by a margin, outside pixels at the mean density as if the
    // region went on, and only samples on allowed pixels are kept: the region's outline is then
    // no border to the diffusion.
    const int pad = static_cast<int>(std::ceil(2 / std::sqrt(std::max(options.sampleFraction, 1e-6))));
    const int pw = bw + 2 * pad, ph = bh + 2 * pad;
    std::vector<double> field(static_cast<size_t>(pw) * ph, target / count);
    for (int j = 0; j < bh; ++j)
        for (int i = 0; i < bw; ++i)
            if (inRegion(i, j)) field[(j + pad) * pw + i + pad] = density[j * bw + i];
    static const int jjn[12][3] = {{1, 0, 7}, {2, 0, 5},  {-2, 1, 3}, {-1, 1, 5},
                                   {0, 1, 7}, {1, 1, 5},  {2, 1, 3},  {-2, 2, 1},
                                   {-1, 2, 3}, {0, 2, 5}, {1, 2, 3},  {2, 2, 1}};
    for (int j = 0; j < ph; ++j) {
        const bool forward = j % 2 == 0;  // serpentine
        for (int step = 0; step < pw; ++step) {
            const int i = forward ? step : pw - 1 - step;
            const double v = field[j * pw + i];
            const bool sample = v >= 0.5;
            const double err = sample ? v - 1 : v;
            if (sample && inRegion(i - pad, j - pad))
                samples.push_back({x0 + i - pad + 0.5, y0 + j - pad + 0.5});
            for (const auto& t : jjn) {
                const int ti = forward ? i + t[0] : i - t[0], tj = j + t[1];
                if (ti >= 0 && ti < pw && tj < ph) field[tj * pw + ti] += err * t[2] / 48;
            }
        }
    }
    return samples;
}

}  // namespace

std::vector<float> compassSaliency(const RgbaImage& image, const Region& region) {
    const int w = region.width, h = region.height;
    if (image.width != w || image.height != h)
        throw Error("the image is " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + " pixels but the region's mask is " +
                    std::to_string(w) + "x" + std::to_string(h));
    // The four compass directions 0°, 45°, 90°, 135° (the other four are their negatives).
    static const int kernels[4][9] = {{-1, 0, 1, -2, 0, 2, -1, 0, 1},
                                      {-2, -1, 0, -1, 0, 1, 0, 1, 2},
                                      {-1, -2, -1, 0, 0, 0, 1, 2, 1},
                                      {0, -1, -2, 1, 0, -1, 2, 1, 0}};
    std::vector<float> sal(static_cast<size_t>(w) * h, 0.f);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (!region.mask[k]) continue;
            const float* centre = image.at(x, y);
            const float* nb[9];
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    const bool ok = nx >= 0 && ny >= 0 && nx < w && ny < h &&
                                    region.mask[static_cast<size_t>(ny) * w + nx];
                    nb[(dy + 1) * 3 + dx + 1] = ok ? image.at(nx, ny) : centre;
                }
            float best = 0;
            for (const auto& kern : kernels) {
                float len2 = 0;
                for (int c = 0; c < 3; ++c) {
                    float r = 0;
                    for (int q = 0; q < 9; ++q) r += kern[q] * nb[q][c];
                    len2 += r * r;
                }
                best = std::max(best, len2);
            }
            sal[k] = std::isfinite(best) ? std::sqrt(best) : 0.f;
        }
    }
    return sal;
}

std::vector<Vec2> placeSamples(const Region& region, const std::vector<float>& saliency,
                               const TriangulateOptions& options) {
    return diffuseSamples(region, region.mask, saliency, options);
}

namespace {

// The pixels of the region whose centres are at least `clearance` from every loop edge (found
// through a grid of the edges' widened bounding boxes): samples go only there.
std::vector<uint8_t> pixelsClearOfLoops(const Region& region, const TriMesh& mesh,
                                        const std::vector<Vec2>& pts, int outerCount, int loopCount,
                                        double clearance) {
    double minX = pts[0].x, minY = pts[0].y, maxX = minX, maxY = minY;
    for (int k = 0; k < loopCount; ++k) {
        minX = std::min(minX, pts[k].x), maxX = std::max(maxX, pts[k].x);
        minY = std::min(minY, pts[k].y), maxY = std::max(maxY, pts[k].y);
    }
    const double cell = std::max(2.0, 2 * clearance);
    const int gw = static_cast<int>((maxX - minX) / cell) + 1;
    const int gh = static_cast<int>((maxY - minY) / cell) + 1;
    std::vector<std::vector<std::pair<int, int>>> grid(static_cast<size_t>(gw) * gh);
    auto addLoop = [&](int first, int size) {
        for (int k = 0; k < size; ++k) {
            const int a = first + k, b = first + (k + 1) % size;
            const int cx0 = std::max(
                0, static_cast<int>((std::min(pts[a].x, pts[b].x) - clearance - minX) / cell));
            const int cx1 = std::min(
                gw - 1, static_cast<int>((std::max(pts[a].x, pts[b].x) + clearance - minX) / cell));
            const int cy0 = std::max(
                0, static_cast<int>((std::min(pts[a].y, pts[b].y) - clearance - minY) / cell));
            const int cy1 = std::min(
                gh - 1, static_cast<int>((std::max(pts[a].y, pts[b].y) + clearance - minY) / cell));
            for (int cy = cy0; cy <= cy1; ++cy)
                for (int cx = cx0; cx <= cx1; ++cx) grid[cy * gw + cx].push_back({a, b});
        }
    };
    addLoop(0, outerCount);
    for (const auto& loop : mesh.holeLoops) addLoop(loop.front(), static_cast<int>(loop.size()));
    auto isClear = [&](Vec2 s) {
        const int cx = static_cast<int>((s.x - minX) / cell),
                  cy = static_cast<int>((s.y - minY) / cell);
        if (cx < 0 || cy < 0 || cx >= gw || cy >= gh) return false;
        for (const auto& [a, b] : grid[cy * gw + cx])
            if (pointSegmentDistance(s, pts[a], pts[b]) < clearance) return false;
        return true;
    };
    std::vector<uint8_t> allowed = region.mask;
    for (int y = 0; y < region.height; ++y)
        for (int x = 0; x < region.width; ++x) {
            uint8_t& a = allowed[static_cast<size_t>(y) * region.width + x];
            if (a && !isClear({x + 0.5, y + 0.5})) a = 0;
        }
    return allowed;
}

// The constrained Delaunay triangulation of a region: its loops resampled, saliency-placed
// samples inside, Steiner points where a triangle would map to zero area.
class RegionTriangulator {
public:
    RegionTriangulator(const Region& region, const RegionCorners& corners,
                       const TriangulateOptions& options, TriangulateStats* stats)
        : region_(region), corners_(corners), options_(options), stats_(stats) {}

    TriMesh run(const std::vector<float>& saliency) {
        const double spacing = 1 / std::sqrt(std::clamp(options_.sampleFraction, 1e-6, 1.0));
        const double clearance = std::max(0.5, options_.boundaryClearance * spacing);
        appendLoops(spacing);
        const std::vector<uint8_t> allowed =
            pixelsClearOfLoops(region_, mesh_, pts_, outerCount_, loopCount_, clearance);
        placed_ = diffuseSamples(region_, allowed, saliency, options_);
        for (const Vec2 s : placed_) pts_.push_back(s);
        if (stats_) {
            stats_->samplesPlaced = static_cast<int>(placed_.size());
            stats_->loopVertices = loopCount_;
            stats_->steinerPoints = 0;
        }
        markSidesAndHoles();
        insertPointsAndLoops();
        markDomain(cdt_);
        splitDegenerateFaces();
        collectDomain();
        return std::move(mesh_);
    }

private:
    // Points: the outer loop from the top-left corner, then the hole loops.
    void appendLoops(double spacing) {
        const std::vector<int> outerPos =
            appendResampledLoop(region_.outer.points, corners_.index[0], spacing, pts_);
        outerCount_ = static_cast<int>(pts_.size());
        mesh_.outerLoop.resize(outerCount_);
        for (int k = 0; k < outerCount_; ++k) mesh_.outerLoop[k] = k;
        for (int c = 0; c < 4; ++c) mesh_.corner[c] = outerPos[corners_.index[c]];
        for (const Polygon& hole : region_.holes) {
            const int first = static_cast<int>(pts_.size());
            appendResampledLoop(hole.points, 0, spacing, pts_);
            std::vector<int> loop;
            for (int k = first; k < static_cast<int>(pts_.size()); ++k) loop.push_back(k);
            mesh_.holeLoops.push_back(std::move(loop));
        }
        loopCount_ = static_cast<int>(pts_.size());
    }

    // Which rectangle sides (bit k: side k, from corner k to corner k+1) and which hole each
    // vertex lies on.
    void markSidesAndHoles() {
        sides_.assign(pts_.size(), 0);
        holeOf_.assign(pts_.size(), -1);
        for (int c = 0; c < 4; ++c) {
            const int from = mesh_.corner[c], to = c == 3 ? outerCount_ : mesh_.corner[c + 1];
            for (int k = from; k <= to; ++k)
                sides_[k % outerCount_] |= static_cast<uint8_t>(1u << c);
        }
        for (size_t hIdx = 0; hIdx < mesh_.holeLoops.size(); ++hIdx)
            for (int v : mesh_.holeLoops[hIdx]) holeOf_[v] = static_cast<int>(hIdx);
    }

    void insertPointsAndLoops() {
        handle_.resize(pts_.size());
        std::vector<std::pair<CdtPoint, int>> input;
        input.reserve(pts_.size());
        for (size_t k = 0; k < pts_.size(); ++k)
            input.push_back({CdtPoint(pts_[k].x, pts_[k].y), static_cast<int>(k)});
        cdt_.insert(input.begin(), input.end());
        for (auto v = cdt_.finite_vertices_begin(); v != cdt_.finite_vertices_end(); ++v)
            handle_[v->info()] = v;
        for (int k = 0; k < loopCount_; ++k)
            if (handle_[k] == Cdt::Vertex_handle() || handle_[k]->info() != k)
                throw Error("the region's loops repeat the point (" + std::to_string(pts_[k].x) +
                            ", " + std::to_string(pts_[k].y) + ")");
        try {
            for (int k = 0; k < outerCount_; ++k)
                cdt_.insert_constraint(handle_[k], handle_[(k + 1) % outerCount_]);
            for (const auto& loop : mesh_.holeLoops)
                for (size_t k = 0; k < loop.size(); ++k)
                    cdt_.insert_constraint(handle_[loop[k]], handle_[loop[(k + 1) % loop.size()]]);
        } catch (const Cdt::Intersection_of_constraints_exception&) {
            throw Error("the region's outline crosses itself or a hole");
        }
    }

    bool shareSideOrHole(int a, int b) const {
        return (sides_[a] & sides_[b]) != 0 || (holeOf_[a] >= 0 && holeOf_[a] == holeOf_[b]);
    }

    // Centroids of domain faces with all three vertices on one side or one hole, and midpoints
    // of unconstrained edges between two vertices of one side or hole.
    std::vector<Vec2> degeneratePoints() const {
        std::vector<Vec2> steiner;
        std::set<std::pair<int, int>> splitEdges;  // by vertex ids: the same on every run
        for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f) {
            if (!inDomain(f)) continue;
            const int a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
            const bool sameSide = (sides_[a] & sides_[b] & sides_[c]) != 0;
            const bool sameHole =
                holeOf_[a] >= 0 && holeOf_[a] == holeOf_[b] && holeOf_[a] == holeOf_[c];
            if (sameSide || sameHole) {
                steiner.push_back((1.0 / 3) * (pts_[a] + pts_[b] + pts_[c]));
                continue;
            }
            for (int i = 0; i < 3; ++i) {
                if (cdt_.is_constrained(Cdt::Edge(f, i))) continue;
                const int u = f->vertex(Cdt::ccw(i))->info(), v = f->vertex(Cdt::cw(i))->info();
                // Each edge once (not by face address: that would differ from run to run).
                if (shareSideOrHole(u, v) && splitEdges.insert({std::min(u, v), std::max(u, v)}).second)
                    steiner.push_back(0.5 * (pts_[u] + pts_[v]));
            }
        }
        return steiner;
    }

    // Split whatever would map to zero area, until nothing is left to split. Each Steiner point
    // replaces only faces in its conflict zone by faces that have it as a vertex, so every round
    // removes the offending faces and edges without creating new ones.
    void splitDegenerateFaces() {
        for (int round = 0; round < 100; ++round) {
            const std::vector<Vec2> steiner = degeneratePoints();
            if (steiner.empty()) break;
            for (const Vec2 s : steiner) {
                const auto before = cdt_.number_of_vertices();
                const auto v = cdt_.insert(CdtPoint(s.x, s.y));
                if (cdt_.number_of_vertices() > before) {
                    v->info() = static_cast<int>(pts_.size());
                    pts_.push_back(s);
                    sides_.push_back(0);
                    holeOf_.push_back(-1);
                    handle_.push_back(v);
                }
            }
            if (stats_) stats_->steinerPoints += static_cast<int>(steiner.size());
            markDomain(cdt_);
        }
    }

    // Output: vertices of domain faces, loops first and in order (they all bound a domain face).
    void collectDomain() {
        std::vector<int> newIndex(pts_.size(), -1);
        for (int k = 0; k < loopCount_; ++k) newIndex[k] = k;
        mesh_.vertices.assign(pts_.begin(), pts_.begin() + loopCount_);
        for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f) {
            if (!inDomain(f)) continue;
            std::array<int, 3> tri{};
            for (int i = 0; i < 3; ++i) {
                const int old = f->vertex(i)->info();
                if (newIndex[old] < 0) {
                    newIndex[old] = static_cast<int>(mesh_.vertices.size());
                    mesh_.vertices.push_back(pts_[old]);
                }
                tri[i] = newIndex[old];
            }
            mesh_.triangles.push_back(tri);  // CGAL faces are counterclockwise: positive area here
        }
        if (stats_) {
            stats_->samplesKept = 0;
            for (size_t k = loopCount_; k < loopCount_ + placed_.size(); ++k)
                stats_->samplesKept += newIndex[k] >= 0;
        }
    }

    const Region& region_;
    const RegionCorners& corners_;
    const TriangulateOptions& options_;
    TriangulateStats* stats_;
    TriMesh mesh_;
    std::vector<Vec2> pts_;
    int outerCount_ = 0, loopCount_ = 0;
    std::vector<Vec2> placed_;
    std::vector<uint8_t> sides_;
    std::vector<int> holeOf_;
    Cdt cdt_;
    std::vector<Cdt::Vertex_handle> handle_;
};

}  // namespace

TriMesh triangulateRegion(const RgbaImage& image, const Region& region,
                          const RegionCorners& corners, const TriangulateOptions& options,
                          TriangulateStats* stats) {
    const std::vector<float> saliency = compassSaliency(image, region);
    const int nOuter = static_cast<int>(region.outer.points.size());
    for (int c = 0; c < 4; ++c)
        if (corners.index[c] < 0 || corners.index[c] >= nOuter)
            throw Error("corner " + std::to_string(c) + " is not a point of the outer loop");
    return RegionTriangulator(region, corners, options, stats).run(saliency);
}

}  // namespace gm
