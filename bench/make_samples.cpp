// Writes the benchmark's synthetic and derived inputs as PNGs into OUTDIR (bench/run.sh calls it
// at bench time; nothing it writes is committed).
//
//   make_samples OUTDIR [--samples DIR] [--big N]
//
//   blob.png          512x512 shaded non-convex blob (union of four ellipses), anti-aliased,
//                     transparent background, no holes
//   disc.png          480x480 smoothly shaded disc, no holes
//   amulet.png        the same disc with 21 round holes (1 + a ring of 8 + a ring of 12)
//   annulus.png       480x480 ring: the same shading, one hole
//   horse_mask.png    white where samples/horse.png is dark (the silhouette is in its RGB; its
//                     alpha is opaque but for four corner pixels)
//   apple_N.png, apple_N_mask.png   samples/apple.jpg and apple_mask.png upscaled to NxN
//                     (Catmull-Rom bicubic; default N = 4096; --big 0 skips them)
//
// The shapes are 8x8 supersampled for their coverage (alpha); colour is a smooth function
// evaluated at the pixel centre (straight alpha); fully transparent pixels are (0,0,0,0).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "formats/raster.h"

using namespace gm;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Ellipse {
    double cx, cy, a, b, angleDeg;
    bool inside(double x, double y) const {
        const double t = angleDeg * kPi / 180, c = std::cos(t), s = std::sin(t);
        const double dx = x - cx, dy = y - cy;
        const double u = (c * dx + s * dy) / a, v = (-s * dx + c * dy) / b;
        return u * u + v * v <= 1.0;
    }
};

struct Rgb {
    double r, g, b;
};

// An image whose alpha is the 8x8-supersampled coverage of `inside` and whose colour is
// `colour` at the pixel centre.
RgbaImage paint(int W, int H, const std::function<bool(double, double)>& inside,
                const std::function<Rgb(double, double)>& colour) {
    RgbaImage img(W, H);
    constexpr int S = 8;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int hits = 0;
            for (int j = 0; j < S; ++j)
                for (int i = 0; i < S; ++i)
                    hits += inside(x + (i + 0.5) / S, y + (j + 0.5) / S) ? 1 : 0;
            float* p = img.at(x, y);
            if (!hits) continue;
            const Rgb c = colour(x + 0.5, y + 0.5);
            p[0] = float(std::clamp(c.r, 0.0, 1.0));
            p[1] = float(std::clamp(c.g, 0.0, 1.0));
            p[2] = float(std::clamp(c.b, 0.0, 1.0));
            p[3] = float(hits) / (S * S);
        }
    return img;
}

Rgb mix(Rgb a, Rgb b, double t) {
    return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

double smoothstep(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

// Blob shading: a diagonal orange → crimson ramp, lit from the upper left (radial falloff) with
// a soft highlight.
Rgb blobColor(double x, double y) {
    const double t = smoothstep((x + 0.6 * y - 120) / 520);
    const Rgb base = mix({0.98, 0.62, 0.18}, {0.62, 0.10, 0.32}, t);
    const double r = std::hypot(x - 190, y - 170);
    const double shade = 0.45 + 0.55 * std::exp(-(r * r) / (2 * 190.0 * 190.0));
    const double hl = 0.35 * std::exp(-(r * r) / (2 * 45.0 * 45.0));
    return {base.r * shade + hl, base.g * shade + hl, base.b * shade + hl};
}

// Disc shading: brass, lit from the upper left, darker towards the rim, a faint linear tint.
Rgb discColor(double x, double y) {
    const double cx = 240, cy = 240;
    const double r = std::hypot(x - cx, y - cy) / 220;
    const double l = std::hypot(x - 170, y - 150);
    const double shade = 0.5 + 0.5 * std::exp(-(l * l) / (2 * 160.0 * 160.0));
    const double rim = 1 - 0.25 * r * r;
    const double t = smoothstep((x - y + 240) / 480);
    const Rgb base = mix({0.86, 0.68, 0.30}, {0.70, 0.45, 0.22}, t);
    const double hl = 0.25 * std::exp(-(l * l) / (2 * 50.0 * 50.0));
    return {base.r * shade * rim + hl, base.g * shade * rim + hl, base.b * shade * rim + hl};
}

struct Circle {
    double cx, cy, r;
    bool inside(double x, double y) const {
        return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r;
    }
};

std::vector<Circle> amuletHoles() {
    std::vector<Circle> holes{{240, 240, 28}};
    for (int k = 0; k < 8; ++k) {
        const double a = 2 * kPi * k / 8;
        holes.push_back({240 + 85 * std::cos(a), 240 + 85 * std::sin(a), 16});
    }
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * kPi * (k + 0.5) / 12;
        holes.push_back({240 + 165 * std::cos(a), 240 + 165 * std::sin(a), 11});
    }
    return holes;
}

// Catmull-Rom (Keys a = -0.5) weights.
double cubic(double t) {
    t = std::fabs(t);
    if (t < 1) return 1.5 * t * t * t - 2.5 * t * t + 1;
    if (t < 2) return -0.5 * t * t * t + 2.5 * t * t - 4 * t + 2;
    return 0;
}

// Separable bicubic resampling to W x H (pixel centres aligned, edges clamped, values clamped).
RgbaImage resize(const RgbaImage& src, int W, int H) {
    const int sw = src.width, sh = src.height;
    auto taps = [](int dst, int srcSize, int o, int* idx, double* w) {
        const double s = (o + 0.5) * srcSize / dst - 0.5;
        const int i0 = int(std::floor(s));
        double sum = 0;
        for (int k = 0; k < 4; ++k) {
            const int i = i0 - 1 + k;
            w[k] = cubic(s - i);
            idx[k] = std::clamp(i, 0, srcSize - 1);
            sum += w[k];
        }
        for (int k = 0; k < 4; ++k) w[k] /= sum;
    };
    std::vector<float> tmp(static_cast<size_t>(W) * sh * 4);  // horizontal pass
    for (int x = 0; x < W; ++x) {
        int idx[4];
        double w[4];
        taps(W, sw, x, idx, w);
        for (int y = 0; y < sh; ++y)
            for (int c = 0; c < 4; ++c) {
                double v = 0;
                for (int k = 0; k < 4; ++k) v += w[k] * src.at(idx[k], y)[c];
                tmp[(static_cast<size_t>(y) * W + x) * 4 + c] = float(v);
            }
    }
    RgbaImage out(W, H);
    for (int y = 0; y < H; ++y) {
        int idx[4];
        double w[4];
        taps(H, sh, y, idx, w);
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 4; ++c) {
                double v = 0;
                for (int k = 0; k < 4; ++k)
                    v += w[k] * tmp[(static_cast<size_t>(idx[k]) * W + x) * 4 + c];
                out.at(x, y)[c] = std::clamp(float(v), 0.f, 1.f);
            }
    }
    return out;
}

