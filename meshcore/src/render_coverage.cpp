// The mesh outline and its exact area coverage (the anti-aliased alpha of the renderer).
#include <algorithm>
#include <cmath>

#include "meshcore/bezier_patch.h"
#include "render_internal.h"

namespace gm {
namespace render_detail {

namespace {

constexpr int kMaxOutlineSegments = 4096;  // per boundary curve

}  // namespace

// |B''| ≤ 6·max|Δ²q| and a chord over a parameter step h errs by at most |B''|h²/8.
void flattenCubic(Vec2 q0, Vec2 q1, Vec2 q2, Vec2 q3, double tolerance, std::vector<Vec2>& out) {
    const double m2 = 6 * std::max(norm(q0 - 2 * q1 + q2), norm(q1 - 2 * q2 + q3));
    double nd = std::ceil(std::sqrt(m2 / (8 * tolerance)));
    if (!(nd >= 1)) nd = m2 > 0 ? kMaxOutlineSegments : 1;
    const int n = static_cast<int>(std::min<double>(nd, kMaxOutlineSegments));
    for (int k = 1; k < n; ++k) {
        const double t = static_cast<double>(k) / n, u = 1 - t;
        const double b0 = u * u * u, b1 = 3 * u * u * t, b2 = 3 * u * t * t, b3 = t * t * t;
        out.push_back(b0 * q0 + b1 * q1 + b2 * q2 + b3 * q3);
    }
    out.push_back(q3);
}

namespace {

// The boundary curve of patch (i,j) on one side, as Bézier control points in output pixels.
// side 0: t=0 (s increasing), 1: t=1, 2: s=0 (t increasing), 3: s=1.
void edgeCurve(const GradientMesh& mesh, int i, int j, int side, double scale, Vec2 q[4]) {
    const BezierPatch bz = toBezier(mesh, i, j);
    for (int k = 0; k < 4; ++k) {
        const Vec2 p = side == 0   ? bz.p[k][0]
                       : side == 1 ? bz.p[k][3]
                       : side == 2 ? bz.p[0][k]
                                   : bz.p[3][k];
        q[k] = scale * p;
    }
}

void appendEdge(const GradientMesh& mesh, int i, int j, int side, bool reverse, double scale,
                double tolerance, std::vector<Vec2>& loop) {
    Vec2 q[4];
    edgeCurve(mesh, i, j, side, scale, q);
    if (reverse) {
        std::swap(q[0], q[3]);
        std::swap(q[1], q[2]);
    }
    if (loop.empty()) loop.push_back(q[0]);
    flattenCubic(q[0], q[1], q[2], q[3], tolerance, loop);
}

// Adds the part of a line piece inside one pixel row to the accumulator row: `d` is its signed
// height; it covers (right of itself) d·(c+1−x_mid) of cell c, and the full d of every cell
// further right, which the prefix sum along the row supplies via the c+1 entry.
void addRowPiece(double* row, int width, double xa, double xb, double d) {
    xa = std::min(std::max(xa, 0.0), static_cast<double>(width));
    xb = std::min(std::max(xb, 0.0), static_cast<double>(width));
    if (xa > xb) std::swap(xa, xb);
    const int c0 = static_cast<int>(xa), c1 = static_cast<int>(xb);
    if (c0 == c1 || xb - xa < 1e-12) {
        const double xm = 0.5 * (xa + xb) - c0;
        row[c0] += d * (1 - xm);
        row[c0 + 1] += d * xm;
        return;
    }
    const double slope = d / (xb - xa);
    double x = xa;
    for (int c = c0; c <= c1; ++c) {
        const double xe = std::min(xb, c + 1.0);
        const double dd = (xe - x) * slope, xm = 0.5 * (x + xe) - c;
        row[c] += dd * (1 - xm);
        row[c + 1] += dd * xm;
        x = xe;
    }
}

}  // namespace

std::vector<std::vector<Vec2>> outlineLoops(const GradientMesh& mesh, double scale,
                                            double tolerance) {
    const int C = mesh.columns(), R = mesh.rows();
    std::vector<std::vector<Vec2>> loops;
    // Outer loop: in the parameter domain +u along v_0, +v along u_C, −u along v_R, −v along
    // u_0 (the domain on one fixed side).
    std::vector<Vec2> outer;
    for (int i = 0; i < C; ++i) appendEdge(mesh, i, 0, 0, false, scale, tolerance, outer);
    for (int j = 0; j < R; ++j) appendEdge(mesh, C - 1, j, 3, false, scale, tolerance, outer);
    for (int i = C - 1; i >= 0; --i) appendEdge(mesh, i, R - 1, 1, true, scale, tolerance, outer);
    for (int j = R - 1; j >= 0; --j) appendEdge(mesh, 0, j, 2, true, scale, tolerance, outer);
    loops.push_back(std::move(outer));
    // Each hole with the mesh on the same side as for the outer loop: +u along the lower slit
    // side (the top edges of the patches below the row), then −u along the upper side. In the
    // image this winds opposite to the outer loop, so the hole gets winding number 0.
    for (const Slit& s : mesh.slits) {
        std::vector<Vec2> hole;
        for (int i = s.i0; i < s.i1; ++i)
            appendEdge(mesh, i, s.row, 0, false, scale, tolerance, hole);
        for (int i = s.i1 - 1; i >= s.i0; --i)
            appendEdge(mesh, i, s.row - 1, 1, true, scale, tolerance, hole);
        loops.push_back(std::move(hole));
    }
    return loops;
}

void accumulateCoverage(const std::vector<std::vector<Vec2>>& loops, const LayerRows& band,
                        std::vector<double>& acc, float* alpha) {
    const int width = band.width, rows = band.y1 - band.y0;
    const size_t stride = static_cast<size_t>(width) + 2;
    acc.assign(stride * rows, 0.0);
    const double top = band.y0, bottom = band.y1;
    for (const std::vector<Vec2>& loop : loops) {
        const size_t n = loop.size();
        for (size_t k = 0; k < n; ++k) {
            const Vec2 p = loop[k], q = loop[(k + 1) % n];
            double x0 = p.x - band.originX, y0 = p.y - band.originY;
            double x1 = q.x - band.originX, y1 = q.y - band.originY;
            if (!(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1)))
                continue;
            if (y0 == y1) continue;
            double dir = 1;
            if (y0 > y1) {
                std::swap(x0, x1);
                std::swap(y0, y1);
                dir = -1;
            }
            if (y1 <= top || y0 >= bottom) continue;
            const double dxdy = (x1 - x0) / (y1 - y0);
            const double ys = std::max(y0, top), ye = std::min(y1, bottom);
            const int r0 = static_cast<int>(std::floor(ys)), r1 = static_cast<int>(std::ceil(ye));
            for (int r = r0; r < r1; ++r) {
                const double ya = std::max(ys, double(r)), yb = std::min(ye, r + 1.0);
                if (yb <= ya) continue;
                const double xa = x0 + (ya - y0) * dxdy, xb = x0 + (yb - y0) * dxdy;
                addRowPiece(&acc[static_cast<size_t>(r - band.y0) * stride], width, xa, xb,
                            dir * (yb - ya));
            }
        }
    }
    // Interior pixels sum to exactly ±1 up to rounding; snap so they are opaque, not 0.9999999.
    constexpr double kSnap = 1e-9;
    for (int r = 0; r < rows; ++r) {
        const double* row = &acc[static_cast<size_t>(r) * stride];
        float* out = alpha + static_cast<size_t>(band.y0 + r) * width;
        double sum = 0;
        for (int x = 0; x < width; ++x) {
            sum += row[x];
            const double a = std::fabs(sum);
            out[x] = a >= 1 - kSnap ? 1.0f : (a < kSnap ? 0.0f : static_cast<float>(a));
        }
    }
}

}  // namespace render_detail
}  // namespace gm
