// The raster re-renderer (render.h). Each mesh is drawn as a layer over its bounding box, in
// strips of rows:
//  1. alpha = exact area coverage of the outline loops (outer boundary and holes, nonzero
//     winding), so the outline is anti-aliased and every interior pixel is exactly opaque;
//  2. the patches, in order, are cut into micro-triangles (adaptive counts, crack-free) that
//     are rasterised at pixel centres with an exact fill rule, interpolating the local (s,t);
//  3. outline pixels whose centre no triangle covers borrow the nearest covered sample;
//  4. every painted pixel's colour is the patch's bicubic colour evaluated at its (s,t), and
//     the layer is composited over the image (later meshes over earlier ones).
// Strips run on worker threads.
// Consecutive meshes that share a whole grid row (the hole-free pieces an SVG holds for a mesh
// with holes, read back) are drawn as one layer: along their shared rows a pixel takes the
// coverage of their union and the colour of the piece that covers its centre, so that the
// shared edges are not anti-aliased twice (no seam), as for the mesh they were cut from.
#include "meshcore/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <thread>

#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "render_internal.h"

namespace gm {

using namespace render_detail;

namespace {

void checkStructure(const GradientMesh& mesh, size_t index) {
    const int C = mesh.columns(), R = mesh.rows();
    auto fail = [&](const char* what) {
        throw Error(std::string("cannot render: ") + what, {}, "mesh " + std::to_string(index));
    };
    if (C < 1 || R < 1) fail("the mesh has no patches");
    if (mesh.nodes.size() != (static_cast<size_t>(C) + 1) * (static_cast<size_t>(R) + 1))
        fail("node count does not match the grid");
    for (const Slit& s : mesh.slits) {
        if (s.row <= 0 || s.row >= R || s.i0 <= 0 || s.i1 >= C || s.i0 >= s.i1 ||
            s.below.size() != static_cast<size_t>(s.i1 - s.i0 - 1))
            fail("a slit does not fit the grid");
    }
    for (const CornerTangent& t : mesh.tangents)
        if (t.i < 0 || t.i >= C || t.j < 0 || t.j >= R) fail("a tangent break names no patch");
}

struct Target {
    RgbaImage* image;
    std::vector<PixelSample>* samples;  // null unless wanted
    int threads;
    size_t triangles = 0;
};

// A mesh's layer is processed in strips of kStripRows rows (a fixed height, so the result does
// not depend on the thread count). Each strip is rasterised with kHaloRows extra rows above and
// below, so that its outline pixels can borrow samples from just across the strip border.
constexpr int kStripRows = 64;
constexpr int kHaloRows = 2;

// One worker's buffers for a strip and its halo, reused from strip to strip.
struct StripBuffers {
    std::vector<float> alpha;
    std::vector<float> unionAlpha;  // joined pieces: the coverage of the piece and its neighbours
    std::vector<LayerSample> samples;
    std::vector<uint8_t> kinds;
    std::vector<double> accumulator;
    Tessellation tess;
    std::vector<size_t> pending, queue;
    std::vector<std::pair<size_t, size_t>> assign;
};

// Outline pixels (alpha > 0) that no triangle sampled take the sample of the nearest pixel that
// has one: first from a direct neighbour (edge neighbours before diagonal ones, centre samples
// before centroid ones), then by breadth-first growth for the rare pixels further away.
void lendSamples(StripBuffers& B, int W, int H) {
    B.pending.clear();
    const size_t n = static_cast<size_t>(W) * H;
    for (size_t k = 0; k < n; ++k)
        if (B.kinds[k] == kNoSample && B.alpha[k] > 0) B.pending.push_back(k);
    if (B.pending.empty()) return;
    static const int kDx[8] = {-1, 1, 0, 0, -1, 1, -1, 1};
    static const int kDy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    B.assign.clear();
    for (size_t k : B.pending) {
        const int x = static_cast<int>(k % W), y = static_cast<int>(k / W);
        size_t best = 0;
        int bestRank = 1 << 30;
        for (int d = 0; d < 8; ++d) {
            const int xx = x + kDx[d], yy = y + kDy[d];
            if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
            const size_t q = static_cast<size_t>(yy) * W + xx;
            const uint8_t kind = B.kinds[q];
            if (kind != kCentreSample && kind != kNearSample) continue;
            const int rank = (d < 4 ? 0 : 2) + (kind == kCentreSample ? 0 : 1);
            if (rank < bestRank) {
                bestRank = rank;
                best = q;
            }
        }
        if (bestRank < (1 << 30)) B.assign.emplace_back(k, best);
    }
    B.queue.clear();
    for (const auto& [k, src] : B.assign) {
        B.samples[k] = B.samples[src];
        B.kinds[k] = kBorrowedSample;
        B.queue.push_back(k);
    }
    for (size_t head = 0; head < B.queue.size(); ++head) {
        const size_t p = B.queue[head];
        const int x = static_cast<int>(p % W), y = static_cast<int>(p / W);
        for (int d = 0; d < 8; ++d) {
            const int xx = x + kDx[d], yy = y + kDy[d];
            if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
            const size_t q = static_cast<size_t>(yy) * W + xx;
            if (B.kinds[q] == kNoSample && B.alpha[q] > 0) {
                B.samples[q] = B.samples[p];
                B.kinds[q] = kBorrowedSample;
                B.queue.push_back(q);
            }
        }
    }
}

// One mesh drawn as a layer over its bounding box (one pixel of margin, clipped to the image),
// strip by strip, and composited over the target.
class LayerRenderer {
public:
    // `joined`: the neighbouring pieces this mesh shares a grid row with (drawn into the same
    // group layer, `target`, which starts transparent).
    LayerRenderer(const GradientMesh& mesh, int meshIndex, const RenderOptions& options,
                  Target& target, std::vector<const GradientMesh*> joined = {})
        : mesh_(mesh),
          meshIndex_(meshIndex),
          joined_(std::move(joined)),
          options_(options),
          target_(target),
          image_(*target.image) {}

