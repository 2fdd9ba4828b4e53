// Raster → gradient meshes: the whole pipeline of docs/design.md §3 for every region of an object
// mask, timed per stage (T = regions+corners+triangulate, P = topology+feature map,
// M = grid+colours+refine, as in the paper's Table 1).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "converters/colors.h"
#include "converters/foreground.h"
#include "converters/refine.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

// What a conversion says as it goes (ConvertOptions::progress): the stage it enters and, for
// the stages over regions, how many are done of how many (total 0: not counted).
struct ConvertProgress {
    const char* stage = "";
    int done = 0, total = 0;
};

struct ConvertOptions {
    double maxError = 3.0;        // target E per region, 0–255 units
    int maxPatches = 400;         // patch budget per region
    ColorMode colors = ColorMode::FitBicubic;
    double subPixelEdgePull = 0;  // ColorOptions::subPixelEdgePull of the region's fits
    int minArea = 64;             // pixels: smaller components are dropped
    int minHole = 16;             // pixels: smaller holes are filled
    double sampleFraction = 0.03; // triangulation samples per region pixel
    int maxSamples = 40000;       // ... and at most this many per region
    double targetPatchSize = 96;  // pixels: the initial grid's patch size
    double outerLevel = 0.35;     // RegionOptions::outerLevel
    double outlineTolerance = 0.5;   // pixels: boundary curves against the traced outline
    double holeTolerance = 0.2;      // pixels: the same for hole outlines
    double outlineCover = 0.1;       // pixels: GridOptions::outlineCover (negative: off), with
                                     // the boundary fit's knots, each side within the fit's
                                     // worst deviation (or outlineTolerance) of the outline
    int threads = 0;              // renderer threads inside one region's fit (0: all cores)
    double retryDeviation = 2.0;  // pixels: a boundary fit farther than this from the outline
                                  // is tried again with the corners at the sharpest tips, then
                                  // in parts (keeping the better), for regions of at most
    int retryMaxPixels = 1 << 20; // this many pixels (a retry costs a whole conversion)
    // Called at each stage and each region done (may be empty). Regions converted in parallel
    // call it from their threads, at the same time: it must be thread-safe, and cheap.
    std::function<void(const ConvertProgress&)> progress;
};

inline void reportProgress(const ConvertOptions& options, const char* stage, int done = 0,
                           int total = 0) {
    if (options.progress) options.progress(ConvertProgress{stage, done, total});
}

struct StageSeconds {
    double regions = 0, corners = 0, triangulate = 0, topology = 0, feature = 0, mesh = 0;
    // The paper's Table 1 columns: T (outline to triangulation), P (the maps), M (the mesh).
    double triangulationStages() const { return regions + corners + triangulate; }
    double mapStages() const { return topology + feature; }
    double meshStages() const { return mesh; }
    double total() const { return triangulationStages() + mapStages() + meshStages(); }
    StageSeconds& operator+=(const StageSeconds& o) {
        regions += o.regions, corners += o.corners, triangulate += o.triangulate;
        topology += o.topology, feature += o.feature, mesh += o.mesh;
        return *this;
    }
};

struct RegionReport {
    int pixels = 0, holes = 0;
    int triangles = 0, vertices = 0, flippedTriangles = 0;
    int mapRefinedVertices = 0;  // added by refinement where the slit map folded
    bool tipCorners = false;     // corners moved to the sharpest tips (the first choice squeezed)
    std::string part;            // "" (the whole region), "core" or "thin part ...": a region
                                 // whose map squeezed even so, converted in parts
    int columns = 0, rows = 0, patches = 0;
    StageSeconds seconds;
    FitError error;
    std::vector<RefineStep> refinement;
    int featureSolves = 0;
    double outlineDeviation = 0;  // pixels: boundary curves against the traced outline
    int outlineKnots = 0;         // knots added so the boundary follows the outline
    // The region's hole pixels (background not 4-connected to the outside) and how many of
    // them the region's own meshes paint (alpha ≥ 0.5): a hole must stay a hole. On the
    // region's first report only (a region converted in parts counts all its meshes there).
    long holePixels = 0, holePixelsPainted = 0;
    bool featureMapUsed = true;  // false: the topology map gave a grid that folds less
    int foldedPatches = 0;       // patches of the final mesh that fold (countFoldedPatches)
};

