#include "converters/convert_image.h"

#include <array>
#include <chrono>
#include <algorithm>
#include <cmath>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

#include "converters/boundary.h"
#include "converters/corners.h"
#include "converters/feature_map.h"
#include "converters/grid.h"
#include "converters/regions.h"
#include "converters/topology_map.h"
#include "converters/triangulate.h"
#include "meshcore/error.h"
#include "meshcore/render.h"
#include "meshcore/validate.h"

namespace gm {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// E, RMSE, PSNR, max and uncovered fraction of a rendered document over the mask's pixels.
FitError measure(const Document& doc, const RgbaImage& image, const ObjectMask& mask) {
    return compareOverMask(image, renderDocument(doc, RenderOptions{}).image, mask.mask);
}
}  // namespace

std::string regionLabel(const Region& region) {
    const Vec2 at = region.outer.points.empty() ? Vec2{} : region.outer.points.front();
    return "(" + std::to_string(region.pixelCount) + " px, " + std::to_string(region.holes.size()) +
           " holes, outline from (" + std::to_string(static_cast<int>(at.x)) + ", " +
           std::to_string(static_cast<int>(at.y)) + "))";
}

namespace {
// The budget-independent stages for one choice of corners (kept by RegionMapCache).
struct RegionMaps {
    std::array<int, 4> corners{};
    TriMesh tri;
    TopologyMap topo;
    FeatureMap feature;
};

// Everything up to the grid whose boundary follows the outline, for one choice of corners.
struct RegionGeometry {
    RegionCorners corners;
    std::shared_ptr<const RegionMaps> maps;  // the grid builder refers to its triangulation
    std::unique_ptr<GridBuilder> grid;
    GridOptions go;
    BoundaryFitResult fitted;
    int foldedPatches = 0;        // of the boundary-fitted grid
    bool featureMapUsed = true;   // false: the grid follows the topology map
    StageSeconds seconds;
};

// The boundary-fitted grid's sides refitted one-sided (GridOptions::outlineCover), so that its
// curves go round the tips of a jagged outline instead of cutting them (the pixels there were
// left uncovered), while no side strays farther from the outline than the plain fit's worst
// edge already does (or than the outline tolerance): the knots stay those of the plain fit, and
// the outline deviation reported is measured on the refitted grid.
void coverOutline(const GridBuilder& grid, GridOptions& go, BoundaryFitResult& fitted, double cover,
                  double tolerance) {
    if (cover < 0) return;
    go.outlineCover = cover;
    go.outlineSlack = std::max(tolerance, fitted.maxDeviation);
    fitted.maxDeviation = outlineDeviation(grid, grid.build(go));
}

}  // namespace

struct RegionMapCache::Impl {
    std::mutex mutex;
    std::vector<std::shared_ptr<const RegionMaps>> maps;

    std::shared_ptr<const RegionMaps> find(const std::array<int, 4>& corners) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& m : maps)
            if (m->corners == corners) return m;
        return nullptr;
    }
    void keep(std::shared_ptr<const RegionMaps> m) {
        std::lock_guard<std::mutex> lock(mutex);
        maps.push_back(std::move(m));
    }
};
RegionMapCache::RegionMapCache() : impl_(std::make_unique<Impl>()) {}
RegionMapCache::~RegionMapCache() = default;

