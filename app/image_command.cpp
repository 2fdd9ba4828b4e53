#include "image_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include "converters/bicubic_model.h"
#include "command_limits.h"
#include "converters/convert_image.h"
#include "converters/compact_file.h"
#include "converters/conversion_report.h"
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
#include "verbosity.h"
#include "view_page.h"
#include "conversion_progress.h"

namespace gm {

const std::set<std::string> kImageValuedOptions = {
    "--mask", "--max-error", "--max-patches", "--report", "--colors", "--max-pixels",
    "--min-area", "--min-hole", "--samples", "--segments", "--min-region", "--threads",
    "--total-patches"};
const std::set<std::string> kImageFlagOptions = {"--segment", "--no-strokes",
                                                    "--no-gradients", "--no-residue"};

namespace {

// --colors: bicubic (the default; alias "rule"), hermite (alias "fit"), sampled.
ColorMode colorMode(const std::string& name) {
    if (name == "bicubic" || name == "rule") return ColorMode::FitBicubic;
    if (name == "hermite" || name == "fit") return ColorMode::Fit;
    if (name == "sampled") return ColorMode::Sampled;
    throw std::invalid_argument("--colors expects bicubic, hermite or sampled, got '" + name + "'");
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
        cli::note("gradmesh convert: warning: %s has %d pages; only the first is converted\n",
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
    f.facts = {{"output", out}, {"--colors", colorModeName(co.colors)}, {"target E", jsonNumber(co.maxError)},
               {"patch budget", std::to_string(co.maxPatches) + (segment ? " per region" : "")}};
    if (segment) f.facts.emplace_back("regions", std::to_string(report.regions.size()));
    return f;
}

}  // namespace

namespace {

// A raster conversion as its options ask for it.
struct ImageJob {
    bool segment = false;
    ConvertOptions convert;
    SegmentConvertOptions segmentOptions;
    uint64_t maxPixels = 0;
    std::string reportPath, maskPath;
};

ImageJob parseImageJob(const std::map<std::string, std::string>& values) {
    ImageJob job;
    ConvertOptions& co = job.convert;
    job.segment = values.count("--segment") > 0;
    co.maxError = number(values, "--max-error", co.maxError, 0.0, 255.0);
    co.maxPatches = static_cast<int>(number(values, "--max-patches",
                                            job.segment ? kSegmentMaxPatches : co.maxPatches, 1, 1e6));
    co.minArea = static_cast<int>(number(values, "--min-area", co.minArea, 1, 1e9));
    co.minHole = static_cast<int>(number(values, "--min-hole", co.minHole, 0, 1e9));
    co.sampleFraction = number(values, "--samples", co.sampleFraction, 1e-4, 1.0);
    job.maxPixels =
        static_cast<uint64_t>(number(values, "--max-pixels", double(uint64_t(64) << 20), 1, 1e12));
    if (auto it = values.find("--colors"); it != values.end()) co.colors = colorMode(it->second);
    SegmentConvertOptions& so = job.segmentOptions;
    so.segment.segments = static_cast<int>(number(values, "--segments", 0, 1, 100000));
    so.segment.minRegion = static_cast<int>(number(values, "--min-region", 0, 1, 1e9));
    so.threads = static_cast<int>(number(values, "--threads", 0, 1, 1024));
    so.totalPatches = static_cast<int>(number(values, "--total-patches", 0, 0, 1e8));
    so.flatOnly = values.count("--total-patches") && so.totalPatches == 0;
    so.strokes = values.count("--no-strokes") == 0;
    so.gradients = values.count("--no-gradients") == 0;
    so.residue = values.count("--no-residue") == 0;
    co.threads = so.threads;
    if (!job.segment)
        for (const char* o : {"--segments", "--min-region", "--total-patches", "--no-strokes",
                              "--no-gradients", "--no-residue"})
            if (values.count(o)) throw std::invalid_argument(std::string(o) + " needs --segment");
    if (job.segment && values.count("--mask"))
        throw std::invalid_argument("--segment converts the whole image; it takes no --mask");
    if (auto it = values.find("--report"); it != values.end()) {
        job.reportPath = it->second;
        if (job.reportPath.empty()) throw std::invalid_argument("--report needs a file name");
    }
    if (auto it = values.find("--mask"); it != values.end()) {
        job.maskPath = it->second;
        if (job.maskPath.empty()) throw std::invalid_argument("--mask needs a file name");
    }
    return job;
}

// No output may land on an input or on another output, and each must be writable.
void checkPlaces(const std::string& in, const std::string& out, const ImageJob& job) {
    if (!job.reportPath.empty()) {
        requireWritableDir(job.reportPath);
        if (samePath(in, job.reportPath))
            throw Error("the report would overwrite the input", job.reportPath);
        if (samePath(out, job.reportPath))
            throw Error("the report would overwrite the output", job.reportPath);
        if (!job.maskPath.empty() && samePath(job.maskPath, job.reportPath))
            throw Error("the report would overwrite the mask", job.reportPath);
    }
    requireWritableDir(out);
}

struct Inputs {
    RgbaImage image, maskImage;
    double seconds = 0;
};

// The image and the mask, their sizes checked against the limits before any pixel is
// allocated (and against the render each output or its fallback needs).
Inputs readInputs(const std::string& in, const std::vector<ImageTarget>& targets,
                  const WriteOptions& writeOptions, const ImageJob& job,
                  const CommandLimits& limits) {
    const auto t0 = Clock::now();
    const ImageProbe probe = probeInput(in, job.segment, job.maxPixels, limits);
    for (const ImageTarget& t : targets) {
        if (t.writer->name() == "raster")
            requireRenderWithinLimits(probe.width, probe.height, writeOptions.rasterScale, limits, t.path);
        if (t.writer->name() == "svg" && writeOptions.svgFallback != "none")  // the fallback is a render
            requireRenderWithinLimits(probe.width, probe.height, 1.0, limits, t.path);
    }
    Inputs inputs;
    inputs.image = readQuietly(in, job.maxPixels);
    if (!job.maskPath.empty()) inputs.maskImage = readQuietly(job.maskPath, job.maxPixels);
    inputs.seconds = since(t0);
    return inputs;
}

struct Conversion {
    Document doc;
    SegmentConvertReport report;  // an object's conversion fills report.convert only
    ObjectMask mask;              // an object's
    double maskSeconds = 0;
    // The pixels its error is measured over: the object's, or every pixel with --segment.
    std::vector<uint8_t> measured;
};

// The object (or the whole image) converted. Stages that do not know the file are named here:
// the mask file for an error about the mask, else the image.
Conversion convertInputs(const std::string& in, const Inputs& inputs, ImageJob& job,
                         const CommandLimits& limits) {
    const auto nameFile = [&](const Error& e) {
        const bool aboutMask = e.reason().find("mask") != std::string::npos;
        return Error(e.reason(), aboutMask && !job.maskPath.empty() ? job.maskPath : in, e.where());
    };
    Conversion c;
    try {
        auto t0 = Clock::now();
        if (!job.segment)
            c.mask = objectMask(inputs.image, job.maskPath.empty() ? nullptr : &inputs.maskImage,
                                in, job.maskPath, job.convert.threads);
        c.maskSeconds = since(t0);
        if (job.segment) {
            job.segmentOptions.convert = job.convert;
            c.doc = convertSegmented(inputs.image, job.segmentOptions, in, &c.report);
        } else {
            c.doc = convertImage(inputs.image, c.mask, job.convert, in, &c.report.convert);
        }
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw nameFile(e);
    }
    if (const uint64_t patches = documentPatches(c.doc); patches > limits.maxDocumentPatches)
        throw Error("the conversion made " + std::to_string(patches) +
                        " patches, over the limit of " + std::to_string(limits.maxDocumentPatches) +
                        " (raise it with --max-document-patches, or lower --max-patches)",
                    in);
    c.measured = job.segment ? std::vector<uint8_t>(
                                   static_cast<size_t>(inputs.image.width) * inputs.image.height, 1)
                             : c.mask.mask;
    return c;
}

const CompactCodec kGmbCodec{
    [](const Document& d, int level) { return encodeGmb(d, true, level); },
    [](const std::string& bytes) { return decodeGmb(bytes, ReadLimits{}); }};

CompactTarget compactTarget(const Inputs& inputs, const Conversion& c, const ImageJob& job) {
    return {inputs.image, c.measured, job.convert.colors, job.convert.threads,
            c.report.convert.error};
}

// The JSON report's facts: what was asked, times, and the bytes of each format.
ReportFacts reportFacts(const std::string& in, const std::string& out, const ImageJob& job,
                        const Inputs& inputs, const Conversion& c, uint64_t outBytes) {
    ReportFacts f;
    f.input = in;
    f.output = out;
    f.width = inputs.image.width;
    f.height = inputs.image.height;
    f.segment = job.segment;
    f.colors = job.convert.colors;
    f.maxError = job.convert.maxError;
    f.maxPatches = job.convert.maxPatches;
    f.totalPatches = job.segmentOptions.totalPatches;
    f.meshes = c.doc.meshes.size();
    f.outputBytes = outBytes;
    f.gmbLosslessBytes = encodeGmb(c.doc, false).size();
    // The exact SVG of a whole image or of a mesh of thousands of patches takes longer and
    // more memory to encode than the conversion: left out there; convert the .gmb to .svg to
    // know it.
    if (!job.segment && c.report.convert.patches <= kReportSvgMaxPatches) {
        WriteOptions exact;
        exact.svgColors = "exact";
        f.exactSvgBytes = encodeSvg(c.doc, exact).size();
    }
    return f;
}

// --verbose: each stage's seconds and the conversion's figures, on standard error.
void printStages(const ViewFigures& figures, const Conversion& c, uint64_t outBytes) {
    for (const auto& [stage, seconds] : figures.seconds)
        cli::detail("  %-26s %8.3f s\n", stage.c_str(), seconds);
    const size_t regions = c.report.convert.regions.size();
    cli::detail("  %zu region(s), %zu mesh(es), %llu patches, E %.2f, PSNR %.2f dB, %llu bytes\n",
                regions, c.doc.meshes.size(),
                static_cast<unsigned long long>(documentPatches(c.doc)),
                c.report.convert.error.meanAbs, c.report.convert.error.psnr,
                static_cast<unsigned long long>(outBytes));
}

}  // namespace

void checkImageOptions(const std::map<std::string, std::string>& values) {
    parseImageJob(values);
    commandLimits(values);
}

void convertImageCommand(const std::string& in, const std::string& out, const MeshFormat& writer,
                         const WriteOptions& writeOptions,
                         const std::map<std::string, std::string>& values,
                         ConversionProgress* progress) {
    convertImageToTargets(in, {{out, &writer}}, writeOptions, values, progress);
}

ImageFigures convertImageToTargets(const std::string& in, const std::vector<ImageTarget>& targets,
                                   const WriteOptions& writeOptions,
                                   const std::map<std::string, std::string>& values,
                                   ConversionProgress* progress) {
    const auto tStart = Clock::now();
    ImageJob job = parseImageJob(values);
    const auto stage = [&](const char* name) {
        if (progress) progress->stage(name);
    };
    if (progress) job.convert.progress = progress->callback();
    const std::string& out = targets.at(0).path;  // the one the report describes
    for (const ImageTarget& t : targets) {
        checkPlaces(in, t.path, job);
        // A compact file under a whole-image patch budget is about bytes, and the cubics of
        // ink lines, of shaded regions drawn flat and of residue shapes cost bytes outside the
        // budget (docs/design.md §5).
        if (job.segmentOptions.totalPatches > 0 && writeOptions.compact &&
            t.writer->name() == "gmb") {
            job.segmentOptions.segment.inkLines = false;
            job.segmentOptions.flatRungs = false;
            job.segmentOptions.residue = false;
        }
    }
    // Every output of the run is written to its temporary and renamed into place together at
    // the end: a late failure (a report into /proc, a full disk) leaves an existing output as it
    // was. Created now, so that an unwritable place fails before the conversion's work.
    OutputBatch outputs;
    for (const ImageTarget& t : targets) outputs.reserve(t.path);
    if (!job.reportPath.empty()) outputs.reserve(job.reportPath);
    const CommandLimits limits = commandLimits(values);
    if (const int total = job.segmentOptions.totalPatches;
        total > 0 && static_cast<uint64_t>(total) > limits.maxDocumentPatches)
        throw std::invalid_argument("--total-patches " + std::to_string(total) +
                                    " is over --max-document-patches " +
                                    std::to_string(limits.maxDocumentPatches));

    stage("read");
    const Inputs inputs = readInputs(in, targets, writeOptions, job, limits);
    stage(job.segment || !job.maskPath.empty() ? "convert" : "mask");
    const Conversion c = convertInputs(in, inputs, job, limits);

    // A compact .gmb holds the colours refitted to its grids (the file is the compact file's
    // bytes: re-encoding a quantised document gives the same file).
    WriteOptions wo = writeOptions;
    const bool autoLevel = wo.compact && wo.compactLevel == kCompactLevelAuto;
    bool compactOutput = false;
    for (const ImageTarget& t : targets) compactOutput = compactOutput || (wo.compact && t.writer->name() == "gmb");
    std::optional<CompactFile> compact;
    if (compactOutput || autoLevel) stage("compact");
    if (autoLevel)
        compact = coarsestCompactFile(c.doc, kGmbMaxCompactLevel, compactTarget(inputs, c, job), kGmbCodec);
    else if (compactOutput)
        compact = compactFileAt(c.doc, wo.compactLevel, compactTarget(inputs, c, job), kGmbCodec);
    if (compact) wo.compactLevel = compact->level;

    stage("write");
    auto t0 = Clock::now();
    uint64_t outBytes = 0;
    for (const ImageTarget& t : targets) {
        const bool compactTargetFile = wo.compact && t.writer->name() == "gmb";
        const std::string bytes = t.writer->encode(
            compactTargetFile ? compact->doc
                              : documentForWriter(c.doc, *t.writer, wo, t.path, job.convert.threads),
            t.path, wo);
        outputs.write(t.path, bytes);
        if (&t == &targets[0]) outBytes = bytes.size();
    }
    const double writeSeconds = since(t0);

    if (cli::verbosity() == cli::Verbosity::Verbose)
        printStages(conversionFigures(in, out, job.segment, job.convert, c.report,
                                      {inputs.seconds, c.maskSeconds, writeSeconds, since(tStart)}),
                    c, outBytes);
    if (!job.reportPath.empty()) {
        stage("report");
        const double endToEnd = since(tStart);  // what follows only measures for the report
        std::string report;
        if (isHtmlPath(job.reportPath)) {
            const ViewFigures figures =
                conversionFigures(in, out, job.segment, job.convert, c.report,
                                  {inputs.seconds, c.maskSeconds, writeSeconds, endToEnd});
            report = buildViewPage(c.doc, &inputs.image, figures, writeOptions);
            requireOutputWithinLimit(report.size(), writeOptions, job.reportPath);
        } else {
            if (!compact)
                compact = compactFileAt(c.doc, wo.compact ? wo.compactLevel : 0,
                                        compactTarget(inputs, c, job), kGmbCodec);
            ReportFacts facts = reportFacts(in, out, job, inputs, c, outBytes);
            facts.readSeconds = inputs.seconds;
            facts.maskSeconds = c.maskSeconds;
            facts.writeSeconds = writeSeconds;
            facts.endToEndSeconds = endToEnd;
            facts.compactAuto = autoLevel;
            report = conversionReportJson(facts, c.report, *compact);
        }
        outputs.write(job.reportPath, report);
    }
    outputs.commit();
    return {documentPatches(c.doc), c.report.convert.error.meanAbs, c.report.convert.error.psnr};
}

Document documentForWriter(const Document& doc, const MeshFormat& writer,
                           const WriteOptions& options, const std::string& path, int threads) {
    if (writer.name() != "svg" || options.svgColors == "exact" || !hasHermiteMeshes(doc))
        return doc;
    // A document too large for the output limit is refused before the refit's work.
    requireOutputWithinLimit(writer.leastBytes(doc, options), options, path);
    BicubicConversion c = toBicubicModel(doc, threads);
    cli::note("svg: %d Hermite mesh(es) refitted to the bicubic rule: E %.2f, PSNR %.2f dB, "
              "max %.0f/255 from the Hermite render (--svg-colors exact keeps them exact)\n",
              c.refitted, c.error.meanAbs, c.error.psnr, c.error.maxAbs);
    return std::move(c.doc);
}

}  // namespace gm
