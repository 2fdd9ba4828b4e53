#include "meshcore/render.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>

#include "meshcore/error.h"
#include "meshcore/evaluate.h"
#include "meshcore/mesh_lines.h"
#include "render_meshes.h"

using namespace gm;
using namespace rendertest;

namespace {

RenderOptions withScale(double scale, bool samples = false) {
    RenderOptions o;
    o.scale = scale;
    o.wantSamples = samples;
    return o;
}

// Largest |pixel colour − expected colour at the pixel centre| over opaque pixels, 0–1 units.
template <class Expected>
double maxErrorOverOpaque(const RenderResult& r, double scale, Expected expected, int& count) {
    double worst = 0;
    count = 0;
    for (int y = 0; y < r.image.height; ++y)
        for (int x = 0; x < r.image.width; ++x) {
            const float* p = r.image.at(x, y);
            if (p[3] != 1.0f) continue;
            const Vec3 e = expected(Vec2{(x + 0.5) / scale, (y + 0.5) / scale});
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(p[c] - e[c]));
            ++count;
        }
    return worst;
}

}  // namespace

TEST_CASE("a colour linear in position renders exactly on affine geometry", "[render]") {
    // Uneven knots and a sheared grid: the patches differ, the colour field does not.
    GradientMesh m = affineMesh({0, 1, 2.5, 3, 5}, {0, 0.5, 2, 3}, {12.3, 9.7}, {18, 3}, {-4, 25});
    const Vec3 gx{0.004, -0.003, 0.001}, gy{0.002, 0.005, -0.004}, c0{0.1, 0.2, 0.6};
    setLinearColor(m, gx, gy, c0);
    for (double scale : {1.0, 3.0}) {
        const RenderResult r = renderMesh(m, 128, 96, withScale(scale));
        int count = 0;
        const double err = maxErrorOverOpaque(
            r, scale, [&](Vec2 p) { return p.x * gx + p.y * gy + c0; }, count);
        CHECK(count > 2000 * scale * scale);
        CHECK(err <= 1.0 / 255);
        CHECK(err <= 1e-5);  // affine geometry tessellates exactly: only float rounding is left
    }
}

TEST_CASE("a colour linear in position renders within 1/255 on curved geometry", "[render]") {
    // Steep ramps (0 to 1 over 8 px, far beyond 0–1 across the mesh: overshoot is not clamped)
    // on strongly curved patches: the tessellation must be fine enough that the position
    // error times the colour gradient stays below 1/255, not just below 1/8 px.
    GradientMesh m = curvedMesh(6, 5, 20, 15, 200, 160, 1.5);
    const Vec3 gx{1.0 / 8, -1.0 / 300, 0.0}, gy{0.0, 1.0 / 9, 1.0 / 250};
    setLinearColor(m, gx, gy, {-0.5, -0.3, 0.0});
    for (double scale : {1.0, 2.0}) {
        const RenderResult r = renderMesh(m, 240, 200, withScale(scale));
        int count = 0;
        const double err = maxErrorOverOpaque(
            r, scale,
            [&](Vec2 p) {
                return p.x * gx + p.y * gy + Vec3{-0.5, -0.3, 0.0};
            },
            count);
        CHECK(count > 20000 * scale * scale);
        CHECK(err * 255 <= 1.0);
    }
}