namespace {
std::unique_ptr<RegionGeometry> buildGeometry(const RgbaImage& image, const Region& region,
                                              const ConvertOptions& options,
                                              const RegionCorners& corners,
                                              RegionMapCache* cache) {
    auto g = std::make_unique<RegionGeometry>();
    g->corners = corners;
    g->maps = cache ? cache->impl().find(corners.index) : nullptr;
    if (!g->maps) {
        auto maps = std::make_shared<RegionMaps>();
        maps->corners = corners.index;
        TriangulateOptions to;
        // Large regions get at most maxSamples samples: the maps' solves grow with them, and a
        // 4096² object needs no finer triangulation than a 1024² one.
        to.sampleFraction = std::min(options.sampleFraction,
                                     double(options.maxSamples) / std::max(1, region.pixelCount));
        auto t0 = Clock::now();
        maps->tri = triangulateRegion(image, region, corners, to);
        g->seconds.triangulate = since(t0);
        t0 = Clock::now();
        maps->topo = buildTopologyMapRefining(maps->tri, corners.px, corners.py);
        g->seconds.topology = since(t0);

        t0 = Clock::now();
        FeatureMapOptions fo;
        fo.mask = &region.mask;  // the outline against the background is not a feature
        maps->feature = buildFeatureMap(maps->tri, maps->topo.map, image, fo);
        g->seconds.feature = since(t0);
        if (const int flips = countFlippedTriangles(maps->tri, maps->feature.map); flips != 0)
            throw Error("the parameterisation folded " + std::to_string(flips) + " triangles");
        g->maps = std::move(maps);
        if (cache) cache->impl().keep(g->maps);
    }
    const RegionMaps& maps = *g->maps;

    auto t0 = Clock::now();
    // The initial grid takes at most a quarter of the patch budget: the rest is for the
    // outline and the colours.
    GridOptions base;
    base.targetPatchSize =
        std::max(options.targetPatchSize,
                 std::sqrt(corners.px * corners.py / std::max(1.0, options.maxPatches / 4.0)));
    for (const SlitInfo& slit : maps.topo.slits) base.slits.push_back({slit.v, slit.u0, slit.u1});
    BoundaryFitOptions bf;
    bf.maxPatches = options.maxPatches;
    bf.tolerance = options.outlineTolerance;
    bf.holeTolerance = options.holeTolerance;
    struct Candidate {
        std::unique_ptr<GridBuilder> grid;
        GridOptions go;
        BoundaryFitResult fitted;
        int folded = 0;
    };
    auto candidate = [&](const ParamMap& map) {
        Candidate c{std::make_unique<GridBuilder>(maps.tri, map), base, {}, 0};
        c.fitted = fitBoundary(*c.grid, c.go, bf);
        coverOutline(*c.grid, c.go, c.fitted, options.outlineCover, options.outlineTolerance);
        c.folded = countFoldedPatches(c.grid->build(c.go));
        return c;
    };
    // Stretch minimisation can bend the iso-curves more than cubic patches between the knots
    // follow (thin limbs of a silhouette): their patches fold. The topology map's iso-curves are
    // smoother; its grid is kept when it folds less. It is needed only when the feature map's
    // grid folds, so it is built beside that one when a core is free (object mode), after it
    // otherwise (regions converted in parallel).
    std::future<Candidate> topology;
    if (options.threads != 1 && std::thread::hardware_concurrency() > 1)
        topology = std::async(std::launch::async, candidate, std::cref(maps.topo.map));
    Candidate best = candidate(maps.feature.map);
    if (best.folded > 0) {
        Candidate other = topology.valid() ? topology.get() : candidate(maps.topo.map);
        if (other.folded < best.folded) {
            best = std::move(other);
            g->featureMapUsed = false;
        }
    }
    g->grid = std::move(best.grid);
    g->go = std::move(best.go);
    g->fitted = best.fitted;
    g->foldedPatches = best.folded;
    g->seconds.mesh = since(t0);
    return g;
}
}  // namespace

GradientMesh convertRegion(const RgbaImage& image, const Region& region,
                           const ConvertOptions& options, RegionReport& rr,
                           RegionMapCache* cache) {
    rr = RegionReport{};
    rr.pixels = region.pixelCount;
    rr.holes = static_cast<int>(region.holes.size());
    auto t0 = Clock::now();
    const RegionCorners first = findCorners(region);
    rr.seconds.corners = since(t0);

    // Corners at the region's sharpest tips are the second choice: when the first squeezes a
    // thin part (thin parts should end at corners), or when the patch budget runs out before
    // the boundary follows the outline (tails and fins between two corners need many knots).
    std::unique_ptr<RegionGeometry> g;
    try {
        g = buildGeometry(image, region, options, first, cache);
    } catch (const SqueezeError&) {
        t0 = Clock::now();
        const RegionCorners tips = findTipCorners(region);
        rr.seconds.corners += since(t0);
        if (tips.index == first.index) throw;
        g = buildGeometry(image, region, options, tips, cache);
        rr.tipCorners = true;
    }
    rr.seconds += g->seconds;
    if (!rr.tipCorners && g->fitted.maxDeviation > options.retryDeviation &&
        region.pixelCount <= options.retryMaxPixels) {
        t0 = Clock::now();
        const RegionCorners tips = findTipCorners(region);
        rr.seconds.corners += since(t0);
        if (tips.index != first.index) {
            try {
                std::unique_ptr<RegionGeometry> other =
                    buildGeometry(image, region, options, tips, cache);
                rr.seconds += other->seconds;  // both attempts count
                if (other->fitted.maxDeviation < g->fitted.maxDeviation) {
                    g = std::move(other);
                    rr.tipCorners = true;
                }
            } catch (const MapError&) {
                // The tips do not map: keep the first geometry.
            }
        }
    }
    rr.triangles = static_cast<int>(g->maps->tri.triangles.size());
    rr.vertices = static_cast<int>(g->maps->tri.vertices.size());
    rr.mapRefinedVertices = g->maps->topo.stats.refinedVertices;
    rr.featureSolves = g->maps->feature.solves;
    rr.flippedTriangles = 0;
    rr.outlineDeviation = g->fitted.maxDeviation;
    rr.outlineKnots = g->fitted.addedU + g->fitted.addedV;
    rr.featureMapUsed = g->featureMapUsed;

    t0 = Clock::now();
    RefineOptions rf;
    rf.maxError = options.maxError;
    rf.maxPatches = options.maxPatches;
    rf.color.mode = options.colors;
    rf.color.threads = options.threads;
    RefineResult refined = refineMesh(*g->grid, g->go, image, region, rf);
    rr.seconds.mesh += since(t0);

    rr.columns = refined.mesh.columns();
    rr.rows = refined.mesh.rows();
    rr.patches = refined.mesh.patchCount();
    rr.error = refined.error;
    rr.refinement = refined.steps;
    rr.foldedPatches = countFoldedPatches(refined.mesh);
    return std::move(refined.mesh);
}

