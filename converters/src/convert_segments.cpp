#include "converters/convert_segments.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <thread>

#include "converters/colors.h"
#include "converters/neck.h"
#include "converters/regions.h"
#include "flat_backdrop.h"
#include "converters/flat_residue.h"
#include "thin_on_top.h"
#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "meshcore/render.h"
#include "meshcore/validate.h"

namespace gm {

namespace {
// One report for a region converted in parts: patches and seconds summed, the error combined
// over the parts' own pixels (weighted by covered pixels), the core's geometry figures.
RegionReport mergePartReports(const std::vector<RegionReport>& parts, const Region& own) {
    RegionReport r = parts.front();
    r.pixels = own.pixelCount;
    r.holes = static_cast<int>(own.holes.size());
    r.part = "core + " + std::to_string(parts.size() - 1) + " parts";
    r.patches = 0;
    r.seconds = StageSeconds{};
    r.foldedPatches = 0;
    double sum = 0, sq = 0, covered = 0, uncovered = 0, maxAbs = 0;
    for (const RegionReport& p : parts) {
        r.patches += p.patches;
        r.seconds += p.seconds;
        r.foldedPatches += p.foldedPatches;
        const double c = p.error.pixels * (1 - p.error.uncovered);
        sum += p.error.meanAbs * c;
        sq += p.error.rmse * p.error.rmse * c;
        covered += c;
        uncovered += p.error.pixels * p.error.uncovered;
        if (p.part.find("left uncovered") != std::string::npos) uncovered += p.pixels;
        maxAbs = std::max(maxAbs, p.error.maxAbs);
    }
    r.error.pixels = own.pixelCount;
    r.error.meanAbs = covered > 0 ? sum / covered : 0;
    r.error.rmse = covered > 0 ? std::sqrt(sq / covered) : 0;
    r.error.psnr = r.error.rmse > 0 ? 20 * std::log10(255.0 / r.error.rmse) : INFINITY;
    r.error.maxAbs = maxAbs;
    r.error.uncovered = own.pixelCount > 0 ? std::min(1.0, uncovered / own.pixelCount) : 0;
    return r;
}

// What became of one region of a whole image.
enum class RegionFate {
    Failed,          // no mesh: left to the base mesh
    Whole,           // one conversion of the region as it is
    HolesFilled,     // its holes filled (the slit map failed on them)
    ThinPartsApart,  // its core and its thin parts as meshes of their own
    SplitAtNecks,    // cut at its narrowest necks, each side converted on its own
    Flat,            // one colour: a flat shape, no mesh
};

// How one region of a whole image was converted.
struct RegionOutcome {
    std::vector<GradientMesh> meshes;
    std::vector<FlatShape> shapes;  // Flat
    RegionReport report;
    std::string fallback;  // "" when converted whole at the first try
    RegionFate fate = RegionFate::Failed;
    bool converted() const { return fate != RegionFate::Failed; }
    std::string sideNotes;  // SplitAtNecks: what the sides' own conversions did
    double spill = 0;       // --total-patches: spillSse of the meshes
};

// The squared error (0-255 units; per pixel the mean over its channels, summed over pixels, as
// FitError's rmse² times pixels) that the meshes of region `k` make where they paint pixels of
// the regions drawn before it (drawnAt < k): folds and outline deviation put their colours
// there, on top, and the region's own error does not see them.
double spillSse(const std::vector<GradientMesh>& meshes, const RgbaImage& image,
                const std::vector<int>& drawnAt, int k) {
    Document own;
    own.width = image.width;
    own.height = image.height;
    own.meshes = meshes;
    std::vector<uint8_t> beneath(drawnAt.size());
    for (size_t p = 0; p < beneath.size(); ++p) beneath[p] = drawnAt[p] >= 0 && drawnAt[p] < k;
    RenderOptions renderOptions;
    renderOptions.threads = 1;
    const FitError e = compareOverMask(image, renderDocument(own, renderOptions).image, beneath);
    return e.rmse * e.rmse * double(e.pixels) * (1 - e.uncovered);
}

// The region's budget: its pixels / pixelsPerPatch within [minRegionPatches, maxPatches].
ConvertOptions budgetFor(const Region& own, const ConvertOptions& sharedOptions,
                         const SegmentConvertOptions& options) {
    ConvertOptions convertOptions = sharedOptions;
    if (options.pixelsPerPatch > 0)
        convertOptions.maxPatches =
            std::clamp(static_cast<int>(own.pixelCount / options.pixelsPerPatch),
                       std::min(options.minRegionPatches, convertOptions.maxPatches),
                       convertOptions.maxPatches);
    return convertOptions;
}

// One region whole, reaching under `under` (the regions drawn later): Whole, or Failed with the
// reason in `fallback`.
RegionOutcome convertWhole(const RgbaImage& image, const Region& own,
                           const std::vector<uint8_t>& under, const ConvertOptions& convertOptions,
                           const SegmentConvertOptions& options, RegionMapCache* cache) {
    RegionOutcome out;
    try {
        out.meshes = {convertRegion(image, growRegionInto(own, options.overlap, 0, under),
                                    convertOptions, out.report, cache)};
        out.fate = RegionFate::Whole;
    } catch (const Error& e) {
        out.fallback = e.reason();
    } catch (const std::bad_alloc&) {
        throw;  // out of memory ends the command, not just this attempt
    } catch (const std::exception& e) {
        out.fallback = e.what();
    }
    return out;
}

// After convertWhole failed (`out`, its reason in out.fallback): the region with its holes
// filled, then as its core plus its thin parts apart; else nothing (Failed).
RegionOutcome convertFallbacks(const RgbaImage& image, const Region& own,
                               const std::vector<uint8_t>& under,
                               const ConvertOptions& convertOptions,
                               const SegmentConvertOptions& options, RegionOutcome out) {
    std::string& why = out.fallback;
    if (!own.holes.empty()) {
        // Its holes are other regions, drawn on top: the region without them still paints its
        // own pixels.
        try {
            out.meshes = {convertRegion(
                image, growRegionInto(own, options.overlap, std::numeric_limits<int>::max(), under),
                convertOptions, out.report)};
            out.fate = RegionFate::HolesFilled;
            why = "holes filled (" + why + ")";
            return out;
        } catch (const std::bad_alloc&) {
            throw;  // out of memory ends the command, not just this attempt
        } catch (const std::exception& e) {
            why += "; with holes filled: " + std::string(e.what());
        }
    }
    // Its core without its thin parts, then each thin part its own mesh on top (in parts or
    // tiles where no map works: convertThinParts), reaching under the later regions and a
    // pixel over the core.
    for (const int radius : {2, 5}) try {
        const std::vector<uint8_t> core = openMask(own.mask, own.width, own.height, radius);
        RegionOptions regionOptions;
        regionOptions.minArea = 16;
        regionOptions.minHole = std::numeric_limits<int>::max();
        std::vector<Region> cores =
            extractRegions(coverageFromBits(own.width, own.height, core), regionOptions);
        if (cores.empty()) throw Error("nothing is left without its thin parts");
        Region trimmed = growRegionInto(cores.front(), options.overlap, 0, under);
        out.meshes = {convertRegion(image, trimmed, convertOptions, out.report)};
        out.fate = RegionFate::ThinPartsApart;
        std::vector<uint8_t> rest(own.mask.size());
        PartsBeneath beneath;
        beneath.under = under;
        beneath.overlap = options.overlap;
        for (size_t p = 0; p < rest.size(); ++p) {
            rest[p] = own.mask[p] && !cores.front().mask[p];
            beneath.under[p] = beneath.under[p] || cores.front().mask[p];
        }
        std::vector<RegionReport> parts{out.report};
        convertThinParts(image, rest, convertOptions, beneath, out.meshes, parts);
        out.report = mergePartReports(parts, own);
        why = "parts thinner than " + std::to_string(2 * radius + 1) + " px (" +
              std::to_string(own.pixelCount - cores.front().pixelCount) + " px) as " +
              std::to_string(out.meshes.size() - 1) + " meshes of their own: " + why;
        return out;
    } catch (const std::bad_alloc&) {
        throw;  // out of memory ends the command, not just this attempt
    } catch (const std::exception& e) {
        why += "; without parts thinner than " + std::to_string(2 * radius + 1) +
               " px: " + std::string(e.what());
    }
    out.meshes.clear();
    out.report = RegionReport{};
    out.report.pixels = own.pixelCount;
    out.report.holes = static_cast<int>(own.holes.size());
    why = "left to the base mesh (" + why + ")";
    return out;
}

RegionOutcome convertSegmentRegion(const RgbaImage& image, const Region& own,
                                   const std::vector<uint8_t>& under,
                                   const ConvertOptions& sharedOptions,
                                   const SegmentConvertOptions& options, int depth,
                                   RegionMapCache* cache = nullptr);

// The inverted area (foldedArea) of some meshes, pixels.
double foldedAreaOf(const std::vector<GradientMesh>& meshes) {
    double area = 0;
    for (const GradientMesh& m : meshes) area += foldedArea(m);
    return area;
}

// The region cut at `cut`, each side's pieces converted by convertSegmentRegion (side 1 drawn
// first, reaching under side 2), sharing the region's budget convertOptions.maxPatches by their
// pixels; SplitAtNecks, or Failed when nothing converted. `complete`: every piece converted.
RegionOutcome convertSides(const RgbaImage& image, const Region& own,
                           const std::vector<uint8_t>& under, const ConvertOptions& convertOptions,
                           const SegmentConvertOptions& options, int depth, const NeckCut& cut,
                           bool& complete) {
    RegionOptions regionOptions;
    regionOptions.minArea = 1;
    regionOptions.minHole = convertOptions.minHole;
    std::vector<RegionReport> parts;
    RegionOutcome split;
    std::vector<std::string> notes;
    complete = true;
    for (const uint8_t side : {uint8_t(1), uint8_t(2)}) {
        std::vector<uint8_t> bits(own.mask.size()), beneath = under;
        for (size_t p = 0; p < bits.size(); ++p) {
            bits[p] = cut.side[p] == side;
            if (side == 1 && cut.side[p] == 2) beneath[p] = 1;
        }
        std::vector<Region> pieces;
        try {
            pieces = extractRegions(coverageFromBits(own.width, own.height, bits), regionOptions);
        } catch (const Error&) {
            complete = false;
            continue;
        }
        for (const Region& piece : pieces) {
            ConvertOptions share = convertOptions;
            share.maxPatches = std::max<int>(
                1, static_cast<int>(std::lround(double(convertOptions.maxPatches) *
                                                piece.pixelCount / std::max(1, own.pixelCount))));
            RegionOutcome sub = convertSegmentRegion(image, piece, beneath, share, options, depth + 1);
            for (GradientMesh& m : sub.meshes) split.meshes.push_back(std::move(m));
            if (!sub.converted()) {
                sub.report.part = "left uncovered";
                complete = false;
            }
            parts.push_back(sub.report);
            if (!sub.fallback.empty()) notes.push_back(sub.fallback);
        }
    }
    if (parts.empty() || split.meshes.empty()) {
        complete = false;
        return RegionOutcome{};
    }
    split.report = mergePartReports(parts, own);
    split.report.part = "split at a neck into " + std::to_string(parts.size());
    split.fate = RegionFate::SplitAtNecks;
    char buf[120];
    std::snprintf(buf, sizeof buf, "split at a neck (%.0f px chord at (%.0f, %.0f)-(%.0f, %.0f))",
                  norm(cut.b - cut.a), cut.a.x, cut.a.y, cut.b.x, cut.b.y);
    split.fallback = buf;
    for (const std::string& note : notes) split.sideNotes += "; a side: " + note;
    return split;
}

// The region whole; when that misses the error target by more than neckErrorFactor or fails,
// the region cut at its narrowest neck (findNeck) with each side converted the same way
// (recursively, up to neckSplits cuts deep). A cut is kept when it lowers the region's error by
// 5 %, or, where the whole failed, when every side converted; else the whole's fallbacks
// (convertFallbacks) are tried, and the better of those and the cut kept. `cache`: the
// region's maps from its conversions at other budgets (RegionMapCache), for the whole.
RegionOutcome convertSegmentRegion(const RgbaImage& image, const Region& own,
                                   const std::vector<uint8_t>& under,
                                   const ConvertOptions& sharedOptions,
                                   const SegmentConvertOptions& options, int depth,
                                   RegionMapCache* cache) {
    const ConvertOptions convertOptions = budgetFor(own, sharedOptions, options);
    RegionOutcome out = convertWhole(image, own, under, convertOptions, options, cache);
    const double target = convertOptions.maxError * options.neckErrorFactor;
    const bool mayCut = depth < options.neckSplits && own.pixelCount >= options.neckMinPixels;
    // Folds matter where they paint over regions drawn before this one: the first region drawn
    // has none (whatever it spills over is painted again by the later ones).
    bool earlier = false;
    for (size_t p = 0; p < under.size() && !earlier; ++p) earlier = !own.mask[p] && !under[p];
    const double folded =
        mayCut && earlier && out.converted() && options.foldedArea > 0 ? foldedAreaOf(out.meshes) : 0;
    const bool folds = folded > options.foldedArea;
    std::optional<NeckCut> cut;
    if (mayCut && (!out.converted() || out.report.error.meanAbs > target || folds))
        cut = findNeck(own, options.neck);
    RegionOutcome split;
    bool complete = false;
    if (cut)
        split = convertSides(image, own, under, convertOptions, options, depth, *cut, complete);
    auto take = [&](RegionOutcome& whole) {
        const double e = whole.report.error.meanAbs;
        const bool covers =
            split.report.error.uncovered <= whole.report.error.uncovered + 0.001;
        const double splitFolded = folds && split.converted() ? foldedAreaOf(split.meshes) : 0;
        const bool unfolds = folds && split.converted() && covers &&
                             split.report.error.meanAbs <= 1.1 * e && splitFolded <= folded / 2;
        const bool better =
            split.converted() &&
            (!whole.converted() || (split.report.error.meanAbs < 0.95 * e && covers) || unfolds);
        if (!better) return std::move(whole);
        char buf[120];
        std::snprintf(buf, sizeof buf, ": E %.2f -> %.2f", e, split.report.error.meanAbs);
        if (whole.converted()) split.fallback += buf;
        if (unfolds) {
            std::snprintf(buf, sizeof buf, ", folded area %.0f -> %.0f px", folded, splitFolded);
            split.fallback += buf;
        }
        split.fallback += split.sideNotes;
        if (!whole.fallback.empty()) split.fallback += "; whole: " + whole.fallback;
        return std::move(split);
    };
    if (out.converted()) return take(out);
    if (complete) {
        split.fallback += split.sideNotes + "; whole: " + out.fallback;
        return split;
    }
    RegionOutcome fallback =
        convertFallbacks(image, own, under, convertOptions, options, std::move(out));
    return take(fallback);
}

// The budgets of the --total-patches ladder: 4·2^(i/2) rounded (4, 6, 8, 11, 16, 23, 32, 45, ...).
int budgetRung(int i) {
    return static_cast<int>(std::min(1e9, std::round(4 * std::pow(2.0, i / 2.0))));
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A C×R mesh of straight patches over the whole canvas, colours fitted in the conversion's
// colour mode to the pixels `showing` marks (every pixel when it marks none).
GradientMesh baseMesh(const RgbaImage& image, double patchSize, int threads, ColorMode mode,
                      const std::vector<uint8_t>& showing) {
    const int C = std::max(1, static_cast<int>(std::lround(image.width / patchSize)));
    const int R = std::max(1, static_cast<int>(std::lround(image.height / patchSize)));
    GradientMesh m(C, R);
    const double du = double(image.width) / C, dv = double(image.height) / R;
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            Node& n = m.node(i, j);
            n.pos = {i * du, j * dv};
            n.posU = {du, 0};
            n.posV = {0, dv};
        }
    Region fitted;
    fitted.width = image.width;
    fitted.height = image.height;
    fitted.pixelCount = static_cast<int>(std::count(showing.begin(), showing.end(), 1));
    fitted.mask = showing;
    if (fitted.pixelCount == 0) {
        fitted.mask.assign(static_cast<size_t>(image.width) * image.height, 1);
        fitted.pixelCount = image.width * image.height;
    }
    ColorOptions colorOptions;
    colorOptions.threads = threads;
    colorOptions.mode = mode;
    return computeColors(m, image, fitted, colorOptions).mesh;
}

// Per pixel, whether `drawn` (the regions' meshes and shapes, without the base) leaves some of
// it showing; and the share of pixels it leaves mostly bare (covered under one half, as
// compareOverMask counts them uncovered).
std::vector<uint8_t> pixelsShowing(const Document& drawn, const RgbaImage& image,
                                   double& uncovered) {
    const size_t n = static_cast<size_t>(image.width) * image.height;
    if (drawn.meshes.empty() && drawn.shapes.empty()) {
        uncovered = 1;
        return std::vector<uint8_t>(n, 1);
    }
    const RgbaImage render = renderDocument(drawn, RenderOptions{}).image;
    std::vector<uint8_t> showing(n, 0);
    long bare = 0;
    for (size_t k = 0; k < n; ++k) {
        const float covered = render.pixels[4 * k + 3];
        showing[k] = covered < 0.999f;
        bare += covered < 0.5f;
    }
    uncovered = double(bare) / double(n);
    return showing;
}
}  // namespace

// (convert_segments.h)
std::vector<RdPoint> paretoFront(std::vector<RdPoint> points) {
    std::sort(points.begin(), points.end(), [](const RdPoint& a, const RdPoint& b) {
        return a.patches < b.patches || (a.patches == b.patches && a.sse < b.sse);
    });
    std::vector<RdPoint> front;
    for (const RdPoint& p : points)
        if (front.empty() || (p.patches > front.back().patches && p.sse < front.back().sse))
            front.push_back(p);
    return front;
}

// (convert_segments.h)
std::vector<size_t> allotPatches(const std::vector<std::vector<RdPoint>>& fronts, int total) {
    const size_t n = fronts.size();
    std::vector<size_t> at(n, 0);
    // Patches beyond each region's first point, in units of `unit` patches (rounded up,
    // so that what is chosen always fits); `room` is what the total leaves for them.
    long first = 0, most = 0;
    for (const auto& f : fronts) {
        first += std::lround(f.front().patches);
        most += std::lround(f.back().patches - f.front().patches);
    }
    long room = std::min<long>(static_cast<long>(total) - first, most);
    if (room <= 0 || n == 0) return at;
    const long unit = std::max(1L, static_cast<long>(std::ceil(double(n) * double(room + 1) /
                                                                kAllotCells)));
    const long cells = room / unit + 1;
    // Units beyond its region's first point that point i of front f takes.
    auto unitsOf = [unit](const std::vector<RdPoint>& f, size_t i) {
        return (std::lround(f[i].patches - f.front().patches) + unit - 1) / unit;
    };
    // best[t]: the least summed error of the regions so far with at most t units beyond
    // their first points; pick[k][t]: region k's point there.
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> best(static_cast<size_t>(cells), 0.0), next(best.size());
    std::vector<std::vector<uint16_t>> pick(n, std::vector<uint16_t>(best.size(), 0));
    for (size_t k = 0; k < n; ++k) {
        const auto& f = fronts[k];
        const size_t m = std::min<size_t>(f.size(), 65535);
        std::fill(next.begin(), next.end(), inf);
        for (size_t i = 0; i < m; ++i) {
            const long extra = unitsOf(f, i);
            for (long t = extra; t < cells; ++t) {
                const double v = best[static_cast<size_t>(t - extra)] + f[i].sse;
                if (v < next[static_cast<size_t>(t)]) {
                    next[static_cast<size_t>(t)] = v;
                    pick[k][static_cast<size_t>(t)] = static_cast<uint16_t>(i);
                }
            }
        }
        best.swap(next);
    }
    long t = cells - 1;
    for (size_t k = n; k-- > 0;) {
        at[k] = pick[k][static_cast<size_t>(t)];
        t -= unitsOf(fronts[k], at[k]);
    }
    return at;
}

namespace {

// The image's regions as the segmentation draws them, the ink lines last (drawn over the
// regions they divide, whatever their size), from firstInk on; times and figures into
// segmentReport.
std::vector<Region> segmentRegions(const RgbaImage& image, const SegmentConvertOptions& options,
                                   const std::string& imageName, Segmentation& seg,
                                   size_t& firstInk, SegmentConvertReport& segmentReport) {
    reportProgress(options.convert, "segmentation");
    auto t0 = Clock::now();
    try {
        SegmentOptions segmentOptions = options.segment;
        if (segmentOptions.threads == 0) segmentOptions.threads = options.threads;
        // Free colour slopes bend as steeply as an outline does, in our renderer, the only
        // one that draws them: for them ink lines as flat shapes only cost quality.
        if (options.convert.colors == ColorMode::Fit) segmentOptions.inkLines = false;
        seg = segmentImage(image, segmentOptions);
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw Error("segmentation: " + e.reason(), imageName);
    }
    segmentReport.segmentation = seg.stats;
    segmentReport.segmentSeconds = since(t0);

    t0 = Clock::now();
    RegionOptions regionOptions;
    regionOptions.minArea = 1;
    regionOptions.minHole = options.convert.minHole;
    std::vector<Region> regions =
        extractRegionsFromLabels(seg.width, seg.height, seg.labels, regionOptions);
    const int firstInkLabel = seg.count - seg.inkLabels;
    firstInk = static_cast<size_t>(
        std::stable_partition(regions.begin(), regions.end(),
                              [&](const Region& r) { return r.label < firstInkLabel; }) -
        regions.begin());
    segmentReport.regionsSeconds = since(t0);
    segmentReport.convert.seconds.regions =
        segmentReport.segmentSeconds + segmentReport.regionsSeconds;
    return regions;
}

// flatOnly: a region joins the backdrop when its colour lies within this share of
// --max-error of the backdrop's in every channel (flat_backdrop.h): its pixels then move by
// no more than the error the conversion aims at.
constexpr double kBackdropMergeShare = 1.0;

// Whether the cubic a, h1, h2, b has its handles at the thirds of its chord: a line.
bool isStraight(Vec2 a, Vec2 h1, Vec2 h2, Vec2 b) {
    return norm(h1 - (a + (1.0 / 3) * (b - a))) < 1e-6 &&
           norm(h2 - (a + (2.0 / 3) * (b - a))) < 1e-6;
}

// A subpath's points on a grid of `step` pixels (a closed centreline's last point, its first,
// stays so); a straight segment's handles stay at the thirds of its moved ends, so that it is
// still written as a line.
void snapSubpath(std::vector<Vec2>& path, bool closed, double step) {
    const size_t n = path.size(), segments = closed ? n / 3 : (n - 1) / 3;
    std::vector<char> straight(segments);
    for (size_t m = 0; m < segments; ++m)
        straight[m] =
            isStraight(path[3 * m], path[3 * m + 1], path[3 * m + 2], path[(3 * m + 3) % n]);
    auto snap = [step](Vec2 p) {
        return Vec2{std::round(p.x / step) * step, std::round(p.y / step) * step};
    };
    for (Vec2& p : path) p = snap(p);
    for (size_t m = 0; m < segments; ++m)
        if (straight[m]) {
            const Vec2 a = path[3 * m], b = path[(3 * m + 3) % n];
            path[3 * m + 1] = a + (1.0 / 3) * (b - a);
            path[3 * m + 2] = a + (2.0 / 3) * (b - a);
        }
}

// The shapes' points on a grid of options.coarseGrid pixels when they were fitted within
// `tolerance` of at least options.coarseGridTolerance: a point moves at most 0.71 of a grid
// step, well within the fit, and an SVG writes its coordinates with a decimal fewer.
void snapToGrid(std::vector<FlatShape>& shapes, double tolerance, const FlatOptions& options) {
    if (!(options.coarseGrid > 0) || tolerance < options.coarseGridTolerance) return;
    for (FlatShape& shape : shapes) {
        FlatShape snapped = shape;
        for (std::vector<Vec2>& path : snapped.subpaths)
            snapSubpath(path, !shape.stroked(), options.coarseGrid);
        // A loop that fell onto one grid point is gone (a speck of the region); a shape that
        // would be nothing but specks keeps its points as they were.
        auto collapsed = [&](const std::vector<Vec2>& path) {
            return !shape.stroked() && std::all_of(path.begin(), path.end(),
                                                   [&](Vec2 p) { return p == path.front(); });
        };
        snapped.subpaths.erase(
            std::remove_if(snapped.subpaths.begin(), snapped.subpaths.end(), collapsed),
            snapped.subpaths.end());
        if (!snapped.subpaths.empty()) shape = std::move(snapped);
    }
}

// Converts regions of a whole image, several at once. Regions are drawn in their order
// (largest first): a region reaches under the later ones only, so each pixel keeps the
// colour of its own region and seams show the region beneath.
class RegionConverter {
public:
    // Regions from firstInk on are ink lines (segmentRegions).
    RegionConverter(const RgbaImage& image, const std::vector<Region>& regions, size_t firstInk,
                    const SegmentConvertOptions& options)
        : image_(image), regions_(regions), firstInk_(firstInk), options_(options),
          caches_(regions.size()) {
        // Each region's fit renders on one thread when regions run in parallel.
        const int hw = std::max(1u, std::thread::hardware_concurrency());
        workers_ = std::max(1, std::min<int>(options.threads > 0 ? options.threads : hw,
                                             static_cast<int>(regions.size())));
        convert_ = options.convert;
        convert_.subPixelEdgePull = options.subPixelEdgePull;
        convert_.progress = nullptr;  // regions done are counted here, not their stages
        if (workers_ > 1) convert_.threads = 1;
        drawnAt_ = firstRegionAt(regions);
        drawnAt_.resize(static_cast<size_t>(image.width) * image.height, -1);
        flat_.resize(regions.size());
        graded_.resize(regions.size());
        if (options.flatShapes) {
            // Per pixel the last region holding it: a hole under --min-hole that a region's
            // mask fills is another region's, drawn on top of it.
            std::vector<int> lastAt(drawnAt_.size(), -1);
            for (size_t k = 0; k < regions.size(); ++k)
                for (size_t p = 0; p < lastAt.size(); ++p)
                    if (regions[k].mask[p]) lastAt[p] = static_cast<int>(k);
            parallelFor(static_cast<int>(regions.size()), workers_, [&](int k, int) {
                Region own = regions[static_cast<size_t>(k)];
                for (size_t p = 0; p < own.mask.size(); ++p) own.mask[p] = lastAt[p] == k;
                FlatFit& fit = flat_[static_cast<size_t>(k)];
                fit = fitFlatColour(image, own, options.convert.maxError,
                                    static_cast<size_t>(k) >= firstInk, options.flat);
                if (!fit.flat && options.gradients && static_cast<size_t>(k) < firstInk)
                    graded_[static_cast<size_t>(k)] =
                        fitGradedRegion(image, own, options.convert.maxError, options.gradient);
            });
        }
    }

