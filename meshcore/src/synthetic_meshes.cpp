#include "meshcore/synthetic_meshes.h"

#include <cassert>
#include <cmath>

namespace gm {

namespace {
constexpr double kPi = 3.14159265358979323846;

// A smooth colour field over the unit square (U, V) with its partial derivatives.
struct ColorField {
    double p0, p1, p2;
    explicit ColorField(unsigned seed)
        : p0(0.7 * seed), p1(1.3 + 0.9 * seed), p2(2.1 + 0.4 * seed) {}
    void eval(double U, double V, Vec3& c, Vec3& cU, Vec3& cV) const {
        const double a = 2 * kPi * 1.1 * U + p0, b = 2 * kPi * 0.9 * V + p1,
                     d = kPi * (U + V) + p2;
        c = {0.5 + 0.38 * std::sin(a), 0.5 + 0.36 * std::cos(b), 0.5 + 0.3 * std::sin(d)};
        cU = {0.38 * std::cos(a) * 2 * kPi * 1.1, 0.0, 0.3 * std::cos(d) * kPi};
        cV = {0.0, -0.36 * std::sin(b) * 2 * kPi * 0.9, 0.3 * std::cos(d) * kPi};
    }
};
}  // namespace

GradientMesh makeCurvedMesh(int columns, int rows, double x0, double y0, double w, double h,
                            double curvature, unsigned seed) {
    assert(columns > 0 && rows > 0);
    GradientMesh m(columns, rows);
    const ColorField field(seed);
    const double ax = 0.08 * w * curvature, ay = 0.08 * h * curvature;
    for (int j = 0; j <= rows; ++j) {
        for (int i = 0; i <= columns; ++i) {
            const double U = double(i) / columns, V = double(j) / rows;
            const double sx = kPi * (2 * V + 0.5 * U), sy = kPi * (2 * U + 0.3);
            Node& n = m.node(i, j);
            n.pos = {x0 + w * U + ax * std::sin(sx), y0 + h * V + ay * std::sin(sy)};
            // d/du = d/dU / columns, d/dv = d/dV / rows (uniform knots 0..C, 0..R).
            n.posU = Vec2{w + ax * std::cos(sx) * 0.5 * kPi, ay * std::cos(sy) * 2 * kPi} * (1.0 / columns);
            n.posV = Vec2{ax * std::cos(sx) * 2 * kPi, h} * (1.0 / rows);
            Vec3 cU, cV;
            field.eval(U, V, n.col, cU, cV);
            n.colU = cU * (1.0 / columns);
            n.colV = cV * (1.0 / rows);
        }
    }
    return m;
}

GradientMesh makeHoledMesh(int holes, double x0, double y0, double w, double h, unsigned seed) {
    assert(holes >= 0);
    const int columns = 8, rows = 2 * holes + 2;
    GradientMesh m = makeCurvedMesh(columns, rows, x0, y0, w, h, 0.0, seed);
    const double cellW = w / columns, cellH = h / rows;
    for (int k = 0; k < holes; ++k) {
        Slit s;
        s.row = 2 * k + 2;
        s.i0 = (k % 2 == 0) ? 2 : 3;
        s.i1 = s.i0 + 3 + (k % 3 == 2 ? 1 : 0);
        if (s.i1 >= columns) s.i1 = columns - 1;
        const int span = s.i1 - s.i0;
        const double a = 0.5 * span * cellW;        // half width of the hole
        const double b = 0.38 * cellH;              // half height, below the row spacing
        const double xc = m.node(s.i0, s.row).pos.x + a, yc = m.node(s.i0, s.row).pos.y;
        const double dtheta = kPi / span;           // θ per unit of u
        for (int i = s.i0 + 1; i < s.i1; ++i) {
            const double th = dtheta * (i - s.i0);
            Node& up = m.node(i, s.row);
            Node low = up;
            up.pos = {xc - a * std::cos(th), yc - b * std::sin(th)};
            up.posU = Vec2{a * std::sin(th), -b * std::cos(th)} * dtheta;
            low.pos = {xc - a * std::cos(th), yc + b * std::sin(th)};
            low.posU = Vec2{a * std::sin(th), b * std::cos(th)} * dtheta;
            s.below.push_back(low);
        }
        // Vertical tangents at the ends: the hole outline is smooth there.
        s.left.posU = Vec2{0, -b * dtheta};
        s.right.posU = Vec2{0, b * dtheta};
        m.slits.push_back(s);
    }
    return m;
}

Document makeDemoDocument() {
    Document doc;
    doc.width = 512;
    doc.height = 512;
    doc.meshes.push_back(makeHoledMesh(3, 24, 32, 260, 448, 3));
    doc.meshes.push_back(makeCurvedMesh(10, 12, 300, 40, 190, 430, 0.8, 5));
    return doc;
}

namespace {

// A circle as four cubics, clockwise on screen (y down) or, `reverse`, counter-clockwise.
std::vector<Vec2> circlePath(double cx, double cy, double r, bool reverse) {
    constexpr double kappa = 0.5522847498307936;
    const Vec2 c{cx, cy};
    const Vec2 dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    std::vector<Vec2> path;
    for (int k = 0; k < 4; ++k) {
        const int a = reverse ? (4 - k) % 4 : k, b = reverse ? (7 - k) % 4 : (k + 1) % 4;
        const Vec2 p0 = c + r * dirs[a], p1 = c + r * dirs[b];
        path.insert(path.end(), {p0, p0 + (kappa * r) * dirs[b], p1 + (kappa * r) * dirs[a]});
    }
    return path;
}

// An axis-aligned square of lines (handles at thirds), clockwise or counter-clockwise.
std::vector<Vec2> squarePath(double x0, double y0, double side, bool reverse) {
    std::vector<Vec2> corners = {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
    if (reverse) std::swap(corners[1], corners[3]);
    return polygonAsCubics(corners);
}

}  // namespace

FlatShape makeFlatRing(double cx, double cy, double outer, double inner, Vec3 col, size_t layer) {
    FlatShape s;
    s.col = col;
    s.layer = layer;
    s.subpaths = {circlePath(cx, cy, outer, false), circlePath(cx, cy, inner, true)};
    return s;
}

Document makeFlatDocument() {
    Document d;
    d.width = 240;
    d.height = 180;
    d.meshes.push_back(makeCurvedMesh(4, 3, 0, 0, 240, 180, 0.0, 3));
    d.shapes.push_back(makeFlatRing(90.3, 85.6, 62.2, 27.5, {0.85, 0.1, 0.15}, 1));
    d.meshes.push_back(makeCurvedMesh(3, 3, 130, 40, 90, 110, 0.5, 5));
    FlatShape square;
    square.col = {0.1, 0.3, 0.9};
    square.layer = 2;
    square.subpaths = {squarePath(20.25, 110.5, 60, false), squarePath(40.5, 130.75, 20, true)};
    d.shapes.push_back(square);
    return d;
}

}  // namespace gm