namespace {
// Some meshes rendered alone on a canvas of the image's size.
RgbaImage renderMeshes(const std::vector<GradientMesh>& meshes, int width, int height) {
    Document d;
    d.width = width;
    d.height = height;
    d.meshes = meshes;
    return renderDocument(d, RenderOptions{}).image;
}

// E and uncovered fraction of some meshes over the region's pixels (one render).
FitError measureMeshes(const std::vector<GradientMesh>& meshes, const RgbaImage& image,
                       const Region& region) {
    return compareOverMask(image, renderMeshes(meshes, image.width, image.height), region.mask);
}

// The region's hole pixels (background not 4-connected to the image border, as regions.cpp
// finds holes) and how many of them `meshes` paint (alpha ≥ 0.5). One render, only for regions
// with holes.
void measureHoles(const std::vector<GradientMesh>& meshes, const Region& region, RegionReport& rr) {
    rr.holePixels = rr.holePixelsPainted = 0;
    if (region.holes.empty()) return;
    const int w = region.width, h = region.height;
    std::vector<uint8_t> outside(region.mask.size(), 0);
    std::vector<size_t> stack;
    auto push = [&](int x, int y) {
        const size_t k = static_cast<size_t>(y) * w + x;
        if (!region.mask[k] && !outside[k]) {
            outside[k] = 1;
            stack.push_back(k);
        }
    };
    for (int x = 0; x < w; ++x) push(x, 0), push(x, h - 1);
    for (int y = 0; y < h; ++y) push(0, y), push(w - 1, y);
    while (!stack.empty()) {
        const size_t k = stack.back();
        stack.pop_back();
        const int x = static_cast<int>(k % w), y = static_cast<int>(k / w);
        if (x > 0) push(x - 1, y);
        if (x + 1 < w) push(x + 1, y);
        if (y > 0) push(x, y - 1);
        if (y + 1 < h) push(x, y + 1);
    }
    const RgbaImage render = renderMeshes(meshes, w, h);
    for (size_t k = 0; k < outside.size(); ++k) {
        if (region.mask[k] || outside[k]) continue;
        ++rr.holePixels;
        if (render.pixels[k * 4 + 3] >= 0.5f) ++rr.holePixelsPainted;
    }
}

// The last resort for a piece that no map handles, not even in parts (a network of thin
// leaves, a thin ring with branches): cut across the longer side of its bounding box, each
// 8-connected component of each half its own mesh reaching a pixel under the rest of the
// piece; a component that fails too is cut again, up to kMaxTileDepth times. Components under
// 16 px are left to their neighbours' overlap; what still fails is reported as left uncovered.
// Meshes and reports are appended, `part` saying "tile".
constexpr int kMaxTileDepth = 6;
void convertInTiles(const RgbaImage& image, const Region& piece, const ConvertOptions& options,
                    const PartsBeneath& beneath, std::vector<GradientMesh>& meshes,
                    std::vector<RegionReport>& reports, const std::string& reason, int depth = 0) {
    const int w = piece.width, h = piece.height;
    const PixelBox box = maskBounds(piece.mask, w, h);
    const int x0 = box.x0, y0 = box.y0, x1 = box.x1, y1 = box.y1;
    auto leftUncovered = [&](int pixels, const std::string& why) {
        RegionReport pr;
        pr.pixels = pixels;
        pr.part = "tile left uncovered: " + why;
        reports.push_back(pr);
    };
    if (box.empty()) return;
    if (depth >= kMaxTileDepth || (x1 == x0 && y1 == y0)) {
        leftUncovered(piece.pixelCount, reason);
        return;
    }
    const bool cutX = x1 - x0 >= y1 - y0;
    const int cut = cutX ? (x0 + x1 + 1) / 2 : (y0 + y1 + 1) / 2;  // first column/row of half 2
    RegionOptions ro;
    ro.minArea = 16;
    ro.minHole = options.minHole;
    ro.outerLevel = options.outerLevel;
    for (int half = 0; half < 2; ++half) {
        std::vector<uint8_t> bits(piece.mask.size(), 0);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const size_t k = static_cast<size_t>(y) * w + x;
                const bool second = (cutX ? x : y) >= cut;
                bits[k] = piece.mask[k] && second == (half == 1);
            }
        std::vector<Region> comps;
        try {
            comps = extractRegions(coverageFromBits(w, h, bits), ro);
        } catch (const Error&) {
            continue;  // nothing in this half, or only specks under 16 px
        }
        for (const Region& comp : comps) {
            std::vector<uint8_t> rest(piece.mask.size());
            for (size_t k = 0; k < rest.size(); ++k)
                rest[k] = (piece.mask[k] && !comp.mask[k]) || beneath.at(k);
            RegionReport rr;
            try {
                meshes.push_back(convertRegion(image,
                                               growRegionInto(comp, beneath.reach(), beneath.minHole,
                                                              rest, options.outerLevel),
                                               options, rr));
                rr.part = "tile";
                reports.push_back(rr);
            } catch (const MapError& e) {
                convertInTiles(image, comp, options, beneath, meshes, reports, e.reason(),
                               depth + 1);
            } catch (const Error& e) {
                leftUncovered(comp.pixelCount, e.reason());
            }
        }
    }
}

}  // namespace