    void run() {
        const int imageW = image_.width, imageH = image_.height;
        if (imageW <= 0 || imageH <= 0) return;
        pm_ = prepareMesh(mesh_, options_, imageW, imageH);
        if (pm_.maxX < pm_.minX) return;  // nothing finite
        if (!placeLayer()) return;
        if (options_.antialias) traceOutline();
        findPatchRows();

        const int strips = (height_ + kStripRows - 1) / kStripRows;
        const int workers = std::max(1, std::min(target_.threads, strips));
        std::vector<StripBuffers> buffers(static_cast<size_t>(workers));
        std::atomic<size_t> triangleCount{0};
        parallelFor(strips, workers, [&](int strip, int worker) {
            triangleCount += renderStrip(strip, buffers[static_cast<size_t>(worker)]);
        });
        target_.triangles += triangleCount.load();
    }

private:
    // The layer: the mesh's bounds with one pixel of margin (anti-aliasing, fixed-point
    // rounding), clipped to the image. False when nothing of it is inside.
    bool placeLayer() {
        const double bx0 = std::max(0.0, std::floor(pm_.minX) - 1);
        const double by0 = std::max(0.0, std::floor(pm_.minY) - 1);
        const double bx1 = std::min<double>(image_.width, std::ceil(pm_.maxX) + 2);
        const double by1 = std::min<double>(image_.height, std::ceil(pm_.maxY) + 2);
        if (!(bx1 > bx0 && by1 > by0)) return false;
        originX_ = static_cast<int>(bx0);
        originY_ = static_cast<int>(by0);
        width_ = static_cast<int>(bx1) - originX_;
        height_ = static_cast<int>(by1) - originY_;
        return true;
    }

    void traceOutline() {
        double tol = options_.positionTolerance;
        if (!(tol > 0) || !std::isfinite(tol)) tol = 0.125;
        // Much finer than the triangles: the outline decides alpha, and a chord 1/256 px off
        // the curve changes a pixel's area by under 1/255.
        const double chord = std::max(std::min(tol, 0.125) / 32, 1e-5);
        loops_ = outlineLoops(mesh_, options_.scale, chord);
        if (joined_.empty()) return;
        // The shared rows' edges appear in both loops with opposite directions and cancel.
        unionLoops_ = loops_;
        for (const GradientMesh* m : joined_)
            for (std::vector<Vec2>& loop : outlineLoops(*m, options_.scale, chord))
                unionLoops_.push_back(std::move(loop));
    }