TEST_CASE("hole pixels stay uncovered and the rest is opaque", "[render]") {
    const double x0 = 10, y0 = 8, w = 180, h = 120, hb = 0.6 * h / 4;
    const GradientMesh m = holedMesh(x0, y0, w, h, hb);
    const Vec2 c = {x0 + w / 2, y0 + h / 2};
    const double a = w / 6;
    for (double scale : {1.0, 2.5}) {
        const RenderResult r = renderMesh(m, 200, 140, withScale(scale, true));
        int inHole = 0, inMesh = 0;
        for (int y = 0; y < r.image.height; ++y)
            for (int x = 0; x < r.image.width; ++x) {
                const Vec2 p{(x + 0.5) / scale, (y + 0.5) / scale};
                const double ex = (p.x - c.x) / a, ey = (p.y - c.y) / hb;
                const double e = std::sqrt(ex * ex + ey * ey);
                const float alpha = r.image.at(x, y)[3];
                const PixelSample& s = r.samples[static_cast<size_t>(y) * r.image.width + x];
                if (e < 0.85) {  // well inside the hole
                    ++inHole;
                    CHECK(alpha == 0.0f);
                    CHECK(s.mesh == -1);
                } else if (e > 1.2 && p.x > x0 + 2 && p.x < x0 + w - 2 && p.y > y0 + 2 &&
                           p.y < y0 + h - 2) {
                    ++inMesh;
                    CHECK(alpha == 1.0f);
                    CHECK(s.centre);
                }
            }
        CHECK(inHole > 1000 * scale * scale);
        CHECK(inMesh > 10000 * scale * scale);
    }
}

TEST_CASE("scale 4 box-downsampled matches scale 1", "[render]") {
    const GradientMesh m = curvedMesh(7, 6, 14.3, 11.6, 190, 150, 1.0);
    const RenderResult r1 = renderMesh(m, 220, 180, withScale(1));
    const RenderResult r4 = renderMesh(m, 220, 180, withScale(4));
    REQUIRE(r4.image.width == 880);
    REQUIRE(r4.image.height == 720);
    double sum = 0, worst = 0, worstAlpha = 0;
    int count = 0;
    for (int y = 0; y < r1.image.height; ++y)
        for (int x = 0; x < r1.image.width; ++x) {
            double col[3] = {0, 0, 0}, alpha = 0;
            bool opaque = true;
            for (int dy = 0; dy < 4; ++dy)
                for (int dx = 0; dx < 4; ++dx) {
                    const float* q = r4.image.at(4 * x + dx, 4 * y + dy);
                    alpha += q[3] / 16.0;
                    opaque = opaque && q[3] == 1.0f;
                    for (int c = 0; c < 3; ++c) col[c] += q[c] / 16.0;
                }
            const float* p = r1.image.at(x, y);
            worstAlpha = std::max(worstAlpha, std::fabs(alpha - p[3]));
            if (!opaque || p[3] != 1.0f) continue;
            for (int c = 0; c < 3; ++c) {
                const double e = std::fabs(col[c] - p[c]);
                sum += e;
                worst = std::max(worst, e);
            }
            ++count;
        }
    REQUIRE(count > 20000);
    const double mean = sum / (3.0 * count);
    INFO("mean " << mean * 255 << "/255, max " << worst * 255 << "/255, alpha " << worstAlpha);
    CHECK(mean * 255 <= 0.5);
    CHECK(worst * 255 <= 3.0);
    // Coverage is an exact area at both scales: averaging 16 sub-pixels gives the pixel's.
    CHECK(worstAlpha <= 0.01);
}

TEST_CASE("a curved mesh has no cracks: every interior pixel is opaque and sampled", "[render]") {
    const GradientMesh m = curvedMesh(8, 8, 20.4, 16.8, 170, 150, 1.4);
    const auto outline = denseOutline(m, 16);
    for (double scale : {1.0, 1.7}) {
        RenderOptions o = withScale(scale, true);
        const RenderResult r = renderMesh(m, 210, 190, o);
        int interior = 0;
        for (int y = 0; y < r.image.height; ++y)
            for (int x = 0; x < r.image.width; ++x) {
                const Vec2 p{(x + 0.5) / scale, (y + 0.5) / scale};
                // Pixels whose whole square lies inside the outline, with a margin for the
                // test's own polyline outline.
                if (winding(outline, p) == 0 || distanceTo(outline, p) * scale < 0.75) continue;
                ++interior;
                const PixelSample& s = r.samples[static_cast<size_t>(y) * r.image.width + x];
                REQUIRE(r.image.at(x, y)[3] == 1.0f);
                REQUIRE(s.centre);
                REQUIRE(s.mesh == 0);
            }
        CHECK(interior > 20000 * scale * scale);
    }
}

