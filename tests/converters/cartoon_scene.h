// A synthetic cartoon for the ink-line tests: 240x180, on white, a body (an ellipse) parted by a
// curved line into an orange-to-yellow front and a purple-to-red back, a green fin partly
// behind it, and an eye (a white disc with a black pupil), every part outlined in near-black
// ink 2-3 px wide. The fills
// are smooth gradients, as a cartoon's shading is; outlines and fills are anti-aliased (8x8
// samples per pixel).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "meshcore/image.h"
#include "thin_structures.h"

namespace gm::test {

struct CartoonScene {
    static constexpr int kWidth = 240, kHeight = 180;
    std::vector<ThinStructure> outlines;
    std::vector<std::vector<float>> coverage;  // per outline, per pixel, 0..1
    RgbaImage image;
};

namespace cartoon {

inline bool inEllipse(double x, double y, double cx, double cy, double a, double b) {
    return (x - cx) * (x - cx) / (a * a) + (y - cy) * (y - cy) / (b * b) <= 1;
}

// The fill colour at a sample point: white, the fin, the body's front or back, the eye.
inline void fillAt(double x, double y, float* rgb) {
    const float white[3] = {1, 1, 1};
    std::copy(white, white + 3, rgb);
    if (inEllipse(x, y, 190, 52, 30, 14)) {  // the fin, behind the body
        const float t = static_cast<float>((x - 160) / 60);
        rgb[0] = 0.15f + 0.2f * t, rgb[1] = 0.75f - 0.25f * t, rgb[2] = 0.2f;
    }
    if (inEllipse(x, y, 110, 95, 85, 58)) {
        const double divide = 120 + 18 * std::sin((y - 95) / 58 * 1.4);  // the parting curve
        const float t = static_cast<float>(std::clamp((x - 25) / 170, 0.0, 1.0));
        const float s = static_cast<float>(std::clamp((y - 37) / 116, 0.0, 1.0));
        if (x < divide)
            rgb[0] = 1.0f, rgb[1] = 0.45f + 0.45f * t, rgb[2] = 0.08f + 0.1f * s;
        else
            rgb[0] = 0.45f + 0.4f * s, rgb[1] = 0.1f, rgb[2] = 0.55f - 0.3f * t;
    }
    if (inEllipse(x, y, 70, 75, 13, 13)) std::copy(white, white + 3, rgb);
    if (inEllipse(x, y, 73, 77, 4.5, 4.5)) rgb[0] = rgb[1] = rgb[2] = 0.03f;
}

}  // namespace cartoon

inline CartoonScene cartoonScene() {
    CartoonScene scene;
    const float ink[3] = {0.07f, 0.04f, 0.03f};
    auto outline = [&](const char* name, double width) {
        ThinStructure s;
        s.name = name;
        s.width = width;
        std::copy(ink, ink + 3, s.colour);
        return s;
    };
    ThinStructure body = outline("body outline", 3);
    body.centre = {110, 95}, body.a = 85, body.b = 58;
    ThinStructure eye = outline("eye outline", 2);
    eye.centre = {70, 75}, eye.a = eye.b = 13;
    ThinStructure parting = outline("parting line", 2.5);
    for (int k = 0; k <= 20; ++k) {
        const double y = 95 - 58 + 5.8 * k;
        parting.polyline.push_back({120 + 18 * std::sin((y - 95) / 58 * 1.4), y});
    }
    ThinStructure fin = outline("fin outline", 2.5);
    fin.centre = {190, 52}, fin.a = 30, fin.b = 14;
    scene.outlines = {body, eye, parting, fin};
    const int W = CartoonScene::kWidth, H = CartoonScene::kHeight;
    scene.image = RgbaImage(W, H);
    scene.coverage.assign(scene.outlines.size(), std::vector<float>(static_cast<size_t>(W) * H, 0));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double sum[3] = {0, 0, 0};
            std::vector<int> hits(scene.outlines.size(), 0);
            for (int sy = 0; sy < 8; ++sy)
                for (int sx = 0; sx < 8; ++sx) {
                    const double px = x + (sx + 0.5) / 8, py = y + (sy + 0.5) / 8;
                    float rgb[3];
                    cartoon::fillAt(px, py, rgb);
                    bool inked = false;
                    for (size_t k = 0; k < scene.outlines.size(); ++k)
                        if (scene.outlines[k].distance(px, py) <= scene.outlines[k].width / 2) {
                            ++hits[k];
                            inked = true;
                        }
                    for (int c = 0; c < 3; ++c) sum[c] += inked ? ink[c] : rgb[c];
                }
            float* p = scene.image.at(x, y);
            for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(sum[c] / 64);
            p[3] = 1;
            for (size_t k = 0; k < scene.outlines.size(); ++k)
                scene.coverage[k][static_cast<size_t>(y) * W + x] = hits[k] / 64.0f;
        }
    return scene;
}

}  // namespace gm::test
