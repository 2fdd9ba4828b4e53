// A synthetic drawing of thin structures for the whole-image tests (samples/thin_lines.png is
// this image): 300x200, three flat panels (dark, light, grey), each with a horizontal line, a
// diagonal, a vertical line, a polyline, a ring and a turned ellipse ring, 2, 3 and 4 px wide
// (each panel its own mix), bright on the dark panel, dark on the light one, saturated colours
// on the grey one. Anti-aliased: each pixel's coverage is its share of 8x8 samples within half
// the width of the structure's centre line.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm::test {

struct ThinStructure {
    const char* name;
    std::vector<Vec2> polyline;      // empty: an ellipse ring
    Vec2 centre{0, 0};               // ellipse ring: centre, semi-axes, turn (radians)
    double a = 0, b = 0, turn = 0;
    double width = 2;
    float colour[3] = {0, 0, 0};

    // Distance from (x, y) to the centre line (for the ellipse, to first order).
    double distance(double x, double y) const {
        if (polyline.empty()) {
            const double c = std::cos(turn), s = std::sin(turn);
            const double u = (x - centre.x) * c + (y - centre.y) * s;
            const double v = -(x - centre.x) * s + (y - centre.y) * c;
            const double g = std::sqrt(u * u / (a * a) + v * v / (b * b));
            if (g < 1e-9) return std::min(a, b);
            const double gu = u / (a * a * g), gv = v / (b * b * g);
            return std::abs(g - 1) / std::hypot(gu, gv);
        }
        double best = 1e30;
        for (size_t k = 0; k + 1 < polyline.size(); ++k) {
            const Vec2 p = polyline[k], q = polyline[k + 1];
            const double dx = q.x - p.x, dy = q.y - p.y;
            const double t =
                std::clamp(((x - p.x) * dx + (y - p.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
            best = std::min(best, std::hypot(x - p.x - t * dx, y - p.y - t * dy));
        }
        return best;
    }

    // Points along the centre line, at most half a pixel apart.
    std::vector<Vec2> centreLine() const {
        std::vector<Vec2> out;
        if (polyline.empty()) {
            const int n = static_cast<int>(std::ceil(2 * 2 * M_PI * std::max(a, b)));
            const double c = std::cos(turn), s = std::sin(turn);
            for (int k = 0; k < n; ++k) {
                const double t = 2 * M_PI * k / n;
                const double u = a * std::cos(t), v = b * std::sin(t);
                out.push_back({centre.x + u * c - v * s, centre.y + u * s + v * c});
            }
            return out;
        }
        for (size_t k = 0; k + 1 < polyline.size(); ++k) {
            const Vec2 p = polyline[k], q = polyline[k + 1];
            const int n = static_cast<int>(std::ceil(2 * std::hypot(q.x - p.x, q.y - p.y)));
            for (int i = 0; i <= n; ++i) {
                const double t = static_cast<double>(i) / n;
                out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
            }
        }
        return out;
    }

    // Bounding box of the structure's pixels: x0, y0, x1, y1 (inclusive), clipped to w x h.
    void bounds(int w, int h, int box[4]) const {
        double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
        for (const Vec2& p : centreLine()) {
            x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
            x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
        }
        const double r = width / 2 + 1;
        box[0] = std::max(0, static_cast<int>(std::floor(x0 - r)));
        box[1] = std::max(0, static_cast<int>(std::floor(y0 - r)));
        box[2] = std::min(w - 1, static_cast<int>(std::ceil(x1 + r)));
        box[3] = std::min(h - 1, static_cast<int>(std::ceil(y1 + r)));
    }
};

struct ThinScene {
    static constexpr int kWidth = 300, kHeight = 200, kPanel = 100;
    std::vector<ThinStructure> structures;
    // Per structure, per pixel: coverage 0..1 (w x h).
    std::vector<std::vector<float>> coverage;
    RgbaImage image;
};

// The panels' backgrounds and structure colours, left to right.
inline ThinScene thinStructuresScene() {
    ThinScene scene;
    const float backgrounds[3][3] = {{0.08f, 0.08f, 0.10f}, {0.93f, 0.92f, 0.90f}, {0.5f, 0.5f, 0.5f}};
    const float colours[3][6][3] = {
        {{0.95f, 0.95f, 0.95f}, {1.0f, 0.92f, 0.55f}, {0.85f, 0.95f, 1.0f},
         {0.95f, 0.95f, 0.95f}, {1.0f, 0.92f, 0.55f}, {0.85f, 0.95f, 1.0f}},
        {{0.08f, 0.08f, 0.12f}, {0.25f, 0.12f, 0.05f}, {0.05f, 0.10f, 0.25f},
         {0.08f, 0.08f, 0.12f}, {0.25f, 0.12f, 0.05f}, {0.05f, 0.10f, 0.25f}},
        {{0.90f, 0.08f, 0.08f}, {0.10f, 0.20f, 0.95f}, {0.05f, 0.80f, 0.15f},
         {0.95f, 0.85f, 0.05f}, {0.85f, 0.10f, 0.85f}, {0.05f, 0.85f, 0.90f}},
    };
    // Widths of (horizontal, diagonal, vertical, polyline, ring, ellipse) per panel: every kind
    // at every width.
    const double widths[3][6] = {{2, 3, 4, 3, 4, 2}, {3, 4, 2, 4, 2, 3}, {4, 2, 3, 2, 3, 4}};
    static const char* names[3][6] = {
        {"bright horizontal", "bright diagonal", "bright vertical", "bright polyline",
         "bright ring", "bright ellipse"},
        {"dark horizontal", "dark diagonal", "dark vertical", "dark polyline", "dark ring",
         "dark ellipse"},
        {"red horizontal", "blue diagonal", "green vertical", "yellow polyline", "magenta ring",
         "cyan ellipse"}};
    for (int panel = 0; panel < 3; ++panel) {
        const double o = panel * ThinScene::kPanel;
        std::vector<ThinStructure> s(6);
        s[0].polyline = {{o + 8, 10.5}, {o + 92, 10.5}};
        s[1].polyline = {{o + 8, 24}, {o + 70, 60}};
        s[2].polyline = {{o + 88.5, 24}, {o + 88.5, 190}};
        s[3].polyline = {{o + 8, 78}, {o + 30, 70}, {o + 52, 92}, {o + 74, 74}};
        s[4].centre = {o + 40, 126}, s[4].a = s[4].b = 21;
        s[5].centre = {o + 41, 172}, s[5].a = 30, s[5].b = 14, s[5].turn = 0.2;
        for (int k = 0; k < 6; ++k) {
            s[k].name = names[panel][k];
            s[k].width = widths[panel][k];
            std::copy(colours[panel][k], colours[panel][k] + 3, s[k].colour);
            scene.structures.push_back(s[k]);
        }
    }
    const int W = ThinScene::kWidth, H = ThinScene::kHeight;
    scene.image = RgbaImage(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float* p = scene.image.at(x, y);
            const float* bg = backgrounds[std::min(2, x / ThinScene::kPanel)];
            std::copy(bg, bg + 3, p);
            p[3] = 1;
        }
    for (const ThinStructure& st : scene.structures) {
        std::vector<float> cover(static_cast<size_t>(W) * H, 0.f);
        int box[4];
        st.bounds(W, H, box);
        for (int y = box[1]; y <= box[3]; ++y)
            for (int x = box[0]; x <= box[2]; ++x) {
                int in = 0;
                for (int j = 0; j < 8; ++j)
                    for (int i = 0; i < 8; ++i)
                        in += st.distance(x + (i + .5) / 8, y + (j + .5) / 8) <= st.width / 2;
                const float c = in / 64.f;
                cover[static_cast<size_t>(y) * W + x] = c;
                float* p = scene.image.at(x, y);
                for (int ch = 0; ch < 3; ++ch) p[ch] = p[ch] * (1 - c) + st.colour[ch] * c;
            }
        scene.coverage.push_back(std::move(cover));
    }
    return scene;
}

}  // namespace gm::test
