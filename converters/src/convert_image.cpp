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
    GridOptions gridOptions;
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
// The budget-independent maps of one choice of corners: from the cache when it has them, else
// built (their times into `seconds`) and left in it.
std::shared_ptr<const RegionMaps> regionMaps(const RgbaImage& image, const Region& region,
                                             const ConvertOptions& options,
                                             const RegionCorners& corners, RegionMapCache* cache,
                                             StageSeconds& seconds) {
    if (cache)
        if (std::shared_ptr<const RegionMaps> kept = cache->impl().find(corners.index)) return kept;
    auto maps = std::make_shared<RegionMaps>();
    maps->corners = corners.index;
    TriangulateOptions triangulateOptions;
    // Large regions get at most maxSamples samples: the maps' solves grow with them, and a
    // 4096² object needs no finer triangulation than a 1024² one.
    triangulateOptions.sampleFraction = std::min(
        options.sampleFraction, double(options.maxSamples) / std::max(1, region.pixelCount));
    auto t0 = Clock::now();
    maps->tri = triangulateRegion(image, region, corners, triangulateOptions);
    seconds.triangulate = since(t0);
    t0 = Clock::now();
    maps->topo = buildTopologyMapRefining(maps->tri, corners.px, corners.py);
    seconds.topology = since(t0);

    t0 = Clock::now();
    FeatureMapOptions featureOptions;
    featureOptions.mask = &region.mask;  // the outline against the background is not a feature
    maps->feature = buildFeatureMap(maps->tri, maps->topo.map, image, featureOptions);
    seconds.feature = since(t0);
    if (const int flips = countFlippedTriangles(maps->tri, maps->feature.map); flips != 0)
        throw Error("the parameterisation folded " + std::to_string(flips) + " triangles");
    if (cache) cache->impl().keep(maps);
    return maps;
}

// A grid through one map, its boundary fitted to the outline.
struct GridCandidate {
    std::unique_ptr<GridBuilder> grid;
    GridOptions gridOptions;
    BoundaryFitResult fitted;
    int folded = 0;
};

// The boundary-fitted grid through the feature map, or through the topology map when that one
// folds fewer patches.
class GridChooser {
public:
    GridChooser(const RegionMaps& maps, const ConvertOptions& options, const RegionCorners& corners)
        : maps_(maps), options_(options) {
        // The initial grid takes at most a quarter of the patch budget: the rest is for the
        // outline and the colours.
        base_.targetPatchSize =
            std::max(options.targetPatchSize,
                     std::sqrt(corners.px * corners.py / std::max(1.0, options.maxPatches / 4.0)));
        for (const SlitInfo& slit : maps.topo.slits)
            base_.slits.push_back({slit.v, slit.u0, slit.u1});
        boundaryOptions_.maxPatches = options.maxPatches;
        boundaryOptions_.tolerance = options.outlineTolerance;
        boundaryOptions_.holeTolerance = options.holeTolerance;
    }

    // Stretch minimisation can bend the iso-curves more than cubic patches between the knots
    // follow (thin limbs of a silhouette): their patches fold. The topology map's iso-curves
    // are smoother; its grid is kept when it folds less. It is needed only when the feature
    // map's grid folds, so it is built beside that one when a core is free (object mode), after
    // it otherwise (regions converted in parallel). `featureMapUsed` says which is returned.
    GridCandidate choose(bool& featureMapUsed) const {
        featureMapUsed = true;
        std::future<GridCandidate> topology;
        if (options_.threads != 1 && std::thread::hardware_concurrency() > 1)
            topology = std::async(std::launch::async, [this] { return candidate(maps_.topo.map); });
        GridCandidate best = candidate(maps_.feature.map);
        if (best.folded > 0) {
            GridCandidate other = topology.valid() ? topology.get() : candidate(maps_.topo.map);
            if (other.folded < best.folded) {
                best = std::move(other);
                featureMapUsed = false;
            }
        }
        return best;
    }

private:
    GridCandidate candidate(const ParamMap& map) const {
        GridCandidate c{std::make_unique<GridBuilder>(maps_.tri, map), base_, {}, 0};
        c.fitted = fitBoundary(*c.grid, c.gridOptions, boundaryOptions_);
        coverOutline(*c.grid, c.gridOptions, c.fitted, options_.outlineCover,
                     options_.outlineTolerance);
        c.folded = countFoldedPatches(c.grid->build(c.gridOptions));
        return c;
    }

