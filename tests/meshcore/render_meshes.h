// Meshes with known geometry and colour for the renderer's tests.
#pragma once

#include <cmath>
#include <vector>

#include "meshcore/evaluate.h"
#include "meshcore/gradient_mesh.h"

namespace rendertest {

using gm::GradientMesh;
using gm::Node;
using gm::Vec2;
using gm::Vec3;

constexpr double kPi = 3.14159265358979323846;

// An affine C×R mesh: node (i,j) at origin + u_i·a + v_j·b, with the given knots.
inline GradientMesh affineMesh(const std::vector<double>& u, const std::vector<double>& v,
                               Vec2 origin, Vec2 a, Vec2 b) {
    GradientMesh m(static_cast<int>(u.size()) - 1, static_cast<int>(v.size()) - 1);
    m.u = u;
    m.v = v;
    for (int j = 0; j <= m.rows(); ++j)
        for (int i = 0; i <= m.columns(); ++i) {
            Node& n = m.node(i, j);
            n.pos = origin + u[i] * a + v[j] * b;
            n.posU = a;
            n.posV = b;
        }
    return m;
}

// An axis-aligned rectangle [x0,x1] x [y0,y1] as a C×R mesh of one colour.
inline GradientMesh rectangleMesh(double x0, double y0, double x1, double y1, int C, int R,
                                  Vec3 colour) {
    std::vector<double> u(C + 1), v(R + 1);
    for (int i = 0; i <= C; ++i) u[i] = i;
    for (int j = 0; j <= R; ++j) v[j] = j;
    GradientMesh m = affineMesh(u, v, {x0, y0}, {(x1 - x0) / C, 0}, {0, (y1 - y0) / R});
    for (Node& n : m.nodes) n.col = colour;
    return m;
}

// A smooth warp of [x0,x0+w] x [y0,y0+h] as a C×R mesh with exact derivatives; `amp` scales
// the waviness (0: straight grid lines). Colours vary smoothly and are set by `colour`.
inline GradientMesh curvedMesh(int C, int R, double x0, double y0, double w, double h,
                               double amp = 1.0) {
    GradientMesh m(C, R);
    const double ax = 0.06 * w * amp, ay = 0.06 * h * amp;
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            const double U = double(i) / C, V = double(j) / R;
            const double px = 2 * kPi * V + 1.3 * U, py = 2 * kPi * U + 0.7 * V;
            Node& n = m.node(i, j);
            n.pos = {x0 + w * U + ax * std::sin(px), y0 + h * V + ay * std::sin(py)};
            // d/du = d/dU / C (uniform knots 0..C).
            n.posU = Vec2{w + ax * std::cos(px) * 1.3, ay * std::cos(py) * 2 * kPi} * (1.0 / C);
            n.posV = Vec2{ax * std::cos(px) * 2 * kPi, h + ay * std::cos(py) * 0.7} * (1.0 / R);
            const double a = 2 * kPi * U + 0.3, b = 2 * kPi * V + 1.1, d = kPi * (U + V);
            n.col = {0.5 + 0.4 * std::sin(a), 0.5 + 0.4 * std::cos(b), 0.5 + 0.3 * std::sin(d)};
            n.colU = Vec3{0.4 * std::cos(a) * 2 * kPi, 0, 0.3 * std::cos(d) * kPi} * (1.0 / C);
            n.colV = Vec3{0, -0.4 * std::sin(b) * 2 * kPi, 0.3 * std::cos(d) * kPi} * (1.0 / R);
        }
    return m;
}

// Replaces every colour datum by the same linear function of the position datum, so that the
// colour at any point of the mesh is exactly grad·position + c0 (Ferguson evaluation is linear
// in the node data and reproduces constants).
inline void setLinearColor(GradientMesh& m, Vec3 gx, Vec3 gy, Vec3 c0) {
    auto lin = [&](Vec2 p) { return p.x * gx + p.y * gy; };
    auto apply = [&](Node& n) {
        n.col = lin(n.pos) + c0;
        n.colU = lin(n.posU);
        n.colV = lin(n.posV);
    };
    for (Node& n : m.nodes) apply(n);
    for (gm::Slit& s : m.slits) {
        for (Node& n : s.below) apply(n);
        s.left.colU = lin(s.left.posU);
        s.right.colU = lin(s.right.posU);
    }
    for (gm::CornerTangent& t : m.tangents) t.colU = lin(t.posU);
}