TEST_CASE("outline alpha is the exact area coverage of a rectangle", "[render]") {
    const double x0 = 10.3, y0 = 20.7, x1 = 50.55, y1 = 41.2;
    const GradientMesh m = rectangleMesh(x0, y0, x1, y1, 3, 2, {0.2, 0.4, 0.6});
    for (double scale : {1.0, 1.5}) {
        const RenderResult r = renderMesh(m, 64, 48, withScale(scale));
        double worst = 0, sum = 0;
        for (int y = 0; y < r.image.height; ++y)
            for (int x = 0; x < r.image.width; ++x) {
                const double ox =
                    std::max(0.0, std::min((x + 1) / scale, x1) - std::max(x / scale, x0));
                const double oy =
                    std::max(0.0, std::min((y + 1) / scale, y1) - std::max(y / scale, y0));
                const double exact = ox * oy * scale * scale;
                const float* p = r.image.at(x, y);
                worst = std::max(worst, std::fabs(p[3] - exact));
                sum += p[3];
                if (p[3] > 0) {  // outline pixels take the colour of their covered neighbour
                    CHECK(p[0] == Approx(0.2f));
                    CHECK(p[2] == Approx(0.6f));
                }
            }
        CHECK(worst <= 1e-5);
        CHECK(sum / (scale * scale) == Approx((x1 - x0) * (y1 - y0)).epsilon(1e-6));
    }
}

TEST_CASE("alpha sums to the area of a disc-like mesh", "[render]") {
    const GradientMesh m = discMesh(40.37, 38.81, 29.6);
    const double area = std::fabs(polygonArea(denseOutline(m, 4000)[0]));
    for (double scale : {1.0, 0.5, 3.0}) {
        const RenderResult r = renderMesh(m, 80, 80, withScale(scale));
        double sum = 0;
        int partial = 0;
        for (int y = 0; y < r.image.height; ++y)
            for (int x = 0; x < r.image.width; ++x) {
                sum += r.image.at(x, y)[3];
                partial += r.image.at(x, y)[3] > 0 && r.image.at(x, y)[3] < 1;
            }
        INFO("scale " << scale << ": alpha sum " << sum / (scale * scale) << " vs area " << area);
        CHECK(std::fabs(sum / (scale * scale) - area) <= 5e-4 * area);
        CHECK(partial > 100 * scale);  // the outline really is anti-aliased
    }
}

TEST_CASE("samples name the patch and parameters the colour was evaluated at", "[render]") {
    const GradientMesh holed = holedMesh(5, 6, 150, 100, 14);
    const GradientMesh curved = curvedMesh(5, 4, 30, 20, 130, 110, 1.2);
    for (double scale : {1.0, 2.3}) {
        for (const GradientMesh* m : {&holed, &curved}) {
            const RenderResult r = renderMesh(*m, 170, 140, withScale(scale, true));
            REQUIRE(r.samples.size() == r.image.pixels.size() / 4);
            int painted = 0, centres = 0;
            double worstColor = 0, worstPosition = 0;
            for (int y = 0; y < r.image.height; ++y)
                for (int x = 0; x < r.image.width; ++x) {
                    const PixelSample& s = r.samples[static_cast<size_t>(y) * r.image.width + x];
                    const float* p = r.image.at(x, y);
                    if (s.mesh < 0) {
                        CHECK(p[3] == 0.0f);
                        continue;
                    }
                    ++painted;
                    REQUIRE(s.mesh == 0);
                    REQUIRE(s.s >= 0.0f);
                    REQUIRE(s.s <= 1.0f);
                    const int C = m->columns();
                    const PatchPoint e = evaluatePatch(*m, s.patch % C, s.patch / C, s.s, s.t);
                    for (int c = 0; c < 3; ++c)
                        worstColor = std::max(worstColor, std::fabs(e.col[c] - p[c]));
                    if (s.centre) {
                        ++centres;
                        const Vec2 centre{(x + 0.5) / scale, (y + 0.5) / scale};
                        worstPosition = std::max(worstPosition, norm(e.pos - centre) * scale);
                    }
                }
            CHECK(painted > 8000 * scale * scale);
            CHECK(centres > 0.95 * painted);
            CHECK(worstColor <= 1e-5);
            // The (s,t) of a covered centre maps to within the tessellation tolerance (1/8 output
            // pixel) of it, plus the rasteriser's 1/512-pixel vertex snapping.
            CHECK(worstPosition <= 0.125 + 0.005);
        }
    }
}