    int maxPatches() const { return convert_.maxPatches; }
    bool isFlat(size_t k) const { return flat_[k].flat; }
    // Region k's fitted colour (known with flatShapes only).
    const Vec3& flatColour(size_t k) const { return flat_[k].col; }

    // Converts region jobs[w].first with patch budget jobs[w].second into outcomes[w], the
    // jobs in parallel. A flat region is a flat shape (a mesh when its outline cannot be
    // traced); budget 0 for a shaded one asks for it as a flat shape all the same (Failed when
    // its outline cannot be traced). With --total-patches a region converted at several
    // budgets computes its maps once, and each outcome's spill is measured.
    void run(const std::vector<std::pair<size_t, int>>& jobs,
             std::vector<RegionOutcome>& outcomes) {
        outcomes.resize(jobs.size());
        const bool budgeted = options_.totalPatches > 0;
        const int total = static_cast<int>(jobs.size());
        std::atomic<int> done{0};
        reportProgress(options_.convert, "regions", 0, total);
        parallelFor(total, workers_, [&](int job, int) {
            const size_t w = static_cast<size_t>(job);
            const size_t k = jobs[w].first;
            const bool flatAnyway = jobs[w].second == 0 && !isFlat(k);
            if (isFlat(k) || flatAnyway) outcomes[w] = flatOutcome(k);
            if (!flatAnyway && !outcomes[w].converted()) {
                ConvertOptions convertOptions = convert_;
                convertOptions.maxPatches = jobs[w].second > 0 ? jobs[w].second : convert_.maxPatches;
                outcomes[w] =
                    convertSegmentRegion(image_, regions_[k], drawnLater(k), convertOptions,
                                         options_, 0, budgeted ? &caches_[k] : nullptr);
                if (budgeted && outcomes[w].converted())
                    outcomes[w].spill =
                        spillSse(outcomes[w].meshes, image_, drawnAt_, static_cast<int>(k));
                if (!graded_[k].stops.empty()) preferGraded(k, outcomes[w]);
            }
            reportProgress(options_.convert, "regions", ++done, total);
        });
    }

