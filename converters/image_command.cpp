#include "image_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include "converters/bicubic_model.h"
#include "command_limits.h"
#include "converters/convert_image.h"
#include "converters/convert_segments.h"
#include "converters/foreground.h"
#include "converters/visible_colors.h"
#include "formats/atomic_file.h"
#include "formats/gmb.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/render.h"
#include "view_command.h"
#include "view_page.h"

namespace gm {

const std::set<std::string> kImageValuedOptions = {
    "--mask", "--max-error", "--max-patches", "--report", "--colors", "--max-pixels",
    "--min-area", "--min-hole", "--samples", "--segments", "--min-region", "--threads",
    "--total-patches"};
const std::set<std::string> kImageFlagOptions = {"--segment"};

const char* kImageConvertHelp =
    "  raster input (IN is .png .jpg .tif .exr ...): the object becomes gradient meshes\n"
    "  --mask M.png            object mask (white = object); else the alpha channel when it\n"
    "                          makes 0.1% of the pixels or more transparent (alpha < 0.5);\n"
    "                          else foreground extraction (GrabCut)\n"
    "  --max-error E           target mean error per region, 0-255 units (default 3)\n"
    "  --max-patches N         patch budget per region (default 400; with --segment 8000,\n"
    "                          and at most one patch per 8 pixels of the region)\n"
    "  --colors MODE           bicubic (default: node colours fitted, slopes by SVG's bicubic\n"
    "                          rule, so the SVG is one patch per patch exactly as Inkscape\n"
    "                          draws it; no slopes in the .gmb), hermite (free slopes: the\n"
    "                          least raster error per patch; the SVG refits them) or sampled\n"
    "                          (the paper's: node colours sampled, bicubic). fit and rule are\n"
    "                          the former names of hermite and bicubic\n"
    "  --report R.json         per-stage seconds, patches, errors, bytes, refinement sequence\n"
    "  --report R.html         the same conversion as a page to look at (gradmesh view --help)\n"
    "  --max-pixels N          refuse larger images (default 67108864 = 64 Mi pixels)\n"
    "  --min-area N            drop object components under N pixels (default 64)\n"
    "  --min-hole N            fill holes under N pixels (default 16)\n"
    "  --samples F             triangulation samples per region pixel (default 0.03,\n"
    "                          at most 40000 per region)\n"
    "  --segment               the whole image: segmented into large regions (graph-based,\n"
    "                          GrabCut-refined), one mesh per region, holes included, over a\n"
    "                          coarse base mesh so that every pixel is painted\n"
    "  --segments N            with --segment: roughly how many regions (default: automatic)\n"
    "  --min-region N          with --segment: merge regions under N pixels into a neighbour\n"
    "                          (default: scaled to the image)\n"
    "  --total-patches N       with --segment: one patch budget for the whole image, shared\n"
    "                          out where it lowers the error most (each region converted at\n"
    "                          several budgets; --max-error still stops each region)\n"
    "  --threads N             regions converted at once (default: all cores)\n";

namespace {

// --colors: bicubic (the default; "rule" is its former name), hermite ("fit"), sampled.
ColorMode colorMode(const std::string& name) {
    if (name == "bicubic" || name == "rule") return ColorMode::FitBicubic;
    if (name == "hermite" || name == "fit") return ColorMode::Fit;
    if (name == "sampled") return ColorMode::Sampled;
    throw std::invalid_argument("--colors expects bicubic, hermite or sampled, got '" + name + "'");
}

const char* colorModeName(ColorMode mode) {
    switch (mode) {
        case ColorMode::Fit: return "hermite";
        case ColorMode::Sampled: return "sampled";
        default: return "bicubic";
    }
}

// Above this many patches --report leaves out the exact SVG's size ("svg": null).
constexpr int kReportSvgMaxPatches = 2000;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double number(const std::map<std::string, std::string>& values, const std::string& key,
              double fallback, double lo, double hi) {
    auto it = values.find(key);
    if (it == values.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream s;
        s << key << " expects a number from " << lo << " to " << hi << ", got '" << it->second
          << "'";
        throw std::invalid_argument(s.str());
    }
    return v;
}

// JSON numbers: finite values as they are, infinity (PSNR of a perfect fit) as a large number.
std::string num(double v) {
    if (std::isnan(v)) return "null";
    if (std::isinf(v)) return v > 0 ? "1e308" : "-1e308";
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

std::string jsonString(const std::string& s) {
    std::string r = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            r += '\\';
            r += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            r += b;
        } else {
            r += c;
        }
    }
    return r + "\"";
}

std::string errorJson(const FitError& e) {
    std::ostringstream s;
    s << "{\"E\": " << num(e.meanAbs) << ", \"rmse\": " << num(e.rmse)
      << ", \"psnr\": " << num(e.psnr) << ", \"max\": " << num(e.maxAbs)
      << ", \"uncovered\": " << num(e.uncovered) << ", \"pixels\": " << e.pixels << "}";
    return s.str();
}

std::string secondsJson(const StageSeconds& t) {
    std::ostringstream s;
    s << "{\"regions\": " << num(t.regions) << ", \"corners\": " << num(t.corners)
      << ", \"triangulate\": " << num(t.triangulate) << ", \"topology\": " << num(t.topology)
      << ", \"feature\": " << num(t.feature) << ", \"mesh\": " << num(t.mesh)
      << ", \"T\": " << num(t.triangulationStages()) << ", \"P\": " << num(t.mapStages())
      << ", \"M\": " << num(t.meshStages())
      << ", \"total\": " << num(t.total()) << "}";
    return s.str();
}

void requireWritableDir(const std::string& path) {
    const std::filesystem::path p(path);
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw Error("the output's directory does not exist", path);
    if (std::filesystem::is_directory(p, ec)) throw Error("is a directory, not a file", path);
}

// Whether two paths name the same file, whether or not it exists yet.
bool samePath(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec))
        return std::filesystem::equivalent(a, b, ec);
    const auto na = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ec), ec);
    const auto nb = std::filesystem::weakly_canonical(std::filesystem::absolute(b, ec), ec);
    return !ec && na == nb;
}

