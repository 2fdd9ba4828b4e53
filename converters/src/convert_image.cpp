#include "converters/convert_image.h"

#include <chrono>
#include <algorithm>
#include <cmath>

#include "converters/boundary.h"
#include "converters/corners.h"
#include "converters/feature_map.h"
#include "converters/grid.h"
#include "converters/regions.h"
#include "converters/topology_map.h"
#include "converters/triangulate.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

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

FitError compareOverMask(const RgbaImage& reference, const RgbaImage& test,
                         const std::vector<uint8_t>& mask) {
    FitError e;
    double sum = 0, sq = 0;
    long uncovered = 0, n = 0;
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) {
            if (!mask[static_cast<size_t>(y) * reference.width + x]) continue;
            ++n;
            const float* a = reference.at(x, y);
            const float* b = test.at(x, y);
            if (b[3] < 0.5f) {
                ++uncovered;
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                const double d = std::fabs(double(a[c]) - b[c]) * 255.0;
                sum += d;
                sq += d * d;
                e.maxAbs = std::max(e.maxAbs, d);
            }
        }
    const long covered = n - uncovered;
    e.pixels = n;
    e.uncovered = n ? double(uncovered) / n : 0;
    e.meanAbs = covered ? sum / (3.0 * covered) : 0;
    e.rmse = covered ? std::sqrt(sq / (3.0 * covered)) : 0;
    e.psnr = e.rmse > 0 ? 20 * std::log10(255.0 / e.rmse) : INFINITY;
    return e;
}

std::string regionLabel(const Region& region) {
    const Vec2 at = region.outer.points.empty() ? Vec2{} : region.outer.points.front();
    return "(" + std::to_string(region.pixelCount) + " px, " + std::to_string(region.holes.size()) +
           " holes, outline from (" + std::to_string(static_cast<int>(at.x)) + ", " +
           std::to_string(static_cast<int>(at.y)) + "))";
}

GradientMesh convertRegion(const RgbaImage& image, const Region& region,
                           const ConvertOptions& options, RegionReport& rr) {
    rr = RegionReport{};
    rr.pixels = region.pixelCount;
    rr.holes = static_cast<int>(region.holes.size());
    auto t0 = Clock::now();
    RegionCorners corners = findCorners(region);
    rr.seconds.corners = since(t0);

    TriangulateOptions to;
    // Large regions get at most maxSamples samples: the maps' solves grow with them, and a
    // 4096² object needs no finer triangulation than a 1024² one.
    to.sampleFraction = std::min(options.sampleFraction,
                                 double(options.maxSamples) / std::max(1, region.pixelCount));
    TriMesh tri;
    TopologyMap topo;
    for (int attempt = 0;; ++attempt) {
        t0 = Clock::now();
        tri = triangulateRegion(image, region, corners, to);
        rr.seconds.triangulate += since(t0);
        t0 = Clock::now();
        try {
            topo = buildTopologyMapRefining(tri, corners.px, corners.py);
            rr.seconds.topology += since(t0);
            break;
        } catch (const SqueezeError&) {
            // A long thin part between two corners: once more with the corners at the
            // region's sharpest tips, so thin parts end at corners.
            rr.seconds.topology += since(t0);
            if (attempt > 0) throw;
            t0 = Clock::now();
            const RegionCorners tips = findTipCorners(region);
            rr.seconds.corners += since(t0);
            if (tips.index == corners.index) throw;
            corners = tips;
            rr.tipCorners = true;
        }
    }
    rr.triangles = static_cast<int>(tri.triangles.size());
    rr.vertices = static_cast<int>(tri.vertices.size());
    rr.mapRefinedVertices = topo.stats.refinedVertices;

    t0 = Clock::now();
    const FeatureMap feature = buildFeatureMap(tri, topo.map, image);
    rr.seconds.feature = since(t0);
    rr.featureSolves = feature.solves;
    rr.flippedTriangles = countFlippedTriangles(tri, feature.map);
    if (rr.flippedTriangles != 0)
        throw Error("the parameterisation folded " + std::to_string(rr.flippedTriangles) +
                    " triangles");

    t0 = Clock::now();
    const GridBuilder grid(tri, feature.map);
    GridOptions go;
    // The initial grid takes at most a quarter of the patch budget: the rest is for the
    // outline and the colours.
    go.targetPatchSize =
        std::max(options.targetPatchSize,
                 std::sqrt(corners.px * corners.py / std::max(1.0, options.maxPatches / 4.0)));
    for (const SlitInfo& slit : topo.slits) go.slits.push_back({slit.v, slit.u0, slit.u1});
    BoundaryFitOptions bf;
    bf.maxPatches = options.maxPatches;
    bf.tolerance = options.outlineTolerance;
    const BoundaryFitResult fitted = fitBoundary(grid, go, bf);
    rr.outlineDeviation = fitted.maxDeviation;
    rr.outlineKnots = fitted.addedU + fitted.addedV;
    RefineOptions rf;
    rf.maxError = options.maxError;
    rf.maxPatches = options.maxPatches;
    rf.color.mode = options.colors;
    rf.color.threads = options.threads;
    RefineResult refined = refineMesh(grid, go, image, region, rf);
    rr.seconds.mesh = since(t0);

    rr.columns = refined.mesh.columns();
    rr.rows = refined.mesh.rows();
    rr.patches = refined.mesh.patchCount();
    rr.error = refined.error;
    rr.refinement = refined.steps;
    return std::move(refined.mesh);
}