    // Region k's fill: the gradient flatOutcome paints it with, or none (its flat colour).
    LinearGradient fillGradient(size_t k) const { return flatGradient(k); }

private:
    // Region k as a flat shape reaching under the later regions; Failed (the reason in
    // `fallback`) when its outline cannot be traced.
    RegionOutcome flatOutcome(size_t k) const {
        RegionOutcome out;
        const Region& own = regions_[k];
        LinearGradient gradient;
        try {
            FlatOptions flatOptions = options_.flat;
            const double coarser =
                std::max(1.0, options_.convert.maxError / flatOptions.toleranceError);
            flatOptions.curveTolerance *= coarser;
            flatOptions.inkCurveTolerance *= coarser;
            if (k >= firstInk_) {
                flatOptions.curveTolerance = flatOptions.inkCurveTolerance;
                flatOptions.outlineSmoothing = flatOptions.inkOutlineSmoothing;
                flatOptions.blendEachSide = true;
            }
            gradient = flatGradient(k);
            if (options_.strokes && gradient.stops.empty()) {
                StrokeOptions strokeOptions = options_.stroke;
                strokeOptions.curveTolerance *= coarser;
                strokeOptions.maxMismatch *= coarser;
                strokeOptions.maxWrongShare *= coarser;
                out.shapes = traceStrokes(image_, own, flat_[k].col, drawnLaterOrNone(k),
                                          strokeOptions);
                if (!out.shapes.empty())
                    snapToGrid(out.shapes, strokeOptions.curveTolerance, flatOptions);
            }
            if (out.shapes.empty()) {
                out.shapes = {traceFlatShape(image_, own, flat_[k].col, options_.overlap,
                                             drawnLaterOrNone(k), flatOptions, gradient)};
                snapToGrid(out.shapes, flatOptions.curveTolerance, flatOptions);
            }
        } catch (const Error& e) {
            out.fallback = "as a flat shape: " + e.reason();
            return out;
        }
        out.fate = RegionFate::Flat;
        out.report.pixels = own.pixelCount;
        out.report.holes = static_cast<int>(own.holes.size());
        const bool graded = out.shapes.front().graded();
        out.report.part = out.shapes.front().stroked() ? "stroke" : graded ? "gradient" : "flat";
        out.report.error =
            graded ? gradientFitError(image_, shownPixels(k), gradient) : flat_[k].all;
        return out;
    }