TEST_CASE("later meshes are painted over earlier ones", "[render]") {
    Document doc;
    doc.width = 100;
    doc.height = 80;
    doc.meshes.push_back(rectangleMesh(10, 10, 60, 60, 2, 2, {1, 0, 0}));
    doc.meshes.push_back(rectangleMesh(40.5, 30.25, 90, 70, 2, 2, {0, 0, 1}));
    RenderOptions o = withScale(1, true);
    const RenderResult r = renderDocument(doc, o);
    auto px = [&](int x, int y) { return r.image.at(x, y); };
    auto sample = [&](int x, int y) { return r.samples[static_cast<size_t>(y) * 100 + x]; };
    CHECK(px(50, 50)[2] == 1.0f);  // overlap: blue on top
    CHECK(px(50, 50)[0] == 0.0f);
    CHECK(sample(50, 50).mesh == 1);
    CHECK(px(20, 20)[0] == 1.0f);  // red alone
    CHECK(sample(20, 20).mesh == 0);
    CHECK(px(80, 65)[2] == 1.0f);  // blue alone
    // Blue's half-covered left edge over opaque red: an even blend, still opaque.
    CHECK(px(40, 50)[3] == Approx(1.0f));
    CHECK(px(40, 50)[0] == Approx(0.5f));
    CHECK(px(40, 50)[2] == Approx(0.5f));
    CHECK(sample(40, 50).mesh == 0);  // red covers the centre; blue only its right half
    // Swapping the order swaps the winner.
    std::swap(doc.meshes[0], doc.meshes[1]);
    const RenderResult q = renderDocument(doc, o);
    CHECK(q.image.at(50, 50)[0] == 1.0f);
    CHECK(q.samples[50 * 100 + 50].mesh == 1);
}

TEST_CASE("later patches are painted over earlier ones where a mesh folds", "[render]") {
    // Two patches side by side, the right one pulled over the left one.
    GradientMesh m = affineMesh({0, 1, 2}, {0, 1}, {10, 10}, {20, 0}, {0, 20});
    m.node(1, 0).pos.x = 40;
    m.node(1, 1).pos.x = 40;
    m.node(2, 0).pos.x = 25;
    m.node(2, 1).pos.x = 25;
    for (int j = 0; j <= 1; ++j) {
        m.node(0, j).posU = {30, 0};
        m.node(1, j).posU = {0, 0};
        m.node(2, j).posU = {-15, 0};
        m.node(0, j).col = {1, 0, 0};
        m.node(1, j).col = {1, 0, 0};
        m.node(2, j).col = {0, 1, 0};
    }
    const RenderResult r = renderMesh(m, 60, 40, withScale(1, true));
    const PixelSample& s = r.samples[20 * 60 + 30];
    CHECK(s.patch == 1);
    CHECK(r.image.at(30, 20)[3] == 1.0f);
}