namespace {
// The fallback for a region whose map squeezes even with its corners at its tips (a horse: six
// thin parts, four corners) or whose slit map folds (holes bridged to the outline by thin
// parts): its core without the parts thinner than 2·radius+1 px, and each
// thin part on its own, the core reaching a pixel under them. Returns the meshes, core first;
// throws what convertRegion throws when no radius works for the core.
std::vector<GradientMesh> convertInParts(const RgbaImage& image, const Region& region,
                                         const ConvertOptions& options,
                                         std::vector<RegionReport>& reports, int depth = 0) {
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
        std::vector<uint8_t> rest(region.mask.size());
        for (size_t k = 0; k < rest.size(); ++k) rest[k] = region.mask[k] && !cores.front().mask[k];
        RegionReport rr;
        try {
            meshes.push_back(convertRegion(
                image, growRegionInto(cores.front(), 1, options.minHole, rest, options.outerLevel),
                options, rr));
        } catch (const MapError& e) {
            last = e.reason();
            continue;
        }
        rr.part = "core";
        reports.push_back(rr);
        // The thin parts (and whatever else the opening removed), each its own mesh on top.
        bool restLeft = false;
        for (uint8_t v : rest) restLeft = restLeft || v;
        // Parts under 16 px are left to the core's overlap.
        ro.minArea = 16;
        if (restLeft)
            for (const Region& piece : extractRegions(coverageFromBits(w, h, rest), ro)) {
                RegionReport pr;
                try {
                    meshes.push_back(convertRegion(image, piece, options, pr));
                    pr.part = "thin part";
                } catch (const MapError& e) {
                    std::vector<RegionReport> sub;
                    try {
                        if (depth > 0) throw;
                        for (GradientMesh& m : convertInParts(image, piece, options, sub, depth + 1))
                            meshes.push_back(std::move(m));
                        for (RegionReport& r : sub) r.part = "thin part, " + r.part;
                        reports.insert(reports.end(), sub.begin(), sub.end());
                        continue;
                    } catch (const Error& e2) {
                        pr = RegionReport{};
                        pr.pixels = piece.pixelCount;
                        pr.part = "thin part left uncovered: " + e2.reason();
                    }
                } catch (const Error& e) {
                    pr = RegionReport{};
                    pr.pixels = piece.pixelCount;
                    pr.part = "thin part left uncovered: " + e.reason();
                }
                reports.push_back(pr);
            }
        return meshes;
    }
    throw MapError(last.empty() ? "no core left without the region's thin parts" : last);
}
}  // namespace

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
    for (const Region& region : regions) {
        std::vector<RegionReport> rrs(1);
        try {
            try {
                doc.meshes.push_back(convertRegion(image, region, options, rrs[0]));
            } catch (const MapError& whole) {
                std::vector<GradientMesh> parts;
                try {
                    parts = convertInParts(image, region, options, rrs);
                } catch (const MapError&) {
                    throw whole;  // its message says what to change (--min-hole, ...)
                }
                for (GradientMesh& m : parts) doc.meshes.push_back(std::move(m));
            }
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error("region " + std::to_string(rep.regions.size()) + " " + regionLabel(region) +
                            ": " + e.reason(),
                        imageName);
        }
        for (RegionReport& rr : rrs) {
            rep.patches += rr.patches;
            rep.seconds.corners += rr.seconds.corners;
            rep.seconds.triangulate += rr.seconds.triangulate;
            rep.seconds.topology += rr.seconds.topology;
            rep.seconds.feature += rr.seconds.feature;
            rep.seconds.mesh += rr.seconds.mesh;
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