    // Region k as its graded flat shape instead of `meshed` (its mesh outcome) when that draws
    // it no worse: E and RMSE over the pixels where it shows at most the mesh's.
    void preferGraded(size_t k, RegionOutcome& meshed) const {
        RegionOutcome graded = flatOutcome(k);
        if (!graded.converted()) return;
        const FitError& g = graded.report.error;
        const FitError& m = meshed.report.error;
        if (meshed.converted() && (g.meanAbs > m.meanAbs || g.rmse > m.rmse)) return;
        meshed = std::move(graded);
    }

    // Region k's gradient: the one that fits it in place of a mesh, else (a flat region before
    // the ink lines, with gradients) the one that pays for its bytes, fitted to the pixels
    // inside it that show (border pixels blend with the neighbours); else none.
    LinearGradient flatGradient(size_t k) const {
        if (!graded_[k].stops.empty()) return graded_[k];
        if (!options_.gradients || k >= firstInk_) return {};
        const Region& own = regions_[k];
        const std::vector<size_t> shown = shownPixels(k);
        std::vector<size_t> inside;
        for (size_t p : shown)
            if (insideMask(own.mask, own.width, own.height, p)) inside.push_back(p);
        // A thin region (a rim, a frame) is nearly all border: its few inside pixels say
        // nothing of the colour along it.
        if (double(inside.size()) < options_.flat.minInteriorShare * double(shown.size())) return {};
        GradientFitOptions gradientOptions = options_.gradient;
        gradientOptions.errorPerByte = options_.flatErrorPerByte;
        return fitPayingGradient(image_, inside, flat_[k].col, gradientOptions);
    }