TEST_CASE("tessellation adapts to curvature and colour", "[render]") {
    // Big flat patches need one quad each, whatever their size.
    GradientMesh flat = rectangleMesh(0, 0, 400, 300, 4, 3, {0.5, 0.5, 0.5});
    const RenderResult a = renderMesh(flat, 400, 300, withScale(1));
    CHECK(a.triangles == 2u * 12);
    const RenderResult a4 = renderMesh(flat, 400, 300, withScale(4));
    CHECK(a4.triangles == 2u * 12);
    // Curved patches get more, and more at a larger scale (tolerances are in output pixels).
    const GradientMesh curved = curvedMesh(4, 3, 0, 0, 400, 300, 1.0);
    const RenderResult b = renderMesh(curved, 400, 300, withScale(1));
    const RenderResult b4 = renderMesh(curved, 400, 300, withScale(4));
    CHECK(b.triangles > 2u * 12 * 4);
    CHECK(b4.triangles > 3 * b.triangles);
    CHECK(b4.triangles < 6 * b.triangles);  // error ∝ h²: about twice the count per direction
    // A steep colour ramp on flat geometry needs no more triangles than a gentle one: colour
    // is evaluated exactly at each pixel's (s,t), and affine (s,t) is exact.
    GradientMesh ramp = rectangleMesh(0, 0, 400, 300, 4, 3, {0, 0, 0});
    setLinearColor(ramp, {0.05, 0, 0}, {0, 0.05, 0}, {0, 0, 0});
    CHECK(renderMesh(ramp, 400, 300, withScale(1)).triangles == 2u * 12);
}

TEST_CASE("threads do not change the result", "[render]") {
    Document doc;
    doc.width = 300;
    doc.height = 260;
    doc.meshes.push_back(curvedMesh(9, 8, 10, 10, 260, 230, 1.2));
    doc.meshes.push_back(holedMesh(60, 40, 200, 160, 20));
    RenderOptions one = withScale(1.5, true), four = one;
    one.threads = 1;
    four.threads = 4;
    const RenderResult a = renderDocument(doc, one), b = renderDocument(doc, four);
    CHECK(a.image.pixels == b.image.pixels);
    CHECK(a.triangles == b.triangles);
    bool same = a.samples.size() == b.samples.size();
    for (size_t k = 0; same && k < a.samples.size(); ++k)
        same = a.samples[k].mesh == b.samples[k].mesh && a.samples[k].patch == b.samples[k].patch &&
               a.samples[k].s == b.samples[k].s && a.samples[k].t == b.samples[k].t &&
               a.samples[k].centre == b.samples[k].centre;
    CHECK(same);
}

TEST_CASE("without anti-aliasing alpha is 1 exactly where a patch covers the centre", "[render]") {
    const GradientMesh m = discMesh(30, 30, 20);
    RenderOptions o = withScale(1, true);
    o.antialias = false;
    const RenderResult r = renderMesh(m, 60, 60, o);
    for (size_t k = 0; k < r.samples.size(); ++k) {
        const float a = r.image.pixels[4 * k + 3];
        CHECK((a == 1.0f) == r.samples[k].centre);
        CHECK((a == 0.0f || a == 1.0f));
    }
}