struct ConvertReport {
    std::string maskSource;
    int width = 0, height = 0;
    StageSeconds seconds;  // summed over regions (regions stage once)
    std::vector<RegionReport> regions;
    FitError error;        // over all region pixels, from the final re-render
    int patches = 0;
};

// The stages of a region that do not depend on its patch budget (triangulation, topology and
// feature maps, per choice of corners), kept for its conversions at other budgets. One cache
// serves one region (the same pixels, outline and options but maxPatches); it may be shared by
// threads.
class RegionMapCache {
public:
    RegionMapCache();
    ~RegionMapCache();
    RegionMapCache(const RegionMapCache&) = delete;
    RegionMapCache& operator=(const RegionMapCache&) = delete;
    struct Impl;
    Impl& impl() { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

// One region through corners, triangulate, maps, grid, colours and refine; fills `report`.
// Throws gm::Error (without a file name) when a stage fails. With `cache`: the
// budget-independent stages are taken from it when it has them, and left in it otherwise.
GradientMesh convertRegion(const RgbaImage& image, const Region& region,
                           const ConvertOptions& options, RegionReport& report,
                           RegionMapCache* cache = nullptr);

// What the meshes of a region converted in parts may reach under besides the region's own
// pixels: `under` (width*height, non-zero = drawn on top of this region later; empty: nothing),
// by `overlap` pixels (at least 1), holes of the grown outlines under `minHole` px filled.
struct PartsBeneath {
    int minHole = 0;
    std::vector<uint8_t> under;
    int overlap = 1;
    bool at(size_t k) const { return !under.empty() && under[k]; }
    int reach() const { return overlap > 1 ? overlap : 1; }
};

// The fallback for a region whose map squeezes even with its corners at its tips (a horse: six
// thin parts, four corners) or whose slit map folds (holes bridged to the outline by thin
// parts): its core without the parts thinner than 2·radius+1 px (radius 2, 4 or 7, the first
// that works), the core reaching under its thin parts, and each thin part on its own; a thin
// part that fails is converted in parts itself (once), and failing that in tiles (cut in halves
// across its longer side, each half's components their own meshes, failing ones cut again up to
// 6 times). Returns the meshes, core first; `reports` gets one report per mesh (RegionReport::part
// says which: "core", "thin part", "thin part, tile", ...; a piece that no mesh covers gets a
// report whose part says "left uncovered" and why). Throws MapError when no radius leaves a core
// of at least half the region that converts.
std::vector<GradientMesh> convertInParts(const RgbaImage& image, const Region& region,
                                         const ConvertOptions& options, const PartsBeneath& beneath,
                                         std::vector<RegionReport>& reports, int depth = 0);

// The pieces of `rest` (width*height, non-zero = in; 8-connected, under 16 px left out), each its
// own mesh as convertInParts converts a region's thin parts (a failing piece in parts once when
// depth is 0, else or failing that in tiles), grown into beneath.under when it is not empty.
// Appends meshes and reports ("thin part", "thin part, tile", "thin part left uncovered: ...").
void convertThinParts(const RgbaImage& image, const std::vector<uint8_t>& rest,
                      const ConvertOptions& options, const PartsBeneath& beneath,
                      std::vector<GradientMesh>& meshes, std::vector<RegionReport>& reports,
                      int depth = 0);

// "(N px, H holes, outline from (x, y))": how errors name a region.
std::string regionLabel(const Region& region);

// Converts every region of `mask` (1 = object), each through convertRegion and, where its map
// fails, the fallbacks of docs/design.md §3 ("Fallbacks"). Throws gm::Error naming `imageName`
// for a region it cannot convert even so.
Document convertImage(const RgbaImage& image, const ObjectMask& mask, const ConvertOptions& options,
                      const std::string& imageName, ConvertReport* report = nullptr);

}  // namespace gm