    // The pixels of region k that no later region paints over.
    std::vector<size_t> shownPixels(size_t k) const {
        std::vector<size_t> shown;
        const std::vector<uint8_t>& mask = regions_[k].mask;
        for (size_t p = 0; p < mask.size(); ++p)
            if (mask[p] && !(drawnAt_[p] > static_cast<int>(k))) shown.push_back(p);
        return shown;
    }

    // ... and the pixels of no region (the base mesh paints them, beneath every shape): a flat
    // shape covers such specks rather than leave holes around them.
    std::vector<uint8_t> drawnLaterOrNone(size_t k) const {
        std::vector<uint8_t> m(drawnAt_.size());
        for (size_t p = 0; p < m.size(); ++p)
            m[p] = drawnAt_[p] > static_cast<int>(k) || drawnAt_[p] < 0;
        return m;
    }

    // Pixels of the regions drawn after region k.
    std::vector<uint8_t> drawnLater(size_t k) const {
        std::vector<uint8_t> m(drawnAt_.size());
        for (size_t p = 0; p < m.size(); ++p) m[p] = drawnAt_[p] > static_cast<int>(k);
        return m;
    }

    const RgbaImage& image_;
    const std::vector<Region>& regions_;
    const size_t firstInk_;
    const SegmentConvertOptions& options_;
    ConvertOptions convert_;
    int workers_ = 1;
    std::vector<int> drawnAt_;  // per pixel: the first region (in drawing order) holding it
    std::vector<RegionMapCache> caches_;
    std::vector<FlatFit> flat_;  // per region: its colour and whether it is flat
    std::vector<LinearGradient> graded_;  // per region not flat: the gradient that fits it
};

// --total-patches: every region at the budget ladder up to a generous budget, to measure its
// error curve; then the budget goes where it lowers the summed error most. One outcome per
// region.
std::vector<RegionOutcome> convertWithinTotal(RegionConverter& converter,
                                              const std::vector<Region>& regions,
                                              const SegmentConvertOptions& options,
                                              SegmentConvertReport& segmentReport) {
    const size_t n = regions.size();
    std::vector<std::pair<size_t, int>> jobs;
    long pixels = 0;
    for (const Region& r : regions) pixels += r.pixelCount;
    for (size_t k = 0; k < n; ++k) {
        const double share = options.topBudgetShare * options.totalPatches *
                             double(regions[k].pixelCount) / double(std::max(1L, pixels));
        const double floor = options.topBudgetShare * options.totalPatches / double(n);
        const double want = std::max(share, floor);
        // A flat shape, no patches: the region's colour alone, for a flat one; for a shaded
        // one, the first rung of its ladder.
        const bool flatRung = options.flatRungs && options.flatShapes;
        if (converter.isFlat(k) || flatRung) jobs.push_back({k, 0});
        if (converter.isFlat(k)) continue;
        for (int i = 0;; ++i) {
            const int b = std::min(budgetRung(i), converter.maxPatches());
            jobs.push_back({k, b});
            if (b >= want || b == converter.maxPatches()) break;
        }
    }
    // Largest budgets first: the slowest jobs start first.
    std::stable_sort(jobs.begin(), jobs.end(),
                     [](const auto& x, const auto& y) { return x.second > y.second; });
    std::vector<RegionOutcome> outcomes;
    converter.run(jobs, outcomes);
    std::vector<std::vector<size_t>> tried(n);  // per region: its jobs
    for (size_t w = 0; w < jobs.size(); ++w) tried[jobs[w].first].push_back(w);
    std::vector<std::vector<RdPoint>> curves(n);
    for (size_t k = 0; k < n; ++k) {
        std::vector<RdPoint> points;
        for (size_t w : tried[k]) {
            const RegionOutcome& o = outcomes[w];
            if (!o.converted()) continue;
            const double covered = double(o.report.error.pixels) * (1 - o.report.error.uncovered);
            // Its own pixels' error and what it does to the regions beneath: a mesh that folds
            // over a neighbour looks good on its own.
            points.push_back({double(o.report.patches),
                              o.report.error.rmse * o.report.error.rmse * covered + o.spill, w});
        }
        if (points.empty()) points.push_back({0, 0, tried[k].front()});  // left to the base mesh
        curves[k] = paretoFront(std::move(points));
    }
    const std::vector<size_t> pick = allotPatches(curves, options.totalPatches);
    std::vector<RegionOutcome> chosen(n);
    for (size_t k = 0; k < n; ++k) {
        const size_t w = curves[k][pick[k]].job;
        segmentReport.keptSpill.push_back(outcomes[w].converted() ? outcomes[w].spill : 0);
        chosen[k] = std::move(outcomes[w]);
        int most = 0;
        for (size_t v : tried[k]) most = std::max(most, jobs[v].second);
        segmentReport.largestBudget.push_back(most);
        segmentReport.keptBudget.push_back(jobs[w].second);
    }
    segmentReport.conversions = static_cast<int>(jobs.size());
    return chosen;
}

// The document: the base mesh (coarse when every region converted), then every region's
// meshes in drawing order; the regions' reports and fates counted into segmentReport. The base
// is fitted to the pixels the regions leave showing: fitted to all, its few patches take their
// colours from the whole image, and where a region's mesh leaves a corner of the canvas bare
// they paint it in colours from elsewhere.
Document assembleDocument(const RgbaImage& image, const std::vector<Region>& regions,
                          std::vector<RegionOutcome>& outcomes,
                          const SegmentConvertOptions& options,
                          SegmentConvertReport& segmentReport) {
    ConvertReport& convertReport = segmentReport.convert;
    Document doc;
    doc.width = image.width;
    doc.height = image.height;
    const bool anyFailed = std::any_of(outcomes.begin(), outcomes.end(),
                                       [](const RegionOutcome& o) { return !o.converted(); });
    for (size_t k = 0; k < regions.size(); ++k) {
        RegionOutcome& o = outcomes[k];
        if (o.converted())
            for (GradientMesh& m : o.meshes) doc.meshes.push_back(std::move(m));
        for (FlatShape& shape : o.shapes) {
            shape.layer = doc.meshes.size();
            doc.shapes.push_back(std::move(shape));
        }
        segmentReport.flatRegions += o.fate == RegionFate::Flat;
        segmentReport.failedRegions += o.fate == RegionFate::Failed;
        segmentReport.filledRegions += o.fate == RegionFate::HolesFilled;
        segmentReport.trimmedRegions += o.fate == RegionFate::ThinPartsApart;
        segmentReport.splitRegions += o.fate == RegionFate::SplitAtNecks;
        convertReport.patches += o.report.patches;
        convertReport.seconds += o.report.seconds;
        segmentReport.regionLabels.push_back(regions[k].label);
        segmentReport.fallbacks.push_back(std::move(o.fallback));
        convertReport.regions.push_back(std::move(o.report));
    }
    const auto t0 = Clock::now();
    const std::vector<uint8_t> showing =
        pixelsShowing(doc, image, segmentReport.regionUncovered);
    // A drawing of flat shapes only: the region drawn first, beneath all the others, becomes
    // a backdrop over the whole canvas (an outline of four lines rather than one around every
    // other region), in place of the base mesh, so that the file holds no mesh at all.
    if (!anyFailed && doc.meshes.empty() && !doc.shapes.empty() &&
        outcomes.front().fate == RegionFate::Flat) {
        const size_t firstShapes = outcomes.front().shapes.size();
        const Vec3 col = doc.shapes.front().col;
        doc.shapes.erase(doc.shapes.begin(), doc.shapes.begin() + static_cast<long>(firstShapes));
        doc.shapes.insert(doc.shapes.begin(), canvasRectangle(image.width, image.height, col));
        segmentReport.flatBackdrop = true;
    } else {
        GradientMesh base =
            baseMesh(image, anyFailed ? options.basePatchSize : options.coarseBasePatchSize,
                     options.convert.threads, options.convert.colors, showing);
        segmentReport.basePatches = base.patchCount();
        doc.meshes.insert(doc.meshes.begin(), std::move(base));
        for (FlatShape& shape : doc.shapes) ++shape.layer;
    }
    convertReport.seconds.mesh += since(t0);
    convertReport.patches += segmentReport.basePatches;
    return doc;
}

// The error over every pixel, at region borders and inside (the pixels no region covers are
// counted by assembleDocument).
void measureSegmented(const Document& doc, const RgbaImage& image, const std::vector<int>& labels,
                      SegmentConvertReport& segmentReport) {
    const RenderResult full = renderDocument(doc, RenderOptions{});
    const size_t np = static_cast<size_t>(image.width) * image.height;
    std::vector<uint8_t> all(np, 1), border(np, 0), inner(np, 0);
    const int w = image.width, h = image.height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            const int l = labels[k];
            const bool b = (x > 0 && labels[k - 1] != l) || (x + 1 < w && labels[k + 1] != l) ||
                           (y > 0 && labels[k - w] != l) || (y + 1 < h && labels[k + w] != l);
            (b ? border : inner)[k] = 1;
        }
    segmentReport.convert.error = compareOverMask(image, full.image, all);
    segmentReport.border = compareOverMask(image, full.image, border);
    segmentReport.interior = compareOverMask(image, full.image, inner);
}

// Whether to segment again towards options.shadedSegments (SegmentConvertOptions): the count
// was automatic, a total budget (if any) allows finerPatchesPerSegment patches per region, ink
// lines were looked for and none found, and the shaded regions hold at least shadedShare of
// the pixels.
bool wantsFinerSegments(const SegmentConvertOptions& options, const Segmentation& seg,
                        const std::vector<Region>& regions, size_t firstInk,
                        const RegionConverter& converter) {
    const bool inkLooked =
        options.segment.inkLines && options.convert.colors != ColorMode::Fit;
    if (options.shadedSegments <= 0 || options.segment.segments > 0 ||
        options.segment.threshold > 0 || !inkLooked || seg.inkLabels > 0 || regions.empty())
        return false;
    if (options.flatOnly) return false;
    if (options.totalPatches > 0 &&
        options.totalPatches < options.finerPatchesPerSegment * options.shadedSegments)
        return false;
    long shaded = 0;
    for (size_t k = 0; k < firstInk; ++k)
        if (!converter.isFlat(k)) shaded += regions[k].pixelCount;
    return double(shaded) >= options.shadedShare * double(seg.width) * double(seg.height);
}

// segmentRegions' seconds in `from` added to those in `into`.
void addSegmentationSeconds(SegmentConvertReport& into, const SegmentConvertReport& from) {
    into.segmentSeconds += from.segmentSeconds;
    into.regionsSeconds += from.regionsSeconds;
    into.convert.seconds.regions += from.convert.seconds.regions;
}

// The image segmented again with `finer` (towards shadedSegments regions). Its regions replace
// `regions` (and seg, firstInk) when they are at least twice as many, else they are dropped: a
// photograph whose regions FH does not split further gains nothing from them. The seconds of
// both segmentations are counted in segmentReport.
bool segmentFiner(const RgbaImage& image, const SegmentConvertOptions& finer,
                  const std::string& imageName, Segmentation& seg, std::vector<Region>& regions,
                  size_t& firstInk, SegmentConvertReport& segmentReport) {
    SegmentConvertReport finerReport = segmentReport;
    Segmentation finerSeg;
    size_t finerInk = 0;
    std::vector<Region> finerRegions =
        segmentRegions(image, finer, imageName, finerSeg, finerInk, finerReport);
    const bool kept = finerRegions.size() >= 2 * regions.size();
    if (kept) {
        addSegmentationSeconds(finerReport, segmentReport);
        finerReport.finerSegments = finer.segment.segments;
        segmentReport = std::move(finerReport);
        seg = std::move(finerSeg);
        regions = std::move(finerRegions);
        firstInk = finerInk;
    } else {
        addSegmentationSeconds(segmentReport, finerReport);
    }
    return kept;
}

// Thin flat regions (at most options.stroke.maxWidth thick) drawn after the other regions
// before the ink lines, where they become strokes on top; then the flat regions of one colour
// that a thin one or an ink line parted merge (thin_on_top.h). Returns whether the regions
// may have changed.
bool liftThinFlatRegions(std::vector<Region>& regions, size_t& firstInk,
                         const SegmentConvertOptions& options, const RegionConverter& converter,
                         SegmentConvertReport& segmentReport) {
    std::vector<char> thin(regions.size(), 0), flat(regions.size(), 0);
    std::vector<Vec3> colours;
    size_t thinCount = 0;
    for (size_t k = 0; k < regions.size(); ++k) {
        flat[k] = converter.isFlat(k);
        colours.push_back(converter.flatColour(k));
        thin[k] = k > 0 && k < firstInk && flat[k] &&
                  regions[k].pixelCount >= options.stroke.minPixels &&
                  regionThickness(regions[k]) <= options.stroke.maxWidth;
        thinCount += thin[k];
    }
    if (thinCount == 0 && firstInk == regions.size()) return false;
    // The flat marks and colours in the new order: the others, the thin ones, the ink lines.
    std::vector<char> liftedFlat;
    std::vector<Vec3> liftedColours;
    for (int pass = 0; pass < 3; ++pass)
        for (size_t k = 0; k < regions.size(); ++k)
            if ((k >= firstInk ? 2 : thin[k] ? 1 : 0) == pass) {
                liftedFlat.push_back(flat[k]);
                liftedColours.push_back(colours[k]);
            }
    const size_t firstThin = liftThinRegions(regions, firstInk, thin);
    segmentReport.liftedThin = static_cast<int>(thinCount);
    segmentReport.mergedAcrossThin = static_cast<int>(
        mergeAcrossThin(regions, firstThin, firstInk, liftedFlat, liftedColours,
                        options.convert.maxError / 255));
    return true;
}

// What the flat regions' paint misses by far, as regions of their own on top of them
// (flat_residue.h). Returns whether any was added.
bool addResidue(const RgbaImage& image, std::vector<Region>& regions, size_t& firstInk,
                const SegmentConvertOptions& options, const RegionConverter& converter,
                SegmentConvertReport& segmentReport) {
    std::vector<LinearGradient> fills(firstInk);
    for (size_t k = 0; k < firstInk; ++k) fills[k] = converter.fillGradient(k);
    const auto paint = [&](size_t k, size_t p) {
        if (fills[k].stops.empty()) return converter.flatColour(k);
        return fills[k].colourAt({double(p % image.width) + 0.5, double(p / image.width) + 0.5});
    };
    const size_t added =
        addResidueRegions(image, regions, firstInk, paint, options.convert.maxError,
                          options.flatErrorPerByte,
                          options.residueOptions);
    segmentReport.residueRegions = static_cast<int>(added);
    return added > 0;
}


// What a shaded document's SVG costs, roughly, in bytes: a patch written in the compact syntax
// with its share of the meshes' outline paths, and a flat shape's element and segments.
double estimatedSvgBytes(const Document& doc) {
    constexpr double kPerPatch = 120;
    double bytes = 0;
    for (const GradientMesh& mesh : doc.meshes) bytes += kPerPatch * mesh.patchCount();
    for (const FlatShape& shape : doc.shapes) bytes += flatShapeSvgBytes(shape);
    return bytes;
}

// What the drawn document misses by far (a highlight, a speck inside a mesh), as flat shapes
// on top of everything (flat_residue.h). A shape must win back residuePriceOverAverage times
// the squared error the document wins back per byte on average: where the squared error falls
// as bytes^-a, the last bytes bought a times the average, and the whole-image curves fall
// with a of 0.4 to 0.6.
void addResidueShapes(Document& doc, const RgbaImage& image, const std::vector<Region>& regions,
                      size_t firstInk, const SegmentConvertOptions& options,
                      SegmentConvertReport& segmentReport) {
    RenderOptions drawOptions;
    drawOptions.threads = options.convert.threads;
    const RenderResult drawn = renderDocument(doc, drawOptions);
    std::vector<Vec3> painted(static_cast<size_t>(image.width) * image.height);
    double squaredError = 0;
    for (size_t p = 0; p < painted.size(); ++p) {
        painted[p] = pixelColour(drawn.image, p);
        const Vec3 d = 255.0 * (pixelColour(image, p) - painted[p]);
        squaredError += (d.r * d.r + d.g * d.g + d.b * d.b) / 3;
    }
    const double price =
        options.residuePriceOverAverage * squaredError / std::max(1.0, estimatedSvgBytes(doc));
    FlatOptions flat = options.flat;
    flat.curveTolerance *= std::max(1.0, options.convert.maxError / flat.toleranceError);
    std::vector<FlatShape> shapes =
        residueShapes(image, regions, firstInk, std::move(painted), options.convert.maxError,
                      price, flat, options.meshResidueOptions);
    snapToGrid(shapes, flat.curveTolerance, flat);
    for (FlatShape& shape : shapes) {
        shape.layer = doc.meshes.size();
        doc.shapes.push_back(std::move(shape));
    }
    segmentReport.residueRegions = static_cast<int>(shapes.size());
}

}  // namespace