// libpng (through OpenImageIO) prints its errors and warnings on stderr besides returning them;
// the message we throw already holds them, and errors are one line. Silences fd 2 while alive.
class QuietStderr {
public:
    QuietStderr() {
        std::fflush(stderr);
        saved_ = ::dup(2);
        const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
        if (null >= 0) ::close(null);
    }
    ~QuietStderr() {
        std::fflush(stderr);
        if (saved_ >= 0) {
            ::dup2(saved_, 2);
            ::close(saved_);
        }
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    int saved_ = -1;
};

void requireNonEmpty(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) == 0 && !ec)
        throw Error("file is empty (0 bytes)", path);
}

RgbaImage readQuietly(const std::string& path, uint64_t maxPixels) {
    requireNonEmpty(path);
    QuietStderr quiet;
    return readImage(path, maxPixels);
}

// The header of the input, checked against the limits before its pixels are decoded: the
// conversion's memory grows with the pixels the header claims, however small the file.
ImageProbe probeInput(const std::string& path, bool segment, uint64_t maxPixels,
                      const CommandLimits& limits) {
    requireNonEmpty(path);
    ImageProbe probe;
    {
        QuietStderr quiet;
        probe = probeImage(path);
    }
    const double pixels = static_cast<double>(probe.width) * probe.height;
    if (pixels <= static_cast<double>(maxPixels))  // else readImage says it is over --max-pixels
        requireMemoryBudget(pixels * (segment ? kSegmentBytesPerPixel : kObjectBytesPerPixel),
                            limits.maxMemory,
                            "a " + std::to_string(probe.width) + "x" + std::to_string(probe.height) +
                                " image" + (segment ? " (--segment)" : ""),
                            path);
    if (probe.pages > 1)
        std::fprintf(stderr, "gradmesh convert: warning: %s has %d pages; only the first is converted\n",
                     path.c_str(), probe.pages);
    return probe;
}

