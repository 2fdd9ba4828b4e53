// Synthetic scenes for the end-to-end convertImage tests: an object given by a signed distance
// function (negative inside, pixels), its mask (pixel (x, y) is object when its centre
// (x+.5, y+.5) is inside), a smooth colour image, and checks on the re-rendered Document.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "converters/convert_image.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

namespace gmtest {

using Sdf = std::function<double(double, double)>;  // < 0 inside, ≈ distance to the edge

inline double discSdf(double x, double y, double cx, double cy, double r) {
    return std::hypot(x - cx, y - cy) - r;
}
// Axis-aligned box [x0,x1] × [y0,y1].
inline double boxSdf(double x, double y, double x0, double y0, double x1, double y1) {
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    const double dx = std::abs(x - cx) - (x1 - x0) / 2, dy = std::abs(y - cy) - (y1 - y0) / 2;
    const double ox = std::max(dx, 0.0), oy = std::max(dy, 0.0);
    return std::hypot(ox, oy) + std::min(std::max(dx, dy), 0.0);
}

struct Hole {
    double cx, cy, r;
    double sdf(double x, double y) const { return discSdf(x, y, cx, cy, r); }
};

// A smooth colour: linear ramps in x and y plus a wide radial bump, all within 0.2–0.8.
inline gm::RgbaImage smoothImage(int w, int h) {
    gm::RgbaImage img(w, h);
    const double sigma = 0.35 * std::max(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double px = x + .5, py = y + .5;
            const double d2 = (px - 0.4 * w) * (px - 0.4 * w) + (py - 0.45 * h) * (py - 0.45 * h);
            float* p = img.at(x, y);
            p[0] = static_cast<float>(0.25 + 0.5 * px / w);
            p[1] = static_cast<float>(0.7 - 0.4 * py / h);
            p[2] = static_cast<float>(0.3 + 0.45 * std::exp(-d2 / (2 * sigma * sigma)));
            p[3] = 1;
        }
    return img;
}

inline gm::ObjectMask maskFromSdf(int w, int h, const Sdf& sdf) {
    gm::ObjectMask m;
    m.width = w;
    m.height = h;
    m.source = gm::MaskSource::MaskImage;
    m.mask.assign(static_cast<size_t>(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) m.mask[static_cast<size_t>(y) * w + x] = sdf(x + .5, y + .5) < 0;
    return m;
}

struct Outcome {
    gm::Document doc;
    gm::ConvertReport report;
    gm::RgbaImage render;  // anti-aliased re-render at scale 1
    double seconds = 0;    // convertImage alone
    bool threw = false;
    std::string error;     // gm::Error::what() when it threw
};

inline Outcome convert(const gm::RgbaImage& image, const gm::ObjectMask& mask,
                       const gm::ConvertOptions& options, const std::string& name) {
    Outcome o;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        o.doc = gm::convertImage(image, mask, options, name, &o.report);
    } catch (const gm::Error& e) {
        o.threw = true;
        o.error = e.what();
    }
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!o.threw) o.render = gm::renderDocument(o.doc).image;
    return o;
}

inline float alphaAt(const gm::RgbaImage& r, int x, int y) { return r.at(x, y)[3]; }

// Fraction of the pixels selected by `pick` whose re-rendered alpha is ≥ 0.5 (covered); 1 when
// none is selected. `count` receives how many were selected.
inline double coveredFraction(const gm::RgbaImage& r, const std::function<bool(int, int)>& pick,
                              long* count = nullptr) {
    long n = 0, c = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            if (pick(x, y)) {
                ++n;
                c += alphaAt(r, x, y) >= 0.5f;
            }
    if (count) *count = n;
    return n ? double(c) / n : 1.0;
}

// E (mean absolute channel error, 0–255) over the covered object pixels, measured here.
inline double meanError(const gm::RgbaImage& r, const gm::RgbaImage& image, const gm::ObjectMask& m) {
    double sum = 0;
    long n = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            if (!m.mask[static_cast<size_t>(y) * m.width + x] || alphaAt(r, x, y) < 0.5f) continue;
            for (int c = 0; c < 3; ++c) sum += std::fabs(double(r.at(x, y)[c]) - image.at(x, y)[c]) * 255;
            n += 3;
        }
    return n ? sum / n : 0;
}

// Fraction of hole pixels (centre inside the hole, more than 1 px from its edge) that the
// re-render leaves uncovered (alpha < 0.5).
inline double holeUncovered(const gm::RgbaImage& r, const Hole& h, long* count = nullptr) {
    return 1.0 - coveredFraction(r, [&](int x, int y) { return h.sdf(x + .5, y + .5) < -1; }, count);
}

inline void note(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline void note(const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stdout, fmt, ap);
    va_end(ap);
    std::fputc('\n', stdout);
    std::fflush(stdout);
}

}  // namespace gmtest