    const RegionMaps& maps_;
    const ConvertOptions& options_;
    GridOptions base_;
    BoundaryFitOptions boundaryOptions_;
};

std::unique_ptr<RegionGeometry> buildGeometry(const RgbaImage& image, const Region& region,
                                              const ConvertOptions& options,
                                              const RegionCorners& corners, RegionMapCache* cache) {
    auto geometry = std::make_unique<RegionGeometry>();
    geometry->corners = corners;
    geometry->maps = regionMaps(image, region, options, corners, cache, geometry->seconds);
    const auto t0 = Clock::now();
    GridCandidate best =
        GridChooser(*geometry->maps, options, corners).choose(geometry->featureMapUsed);
    geometry->grid = std::move(best.grid);
    geometry->gridOptions = std::move(best.gridOptions);
    geometry->fitted = best.fitted;
    geometry->foldedPatches = best.folded;
    geometry->seconds.mesh = since(t0);
    return geometry;
}
}  // namespace

namespace {
// Fallbacks 1 and 2 of fallbackAfter's list: the region's geometry with its first corners, or
// with the corners at its sharpest tips (thin parts should end at corners) when the first
// squeeze, or when the boundary fit stays farther than retryDeviation from the outline and
// the tips' fit is closer (tails and fins between two corners need many knots).
std::unique_ptr<RegionGeometry> geometryWithBestCorners(const RgbaImage& image,
                                                        const Region& region,
                                                        const ConvertOptions& options,
                                                        RegionReport& report,
                                                        RegionMapCache* cache) {
    auto t0 = Clock::now();
    const RegionCorners first = findCorners(region);
    report.seconds.corners = since(t0);
    auto tipCorners = [&] {
        t0 = Clock::now();
        const RegionCorners tips = findTipCorners(region);
        report.seconds.corners += since(t0);
        return tips;
    };
    std::unique_ptr<RegionGeometry> geometry;
    try {
        geometry = buildGeometry(image, region, options, first, cache);
    } catch (const SqueezeError&) {
        const RegionCorners tips = tipCorners();
        if (tips.index == first.index) throw;
        geometry = buildGeometry(image, region, options, tips, cache);
        report.tipCorners = true;
    }
    report.seconds += geometry->seconds;
    const bool retry = !report.tipCorners &&
                       geometry->fitted.maxDeviation > options.retryDeviation &&
                       region.pixelCount <= options.retryMaxPixels;
    if (!retry) return geometry;
    const RegionCorners tips = tipCorners();
    if (tips.index == first.index) return geometry;
    try {
        std::unique_ptr<RegionGeometry> other = buildGeometry(image, region, options, tips, cache);
        report.seconds += other->seconds;  // both attempts count
        if (other->fitted.maxDeviation < geometry->fitted.maxDeviation) {
            geometry = std::move(other);
            report.tipCorners = true;
        }
    } catch (const MapError&) {
        // The tips do not map: keep the first geometry.
    }
    return geometry;
}
}  // namespace

GradientMesh convertRegion(const RgbaImage& image, const Region& region,
                           const ConvertOptions& options, RegionReport& report,
                           RegionMapCache* cache) {
    report = RegionReport{};
    report.pixels = region.pixelCount;
    report.holes = static_cast<int>(region.holes.size());
    reportProgress(options, "maps");
    const std::unique_ptr<RegionGeometry> geometry =
        geometryWithBestCorners(image, region, options, report, cache);
    const RegionMaps& maps = *geometry->maps;
    report.triangles = static_cast<int>(maps.tri.triangles.size());
    report.vertices = static_cast<int>(maps.tri.vertices.size());
    report.mapRefinedVertices = maps.topo.stats.refinedVertices;
    report.featureSolves = maps.feature.solves;
    report.flippedTriangles = 0;
    report.outlineDeviation = geometry->fitted.maxDeviation;
    report.outlineKnots = geometry->fitted.addedU + geometry->fitted.addedV;
    report.featureMapUsed = geometry->featureMapUsed;

    reportProgress(options, "mesh");
    const auto t0 = Clock::now();
    RefineOptions refineOptions;
    refineOptions.maxError = options.maxError;
    refineOptions.maxPatches = options.maxPatches;
    refineOptions.color.mode = options.colors;
    refineOptions.color.threads = options.threads;
    refineOptions.color.subPixelEdgePull = options.subPixelEdgePull;
    RefineResult refined =
        refineMesh(*geometry->grid, geometry->gridOptions, image, region, refineOptions);
    report.seconds.mesh += since(t0);

    report.columns = refined.mesh.columns();
    report.rows = refined.mesh.rows();
    report.patches = refined.mesh.patchCount();
    report.error = refined.error;
    report.refinement = refined.steps;
    report.foldedPatches = countFoldedPatches(refined.mesh);
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
void measureHoles(const std::vector<GradientMesh>& meshes, const Region& region,
                  RegionReport& report) {
    report.holePixels = report.holePixelsPainted = 0;
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
        ++report.holePixels;
        if (render.pixels[k * 4 + 3] >= 0.5f) ++report.holePixelsPainted;
    }
}