    bool joined() const { return options_.antialias && !joined_.empty(); }

    // Layer rows each visible patch touches, inclusive.
    void findPatchRows() {
        const int patchCount = static_cast<int>(pm_.patches.size());
        rowLo_.assign(static_cast<size_t>(patchCount), 0);
        rowHi_.assign(rowLo_.size(), 0);
        for (int p = 0; p < patchCount; ++p) {
            const PreparedPatch& P = pm_.patches[static_cast<size_t>(p)];
            if (!P.visible) continue;
            const double lo = std::floor(P.minY) - 1 - originY_,
                         hi = std::ceil(P.maxY) + 1 - originY_;
            rowLo_[p] = static_cast<int>(std::max(0.0, std::min(lo, height_ - 1.0)));
            rowHi_[p] = static_cast<int>(std::max(0.0, std::min(hi, height_ - 1.0)));
        }
    }

    // Rasterises and composites one strip; returns the triangles of the patches it owns (those
    // whose first row lies in it, so that each patch counts once).
    size_t renderStrip(int strip, StripBuffers& B) {
        const int core0 = strip * kStripRows, core1 = std::min(height_, core0 + kStripRows);
        const int ext0 = std::max(0, core0 - kHaloRows),
                  ext1 = std::min(height_, core1 + kHaloRows);
        const int rows = ext1 - ext0;
        const size_t n = static_cast<size_t>(width_) * rows;
        B.alpha.assign(n, 0.0f);
        B.kinds.assign(n, kNoSample);
        if (B.samples.size() < n) B.samples.resize(n);
        LayerRows view;  // buffer row 0 is layer row ext0
        view.originX = originX_;
        view.originY = originY_ + ext0;
        view.width = width_;
        view.y0 = 0;
        view.y1 = rows;

        if (options_.antialias) accumulateCoverage(loops_, view, B.accumulator, B.alpha.data());
        if (joined()) {
            B.unionAlpha.assign(n, 0.0f);
            accumulateCoverage(unionLoops_, view, B.accumulator, B.unionAlpha.data());
        }
        const size_t owned = rasterizePatches(B, view, core0, core1, ext0, ext1);
        if (options_.antialias) {
            lendSamples(B, width_, rows);
        } else {
            for (size_t k = 0; k < n; ++k) B.alpha[k] = B.kinds[k] == kCentreSample ? 1.0f : 0.0f;
        }
        for (int y = core0; y < core1; ++y) compositeRow(B, y, ext0);
        return owned;
    }

    // Every visible patch reaching the strip (halo included), tessellated and rasterised at
    // pixel centres into the strip's samples.
    size_t rasterizePatches(StripBuffers& B, const LayerRows& view, int core0, int core1, int ext0,
                            int ext1) {
        size_t owned = 0;
        const int64_t top = int64_t(view.originY) << kSubpixelBits;
        const int64_t bottom = int64_t(view.originY + (ext1 - ext0)) << kSubpixelBits;
        const int patchCount = static_cast<int>(pm_.patches.size());
        for (int p = 0; p < patchCount; ++p) {
            if (!pm_.patches[static_cast<size_t>(p)].visible) continue;
            if (rowHi_[p] < ext0 || rowLo_[p] >= ext1) continue;
            tessellatePatch(pm_, p, B.tess);
            const TessVertex* v = B.tess.vertices.data();
            const int* tri = B.tess.triangles.data();
            const size_t count = B.tess.triangles.size() / 3;
            for (size_t k = 0; k < count; ++k) {
                const TessVertex &a = v[tri[3 * k]], &b = v[tri[3 * k + 1]], &c = v[tri[3 * k + 2]];
                if (std::max({a.Y, b.Y, c.Y}) < top || std::min({a.Y, b.Y, c.Y}) >= bottom)
                    continue;
                rasterizeTriangle(a, b, c, p, view, B.samples.data(), B.kinds.data());
            }
            if (rowLo_[p] >= core0 && rowLo_[p] < core1) owned += count;
        }
        return owned;
    }

