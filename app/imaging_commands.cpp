// The commands of `gradmesh` that read or write images (convert, render, compare, view,
// sample) and the dispatch of every command: the program gradmesh-imaging, which links the
// image libraries (docs/design.md, "Start-up"). The launcher, gradmesh_main.cpp, runs this
// program for them.
#include "imaging_commands.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include "batch_command.h"
#include "cli_common.h"
#include "command_limits.h"
#include "conversion_progress.h"
#include "convert_routes.h"
#include "formats/atomic_file.h"
#include "formats/gmb.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "image_command.h"
#include "info_command.h"
#include "meshcore/color_text.h"
#include "meshcore/error.h"
#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"
#include "std_streams.h"
#include "verbosity.h"
#include "view_command.h"

namespace gm::cli {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::array<float, 4> parseColor(const std::string& text) {
    if (const auto color = gm::parseColorText(text)) return *color;
    throw UsageError("--background expects #rrggbb, #rrggbbaa, white, black or none, got '" + text + "'");
}

// --compact and --compact-level L|auto.
void parseCompact(const Args& a, gm::WriteOptions& wo) {
    wo.compact = a.flags.count("--compact") > 0;
    auto it = a.values.find("--compact-level");
    if (it == a.values.end()) return;
    wo.compact = true;
    if (it->second == "auto") {
        wo.compactLevel = gm::kCompactLevelAuto;
        return;
    }
    const double level = parseNumber("--compact-level", it->second, 0, gm::kGmbMaxCompactLevel);
    if (level != std::floor(level))
        throw UsageError("--compact-level expects a whole number or auto, got '" + it->second + "'");
    wo.compactLevel = static_cast<int>(level);
}

// The options every writer reads (--svg-*, --color-tolerance, --scale, ...).
gm::WriteOptions parseWriteOptions(const Args& a) {
    gm::WriteOptions wo;
    parseCompact(a, wo);
    wo.legacy = a.flags.count("--legacy") > 0;
    wo.textShading = a.flags.count("--text-shading") > 0;
    auto choice = [&](const char* option, std::initializer_list<const char*> allowed,
                      const char* expects, std::string& into) {
        auto it = a.values.find(option);
        if (it == a.values.end()) return;
        for (const char* c : allowed)
            if (it->second == c) {
                into = it->second;
                return;
            }
        throw UsageError(std::string(option) + " expects " + expects + ", got '" + it->second + "'");
    };
    choice("--svg-colors", {"exact", "bicubic", "editable"}, "bicubic or exact", wo.svgColors);
    choice("--svg-script", {"embed", "none"}, "embed or none", wo.svgScript);
    if (auto it = a.values.find("--color-tolerance"); it != a.values.end())
        wo.colorTolerance = parseNumber("--color-tolerance", it->second, 0.01, 64) / 255.0;
    if (auto it = a.values.find("--min-piece"); it != a.values.end())
        wo.minPiece = parseNumber("--min-piece", it->second, 0, 64);
    choice("--svg-fallback", {"png", "webp", "none"}, "png, webp or none", wo.svgFallback);
    if (auto it = a.values.find("--scale"); it != a.values.end())
        wo.rasterScale = parseNumber("--scale", it->second, 0.01, 64);
    if (auto it = a.values.find("--background"); it != a.values.end()) wo.background = parseColor(it->second);
    if (auto it = a.values.find("--mesh-lines"); it != a.values.end()) {
        wo.meshLines = parseColor(it->second);
        if (wo.meshLines[3] <= 0) throw UsageError("--mesh-lines needs a visible colour, got '" + it->second + "'");
    }
    if (auto it = a.values.find("--max-output-bytes"); it != a.values.end())
        wo.maxOutputBytes = static_cast<uint64_t>(parseNumber("--max-output-bytes", it->second, 1, 1e15));
    return wo;
}

// convert IMAGE: the pipeline (image_command.h), with the raster-only options.
void convertRasterInput(const Args& a, const std::string& in, const std::string& out,
                        const gm::MeshFormat& writer, const gm::WriteOptions& wo,
                        gm::ConversionProgress& progress) {
    if (auto it = a.values.find("--mask"); it != a.values.end()) {
        if (it->second.empty()) throw UsageError("--mask needs a file name");
        requireInputFile(it->second);
        gm::refuseOverwritingInput(it->second, out, "mask");
    }
    std::map<std::string, std::string> values = a.values;
    for (const std::string& f : gm::kImageFlagOptions)
        if (a.flags.count(f)) values[f] = "1";
    try {
        gm::convertImageCommand(in, out, writer, wo, values, &progress);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

// The raster-only options given for a mesh file are usage errors.
void refuseImageOptions(const Args& a, const gm::WriteOptions& wo) {
    for (const std::string& o : gm::kImageValuedOptions)
        if (a.values.count(o)) throw UsageError(o + " applies to raster inputs only");
    if (wo.compactLevel == gm::kCompactLevelAuto)
        throw UsageError("--compact-level auto applies to raster inputs only (it measures each "
                         "level's file against the image)");
    for (const std::string& o : gm::kImageFlagOptions)
        if (a.flags.count(o)) throw UsageError(o + " applies to raster inputs only");
}

// convert/render of a mesh file: read within the limits, write through `writer`.
void convertMeshFile(const std::string& in, const std::string& out, const gm::MeshFormat& writer,
                     const gm::WriteOptions& wo, const gm::CommandLimits& limits,
                     gm::ConversionProgress& progress) {
    gm::ReadOptions ro;
    ro.limits.maxPatches = limits.maxDocumentPatches;
    progress.stage("read");
    auto t0 = std::chrono::steady_clock::now();
    const gm::Document doc = readDocument(gm::FormatRegistry::builtin(), in, ro);
    const double readSeconds = secondsSince(t0);
    if (writer.name() == "raster")
        gm::requireRenderWithinLimits(doc.width, doc.height, wo.rasterScale, limits, out);
    if (writer.name() == "svg" && wo.svgFallback != "none")  // the fallback is a render
        gm::requireRenderWithinLimits(doc.width, doc.height, 1.0, limits, out);
    progress.stage(writer.name() == "raster" ? "render" : "write");
    t0 = std::chrono::steady_clock::now();
    writer.write(gm::documentForWriter(doc, writer, wo, out), out, wo);
    detail("  %-26s %8.3f s\n  %-26s %8.3f s\n  %zu mesh(es), %llu patches\n", "read", readSeconds,
           writer.name() == "raster" ? "render" : "write", secondsSince(t0), doc.meshes.size(),
           static_cast<unsigned long long>(gm::documentPatches(doc)));
}

int cmdConvert(const std::string& command, const Args& a) {
    const gm::WriteOptions wo = parseWriteOptions(a);
    gm::CommandLimits limits;
    try {
        limits = gm::commandLimits(a.values);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    return runConversions(command, a, [&](const std::string& in, const std::string& out,
                                          const gm::MeshFormat& writer) {
        requireInputFile(in);
        gm::refuseOverwritingInput(in, out);
        gm::ConversionProgress progress(command + " " + std::filesystem::path(in).filename().string());
        if (command == "convert") {
            const gm::MeshFormat* reader = gm::FormatRegistry::builtin().forReading(in);
            if (reader && reader->name() == "raster") {
                convertRasterInput(a, in, out, writer, wo, progress);
                return;
            }
            refuseImageOptions(a, wo);
        }
        convertMeshFile(in, out, writer, wo, limits, progress);
    });
}

// The pixels compared: the mask's white, else A's opaque pixels (alpha at least 1/2); then
// eroded by `erode` pixels (Chebyshev), which leaves out the outline.
std::vector<uint8_t> comparedPixels(const gm::RgbaImage& A, const gm::RgbaImage* M, int erode) {
    const int W = A.width, H = A.height;
    std::vector<uint8_t> in(static_cast<size_t>(W) * H, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            in[static_cast<size_t>(y) * W + x] =
                M ? M->at(x, y)[0] * M->at(x, y)[3] >= 0.5f : A.at(x, y)[3] >= 0.5f;
    if (erode <= 0) return in;
    std::vector<uint8_t> out(in.size(), 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool all = true;
            for (int dy = -erode; dy <= erode && all; ++dy)
                for (int dx = -erode; dx <= erode && all; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    all = xx >= 0 && yy >= 0 && xx < W && yy < H && in[static_cast<size_t>(yy) * W + xx];
                }
            out[static_cast<size_t>(y) * W + x] = all;
        }
    return out;
}

int cmdCompare(const Args& a) {
    if (a.positional.size() != 2) throw UsageError("expects two images A B");
    for (const auto& p : a.positional) requireInputFile(p);
    gm::RgbaImage A = gm::readImage(a.positional[0]);
    gm::RgbaImage B = gm::readImage(a.positional[1]);
    if (A.width != B.width || A.height != B.height)
        throw Error("size " + std::to_string(B.width) + "x" + std::to_string(B.height) +
                        " differs from " + std::to_string(A.width) + "x" + std::to_string(A.height) +
                        " of " + a.positional[0],
                    a.positional[1]);
    gm::RgbaImage M;
    const bool hasMask = a.values.count("--mask") > 0;
    if (hasMask) {
        const std::string mp = a.values.at("--mask");
        requireInputFile(mp);
        M = gm::readImage(mp);
        if (M.width != A.width || M.height != A.height)
            throw Error("mask size " + std::to_string(M.width) + "x" + std::to_string(M.height) +
                            " differs from the images' " + std::to_string(A.width) + "x" +
                            std::to_string(A.height),
                        mp);
    }
    const int erode = a.values.count("--erode")
                          ? static_cast<int>(parseNumber("--erode", a.values.at("--erode"), 0, 64))
                          : 0;
    const std::vector<uint8_t> in = comparedPixels(A, hasMask ? &M : nullptr, erode);
    if (auto it = a.values.find("--background"); it != a.values.end()) {
        const std::array<float, 4> bg = parseColor(it->second);
        if (bg[3] < 1.0f) throw UsageError("--background needs an opaque colour, got '" + it->second + "'");
        gm::compositeOver(A, bg);
        gm::compositeOver(B, bg);
    }
    double sum = 0, sq = 0, mx = 0;
    size_t n = 0, uncovered = 0;
    std::vector<float> errors;
    for (int y = 0; y < A.height; ++y) {
        for (int x = 0; x < A.width; ++x) {
            if (!in[static_cast<size_t>(y) * A.width + x]) continue;
            ++n;
            if (B.at(x, y)[3] < 0.5f) ++uncovered;
            for (int c = 0; c < 3; ++c) {
                const double e = std::fabs(double(A.at(x, y)[c]) - B.at(x, y)[c]) * 255.0;
                sum += e;
                sq += e * e;
                mx = std::max(mx, e);
                errors.push_back(static_cast<float>(e));
            }
        }
    }
    if (n == 0) throw Error("no pixels to compare (the mask or A's alpha selects none)", hasMask ? a.values.at("--mask") : a.positional[0]);
    const double E = sum / (3.0 * n), rmse = std::sqrt(sq / (3.0 * n));
    const double psnr = rmse > 0 ? 20.0 * std::log10(255.0 / rmse) : INFINITY;
    const size_t k99 = std::min(errors.size() - 1, static_cast<size_t>(0.99 * errors.size()));
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(k99), errors.end());
    std::printf("pixels: %zu\nE: %.4f\nRMSE: %.4f\nPSNR: %.2f\nmax: %.2f\np99: %.2f\nuncovered: %.6f\n",
                n, E, rmse, psnr, mx, errors[k99], double(uncovered) / n);
    return 0;
}

int cmdSample(const Args& a) {
    if (a.positional.size() != 1) throw UsageError("expects exactly one output file");
    const std::string out = a.positional[0];
    gm::FormatRegistry::builtin().writerFor(out).write(gm::makeDemoDocument(), out, gm::WriteOptions{});
    return 0;
}


// The valued options and the flags of convert (or render).
std::pair<std::set<std::string>, std::set<std::string>> convertOptionNames(
    const std::string& command) {
    std::set<std::string> valued = {"--output", "--svg-colors", "--svg-script", "--color-tolerance",
                                    "--min-piece", "--scale", "--background", "--mesh-lines",
                                    "--max-output-bytes", "--svg-fallback", "--to",
                                    "--output-dir"};
    valued.insert(std::begin(gm::kLimitOptions), std::end(gm::kLimitOptions));
    std::set<std::string> flags = {"--compact", "--legacy", "--text-shading"};
    if (command == "convert") {
        valued.insert("--compact-level");
        valued.insert(gm::kImageValuedOptions.begin(), gm::kImageValuedOptions.end());
        flags.insert(gm::kImageFlagOptions.begin(), gm::kImageFlagOptions.end());
    }
    return {valued, flags};
}

int runConvert(const std::string& command, int argc, char** argv) {
    const auto [valued, flags] = convertOptionNames(command);
    return cmdConvert(command, parseArgs(command, argc, argv, valued, flags));
}

// batch (batch_command.h): convert's options and their parsing, for each image.
int runBatch(const std::string&, int argc, char** argv) {
    gm::ConvertSyntax syntax;
    std::tie(syntax.valued, syntax.flags) = convertOptionNames("convert");
    for (const char* own : {"--to", "--output-dir"}) syntax.valued.erase(own);  // batch's own
    syntax.writeOptions = [](const std::map<std::string, std::string>& values,
                             const std::set<std::string>& flags) {
        Args a;
        a.values = values;
        a.flags = flags;
        return parseWriteOptions(a);
    };
    try {
        return gm::batchCommand(std::vector<std::string>(argv + 2, argv + argc), syntax);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

int runView(const std::string& command, int argc, char** argv) {
    std::set<std::string> valued = gm::kViewValuedOptions;
    valued.insert("--output");
    valued.insert(std::begin(gm::kLimitOptions), std::end(gm::kLimitOptions));
    const Args a = parseArgs(command, argc, argv, valued, {});
    try {
        gm::viewCommand(a.positional, a.values);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    return 0;
}

// info IN, or info - for a mesh file on standard input.
int runInfo(const std::string& command, int argc, char** argv) {
    Args a = parseArgs(command, argc, argv, {}, {});
    if (a.positional.size() != 1 || !isStdStream(a.positional[0]))
        return infoCommand(a, gm::FormatRegistry::builtin());
    PrivateDir dir;
    a.positional[0] = spoolStandardInput(dir, gm::FormatRegistry::builtin());
    return withFileNamed(a.positional[0], kStdinName,
                         [&] { return infoCommand(a, gm::FormatRegistry::builtin(), kStdinName); });
}

int runCompare(const std::string& command, int argc, char** argv) {
    return cmdCompare(parseArgs(command, argc, argv, {"--mask", "--background", "--erode"}, {}));
}

int runSample(const std::string& command, int argc, char** argv) {
    return cmdSample(parseArgs(command, argc, argv, {}, {}));
}

}  // namespace

int runCommand(const std::string& command, int argc, char** argv) {
    // Every command of commands.cpp, by name.
    using Runner = int (*)(const std::string&, int, char**);
    static const std::map<std::string, Runner> runners = {
        {"convert", runConvert}, {"render", runConvert}, {"info", runInfo},
        {"compare", runCompare}, {"view", runView},      {"sample", runSample},
        {"batch", runBatch},
    };
    const auto it = runners.find(command);
    if (it == runners.end()) return 2;  // answerWithoutRunning reports unknown commands
    return runReportingErrors(command, [&] { return it->second(command, argc, argv); });
}

}  // namespace gm::cli