void save(const RgbaImage& img, const std::filesystem::path& path) {
    writeImage(img, path.string());
    std::printf("%s %dx%d\n", path.string().c_str(), img.width, img.height);
}

}  // namespace

int main(int argc, char** argv) {
    std::string outDir, samples = "samples";
    int big = 4096;
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a == "--samples" && k + 1 < argc)
            samples = argv[++k];
        else if (a == "--big" && k + 1 < argc)
            big = std::atoi(argv[++k]);
        else if (!a.empty() && a[0] != '-' && outDir.empty())
            outDir = a;
        else {
            std::fprintf(stderr, "usage: make_samples OUTDIR [--samples DIR] [--big N]\n");
            return 2;
        }
    }
    if (outDir.empty()) {
        std::fprintf(stderr, "usage: make_samples OUTDIR [--samples DIR] [--big N]\n");
        return 2;
    }
    try {
        const std::filesystem::path out(outDir);
        std::filesystem::create_directories(out);

        const std::vector<Ellipse> lobes{{235, 300, 150, 100, -20},
                                         {345, 175, 95, 68, 35},
                                         {150, 165, 72, 55, 15},
                                         {390, 360, 62, 46, -10}};
        save(paint(
                 512, 512,
                 [&](double x, double y) {
                     for (const Ellipse& e : lobes)
                         if (e.inside(x, y)) return true;
                     return false;
                 },
                 blobColor),
             out / "blob.png");

        const Circle disc{240, 240, 220};
        const std::vector<Circle> holes = amuletHoles();
        save(paint(480, 480, [&](double x, double y) { return disc.inside(x, y); }, discColor),
             out / "disc.png");
        save(paint(
                 480, 480,
                 [&](double x, double y) {
                     if (!disc.inside(x, y)) return false;
                     for (const Circle& h : holes)
                         if (h.inside(x, y)) return false;
                     return true;
                 },
                 discColor),
             out / "amulet.png");
        const Circle inner{240, 240, 95};
        save(paint(
                 480, 480,
                 [&](double x, double y) { return disc.inside(x, y) && !inner.inside(x, y); },
                 discColor),
             out / "annulus.png");

        const std::filesystem::path in(samples);
        {
            const RgbaImage horse = readImage((in / "horse.png").string());
            RgbaImage m(horse.width, horse.height);
            for (int y = 0; y < horse.height; ++y)
                for (int x = 0; x < horse.width; ++x) {
                    const float* p = horse.at(x, y);
                    const float v = (p[0] + p[1] + p[2]) / 3 < 0.5f ? 1.f : 0.f;
                    float* d = m.at(x, y);
                    d[0] = d[1] = d[2] = v;
                    d[3] = 1;
                }
            save(m, out / "horse_mask.png");
        }
        if (big > 0) {
            const std::string n = std::to_string(big);
            save(resize(readImage((in / "apple.jpg").string()), big, big),
                 out / ("apple_" + n + ".png"));
            save(resize(readImage((in / "apple_mask.png").string()), big, big),
                 out / ("apple_" + n + "_mask.png"));
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make_samples: %s\n", e.what());
        return 1;
    }
    return 0;
}