    // Shades one of the strip's own rows and composites it (straight alpha "over"; exact copies
    // where nothing shows through).
    void compositeRow(const StripBuffers& B, int y, int ext0) {
        const size_t rowBase = static_cast<size_t>(y - ext0) * width_;
        const int oy = originY_ + y;
        float* outRow = image_.at(originX_, oy);
        PixelSample* sampleRow =
            target_.samples ? &(*target_.samples)[static_cast<size_t>(oy) * image_.width + originX_]
                            : nullptr;
        for (int x = 0; x < width_; ++x) {
            const size_t k = rowBase + x;
            const uint8_t kind = B.kinds[k];
            if (kind == kNoSample) continue;
            float a = B.alpha[k];
            // A covered centre in a pixel the outline does not touch at all (chords stay within
            // 1/8 px of the outline, so this is no rounding matter) lies where a folded mesh
            // overlaps itself with opposite orientations and the windings cancel; the patches
            // still paint it.
            if (a == 0.0f && kind == kCentreSample) a = 1.0f;
            if (!(a > 0)) continue;
            const LayerSample& S = B.samples[k];
            float* out = outRow + 4 * static_cast<size_t>(x);
            if (joined()) {
                // A piece's pixel: the union's coverage; a centre it does not cover is left to
                // the neighbour that does (or has already lent it a colour).
                if (kind != kCentreSample && out[3] > 0) continue;
                a = B.unionAlpha[k];
                if (!(a > 0)) a = 1.0f;
                out[3] = 0;  // replaces: the group layer holds the pieces side by side
            }
            paintPixel(out, S, a);
            if (sampleRow) recordSample(sampleRow[x], S, kind == kCentreSample, a);
        }
    }

    void paintPixel(float* out, const LayerSample& S, float a) const {
        const PreparedPatch& P = pm_.patches[static_cast<size_t>(S.patch)];
        float col[3];
        P.colour.eval(S.s, S.t, col);
        const float d = out[3];
        if (a >= 1.0f || d <= 0.0f) {
            out[0] = col[0], out[1] = col[1], out[2] = col[2], out[3] = a;
        } else {
            const float under = d * (1 - a), total = a + under;
            for (int c = 0; c < 3; ++c) out[c] = (col[c] * a + out[c] * under) / total;
            out[3] = total;
        }
    }

    // The topmost mesh covering the centre names the pixel; a mesh that only reaches it with
    // its anti-aliased outline does so when nothing below covers the centre or when it hides
    // what is below.
    void recordSample(PixelSample& ps, const LayerSample& S, bool centre, float a) const {
        if (centre || !ps.centre || a >= 1.0f) {
            ps.mesh = meshIndex_;
            ps.patch = S.patch;
            ps.s = S.s;
            ps.t = S.t;
            ps.centre = centre;
        }
    }