// The figures of a conversion as its view page (--report PAGE.html) shows them.
struct ConversionTimes {
    double read = 0, mask = 0, write = 0, endToEnd = 0;
};
ViewFigures conversionFigures(const std::string& in, const std::string& out, bool segment,
                              const ConvertOptions& co, const SegmentConvertReport& segReport,
                              const ConversionTimes& times) {
    const ConvertReport& report = segReport.convert;
    ViewFigures f;
    f.title = std::filesystem::path(out).filename().string();
    f.sourceName = std::filesystem::path(in).filename().string();
    f.haveError = true;
    f.meanAbs = report.error.meanAbs;
    f.psnr = report.error.psnr;
    const std::string objectFrom = report.maskSource == "mask"    ? "the mask file"
                                   : report.maskSource == "alpha" ? "the alpha channel"
                                                                  : "foreground extraction";
    f.errorOver = segment ? "every pixel of the image" : "the object's pixels (from " + objectFrom + ")";
    const StageSeconds& t = report.seconds;
    f.seconds = {{"read", times.read}};
    if (segment) {
        // Regions are converted side by side: their stages are summed, and the wall time of
        // the whole is given after them. t.regions holds the segmentation too.
        f.seconds.emplace_back("segmentation", segReport.segmentSeconds);
        f.seconds.emplace_back("regions", segReport.regionsSeconds);
    } else {
        f.seconds.emplace_back("mask", times.mask);
        f.seconds.emplace_back("regions", t.regions);
    }
    const std::string sum = segment ? " (sum)" : "";
    for (const auto& [stage, seconds] :
         {std::pair<const char*, double>{"corners", t.corners}, {"triangulate", t.triangulate},
          {"topology", t.topology}, {"feature", t.feature}, {"mesh", t.mesh}})
        f.seconds.emplace_back(stage + sum, seconds);
    if (segment) f.seconds.emplace_back("regions converted (wall)", segReport.convertSeconds);
    f.seconds.emplace_back("write", times.write);
    f.seconds.emplace_back("end to end", times.endToEnd);
    f.facts = {{"output", out}, {"--colors", colorModeName(co.colors)}, {"target E", num(co.maxError)},
               {"patch budget", std::to_string(co.maxPatches) + (segment ? " per region" : "")}};
    if (segment) f.facts.emplace_back("regions", std::to_string(report.regions.size()));
    return f;
}

}  // namespace