// ---------------------------------------------------------------------------------------
// Fallbacks: which applies when, and why. docs/design.md §3 ("Fallbacks") has the same list as
// a table, numbered alike:
//  1. the first corners' map squeezes: corners at the sharpest tips    (geometryWithBestCorners)
//  2. the outline is missed by more than retryDeviation: the tips too  (geometryWithBestCorners)
//  3. a region's map fails: in parts                                    (fallbackAfter)
//  4. a region converted whole still misses its outline: parts too     (preferPartsForOutline)
//  5. a thin part's map fails: that part in parts, once                 (fallbackAfter)
//  6. a piece fails even in parts: in tiles, up to kMaxTileDepth deep   (fallbackAfter)
//  7. a tile still fails: left uncovered and reported                   (fallbackAfter)
// 1, 2 and 4 choose between results; 3, 5, 6 and 7 follow a map that fails (MapError), and
// fallbackAfter alone decides which. Any other error leaves a thin part or a tile uncovered
// (reported) and fails a region.

// What is being converted.
enum class Piece {
    Region,    // a region of the object mask (convertImage)
    ThinPart,  // a piece a region's core left out (convertThinParts)
    Tile,      // a component of half a piece cut in two (convertInTiles)
};

// How a piece is converted.
enum class Strategy {
    Whole,          // one mesh (convertRegion)
    InParts,        // its core without the thin parts, and each thin part (convertInParts)
    InTiles,        // cut in halves, each half's components their own meshes (convertInTiles)
    LeftUncovered,  // no mesh: a report says which pixels and why
    Refused,        // no mesh: the conversion fails with the whole piece's error
};

// A piece cut in tiles is cut again at most this many times.
constexpr int kMaxTileDepth = 6;

// What is tried after `failed` throws MapError for `piece`; `depth` counts how many times the
// piece's ancestors were converted in parts (thin parts) or cut in halves (tiles).
Strategy fallbackAfter(Piece piece, Strategy failed, int depth) {
    switch (piece) {
        case Piece::Region:
            // 3. One map cannot unfold a region with thin limbs, or with holes bridged to the
            // outline by thin parts. When even its parts fail, the whole's error stands: it says
            // what to change (--min-hole, ...).
            return failed == Strategy::Whole ? Strategy::InParts : Strategy::Refused;
        case Piece::ThinPart:
            // 5. The same reason one level down, once. 6. A network of thin leaves (or a thin
            // ring with branches) has no usable core: tiles.
            return failed == Strategy::Whole && depth == 0 ? Strategy::InParts : Strategy::InTiles;
        case Piece::Tile:
            // 6. Smaller tiles map more easily. 7. Never silently: what still fails is reported.
            return depth + 1 < kMaxTileDepth ? Strategy::InTiles : Strategy::LeftUncovered;
    }
    return Strategy::Refused;
}

RegionReport leftUncoveredReport(int pixels, const std::string& part) {
    RegionReport report;
    report.pixels = pixels;
    report.part = part;
    return report;
}

// Appends `from` to `to`, each report's part prefixed.
void appendReports(std::vector<RegionReport>& to, std::vector<RegionReport>& from,
                   const std::string& prefix) {
    for (RegionReport& r : from) r.part = prefix + r.part;
    to.insert(to.end(), from.begin(), from.end());
}