void convertThinParts(const RgbaImage& image, const std::vector<uint8_t>& rest,
                      const ConvertOptions& options, const PartsBeneath& beneath,
                      std::vector<GradientMesh>& meshes, std::vector<RegionReport>& reports,
                      int depth) {
    RegionOptions ro;
    ro.minArea = 16;
    ro.minHole = options.minHole;
    ro.outerLevel = options.outerLevel;
    std::vector<Region> pieces;
    try {
        pieces = extractRegions(coverageFromBits(image.width, image.height, rest), ro);
    } catch (const Error&) {
        return;  // nothing left, or every piece under 16 px
    }
    for (const Region& piece : pieces) {
        RegionReport pr;
        try {
            meshes.push_back(convertRegion(
                image,
                beneath.under.empty() ? piece
                                      : growRegionInto(piece, beneath.reach(), beneath.minHole,
                                                       beneath.under, options.outerLevel),
                options, pr));
            pr.part = "thin part";
        } catch (const MapError&) {
            std::vector<RegionReport> sub;
            try {
                if (depth > 0) throw;
                for (GradientMesh& m :
                     convertInParts(image, piece, options, beneath, sub, depth + 1))
                    meshes.push_back(std::move(m));
                for (RegionReport& r : sub) r.part = "thin part, " + r.part;
                reports.insert(reports.end(), sub.begin(), sub.end());
                continue;
            } catch (const Error& e2) {
                // Not even in parts: in tiles.
                std::vector<RegionReport> tiles;
                convertInTiles(image, piece, options, beneath, meshes, tiles, e2.reason());
                for (RegionReport& r : tiles) r.part = "thin part, " + r.part;
                reports.insert(reports.end(), tiles.begin(), tiles.end());
                continue;
            }
        } catch (const Error& e) {
            pr = RegionReport{};
            pr.pixels = piece.pixelCount;
            pr.part = "thin part left uncovered: " + e.reason();
        }
        reports.push_back(pr);
    }
}