TEST_CASE("degenerate and extreme patches neither hang nor explode", "[render]") {
    const auto start = std::chrono::steady_clock::now();
    auto sane = [](const RenderResult& r) {
        for (size_t k = 0; k < r.image.pixels.size(); k += 4) {
            const float a = r.image.pixels[k + 3];
            if (!(a >= 0.0f && a <= 1.0f)) return false;
            if (a > 0 &&
                !(std::isfinite(r.image.pixels[k]) && std::isfinite(r.image.pixels[k + 1]) &&
                  std::isfinite(r.image.pixels[k + 2])))
                return false;
        }
        return true;
    };
    // Every node at one point: zero area.
    GradientMesh point = curvedMesh(4, 4, 0, 0, 100, 100);
    for (Node& n : point.nodes) n.pos = {50, 50}, n.posU = {0, 0}, n.posV = {0, 0};
    CHECK(sane(renderMesh(point, 100, 100)));
    // A line: zero area, non-zero length.
    GradientMesh line = curvedMesh(3, 3, 10, 10, 80, 80);
    for (Node& n : line.nodes) n.pos.y = 40, n.posU.y = 0, n.posV.y = 0;
    CHECK(sane(renderMesh(line, 100, 100)));
    // Wildly folded: huge random-looking tangents.
    GradientMesh folded = curvedMesh(6, 6, 10, 10, 80, 80);
    for (size_t k = 0; k < folded.nodes.size(); ++k) {
        folded.nodes[k].posU = {std::sin(k * 1.7) * 4000, std::cos(k * 2.3) * 3000};
        folded.nodes[k].posV = {std::cos(k * 0.7) * 5000, std::sin(k * 1.1) * 4000};
    }
    CHECK(sane(renderMesh(folded, 100, 100)));
    // Extreme but finite coordinates, partly on the canvas.
    GradientMesh extreme = curvedMesh(3, 3, 10, 10, 80, 80);
    extreme.node(1, 1).pos = {1e15, -1e15};
    extreme.node(2, 2).posU = {1e200, 1e200};
    extreme.node(0, 3).colU = {1e30, -1e30, 0};
    CHECK(sane(renderMesh(extreme, 100, 100, withScale(2))));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(seconds < 5.0);
}

TEST_CASE("bad scales, oversized outputs and malformed meshes are errors", "[render]") {
    const GradientMesh m = rectangleMesh(0, 0, 10, 10, 1, 1, {0, 0, 0});
    CHECK_THROWS_AS(renderMesh(m, 10, 10, withScale(0)), Error);
    CHECK_THROWS_AS(renderMesh(m, 10, 10, withScale(-2)), Error);
    CHECK_THROWS_AS(renderMesh(m, 10, 10, withScale(std::nan(""))), Error);
    CHECK_THROWS_AS(renderMesh(m, 10, 10, withScale(1e300)), Error);
    CHECK_THROWS_AS(renderMesh(m, 2000000000, 10, withScale(4)), Error);
    GradientMesh broken = m;
    broken.nodes.pop_back();
    CHECK_THROWS_AS(renderMesh(broken, 10, 10), Error);
    const RenderResult empty = renderMesh(m, 0, 0);
    CHECK(empty.image.width == 0);
    CHECK(empty.image.pixels.empty());
}

TEST_CASE("mesh lines are drawn on every patch edge and nowhere else", "[render][lines]") {
    // A 2×2 grid over [10,50]²: lines at x, y = 10, 30, 50 (output pixels at scale 2: 20, 60, 100).
    Document d;
    d.width = d.height = 64;
    d.meshes.push_back(rectangleMesh(10, 10, 50, 50, 2, 2, {0.2, 0.4, 0.6}));
    const double scale = 2;
    RgbaImage img = renderDocument(d, withScale(scale)).image;
    const RgbaImage before = img;
    drawMeshLines(img, d, scale, {1, 0, 0, 1});
    auto redness = [&](int x, int y) { return img.at(x, y)[0] - before.at(x, y)[0]; };
    // On grid lines (the pixels each side of the line at 60.0: 59 and 60).
    for (int y : {30, 45, 70, 90}) {
        CHECK(std::max(redness(59, y), redness(60, y)) > 0.3f);  // the middle column line
        CHECK(std::max(redness(19, y), redness(20, y)) > 0.3f);  // the left outline
    }
    CHECK(std::max(redness(40, 59), redness(40, 60)) > 0.3f);  // the middle row line
    // Away from every line: untouched.
    for (auto [x, y] : {std::pair{40, 40}, std::pair{80, 80}, std::pair{40, 85}, std::pair{5, 5}}) {
        CHECK(img.at(x, y)[0] == before.at(x, y)[0]);
        CHECK(img.at(x, y)[3] == before.at(x, y)[3]);
    }
    // Outside the mesh the line colour is opaque-ish over a transparent background.
    CHECK(img.at(19, 40)[3] > 0.3f);
}