// The pixels of `piece` in one half of its bounding box (cut across its longer side), each
// 8-connected component of at least 16 px its own region; none when the half has none.
std::vector<Region> halfOfPiece(const Region& piece, const PixelBox& box, int half,
                                const ConvertOptions& options) {
    const int w = piece.width, h = piece.height;
    const bool cutX = box.x1 - box.x0 >= box.y1 - box.y0;
    const int cut = cutX ? (box.x0 + box.x1 + 1) / 2 : (box.y0 + box.y1 + 1) / 2;  // half 2 from
    std::vector<uint8_t> bits(piece.mask.size(), 0);
    for (int y = box.y0; y <= box.y1; ++y)
        for (int x = box.x0; x <= box.x1; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            const bool second = (cutX ? x : y) >= cut;
            bits[k] = piece.mask[k] && second == (half == 1);
        }
    RegionOptions regionOptions;
    regionOptions.minArea = 16;
    regionOptions.minHole = options.minHole;
    regionOptions.outerLevel = options.outerLevel;
    try {
        return extractRegions(coverageFromBits(w, h, bits), regionOptions);
    } catch (const Error&) {
        return {};  // nothing in this half, or only specks under 16 px
    }
}

// Fallback 6, the last resort for a piece that no map handles, not even in parts: cut across
// the longer side of its bounding box, each 8-connected component of each half its own mesh
// reaching a pixel under the rest of the piece; a component that fails is cut again or left
// uncovered as fallbackAfter says. Components under 16 px are left to their neighbours'
// overlap. Meshes and reports are appended, `part` saying "tile".
void convertInTiles(const RgbaImage& image, const Region& piece, const ConvertOptions& options,
                    const PartsBeneath& beneath, std::vector<GradientMesh>& meshes,
                    std::vector<RegionReport>& reports, const std::string& reason, int depth = 0) {
    const PixelBox box = maskBounds(piece.mask, piece.width, piece.height);
    if (box.empty()) return;
    if (box.x1 == box.x0 && box.y1 == box.y0) {  // one pixel: nothing to cut
        reports.push_back(leftUncoveredReport(piece.pixelCount, "tile left uncovered: " + reason));
        return;
    }
    for (int half = 0; half < 2; ++half) {
        for (const Region& tile : halfOfPiece(piece, box, half, options)) {
            std::vector<uint8_t> rest(piece.mask.size());
            for (size_t k = 0; k < rest.size(); ++k)
                rest[k] = (piece.mask[k] && !tile.mask[k]) || beneath.at(k);
            RegionReport tileReport;
            try {
                meshes.push_back(
                    convertRegion(image,
                                  growRegionInto(tile, beneath.reach(), beneath.minHole, rest,
                                                 options.outerLevel),
                                  options, tileReport));
                tileReport.part = "tile";
                reports.push_back(tileReport);
            } catch (const MapError& e) {
                if (fallbackAfter(Piece::Tile, Strategy::Whole, depth) == Strategy::InTiles)
                    convertInTiles(image, tile, options, beneath, meshes, reports, e.reason(),
                                   depth + 1);
                else
                    reports.push_back(
                        leftUncoveredReport(tile.pixelCount, "tile left uncovered: " + e.reason()));
            } catch (const Error& e) {
                reports.push_back(
                    leftUncoveredReport(tile.pixelCount, "tile left uncovered: " + e.reason()));
            }
        }
    }
}

// A thin part whose map failed (`reason`): in parts or in tiles, as fallbackAfter says.
void convertFailedThinPart(const RgbaImage& image, const Region& piece,
                           const ConvertOptions& options, const PartsBeneath& beneath,
                           std::vector<GradientMesh>& meshes, std::vector<RegionReport>& reports,
                           int depth, std::string reason) {
    if (fallbackAfter(Piece::ThinPart, Strategy::Whole, depth) == Strategy::InParts) {
        std::vector<RegionReport> partReports;
        try {
            for (GradientMesh& m :
                 convertInParts(image, piece, options, beneath, partReports, depth + 1))
                meshes.push_back(std::move(m));
            appendReports(reports, partReports, "thin part, ");
            return;
        } catch (const Error& e) {
            // Whatever stopped the parts (fallbackAfter(ThinPart, InParts) is InTiles).
            reason = e.reason();
        }
    }
    std::vector<RegionReport> tileReports;
    convertInTiles(image, piece, options, beneath, meshes, tileReports, reason);
    appendReports(reports, tileReports, "thin part, ");
}

}  // namespace

