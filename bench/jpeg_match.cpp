// The JPEG size at a given PSNR: encodes the whole image as JPEG at qualities 1..100 in several
// modes, decodes each file back with the same reader gradmesh uses, and
// measures it over the object's pixels exactly as `gradmesh convert --report` does: the mask comes
// from objectMask (mask image, else alpha, else GrabCut) and extractRegions (--min-area,
// --min-hole as convert's defaults), E = mean absolute error per channel in 0-255 units,
// RMSE likewise, PSNR = 20 log10(255 / RMSE). Prints one JSON object on stdout.
//
//   jpeg_match IMAGE [--mask M.png | --whole] [--psnr P] [--scan] [--curve] [--subsampling LIST]
//              [--tmp DIR] [--min-area N] [--min-hole N] [--max-pixels N]
//
//   without --psnr: only the object's statistics (pixels, regions, holes, mask source)
//   --psnr P        the smallest JPEG file whose PSNR >= P; quality is searched by bisection
//                   (PSNR rises with quality), then the qualities just below the answer are
//                   checked; --scan encodes every quality and reports where PSNR is not monotone
//   --subsampling   modes to try, comma separated; the answer is the smallest file over all of
//                   them. A mode is a chroma subsampling, 4:2:0 or 4:4:4, alone (OpenImageIO's
//                   JPEG writer: baseline, libjpeg's standard Huffman tables), with
//                   "/progressive" (OpenImageIO, progressive: libjpeg optimises the tables of
//                   each scan) or with "/optimized" (libjpeg-turbo directly: baseline with
//                   optimize_coding, the tables fitted to the image, as ImageMagick or libvips
//                   write it). Default: all six. At low quality the tables are much of a small
//                   file: HappyFish q1 is 2,314 B baseline, 1,394 B optimised, same pixels.
//   --whole         measure every pixel of the image (no mask, no object: convert --segment)
//   --curve         the rate-distortion curve: every quality 1..100 in every subsampling mode,
//                   "curve": [{"subsampling", "points": [[quality, bytes, psnr, E], ...]}]
//   bytes are the whole .jpg file (headers included) for the whole image, not only the object:
//   JPEG has no notion of the mask, and any alpha is dropped (straight colour is encoded).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <jpeglib.h>
#include <unistd.h>

#include "converters/convert_image.h"
#include "converters/foreground.h"
#include "converters/regions.h"
#include "formats/raster.h"

using namespace gm;

namespace {

struct Measure {
    long bytes = 0;
    double E = 0, rmse = 0, psnr = 0;
};

struct Subject {
    const RgbaImage* image;
    std::vector<uint8_t> mask;  // the measured pixels
    std::vector<uint8_t> rgb;   // 8-bit straight colour, what the JPEG encodes
    std::string tmpBase;
};

std::string num(double v) {
    if (std::isinf(v)) return v > 0 ? "1e308" : "-1e308";
    if (std::isnan(v)) return "null";
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

// libjpeg-turbo directly: baseline, Huffman tables optimised for the image (optimize_coding).
void writeOptimized(const Subject& s, int quality, bool subsample, const std::string& path) {
    const RgbaImage& img = *s.image;
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + path);
    jpeg_compress_struct cinfo;
    jpeg_error_mgr jerr;
    cinfo.err = jpeg_std_error(&jerr);
    jpeg_create_compress(&cinfo);
    jpeg_stdio_dest(&cinfo, f);
    cinfo.image_width = static_cast<JDIMENSION>(img.width);
    cinfo.image_height = static_cast<JDIMENSION>(img.height);
    cinfo.input_components = 3;
    cinfo.in_color_space = JCS_RGB;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, quality, TRUE);
    cinfo.optimize_coding = TRUE;
    for (int c = 0; c < 3; ++c)
        cinfo.comp_info[c].h_samp_factor = cinfo.comp_info[c].v_samp_factor =
            (c == 0 && subsample) ? 2 : 1;
    jpeg_start_compress(&cinfo, TRUE);
    const size_t stride = static_cast<size_t>(img.width) * 3;
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW row = const_cast<JSAMPROW>(s.rgb.data() + cinfo.next_scanline * stride);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path);
}

