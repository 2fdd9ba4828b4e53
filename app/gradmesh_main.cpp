// The `gradmesh` command. Only this layer turns errors into messages and exit codes:
// 0 success, 1 a failure with the input or output, 2 a usage error.
#include <malloc.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "converters/bicubic_model.h"
#include "formats/gmb.h"
#include "formats/input_file.h"
#include "formats/raster.h"
#include "batch_command.h"
#include "command_limits.h"
#include "image_command.h"
#include "view_command.h"
#include "formats/registry.h"
#include "formats/svg.h"
#include "formats/temp_registry.h"
#include "meshcore/error.h"
#include "meshcore/printable_text.h"
#include "meshcore/render.h"
#include "meshcore/split_legacy.h"
#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"

namespace {

using gm::Error;

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

const char* kMainHelp =
    "gradmesh — raster images to topology-preserving gradient meshes\n"
    "\n"
    "usage: gradmesh <command> [options]\n"
    "\n"
    "commands:\n"
    "  convert IN -o OUT     convert an image (.png .jpg ...) or a mesh file to .gmb .svg .eps .pdf .png\n"
    "  render IN -o OUT.png  re-render a mesh file as a raster image\n"
    "  info IN               meshes, grid sizes, holes, patches, bytes\n"
    "  view IN -o PAGE.html  a page to look at a mesh file: render, mesh lines, zoom, figures\n"
    "  compare A B           error figures between two images (E, RMSE, PSNR, max, coverage)\n"
    "  sample OUT.gmb        write the built-in sample document (a mesh with 3 holes + a curved mesh)\n"
    "  batch INPUTS --output-dir DIR  many images (directories, globs, manifests), resumable\n"
    "\n"
    "`gradmesh <command> --help` describes each command.\n";

const std::map<std::string, std::string> kHelp = {
    {"convert",
     "usage: gradmesh convert IN -o OUT [options]\n"
     "  Reads IN (by content and extension) and writes OUT in the format of its extension.\n"
     "  -o, --output PATH       output file (required; never the input)\n"
     "  --compact               .gmb: quantised, compressed (positions within 1/64 px)\n"
     "  --compact-level L       .gmb: compact on coarser grids, L = 0 (as --compact) to 6, or\n"
     "                          auto (image inputs): the coarsest level whose file adds at most\n"
     "                          5% to the mesh's E; 2 is ~40% smaller for ~0.2 dB on a photo.\n"
     "                          From an image, colours are refitted to the file's grids\n"
     "  --legacy                write every mesh with holes as its hole-free pieces\n"
     "  --svg-colors MODE       SVG: bicubic (default: one patch per patch, type=bicubic, as\n"
     "                          Inkscape draws it; Hermite meshes are refitted to it and the\n"
     "                          error printed) or exact (Hermite colours kept by subdividing\n"
     "                          patches; large). OUT.svgz writes it gzipped\n"
     "  --svg-script MODE       SVG: embed (default: a script that draws the meshes in web\n"
     "                          browsers, which have no mesh support; docs/browsers.md) or none\n"
     "  --color-tolerance T     exact-colour subdivision tolerance, 0-255 units (default 1)\n"
     "  --min-piece PX          exact colours: sub-patches at least PX canvas pixels long\n"
     "                          (default 1; 0: split until within the tolerance, however small)\n"
     "  --svg-fallback KIND     SVG: our render beneath the meshes, for viewers that draw no\n"
     "                          meshes (browsers' <img>, CSS, librsvg): png (every viewer),\n"
     "                          webp (lossless, smaller; browsers only, not librsvg) or none\n"
     "                          (default). Not updated when the mesh is edited in Inkscape\n"
     "  --text-shading          EPS/PDF: text DataSource instead of the binary stream\n"
     "  --scale S               raster outputs: pixels per canvas pixel (default 1)\n"
     "  --background COLOR      raster outputs: #rrggbb, #rrggbbaa, white, black or none\n"
     "  --mesh-lines COLOR      raster outputs: draw every patch edge and node in COLOR\n"
     "  limits (docs/limits.md), checked before the work:\n"
     "  --max-memory SIZE       memory budget, e.g. 4G (default), 512M\n"
     "  --max-document-patches N  patches of all meshes read or converted (default 1048576)\n"
     "  --max-output-bytes N    SVG/EPS/PDF outputs (default 1073741824)\n"
     "  --max-canvas-pixels N   raster outputs (default 268435456 = 16384^2)\n"},
    {"render",
     "usage: gradmesh render IN -o OUT.png [--scale S] [--background COLOR] [--mesh-lines COLOR]\n"
     "  Re-renders the meshes of IN (exact Ferguson evaluation, anti-aliased outline).\n"
     "  -o, --output PATH       .png .jpg .tif .exr\n"
     "  --scale S               output pixels per canvas pixel (default 1)\n"
     "  --background COLOR      #rrggbb, #rrggbbaa, white, black or none (default none)\n"
     "  --mesh-lines COLOR      draw every patch edge (grid lines, outline, slits) and node in\n"
     "                          COLOR over the render, as a mesh tool shows them\n"
     "  --max-memory SIZE, --max-document-patches N, --max-canvas-pixels N: as for convert\n"},
    {"info",
     "usage: gradmesh info IN\n"
     "  Prints the canvas, and per mesh its grid, patches, holes and legacy piece count.\n"},
    {"compare",
     "usage: gradmesh compare A B [--mask M] [--background COLOR] [--erode N]\n"
     "  Error of image B against image A over the pixels where the mask is white (default:\n"
     "  where A is opaque), in 0-255 units: E (mean absolute error per channel), RMSE, PSNR,\n"
     "  max, the 99th percentile of the channel errors, and the fraction of those pixels that\n"
     "  B leaves uncovered.\n"
     "  --background COLOR  composite both images over this opaque colour first: B's partly\n"
     "                      transparent pixels (seams between meshes) then count as the\n"
     "                      background shows through them\n"
     "  --erode N           leave out pixels within N px of the compared area's edge\n"},
    {"view", gm::kViewHelp},
    {"batch", gm::kBatchHelp},
    {"sample",
     "usage: gradmesh sample OUT\n"
     "  Writes the built-in sample document (512x512: a mesh with 3 holes and a curved mesh)\n"
     "  in the format of OUT's extension.\n"},
};

struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;
    std::set<std::string> flags;
};