    const GradientMesh& mesh_;
    const int meshIndex_;
    const std::vector<const GradientMesh*> joined_;
    const RenderOptions& options_;
    Target& target_;
    RgbaImage& image_;
    PreparedMesh pm_;
    int originX_ = 0, originY_ = 0, width_ = 0, height_ = 0;
    std::vector<std::vector<Vec2>> loops_, unionLoops_;
    std::vector<int> rowLo_, rowHi_;
};

void renderLayer(const GradientMesh& mesh, int meshIndex, const RenderOptions& options,
                 Target& target, std::vector<const GradientMesh*> joined = {}) {
    LayerRenderer(mesh, meshIndex, options, target, std::move(joined)).run();
}

// Whether `lower` continues `upper` below it: as many patch columns, and the two end nodes of
// upper's last grid row are lower's first row's (the rows may differ between them: a slit).
bool sharesRow(const GradientMesh& upper, const GradientMesh& lower) {
    const int C = upper.columns();
    if (C != lower.columns() || upper.rows() < 1 || lower.rows() < 1) return false;
    for (int i : {0, C}) {
        const Vec2 d = upper.node(i, upper.rows()).pos - lower.node(i, 0).pos;
        if (!(std::fabs(d.x) <= 1e-9 && std::fabs(d.y) <= 1e-9)) return false;
    }
    return true;
}

// Straight-alpha "over" of the group layer onto the image.
void compositeOver(const RgbaImage& layer, RgbaImage& image) {
    for (size_t k = 0; k < layer.pixels.size(); k += 4) {
        const float a = layer.pixels[k + 3];
        if (!(a > 0)) continue;
        float* out = &image.pixels[k];
        const float under = out[3] * (1 - a), total = a + under;
        for (int c = 0; c < 3; ++c) out[c] = (layer.pixels[k + c] * a + out[c] * under) / total;
        out[3] = total;
    }
}

// Meshes [first, last] joined by shared rows, drawn into one layer composited over the image.
void renderGroup(const std::vector<const GradientMesh*>& meshes, size_t first, size_t last,
                 const RenderOptions& options, Target& target) {
    RgbaImage layer(target.image->width, target.image->height);
    Target group{&layer, target.samples, target.threads};
    for (size_t m = first; m <= last; ++m) {
        std::vector<const GradientMesh*> joined;
        if (m > first) joined.push_back(meshes[m - 1]);
        if (m < last) joined.push_back(meshes[m + 1]);
        renderLayer(*meshes[m], static_cast<int>(m), options, group, std::move(joined));
    }
    compositeOver(layer, *target.image);
    target.triangles += group.triangles;
}

int outputSide(int canvas, double scale) {
    const double side = std::round(std::max(canvas, 0) * scale);
    if (!(side <= kMaxOutputSide))
        throw Error("render size too large: " + std::to_string(side) + " pixels along a side");
    return static_cast<int>(side);
}

RenderResult renderMeshes(const std::vector<const GradientMesh*>& meshes, int canvasWidth,
                          int canvasHeight, const RenderOptions& options,
                          const std::vector<FlatShape>& shapes = {}) {
    if (!(options.scale > 0) || !std::isfinite(options.scale))
        throw Error("render scale must be a positive number, not " + std::to_string(options.scale));
    for (size_t m = 0; m < meshes.size(); ++m) checkStructure(*meshes[m], m);
    const int W = outputSide(canvasWidth, options.scale);
    const int H = outputSide(canvasHeight, options.scale);
    RenderResult result;
    result.image = RgbaImage(W, H);
    if (options.wantSamples) {
        const size_t n = static_cast<size_t>(W) * H;
        result.samples.reserve(n);
        adviseHugePages(result.samples.data(), n * sizeof(PixelSample));
        result.samples.assign(n, PixelSample{});
    }
    int threads = options.threads;
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    Target target{&result.image, options.wantSamples ? &result.samples : nullptr, threads};
    size_t nextShape = 0;
    auto shapesUpTo = [&](size_t layer) {
        for (; nextShape < shapes.size() && shapes[nextShape].layer <= layer; ++nextShape)
            renderShape(shapes[nextShape], options, result.image, target.samples);
    };
    // Whether a shape is painted between meshes m - 1 and m (shapes are in paint order, and
    // those up to the group's first mesh are painted).
    auto shapeBefore = [&](size_t m) {
        return nextShape < shapes.size() && shapes[nextShape].layer <= m;
    };
    for (size_t m = 0; m < meshes.size();) {
        shapesUpTo(m);
        size_t last = m;
        while (options.antialias && last + 1 < meshes.size() && !shapeBefore(last + 1) &&
               sharesRow(*meshes[last], *meshes[last + 1]))
            ++last;
        if (last == m)
            renderLayer(*meshes[m], static_cast<int>(m), options, target);
        else
            renderGroup(meshes, m, last, options, target);
        m = last + 1;
    }
    shapesUpTo(SIZE_MAX);
    result.triangles = target.triangles;
    return result;
}

}  // namespace

RenderResult renderDocument(const Document& doc, const RenderOptions& options) {
    std::vector<const GradientMesh*> meshes;
    for (const GradientMesh& m : doc.meshes) meshes.push_back(&m);
    return renderMeshes(meshes, doc.width, doc.height, options, doc.shapes);
}

RenderResult renderMesh(const GradientMesh& mesh, int canvasWidth, int canvasHeight,
                        const RenderOptions& options) {
    return renderMeshes({&mesh}, canvasWidth, canvasHeight, options);
}

}  // namespace gm