// An affine 6×4 mesh over [x0,x0+w] x [y0,y0+h] with one slit on row 2 from column 2 to 4,
// opened into an ellipse centred on the row with half axes (w/6, hb): the copies above move
// up, the copies below move down, and the ±d slit-end tangents are vertical.
inline GradientMesh holedMesh(double x0, double y0, double w, double h, double hb) {
    std::vector<double> u = {0, 1, 2, 3, 4, 5, 6}, v = {0, 1, 2, 3, 4};
    GradientMesh m = affineMesh(u, v, {x0, y0}, {w / 6, 0}, {0, h / 4});
    gm::Slit s;
    s.row = 2;
    s.i0 = 2;
    s.i1 = 4;
    const double a = w / 6;  // half width: two columns
    const Vec2 c = m.node(3, 2).pos;
    const double dtheta = kPi / 2;  // θ per unit of u
    Node& up = m.node(3, 2);
    Node low = up;
    up.pos = {c.x, c.y - hb};
    up.posU = Vec2{a, 0} * dtheta;
    low.pos = {c.x, c.y + hb};
    low.posU = Vec2{a, 0} * dtheta;
    s.below.push_back(low);
    s.left.posU = {0, -hb * dtheta};
    s.right.posU = {0, hb * dtheta};
    m.slits.push_back(s);
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 6; ++i) m.node(i, j).col = {0.2 + 0.1 * i, 0.8 - 0.15 * j, 0.5};
    m.slits[0].below[0].col = {0.9, 0.1, 0.3};
    return m;
}

// A 4×4 mesh mapping the square onto the disc of radius r about (cx, cy) (x·√(1−y²/2),
// y·√(1−x²/2)), with exact derivatives: its outline is close to, not exactly, the circle.
inline GradientMesh discMesh(double cx, double cy, double r) {
    const int N = 4;
    GradientMesh m(N, N);
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            const double x = -1 + 2.0 * i / N, y = -1 + 2.0 * j / N;
            const double sx = std::sqrt(1 - y * y / 2), sy = std::sqrt(1 - x * x / 2);
            Node& n = m.node(i, j);
            n.pos = {cx + r * x * sx, cy + r * y * sy};
            // d/du = d/dx · 2/N.
            n.posU = Vec2{r * sx, r * y * (-x / 2) / sy} * (2.0 / N);
            n.posV = Vec2{r * x * (-y / 2) / sx, r * sy} * (2.0 / N);
            n.col = {0.3 + 0.1 * i, 0.3 + 0.1 * j, 0.6};
        }
    return m;
}

// The mesh outline, densely sampled by exact evaluation: outer loop, then each hole.
inline std::vector<std::vector<Vec2>> denseOutline(const GradientMesh& m, int perEdge = 400) {
    const int C = m.columns(), R = m.rows();
    std::vector<std::vector<Vec2>> loops(1);
    auto edge = [&](std::vector<Vec2>& out, int i, int j, int side, bool rev) {
        for (int k = 0; k < perEdge; ++k) {
            double t = double(k) / perEdge;
            if (rev) t = 1 - t;
            const double s = side < 2 ? t : (side == 2 ? 0.0 : 1.0);
            const double tt = side < 2 ? (side == 0 ? 0.0 : 1.0) : t;
            out.push_back(gm::evaluatePatch(m, i, j, s, tt).pos);
        }
    };
    for (int i = 0; i < C; ++i) edge(loops[0], i, 0, 0, false);
    for (int j = 0; j < R; ++j) edge(loops[0], C - 1, j, 3, false);
    for (int i = C - 1; i >= 0; --i) edge(loops[0], i, R - 1, 1, true);
    for (int j = R - 1; j >= 0; --j) edge(loops[0], 0, j, 2, true);
    for (const gm::Slit& s : m.slits) {
        std::vector<Vec2> hole;
        for (int i = s.i0; i < s.i1; ++i) edge(hole, i, s.row, 0, false);
        for (int i = s.i1 - 1; i >= s.i0; --i) edge(hole, i, s.row - 1, 1, true);
        loops.push_back(hole);
    }
    return loops;
}

inline double polygonArea(const std::vector<Vec2>& p) {
    double a = 0;
    for (size_t k = 0; k < p.size(); ++k) {
        const Vec2 q = p[k], r = p[(k + 1) % p.size()];
        a += q.x * r.y - r.x * q.y;
    }
    return 0.5 * a;
}

// Winding number of the loops around point q (nonzero: inside), and the distance to them.
inline int winding(const std::vector<std::vector<Vec2>>& loops, Vec2 q) {
    int w = 0;
    for (const auto& p : loops)
        for (size_t k = 0; k < p.size(); ++k) {
            const Vec2 a = p[k], b = p[(k + 1) % p.size()];
            const double cr = (b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y);
            if (a.y <= q.y) {
                if (b.y > q.y && cr > 0) ++w;
            } else if (b.y <= q.y && cr < 0) {
                --w;
            }
        }
    return w;
}

inline double distanceTo(const std::vector<std::vector<Vec2>>& loops, Vec2 q) {
    double best = 1e300;
    for (const auto& p : loops)
        for (size_t k = 0; k < p.size(); ++k) {
            const Vec2 a = p[k], b = p[(k + 1) % p.size()], ab = b - a;
            double t = gm::dot(q - a, ab) / std::max(gm::dot(ab, ab), 1e-300);
            t = std::min(1.0, std::max(0.0, t));
            best = std::min(best, gm::norm(q - (a + t * ab)));
        }
    return best;
}

}  // namespace rendertest