Measure encode(const Subject& s, int quality, const std::string& mode) {
    const RgbaImage& img = *s.image;
    const std::string path = s.tmpBase + "_" + std::to_string(quality) + ".jpg";
    const size_t slash = mode.find('/');
    const std::string subsampling = mode.substr(0, slash);
    const std::string coder = slash == std::string::npos ? "" : mode.substr(slash + 1);
    if (subsampling != "4:2:0" && subsampling != "4:4:4")
        throw std::runtime_error("unknown subsampling in mode " + mode);
    if (coder == "optimized") {
        writeOptimized(s, quality, subsampling == "4:2:0", path);
    } else if (!coder.empty() && coder != "progressive") {
        throw std::runtime_error("unknown JPEG coder in mode " + mode);
    } else {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) throw std::runtime_error("no JPEG writer: " + OIIO::geterror());
        OIIO::ImageSpec spec(img.width, img.height, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("Compression", "jpeg:" + std::to_string(quality));
        spec.attribute("CompressionQuality", quality);
        spec.attribute("jpeg:subsampling", subsampling);
        if (coder == "progressive") spec.attribute("jpeg:progressive", 1);
        if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, s.rgb.data()) ||
            !out->close())
            throw std::runtime_error("cannot write " + path + ": " + out->geterror());
    }
    Measure m;
    m.bytes = static_cast<long>(std::filesystem::file_size(path));
    const RgbaImage back = readImage(path);
    std::filesystem::remove(path);
    if (back.width != img.width || back.height != img.height)
        throw std::runtime_error("decoded JPEG has another size");
    const FitError e = compareOverMask(img, back, s.mask);  // a JPEG is opaque: all covered
    m.E = e.meanAbs;
    m.rmse = e.rmse;
    m.psnr = e.psnr;
    return m;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> r;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) r.push_back(item);
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    std::string imagePath, maskPath, tmpDir = std::filesystem::temp_directory_path().string();
    std::string subsampling =
        "4:2:0,4:4:4,4:2:0/progressive,4:4:4/progressive,4:2:0/optimized,4:4:4/optimized";
    double target = NAN;
    bool scan = false, whole = false, curve = false;
    RegionOptions ro;
    ro.minArea = 64;  // convert's defaults (ConvertOptions)
    ro.minHole = 16;
    uint64_t maxPixels = uint64_t(64) << 20;
    const char* usage =
        "usage: jpeg_match IMAGE [--mask M | --whole] [--psnr P] [--scan] [--curve]"
        " [--subsampling LIST] [--tmp DIR] [--min-area N] [--min-hole N] [--max-pixels N]\n";
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        const bool more = k + 1 < argc;
        if (a == "--mask" && more)
            maskPath = argv[++k];
        else if (a == "--psnr" && more)
            target = std::atof(argv[++k]);
        else if (a == "--scan")
            scan = true;
        else if (a == "--whole")
            whole = true;
        else if (a == "--curve")
            curve = true;
        else if (a == "--subsampling" && more)
            subsampling = argv[++k];
        else if (a == "--tmp" && more)
            tmpDir = argv[++k];
        else if (a == "--min-area" && more)
            ro.minArea = std::atoi(argv[++k]);
        else if (a == "--min-hole" && more)
            ro.minHole = std::atoi(argv[++k]);
        else if (a == "--max-pixels" && more)
            maxPixels = std::strtoull(argv[++k], nullptr, 10);
        else if (!a.empty() && a[0] != '-' && imagePath.empty())
            imagePath = a;
        else {
            std::fputs(usage, stderr);
            return 2;
        }
    }
    if (imagePath.empty() || (whole && !maskPath.empty())) {
        std::fputs(usage, stderr);
        return 2;
    }
    try {
        const RgbaImage image = readImage(imagePath, maxPixels);
        Subject s;
        s.image = &image;
        const size_t n = static_cast<size_t>(image.width) * image.height;
        long pixels = 0;
        int holes = 0;
        size_t regionCount = 1;
        std::string maskSource = "whole";
        if (whole) {
            s.mask.assign(n, 1);
            pixels = static_cast<long>(n);
        } else {
            RgbaImage maskImage;
            if (!maskPath.empty()) maskImage = readImage(maskPath, maxPixels);
            const ObjectMask om =
                objectMask(image, maskPath.empty() ? nullptr : &maskImage, imagePath, maskPath);
            const std::vector<Region> regions =
                extractRegions(coverageFromBits(om.width, om.height, om.mask), ro);
            s.mask.assign(om.mask.size(), 0);
            for (const Region& r : regions) {
                for (size_t k = 0; k < r.mask.size(); ++k) s.mask[k] |= r.mask[k];
                pixels += r.pixelCount;
                holes += static_cast<int>(r.holes.size());
            }
            regionCount = regions.size();
            maskSource = maskSourceName(om.source);
        }
        std::ostringstream js;
        js << "{\"width\": " << image.width
           << ", \"height\": " << image.height << ", \"mask_source\": \""
           << maskSource << "\", \"regions\": " << regionCount
           << ", \"pixels\": " << pixels << ", \"holes\": " << holes;

        if (!std::isnan(target) || curve) {
            s.rgb.resize(n * 3);
            for (size_t p = 0; p < n; ++p)
                for (int c = 0; c < 3; ++c)
                    s.rgb[p * 3 + c] = static_cast<uint8_t>(
                        std::lround(std::clamp(image.pixels[p * 4 + c], 0.f, 1.f) * 255));
            s.tmpBase = (std::filesystem::path(tmpDir) /
                         ("jpeg_match_" + std::to_string(::getpid())))
                            .string();
        }
        if (curve) {
            js << ", \"curve\": [";
            const std::vector<std::string> modes = split(subsampling);
            for (size_t mi = 0; mi < modes.size(); ++mi) {
                js << (mi ? ", " : "") << "{\"subsampling\": \"" << modes[mi]
                   << "\", \"points\": [";
                for (int q = 1; q <= 100; ++q) {
                    const Measure m = encode(s, q, modes[mi]);
                    js << (q > 1 ? ", " : "") << "[" << q << ", " << m.bytes << ", "
                       << num(m.psnr) << ", " << num(m.E) << "]";
                }
                js << "]}";
            }
            js << "]";
        }
        if (!std::isnan(target)) {
            js << ", \"target_psnr\": " << num(target) << ", \"modes\": [";
            long bestBytes = -1;
            std::string bestMode;
            int bestQ = 0;
            Measure bestM;
            const std::vector<std::string> modes = split(subsampling);
            for (size_t mi = 0; mi < modes.size(); ++mi) {
                const std::string& mode = modes[mi];
                std::map<int, Measure> seen;
                auto at = [&](int q) -> const Measure& {
                    auto it = seen.find(q);
                    if (it == seen.end()) it = seen.emplace(q, encode(s, q, mode)).first;
                    return it->second;
                };
                int nonMonotone = 0;
                if (scan) {
                    for (int q = 1; q <= 100; ++q) at(q);
                    for (int q = 2; q <= 100; ++q)
                        if (seen[q].psnr < seen[q - 1].psnr) ++nonMonotone;
                }
                // Bisection for the lowest quality reaching the target.
                int found = 0;
                if (at(100).psnr >= target) {
                    int lo = 1, hi = 100;  // invariant: hi reaches it
                    if (at(1).psnr >= target) hi = 1;
                    while (hi - lo > 1) {
                        const int mid = (lo + hi) / 2;
                        (at(mid).psnr >= target ? hi : lo) = mid;
                    }
                    found = hi;
                    for (int q = std::max(1, found - 3); q < found; ++q) at(q);  // verify below
                }
                // The smallest file among everything encoded that reaches the target.
                long bytes = -1;
                int q = 0;
                int belowReaching = 0;  // qualities under `found` that reach the target
                for (const auto& [qq, m] : seen) {
                    if (m.psnr < target) continue;
                    if (found && qq < found) ++belowReaching;
                    if (bytes < 0 || m.bytes < bytes) {
                        bytes = m.bytes;
                        q = qq;
                    }
                }
                js << (mi ? ", " : "") << "{\"subsampling\": \"" << mode << "\"";
                if (bytes >= 0) {
                    const Measure& m = seen[q];
                    js << ", \"quality\": " << q << ", \"bytes\": " << bytes
                       << ", \"psnr\": " << num(m.psnr) << ", \"E\": " << num(m.E);
                    if (bestBytes < 0 || bytes < bestBytes) {
                        bestBytes = bytes;
                        bestMode = mode;
                        bestQ = q;
                        bestM = m;
                    }
                } else {
                    js << ", \"quality\": null, \"bytes\": null, \"psnr_at_100\": "
                       << num(seen[100].psnr) << ", \"bytes_at_100\": " << seen[100].bytes;
                }
                js << ", \"encodes\": " << seen.size() << ", \"below_bisection_reaching\": "
                   << belowReaching;
                if (scan) {
                    js << ", \"non_monotone_steps\": " << nonMonotone << ", \"scan\": [";
                    bool first = true;
                    for (const auto& [qq, m] : seen) {
                        js << (first ? "" : ", ") << "[" << qq << ", " << m.bytes << ", "
                           << num(m.psnr) << "]";
                        first = false;
                    }
                    js << "]";
                }
                js << "}";
            }
            js << "]";
            if (bestBytes >= 0)
                js << ", \"bytes\": " << bestBytes << ", \"quality\": " << bestQ
                   << ", \"subsampling\": \"" << bestMode << "\", \"psnr\": " << num(bestM.psnr)
                   << ", \"E\": " << num(bestM.E);
            else
                js << ", \"bytes\": null";
        }
        js << "}\n";
        std::fputs(js.str().c_str(), stdout);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "jpeg_match: %s\n", e.what());
        return 1;
    }
    return 0;
}