Document convertSegmented(const RgbaImage& image, const SegmentConvertOptions& options,
                          const std::string& imageName, SegmentConvertReport* report) {
    SegmentConvertReport local;
    SegmentConvertReport& segmentReport = report ? *report : local;
    segmentReport = SegmentConvertReport{};
    segmentReport.convert.maskSource = "segmentation";
    segmentReport.convert.width = image.width;
    segmentReport.convert.height = image.height;
    if (image.width <= 0 || image.height <= 0) throw Error("the image has no pixels", imageName);
    const auto tStart = Clock::now();

    Segmentation seg;
    size_t firstInk = 0;
    std::vector<Region> regions =
        segmentRegions(image, options, imageName, seg, firstInk, segmentReport);
    // Its set-up (each region's flat fit) is counted in the conversion's seconds.
    double setupSeconds = 0;
    auto makeConverter = [&](const SegmentConvertOptions& o) {
        const auto t = Clock::now();
        auto made = std::make_unique<RegionConverter>(image, regions, firstInk, o);
        setupSeconds += since(t);
        return made;
    };
    auto converter = makeConverter(options);
    // What the regions are converted with: the options, or those of the finer segmentation.
    SegmentConvertOptions used = options;
    if (wantsFinerSegments(options, seg, regions, firstInk, *converter)) {
        used.segment.segments = options.shadedSegments;
        if (segmentFiner(image, used, imageName, seg, regions, firstInk, segmentReport))
            converter = makeConverter(used);
        else
            used = options;
    }

    // --total-patches 0: every region a flat shape (flatOnly asks for flatShapes' colours).
    const bool allFlat = used.flatOnly && used.flatShapes;
    if (allFlat) {
        std::vector<Vec3> colours;
        for (size_t k = 0; k < regions.size(); ++k) colours.push_back(converter->flatColour(k));
        const size_t merged = mergeIntoBackdrop(regions, firstInk, colours,
                                                kBackdropMergeShare * used.convert.maxError / 255);
        if (merged > 0) {
            firstInk -= merged;
            converter = makeConverter(used);
        }
        segmentReport.mergedIntoBackdrop = static_cast<int>(merged);
    }

    if (used.strokes && used.flatShapes && liftThinFlatRegions(regions, firstInk, used, *converter,
                                                               segmentReport))
        converter = makeConverter(used);
    if (allFlat && used.residue && addResidue(image, regions, firstInk, used, *converter,
                                              segmentReport))
        converter = makeConverter(used);

    auto t0 = Clock::now();
    std::vector<RegionOutcome> outcomes;
    if (used.totalPatches > 0 && !regions.empty()) {
        outcomes = convertWithinTotal(*converter, regions, used, segmentReport);
    } else {
        std::vector<std::pair<size_t, int>> jobs;
        const int budget = allFlat ? 0 : converter->maxPatches();
        for (size_t k = 0; k < regions.size(); ++k) jobs.push_back({k, budget});
        converter->run(jobs, outcomes);
    }
    segmentReport.convertSeconds = setupSeconds + since(t0);

    reportProgress(options.convert, "assemble");
    Document doc = assembleDocument(image, regions, outcomes, used, segmentReport);
    if (!allFlat && used.residue && used.flatShapes) {
        reportProgress(options.convert, "residue");
        addResidueShapes(doc, image, regions, firstInk, used, segmentReport);
    }
    reportProgress(options.convert, "measure");
    t0 = Clock::now();
    measureSegmented(doc, image, seg.labels, segmentReport);
    segmentReport.measureSeconds = since(t0);
    segmentReport.totalSeconds = since(tStart);
    return doc;
}

}  // namespace gm