void convertThinParts(const RgbaImage& image, const std::vector<uint8_t>& rest,
                      const ConvertOptions& options, const PartsBeneath& beneath,
                      std::vector<GradientMesh>& meshes, std::vector<RegionReport>& reports,
                      int depth) {
    RegionOptions regionOptions;
    regionOptions.minArea = 16;
    regionOptions.minHole = options.minHole;
    regionOptions.outerLevel = options.outerLevel;
    std::vector<Region> pieces;
    try {
        pieces = extractRegions(coverageFromBits(image.width, image.height, rest), regionOptions);
    } catch (const Error&) {
        return;  // nothing left, or every piece under 16 px
    }
    for (const Region& piece : pieces) {
        RegionReport partReport;
        try {
            meshes.push_back(convertRegion(
                image,
                beneath.under.empty() ? piece
                                      : growRegionInto(piece, beneath.reach(), beneath.minHole,
                                                       beneath.under, options.outerLevel),
                options, partReport));
            partReport.part = "thin part";
            reports.push_back(partReport);
        } catch (const MapError& e) {
            convertFailedThinPart(image, piece, options, beneath, meshes, reports, depth,
                                  e.reason());
        } catch (const Error& e) {
            reports.push_back(
                leftUncoveredReport(piece.pixelCount, "thin part left uncovered: " + e.reason()));
        }
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
        RegionOptions regionOptions;
        regionOptions.minArea = 1;
        regionOptions.minHole = options.minHole;
        regionOptions.outerLevel = options.outerLevel;
        const std::vector<uint8_t> core = openMask(region.mask, w, h, radius);
        std::vector<Region> cores = extractRegions(coverageFromBits(w, h, core), regionOptions);
        // The core must be most of the region: tiny holes everywhere (or a region that is all
        // thin parts) would leave shreds, worse than the refusal.
        if (cores.empty() || cores.front().pixelCount < region.pixelCount / 2) break;
        std::vector<uint8_t> rest(region.mask.size()), coreUnder(region.mask.size());
        for (size_t k = 0; k < rest.size(); ++k) {
            rest[k] = region.mask[k] && !cores.front().mask[k];
            coreUnder[k] = rest[k] || beneath.at(k);
        }
        RegionReport coreReport;
        try {
            meshes.push_back(
                convertRegion(image,
                              growRegionInto(cores.front(), beneath.reach(), beneath.minHole,
                                             coreUnder, options.outerLevel),
                              options, coreReport));
        } catch (const MapError& e) {
            last = e.reason();
            continue;
        }
        coreReport.part = "core";
        reports.push_back(coreReport);
        // The thin parts (and whatever else the opening removed), each its own mesh on top.
        convertThinParts(image, rest, options, beneath, meshes, reports, depth);
        return meshes;
    }
    throw MapError(last.empty() ? "no core left without the region's thin parts" : last);
}