Args parseArgs(const std::string& command, int argc, char** argv, const std::set<std::string>& valued,
               const std::set<std::string>& flagNames) {
    Args a;
    for (int k = 2; k < argc; ++k) {
        std::string s = argv[k];
        if (s == "-o") s = "--output";
        if (s.size() > 1 && s[0] == '-' && !(s.size() > 1 && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.'))) {
            std::string value;
            const size_t eq = s.find('=');
            bool hasValue = false;
            if (eq != std::string::npos) {
                value = s.substr(eq + 1);
                s = s.substr(0, eq);
                hasValue = true;
            }
            if (valued.count(s)) {
                if (!hasValue) {
                    if (k + 1 >= argc) throw UsageError(s + " needs a value");
                    value = argv[++k];
                }
                a.values[s] = value;
            } else if (flagNames.count(s) && !hasValue) {
                a.flags.insert(s);
            } else {
                throw UsageError("unknown option '" + s + "' for '" + command + "'");
            }
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

double parseNumber(const std::string& option, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        char range[64];
        std::snprintf(range, sizeof range, "%g to %g", lo, hi);
        throw UsageError(option + " expects a number from " + range + ", got '" + text + "'");
    }
    return v;
}

std::array<float, 4> parseColor(const std::string& text) {
    if (text == "none" || text == "transparent") return {0, 0, 0, 0};
    if (text == "white") return {1, 1, 1, 1};
    if (text == "black") return {0, 0, 0, 1};
    if ((text.size() == 7 || text.size() == 9) && text[0] == '#' &&
        text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        std::array<float, 4> c = {0, 0, 0, 1};
        for (size_t k = 0; k * 2 + 1 < text.size(); ++k)
            c[k] = std::stoi(text.substr(1 + 2 * k, 2), nullptr, 16) / 255.f;
        return c;
    }
    throw UsageError("--background expects #rrggbb, #rrggbbaa, white, black or none, got '" + text + "'");
}

// Refuses a missing input and anything but a regular file (a FIFO would hang the run, a device
// feed it without end) before anything opens it.
void requireInputFile(const std::string& path) { gm::requireRegularFile(path); }

// Refuses an output that is the input (same file, whatever the spelling).
void requireDistinct(const std::string& in, const std::string& out, const char* role = "input") {
    std::error_code ec;
    if (std::filesystem::exists(out, ec) && std::filesystem::equivalent(in, out, ec))
        throw Error(std::string("output is the ") + role + " file; refusing to overwrite it", out);
}

// Errors are one line: libraries' messages (OpenImageIO's) may hold several, often repeated.
std::string oneLine(const std::string& message) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (start <= message.size()) {
        size_t end = message.find_first_of("\r\n", start);
        if (end == std::string::npos) end = message.size();
        std::string part = message.substr(start, end - start);
        const size_t a = part.find_first_not_of(" \t"), b = part.find_last_not_of(" \t");
        part = a == std::string::npos ? std::string() : part.substr(a, b - a + 1);
        bool seen = part.empty();
        for (const std::string& p : parts)
            seen = seen || p.find(part) != std::string::npos;
        if (!seen) parts.push_back(part);
        start = end + 1;
    }
    std::string line;
    for (const std::string& p : parts) line += (line.empty() ? "" : "; ") + p;
    return line;
}

// What an error prints: one line, input text in it (file names, SVG ids, attribute values)
// with its control characters escaped.
std::string messageLine(const std::string& message) { return gm::printableText(oneLine(message)); }

const gm::MeshFormat* readerFor(const std::string& path) {
    const gm::MeshFormat* f = gm::FormatRegistry::builtin().forReading(path);
    if (!f || !f->canRead()) {
        throw Error(f ? "cannot read meshes from " + f->name() + " files" : "unknown file type '" + gm::lowerExtension(path) + "'", path);
    }
    return f;
}

const gm::MeshFormat* writerFor(const std::string& path) {
    const gm::MeshFormat* f = gm::FormatRegistry::builtin().forPath(path);
    if (!f || !f->canWrite()) {
        std::string known;
        for (const gm::MeshFormat* g : gm::FormatRegistry::builtin().all())
            if (g->canWrite())
                for (const std::string& e : g->extensions()) known += (known.empty() ? "" : " ") + e;
        throw Error("cannot write '" + gm::lowerExtension(path) + "' files (known: " + known + ")", path);
    }
    return f;
}

gm::Document readDocument(const std::string& path, const gm::ReadOptions& options = {}) {
    requireInputFile(path);
    gm::Document doc = readerFor(path)->read(path, options);
    if (std::string e = gm::validateDocument(doc); !e.empty()) throw Error("invalid mesh: " + e, path);
    return doc;
}

std::string requireOutput(const Args& a) {
    auto it = a.values.find("--output");
    if (it == a.values.end() || it->second.empty()) throw UsageError("missing -o OUTPUT");
    return it->second;
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
                        const gm::MeshFormat& writer, const gm::WriteOptions& wo) {
    if (auto it = a.values.find("--mask"); it != a.values.end()) {
        if (it->second.empty()) throw UsageError("--mask needs a file name");
        requireInputFile(it->second);
        requireDistinct(it->second, out, "mask");
    }
    std::map<std::string, std::string> values = a.values;
    for (const std::string& f : gm::kImageFlagOptions)
        if (a.flags.count(f)) values[f] = "1";
    try {
        gm::convertImageCommand(in, out, writer, wo, values);
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
                     const gm::WriteOptions& wo, const gm::CommandLimits& limits) {
    gm::ReadOptions ro;
    ro.limits.maxPatches = limits.maxDocumentPatches;
    const gm::Document doc = readDocument(in, ro);
    if (writer.name() == "raster")
        gm::requireRenderWithinLimits(doc.width, doc.height, wo.rasterScale, limits, out);
    if (writer.name() == "svg" && wo.svgFallback != "none")  // the fallback is a render
        gm::requireRenderWithinLimits(doc.width, doc.height, 1.0, limits, out);
    writer.write(gm::documentForWriter(doc, writer, wo, out), out, wo);
}

int cmdConvert(const Args& a, bool renderOnly) {
    if (a.positional.size() != 1) throw UsageError("expects exactly one input file");
    const std::string in = a.positional[0];
    const std::string out = requireOutput(a);
    const gm::WriteOptions wo = parseWriteOptions(a);
    gm::CommandLimits limits;
    try {
        limits = gm::commandLimits(a.values);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    const gm::MeshFormat* writer = writerFor(out);
    if (renderOnly && writer->name() != "raster")
        throw UsageError("render writes raster images (.png .jpg .tif .exr); use convert for '" +
                         gm::lowerExtension(out) + "'");
    requireInputFile(in);
    requireDistinct(in, out);
    if (!renderOnly) {
        const gm::MeshFormat* reader = gm::FormatRegistry::builtin().forReading(in);
        if (reader && reader->name() == "raster") {
            convertRasterInput(a, in, out, *writer, wo);
            return 0;
        }
        refuseImageOptions(a, wo);
    }
    convertMeshFile(in, out, *writer, wo, limits);
    return 0;
}

int cmdInfo(const Args& a) {
    if (a.positional.size() != 1) throw UsageError("expects exactly one input file");
    const std::string in = a.positional[0];
    const gm::Document doc = readDocument(in);
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(in, ec);
    int patches = 0, holes = 0, pieces = 0;
    for (const gm::GradientMesh& m : doc.meshes) {
        patches += m.patchCount();
        holes += m.holeCount();
        pieces += gm::legacyPieceCount(m);
    }
    std::printf("file: %s\nformat: %s\nbytes: %llu\ncanvas: %d x %d\nmeshes: %zu\npatches: %d\n"
                "holes: %d\nlegacy pieces: %d\n",
                gm::printableText(in).c_str(), readerFor(in)->name().c_str(), static_cast<unsigned long long>(bytes),
                doc.width, doc.height, doc.meshes.size(), patches, holes, pieces);
    for (size_t k = 0; k < doc.meshes.size(); ++k) {
        const gm::GradientMesh& m = doc.meshes[k];
        std::printf("mesh %zu: %s, grid %d x %d, %d patches, %d holes, %d legacy pieces", k,
                    m.colorModel == gm::ColorModel::Bicubic ? "bicubic" : "hermite", m.columns(),
                    m.rows(), m.patchCount(), m.holeCount(), gm::legacyPieceCount(m));
        if (!m.tangents.empty()) std::printf(", %zu tangent breaks", m.tangents.size());
        std::printf("\n");
    }
    // A Hermite mesh's colour slopes are its own; the SVG carries the bicubic rule's, so
    // convert refits its colours: say how close that comes.
    if (gm::hasHermiteMeshes(doc)) {
        const gm::BicubicConversion c = gm::toBicubicModel(doc);
        std::printf("bicubic refit (svg): %d hermite mesh(es), E %.2f, PSNR %.2f dB, max %.0f/255 "
                    "from the hermite render\n",
                    c.refitted, c.error.meanAbs, c.error.psnr, c.error.maxAbs);
    }
    return 0;
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
    writerFor(out)->write(gm::makeDemoDocument(), out, gm::WriteOptions{});
    return 0;
}

// The valued options and the flags of convert (or render).
std::pair<std::set<std::string>, std::set<std::string>> convertOptionNames(const std::string& command) {
    std::set<std::string> valued = {"--output", "--svg-colors", "--svg-script", "--color-tolerance", "--min-piece",
                                    "--scale", "--background", "--mesh-lines", "--max-output-bytes"};
    valued.insert(std::begin(gm::kLimitOptions), std::end(gm::kLimitOptions));
    valued.insert("--svg-fallback");
    if (command == "convert") valued.insert("--compact-level");
    if (command == "convert") valued.insert(gm::kImageValuedOptions.begin(), gm::kImageValuedOptions.end());
    std::set<std::string> flags = {"--compact", "--legacy", "--text-shading"};
    if (command == "convert") flags.insert(gm::kImageFlagOptions.begin(), gm::kImageFlagOptions.end());
    return {valued, flags};
}

// batch (batch_command.h): convert's options and their parsing, for each image.
int cmdBatch(int argc, char** argv) {
    gm::ConvertSyntax syntax;
    std::tie(syntax.valued, syntax.flags) = convertOptionNames("convert");
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

}  // namespace

// A thread that cannot start (std::thread's system_error EAGAIN, TBB's "pthread_create has
// failed") means the process has no memory left for the thread's stack.
static bool isThreadStartFailure(const std::exception& e) {
    if (std::string(e.what()).find("pthread_create") != std::string::npos) return true;
    const auto* system = dynamic_cast<const std::system_error*>(&e);
    return system && system->code() == std::errc::resource_unavailable_try_again;
}

int main(int argc, char** argv) {
    // Refinement allocates and frees the same image-sized buffers (render samples, the fit's
    // system) on every step; glibc hands blocks over its mmap threshold back to the kernel and
    // the next step faults them in again, a large share of a long conversion's time.
    // Blocks up to 32 MB stay in the heap, which is trimmed only above 256 MB of free space.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    // Interrupted or terminated, the run removes its temporaries before it dies; over a file
    // size limit (ulimit -f), a write fails with an error instead of killing the run.
    gm::removeTemporariesOnSignals();
    std::signal(SIGXFSZ, SIG_IGN);
    if (argc < 2) {
        std::fputs(kMainHelp, stderr);
        return 2;
    }
    const std::string command = argv[1];
    if (command == "--help" || command == "-h" || command == "help") {
        std::fputs(kMainHelp, stdout);
        return 0;
    }
    if (command == "--version") {
        std::puts("gradmesh 0.1.0");
        return 0;
    }
    if (!kHelp.count(command)) {
        std::fprintf(stderr, "gradmesh: unknown command '%s' (try gradmesh --help)\n",
                     gm::printableText(command).c_str());
        return 2;
    }
    for (int k = 2; k < argc; ++k) {
        if (std::strcmp(argv[k], "--help") == 0 || std::strcmp(argv[k], "-h") == 0) {
            std::fputs(kHelp.at(command).c_str(), stdout);
            if (command == "convert") std::fputs(gm::kImageConvertHelp, stdout);
            return 0;
        }
    }
    try {
        if (command == "convert" || command == "render") {
            const auto [valued, flags] = convertOptionNames(command);
            const Args a = parseArgs(command, argc, argv, valued, flags);
            return cmdConvert(a, command == "render");
        }
        if (command == "batch") return cmdBatch(argc, argv);
        if (command == "info") return cmdInfo(parseArgs(command, argc, argv, {}, {}));
        if (command == "compare")
            return cmdCompare(parseArgs(command, argc, argv, {"--mask", "--background", "--erode"}, {}));
        if (command == "view") {
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
        if (command == "sample") return cmdSample(parseArgs(command, argc, argv, {}, {}));
    } catch (const UsageError& e) {
        std::fprintf(stderr, "gradmesh %s: %s (see gradmesh %s --help)\n", command.c_str(),
                     messageLine(e.what()).c_str(), command.c_str());
        return 2;
    } catch (const gm::Error& e) {
        std::fprintf(stderr, "gradmesh %s: %s\n", command.c_str(), messageLine(e.what()).c_str());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "gradmesh %s: out of memory\n", command.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gradmesh %s: %s%s\n", command.c_str(),
                     isThreadStartFailure(e) ? "out of memory: cannot start a thread: " : "",
                     messageLine(e.what()).c_str());
        return 1;
    }
    return 2;
}