std::vector<GradientMesh> convertInParts(const RgbaImage& image, const Region& region,
                                         const ConvertOptions& options, const PartsBeneath& beneath,
                                         std::vector<RegionReport>& reports, int depth) {
    const int w = region.width, h = region.height;
    std::string last;
    for (const int radius : {2, 4, 7}) {
        reports.clear();
        std::vector<GradientMesh> meshes;
        RegionOptions ro;
        ro.minArea = 1;
        ro.minHole = options.minHole;
        ro.outerLevel = options.outerLevel;
        const std::vector<uint8_t> core = openMask(region.mask, w, h, radius);
        std::vector<Region> cores = extractRegions(coverageFromBits(w, h, core), ro);
        // The core must be most of the region: tiny holes everywhere (or a region that is all
        // thin parts) would leave shreds, worse than the refusal.
        if (cores.empty() || cores.front().pixelCount < region.pixelCount / 2) break;
        std::vector<uint8_t> rest(region.mask.size()), coreUnder(region.mask.size());
        for (size_t k = 0; k < rest.size(); ++k) {
            rest[k] = region.mask[k] && !cores.front().mask[k];
            coreUnder[k] = rest[k] || beneath.at(k);
        }
        RegionReport rr;
        try {
            meshes.push_back(convertRegion(image,
                                           growRegionInto(cores.front(), beneath.reach(),
                                                          beneath.minHole, coreUnder, options.outerLevel),
                                           options, rr));
        } catch (const MapError& e) {
            last = e.reason();
            continue;
        }
        rr.part = "core";
        reports.push_back(rr);
        // The thin parts (and whatever else the opening removed), each its own mesh on top.
        convertThinParts(image, rest, options, beneath, meshes, reports, depth);
        return meshes;
    }
    throw MapError(last.empty() ? "no core left without the region's thin parts" : last);
}

Document convertImage(const RgbaImage& image, const ObjectMask& mask, const ConvertOptions& options,
                      const std::string& imageName, ConvertReport* report) {
    ConvertReport local;
    ConvertReport& rep = report ? *report : local;
    rep = ConvertReport{};
    rep.maskSource = maskSourceName(mask.source);
    rep.width = image.width;
    rep.height = image.height;

    auto t0 = Clock::now();
    RegionOptions ro;
    ro.minArea = options.minArea;
    ro.minHole = options.minHole;
    ro.outerLevel = options.outerLevel;
    const std::vector<Region> regions =
        extractRegions(coverageFromBits(mask.width, mask.height, mask.mask), ro);
    rep.seconds.regions = since(t0);
    if (regions.empty())
        throw Error("no region of at least " + std::to_string(options.minArea) +
                        " pixels in the object mask",
                    imageName);
    Document doc;
    doc.width = image.width;
    doc.height = image.height;
    PartsBeneath alone;  // object mode: parts reach under each other only
    alone.minHole = options.minHole;
    for (const Region& region : regions) {
        std::vector<RegionReport> rrs(1);
        try {
            std::vector<GradientMesh> meshes;
            try {
                meshes.push_back(convertRegion(image, region, options, rrs[0]));
            } catch (const MapError& whole) {
                try {
                    meshes = convertInParts(image, region, options, alone, rrs);
                } catch (const MapError&) {
                    throw whole;  // its message says what to change (--min-hole, ...)
                }
            }
            if (rrs.size() == 1 && rrs[0].outlineDeviation > options.retryDeviation &&
                region.pixelCount <= options.retryMaxPixels) {
                // The budget ran out before the boundary followed the outline (fins, tails):
                // in parts, if that covers the region clearly better and keeps its holes.
                std::vector<RegionReport> partReports;
                try {
                    std::vector<GradientMesh> parts =
                        convertInParts(image, region, options, alone, partReports);
                    // Only when every hole stays a hole of a mesh (an opening can cut the
                    // wall between a hole and the outline: the hole would become a notch).
                    int holes = 0;
                    for (const GradientMesh& m : parts) holes += m.holeCount();
                    const FitError whole = measureMeshes(meshes, image, region);
                    const FitError split = measureMeshes(parts, image, region);
                    if (holes == meshes.front().holeCount() && split.uncovered * 2 < whole.uncovered &&
                        split.meanAbs <= 1.1 * whole.meanAbs) {
                        partReports.front().seconds += rrs[0].seconds;  // both count
                        meshes = std::move(parts);
                        rrs = std::move(partReports);
                    } else {
                        for (const RegionReport& r : partReports) rrs[0].seconds += r.seconds;
                    }
                } catch (const Error&) {
                    // No parts: the whole region's mesh stays.
                }
            }
            measureHoles(meshes, region, rrs[0]);
            for (GradientMesh& m : meshes) doc.meshes.push_back(std::move(m));
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error("region " + std::to_string(rep.regions.size()) + " " + regionLabel(region) +
                            ": " + e.reason(),
                        imageName);
        }
        for (RegionReport& rr : rrs) {
            rep.patches += rr.patches;
            rep.seconds += rr.seconds;
            rep.regions.push_back(std::move(rr));
        }
    }
    // Measured over the regions' pixels: dropped specks and filled holes are not the object.
    ObjectMask measured = mask;
    std::fill(measured.mask.begin(), measured.mask.end(), uint8_t(0));
    for (const Region& region : regions)
        for (size_t k = 0; k < region.mask.size(); ++k) measured.mask[k] |= region.mask[k];
    rep.error = measure(doc, image, measured);
    return doc;
}

}  // namespace gm