void convertImageCommand(const std::string& in, const std::string& out, const MeshFormat& writer,
                         const WriteOptions& writeOptions,
                         const std::map<std::string, std::string>& values) {
    const auto tStart = Clock::now();
    ConvertOptions co;
    co.maxError = number(values, "--max-error", co.maxError, 0.0, 255.0);
    const bool segment = values.count("--segment") > 0;
    co.maxPatches = static_cast<int>(number(values, "--max-patches",
                                            segment ? kSegmentMaxPatches : co.maxPatches, 1, 1e6));
    co.minArea = static_cast<int>(number(values, "--min-area", co.minArea, 1, 1e9));
    co.minHole = static_cast<int>(number(values, "--min-hole", co.minHole, 0, 1e9));
    co.sampleFraction = number(values, "--samples", co.sampleFraction, 1e-4, 1.0);
    const uint64_t maxPixels =
        static_cast<uint64_t>(number(values, "--max-pixels", double(uint64_t(64) << 20), 1, 1e12));
    if (auto it = values.find("--colors"); it != values.end()) co.colors = colorMode(it->second);
    SegmentConvertOptions so;
    so.segment.segments = static_cast<int>(number(values, "--segments", 0, 1, 100000));
    so.segment.minRegion = static_cast<int>(number(values, "--min-region", 0, 1, 1e9));
    so.threads = static_cast<int>(number(values, "--threads", 0, 1, 1024));
    so.totalPatches = static_cast<int>(number(values, "--total-patches", 0, 1, 1e8));
    co.threads = so.threads;
    if (!segment)
        for (const char* o : {"--segments", "--min-region", "--total-patches"})
            if (values.count(o)) throw std::invalid_argument(std::string(o) + " needs --segment");
    if (segment && values.count("--mask"))
        throw std::invalid_argument("--segment converts the whole image; it takes no --mask");
    std::string reportPath;
    if (auto it = values.find("--report"); it != values.end()) {
        reportPath = it->second;
        if (reportPath.empty()) throw std::invalid_argument("--report needs a file name");
        requireWritableDir(reportPath);
        if (samePath(in, reportPath))
            throw Error("the report would overwrite the input", reportPath);
        if (samePath(out, reportPath))
            throw Error("the report would overwrite the output", reportPath);
    }
    std::string maskPath;
    if (auto it = values.find("--mask"); it != values.end()) {
        maskPath = it->second;
        if (maskPath.empty()) throw std::invalid_argument("--mask needs a file name");
        if (!reportPath.empty() && samePath(maskPath, reportPath))
            throw Error("the report would overwrite the mask", reportPath);
    }
    requireWritableDir(out);
    // Every output of the run is written to its temporary and renamed into place together at
    // the end: a late failure (a report into /proc, a full disk) leaves an existing output as it
    // was. Created now, so that an unwritable place fails before the conversion's work.
    OutputBatch outputs;
    outputs.reserve(out);
    if (!reportPath.empty()) outputs.reserve(reportPath);
    const CommandLimits limits = commandLimits(values);
    if (so.totalPatches > 0 && static_cast<uint64_t>(so.totalPatches) > limits.maxDocumentPatches)
        throw std::invalid_argument("--total-patches " + std::to_string(so.totalPatches) +
                                    " is over --max-document-patches " +
                                    std::to_string(limits.maxDocumentPatches));

    // Read: sizes are checked against the limits before any pixel is allocated.
    auto t0 = Clock::now();
    const ImageProbe probe = probeInput(in, segment, maxPixels, limits);
    if (writer.name() == "raster")
        requireRenderWithinLimits(probe.width, probe.height, writeOptions.rasterScale, limits, out);
    if (writer.name() == "svg" && writeOptions.svgFallback != "none")  // the fallback is a render
        requireRenderWithinLimits(probe.width, probe.height, 1.0, limits, out);
    const RgbaImage image = readQuietly(in, maxPixels);
    RgbaImage maskImage;
    if (!maskPath.empty()) maskImage = readQuietly(maskPath, maxPixels);
    const double readSeconds = since(t0);

    // Some stages do not know the file: name it, the mask file for an error about the mask.
    const auto nameFile = [&](const Error& e) {
        const bool aboutMask = e.reason().find("mask") != std::string::npos;
        return Error(e.reason(), aboutMask && !maskPath.empty() ? maskPath : in, e.where());
    };
    t0 = Clock::now();
    ObjectMask mask;
    try {
        if (!segment)
            mask = objectMask(image, maskPath.empty() ? nullptr : &maskImage, in, maskPath, co.threads);
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw nameFile(e);
    }
    const double maskSeconds = since(t0);

    SegmentConvertReport segReport;
    ConvertReport& report = segReport.convert;
    Document doc;
    try {
        if (segment) {
            so.convert = co;
            doc = convertSegmented(image, so, in, &segReport);
        } else {
            doc = convertImage(image, mask, co, in, &report);
        }
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw nameFile(e);
    }
    if (const uint64_t patches = documentPatches(doc); patches > limits.maxDocumentPatches)
        throw Error("the conversion made " + std::to_string(patches) +
                        " patches, over the limit of " + std::to_string(limits.maxDocumentPatches) +
                        " (raise it with --max-document-patches, or lower --max-patches)",
                    in);

    // Compact .gmb figures are measured over the pixels "error" is (the object's, or all of
    // them with --segment), on the decoded file's re-render: its size is weighed against its own
    // quality, not the unquantised mesh's.
    std::vector<uint8_t> measuredMask;  // filled when first needed (auto level, report)
    auto measured = [&]() -> const std::vector<uint8_t>& {
        if (!segment) return mask.mask;
        if (measuredMask.empty()) measuredMask.assign(static_cast<size_t>(image.width) * image.height, 1);
        return measuredMask;
    };
    // A compact file at `level`: its colours refitted to the quantised geometry and slopes, over
    // the measured pixels where each mesh is on top (visible_colors.h), and its figures.
    struct Compact {
        Document doc;  // what the file holds
        std::string bytes;
        FitError error;
        std::string refit;  // QuantisedColors::how
    };
    auto compactAt = [&](int level) {
        const auto quantise = [level](const Document& d) {
            return decodeGmb(encodeGmb(d, true, level), ReadLimits{});
        };
        // report.error is the mesh's own, over the same pixels.
        QuantisedColors q = colorsForQuantisation(doc, image, measured(), co.colors, quantise,
                                                  co.threads, &report.error);
        Compact c;
        // q.doc is a file's content: written again, it is the same file (tests/cli_convert).
        c.bytes = encodeGmb(q.doc, true, level);
        c.error = q.error;
        c.doc = std::move(q.doc);
        c.refit = std::move(q.how);
        return c;
    };
    WriteOptions wo = writeOptions;
    Compact compact;
    bool haveCompact = false;
    const bool compactOutput = wo.compact && writer.name() == "gmb";
    const bool autoLevel = wo.compact && wo.compactLevel == kCompactLevelAuto;
    if (autoLevel) {
        // The coarsest level whose file adds at most 5 % (and 0.02) to the mesh's E. Each level
        // is first measured as it quantises (one encode and render); only a level within 25 %
        // of the bound gets the colour refit, which can bring it under (a refit of a whole
        // image is about a second).
        const double bound = 1.05 * report.error.meanAbs + 0.02;
        for (int level = kGmbMaxCompactLevel; level >= 0; --level) {
            const double plainE =
                compareOverMask(image,
                                renderDocument(decodeGmb(encodeGmb(doc, true, level), ReadLimits{}),
                                               RenderOptions{})
                                    .image,
                                measured())
                    .meanAbs;
            if (plainE > 1.25 * bound && level > 0) continue;
            compact = compactAt(level);
            wo.compactLevel = level;
            if (compact.error.meanAbs <= bound) break;
        }
        haveCompact = true;
    } else if (compactOutput) {
        compact = compactAt(wo.compactLevel);
        haveCompact = true;
    }

    t0 = Clock::now();
    // A compact .gmb holds the refitted colours (the file is compact's bytes: re-encoding a
    // quantised document gives the same file).
    size_t outBytes = 0;
    {
        const std::string bytes = writer.encode(
            compactOutput ? compact.doc : documentForWriter(doc, writer, wo, out, co.threads), out, wo);
        outBytes = bytes.size();
        outputs.write(out, bytes);
    }
    const double writeSeconds = since(t0);

    if (reportPath.empty()) {
        outputs.commit();
        return;
    }
    const double endToEnd = since(tStart);  // what follows only measures for the report
    if (isHtmlPath(reportPath)) {
        const ViewFigures figures = conversionFigures(
            in, out, segment, co, segReport, {readSeconds, maskSeconds, writeSeconds, endToEnd});
        const std::string page = buildViewPage(doc, &image, figures, writeOptions);
        requireOutputWithinLimit(page.size(), writeOptions, reportPath);
        outputs.write(reportPath, page);
        outputs.commit();
        return;
    }
    const int compactLevel = wo.compact ? wo.compactLevel : 0;
    if (!haveCompact) compact = compactAt(compactLevel);
    std::ostringstream s;
    s << "{\n  \"input\": " << jsonString(in) << ",\n  \"output\": " << jsonString(out)
      << ",\n  \"width\": " << image.width << ",\n  \"height\": " << image.height
      << ",\n  \"mask_source\": " << jsonString(report.maskSource)
      << ",\n  \"colors\": " << jsonString(colorModeName(co.colors))
      << ",\n  \"max_error\": " << num(co.maxError) << ",\n  \"max_patches\": " << co.maxPatches
      << ",\n  \"seconds\": " << secondsJson(report.seconds) << ",\n  \"io_seconds\": {\"read\": "
      << num(readSeconds) << ", \"mask\": " << num(maskSeconds) << ", \"write\": "
      << num(writeSeconds) << ", \"end_to_end\": " << num(endToEnd) << "}"
      << ",\n  \"meshes\": " << doc.meshes.size() << ",\n  \"patches\": " << report.patches
      << ",\n  \"error\": " << errorJson(report.error) << ",\n  \"bytes\": {\"output\": "
      << outBytes << ", \"gmb_lossless\": " << encodeGmb(doc, false).size()
      << ", \"gmb_compact\": " << compact.bytes.size() << ", \"svg\": ";
    // The exact SVG of a whole image or of a mesh of thousands of patches takes longer to
    // encode than the conversion (apple at 12,000 patches: 357 MB, ~14 s, ~2 GB): left out
    // there; convert the .gmb to .svg to know it.
    if (segment || report.patches > kReportSvgMaxPatches) {
        s << "null}";
    } else {
        WriteOptions exact;
        exact.svgColors = "exact";
        s << encodeSvg(doc, exact).size() << "}";
    }
    s << ",\n  \"compact\": {\"level\": " << compactLevel << ", \"auto\": " << (autoLevel ? "true" : "false")
      << ", \"bytes\": " << compact.bytes.size() << ", \"colors_refit\": " << jsonString(compact.refit)
      << ", \"error\": " << errorJson(compact.error) << "}";
    if (segment) {
        const SegmentStats& st = segReport.segmentation;
        s << ",\n  \"segments\": {\"count\": " << report.regions.size()
          << ", \"graph_regions\": " << st.fhRegions << ", \"grabcut_changed\": " << st.grabCutChanged
          << ", \"border_refined\": " << st.borderRefined
          << ", \"grown\": " << st.grown << ", \"merged\": " << st.merged
          << ", \"failed\": " << segReport.failedRegions
          << ", \"holes_filled\": " << segReport.filledRegions
          << ", \"thin_parts_apart\": " << segReport.trimmedRegions
          << ", \"split_at_necks\": " << segReport.splitRegions
          << ", \"base_patches\": " << segReport.basePatches
          << ", \"region_uncovered\": " << num(segReport.regionUncovered)
          << ", \"total_patches\": " << so.totalPatches
          << ", \"conversions\": " << segReport.conversions
          << ",\n    \"seconds\": {\"segmentation\": " << num(segReport.segmentSeconds)
          << ", \"graph\": " << num(st.fhSeconds) << ", \"grabcut\": " << num(st.grabCutSeconds)
          << ", \"grow\": " << num(st.growSeconds) << ", \"merge\": " << num(st.mergeSeconds)
          << ", \"regions\": " << num(segReport.regionsSeconds)
          << ", \"convert_wall\": " << num(segReport.convertSeconds)
          << ", \"measure\": " << num(segReport.measureSeconds)
          << ", \"total_wall\": " << num(segReport.totalSeconds) << "}"
          << ",\n    \"border_error\": " << errorJson(segReport.border)
          << ",\n    \"interior_error\": " << errorJson(segReport.interior) << "}";
    }
    s << ",\n  \"regions\": [";
    for (size_t k = 0; k < report.regions.size(); ++k) {
        const RegionReport& r = report.regions[k];
        s << (k ? "," : "") << "\n    {\"pixels\": " << r.pixels << ", \"holes\": " << r.holes;
        if (segment)
            s << ", \"label\": " << segReport.regionLabels[k]
              << ", \"fallback\": " << jsonString(segReport.fallbacks[k]);
        if (segment && k < segReport.keptBudget.size())
            s << ", \"largest_budget\": " << segReport.largestBudget[k]
              << ", \"budget\": " << segReport.keptBudget[k]
              << ", \"spill_sse\": " << num(segReport.keptSpill[k]);
        s
          << ", \"triangles\": " << r.triangles << ", \"vertices\": " << r.vertices
          << ", \"map_refined_vertices\": " << r.mapRefinedVertices
          << ", \"tip_corners\": " << (r.tipCorners ? "true" : "false")
          << ", \"part\": " << jsonString(r.part)
          << ", \"flipped_triangles\": " << r.flippedTriangles << ", \"grid\": [" << r.columns
          << ", " << r.rows << "], \"patches\": " << r.patches
          << ", \"feature_solves\": " << r.featureSolves
          << ", \"outline_deviation\": " << r.outlineDeviation
          << ", \"outline_knots\": " << r.outlineKnots
          << ", \"hole_pixels\": " << r.holePixels << ", \"hole_pixels_painted\": " << r.holePixelsPainted
          << ", \"feature_map\": " << (r.featureMapUsed ? "true" : "false")
          << ", \"folded_patches\": " << r.foldedPatches
          << ",\n     \"seconds\": " << secondsJson(r.seconds)
          << ",\n     \"error\": " << errorJson(r.error) << ",\n     \"refinement\": [";
        for (size_t j = 0; j < r.refinement.size(); ++j) {
            const RefineStep& st = r.refinement[j];
            s << (j ? ", " : "") << "\n       {\"grid\": [" << st.columns << ", " << st.rows
              << "], \"patches\": " << st.patches << ", \"E\": " << num(st.meanAbs)
              << ", \"psnr\": " << num(st.psnr) << ", \"axis\": "
              << (st.axis ? jsonString(std::string(1, st.axis)) : "null")
              << ", \"knot\": " << num(st.knot) << ", \"seconds\": " << num(st.seconds) << "}";
        }
        s << "]}";
    }
    s << "\n  ]\n}\n";
    outputs.write(reportPath, s.str());
    outputs.commit();
}

Document documentForWriter(const Document& doc, const MeshFormat& writer,
                           const WriteOptions& options, const std::string& path, int threads) {
    if (writer.name() != "svg" || options.svgColors == "exact" || !hasHermiteMeshes(doc))
        return doc;
    // A document too large for the output limit is refused before the refit's work.
    requireOutputWithinLimit(writer.leastBytes(doc, options), options, path);
    BicubicConversion c = toBicubicModel(doc, threads);
    std::fprintf(stderr,
                 "svg: %d Hermite mesh(es) refitted to the bicubic rule: E %.2f, PSNR %.2f dB, "
                 "max %.0f/255 from the Hermite render (--svg-colors exact keeps them exact)\n",
                 c.refitted, c.error.meanAbs, c.error.psnr, c.error.maxAbs);
    return std::move(c.doc);
}

}  // namespace gm