namespace {
// Fallback 4: a region converted whole whose outline is still farther than retryDeviation
// (the budget ran out before the boundary followed fins and tails) is converted in parts too;
// the parts replace the whole's mesh when they leave under half its uncovered pixels, raise E
// by at most 10 % and keep every hole a hole of a mesh (an opening can cut the wall between a
// hole and the outline: the hole would become a notch). Parts cover fins better than one
// stretched grid.
void preferPartsForOutline(const RgbaImage& image, const Region& region,
                           const ConvertOptions& options, const PartsBeneath& beneath,
                           std::vector<GradientMesh>& meshes,
                           std::vector<RegionReport>& regionReports) {
    std::vector<RegionReport> partReports;
    try {
        std::vector<GradientMesh> parts =
            convertInParts(image, region, options, beneath, partReports);
        int holes = 0;
        for (const GradientMesh& m : parts) holes += m.holeCount();
        const FitError whole = measureMeshes(meshes, image, region);
        const FitError split = measureMeshes(parts, image, region);
        if (holes == meshes.front().holeCount() && split.uncovered * 2 < whole.uncovered &&
            split.meanAbs <= 1.1 * whole.meanAbs) {
            partReports.front().seconds += regionReports[0].seconds;  // both count
            meshes = std::move(parts);
            regionReports = std::move(partReports);
        } else {
            for (const RegionReport& r : partReports) regionReports[0].seconds += r.seconds;
        }
    } catch (const Error&) {
        // No parts: the whole region's mesh stays.
    }
}

// One region of the object mask: whole, or as fallbackAfter says when its map fails, and
// preferPartsForOutline. `regionReports` (one report on entry) gets one report per mesh.
std::vector<GradientMesh> convertObjectRegion(const RgbaImage& image, const Region& region,
                                              const ConvertOptions& options,
                                              std::vector<RegionReport>& regionReports) {
    PartsBeneath alone;  // object mode: parts reach under each other only
    alone.minHole = options.minHole;
    std::vector<GradientMesh> meshes;
    try {
        meshes.push_back(convertRegion(image, region, options, regionReports[0]));
    } catch (const MapError& whole) {
        if (fallbackAfter(Piece::Region, Strategy::Whole, 0) != Strategy::InParts) throw;
        try {
            meshes = convertInParts(image, region, options, alone, regionReports);
        } catch (const MapError&) {
            // fallbackAfter(Region, InParts) is Refused: the whole's error.
            throw whole;
        }
    }
    if (regionReports.size() == 1 && regionReports[0].outlineDeviation > options.retryDeviation &&
        region.pixelCount <= options.retryMaxPixels)
        preferPartsForOutline(image, region, options, alone, meshes, regionReports);
    measureHoles(meshes, region, regionReports[0]);
    return meshes;
}

// The regions' pixels: dropped specks and filled holes are not the object.
ObjectMask regionPixels(const ObjectMask& mask, const std::vector<Region>& regions) {
    ObjectMask measured = mask;
    std::fill(measured.mask.begin(), measured.mask.end(), uint8_t(0));
    for (const Region& region : regions)
        for (size_t k = 0; k < region.mask.size(); ++k) measured.mask[k] |= region.mask[k];
    return measured;
}
}  // namespace

Document convertImage(const RgbaImage& image, const ObjectMask& mask, const ConvertOptions& options,
                      const std::string& imageName, ConvertReport* report) {
    ConvertReport local;
    ConvertReport& convertReport = report ? *report : local;
    convertReport = ConvertReport{};
    convertReport.maskSource = maskSourceName(mask.source);
    convertReport.width = image.width;
    convertReport.height = image.height;

    reportProgress(options, "regions");
    const auto t0 = Clock::now();
    RegionOptions regionOptions;
    regionOptions.minArea = options.minArea;
    regionOptions.minHole = options.minHole;
    regionOptions.outerLevel = options.outerLevel;
    const std::vector<Region> regions =
        extractRegions(coverageFromBits(mask.width, mask.height, mask.mask), regionOptions);
    convertReport.seconds.regions = since(t0);
    if (regions.empty())
        throw Error("no region of at least " + std::to_string(options.minArea) +
                        " pixels in the object mask",
                    imageName);
    Document doc;
    doc.width = image.width;
    doc.height = image.height;
    const int regionCount = static_cast<int>(regions.size());
    for (const Region& region : regions) {
        reportProgress(options, "regions", static_cast<int>(&region - regions.data()), regionCount);
        std::vector<RegionReport> regionReports(1);
        try {
            for (GradientMesh& m : convertObjectRegion(image, region, options, regionReports))
                doc.meshes.push_back(std::move(m));
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error("region " + std::to_string(convertReport.regions.size()) + " " +
                            regionLabel(region) + ": " + e.reason(),
                        imageName);
        }
        for (RegionReport& regionReport : regionReports) {
            convertReport.patches += regionReport.patches;
            convertReport.seconds += regionReport.seconds;
            convertReport.regions.push_back(std::move(regionReport));
        }
    }
    reportProgress(options, "regions", regionCount, regionCount);
    reportProgress(options, "measure");
    convertReport.error = measure(doc, image, regionPixels(mask, regions));
    return doc;
}

}  // namespace gm
