// Per-patch preparation and adaptive tessellation for the raster re-renderer.
#include <algorithm>
#include <cmath>
#include <limits>

#include "meshcore/bezier_patch.h"
#include "meshcore/evaluate.h"
#include "meshcore/geometry.h"
#include "render_internal.h"

namespace gm {
namespace render_detail {

namespace {

// Bernstein → power basis: row m holds the coefficients of s^m in B_0..B_3.
constexpr double kToPower[4][4] = {{1, 0, 0, 0}, {-3, 3, 0, 0}, {3, -6, 3, 0}, {-1, 3, -3, 1}};

template <class Get>
Poly2 powerForm(Get controlPoint) {
    double tmp[4][4];  // tmp[m][b] = Σ_a kToPower[m][a] p[a][b]
    for (int m = 0; m < 4; ++m)
        for (int b = 0; b < 4; ++b) {
            double v = 0;
            for (int a = 0; a < 4; ++a) v += kToPower[m][a] * controlPoint(a, b);
            tmp[m][b] = v;
        }
    Poly2 p;
    for (int m = 0; m < 4; ++m)
        for (int n = 0; n < 4; ++n) {
            double v = 0;
            for (int b = 0; b < 4; ++b) v += tmp[m][b] * kToPower[n][b];
            p.k[m][n] = v;
        }
    return p;
}

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite(Vec3 v) { return std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b); }

PatchHermite scaledHermite(const GradientMesh& mesh, int i, int j, double scale, bool& ok) {
    PatchHermite h = patchHermite(mesh, i, j);
    ok = true;
    for (auto& row : h.corner)
        for (HermiteCorner& c : row) {
            c.pos = scale * c.pos;
            c.posS = scale * c.posS;
            c.posT = scale * c.posT;
            ok = ok && finite(c.pos) && finite(c.posS) && finite(c.posT) && finite(c.col) &&
                 finite(c.colS) && finite(c.colT);
        }
    return h;
}

// Largest image-space colour gradient (colour per output pixel, worst channel) seen at a few
// interior points. The colour at a pixel is evaluated exactly at the (s,t) the tessellation
// assigns to the pixel centre, and that (s,t) belongs to a point up to the position error
// away, so the colour error is this gradient times the position error. Corners are left out:
// a collapsed corner has a singular Jacobian there and would demand infinite subdivision.
double colorGradientEstimate(const PatchHermite& h) {
    static const double kAt[3] = {1.0 / 6, 0.5, 5.0 / 6};
    double worst = 0;
    for (double s : kAt) {
        for (double t : kAt) {
            const PatchPoint p = evaluatePatch(h, s, t);
            double hs[4], ht[4], dhs[4], dht[4];
            hermiteBasis(s, hs);
            hermiteBasis(t, ht);
            hermiteBasisDerivative(s, dhs);
            hermiteBasisDerivative(t, dht);
            auto col = [](const HermiteCorner& c) { return c.col; };
            auto colS = [](const HermiteCorner& c) { return c.colS; };
            auto colT = [](const HermiteCorner& c) { return c.colT; };
            const Vec3 cs = hermiteSum<Vec3>(h, dhs, ht, col, colS, colT);
            const Vec3 ct = hermiteSum<Vec3>(h, hs, dht, col, colS, colT);
            const double det = cross(p.posS, p.posT);
            for (int k = 0; k < 3; ++k) {
                // (c_s, c_t) · J⁻¹ with J = [posS posT].
                const double gx = cs[k] * p.posT.y - ct[k] * p.posS.y;
                const double gy = -cs[k] * p.posT.x + ct[k] * p.posS.x;
                const double num = std::sqrt(gx * gx + gy * gy);
                if (num == 0) continue;
                if (det == 0) return std::numeric_limits<double>::infinity();
                worst = std::max(worst, num / std::fabs(det));
            }
        }
    }
    return worst;
}

int subdivisionsFor(double bound, double tolerance) {
    // Linear interpolation over a triangle whose vertices lie in an h_s x h_t parameter box
    // errs by at most (M_ss h_s² + 2 M_st h_s h_t + M_tt h_t²)/8 ≤ ((M_ss+M_st) h_s² +
    // (M_tt+M_st) h_t²)/8; giving each direction half the tolerance yields n = √(M/(4 tol)).
    const double n = std::ceil(std::sqrt(bound / (4 * tolerance)));
    if (!(n >= 1)) return bound > 0 ? kMaxSubdivisions : 1;  // NaN: extreme data
    return static_cast<int>(std::min<double>(n, kMaxSubdivisions));
}

}  // namespace

void chooseSubdivisions(const PatchHermite& scaled, const RenderOptions& options, int& ns,
                        int& nt) {
    double posTol = options.positionTolerance;
    if (!(posTol > 0) || !std::isfinite(posTol)) posTol = 0.125;
    posTol = std::max(posTol, 1e-4);
    double colTol = options.colorTolerance;
    if (!(colTol > 0) || !std::isfinite(colTol)) colTol = 1.0 / 255.0;

    const double g = colorGradientEstimate(scaled);
    // Tighten the position tolerance so that gradient x position error stays below the colour
    // tolerance, but by at most 8x: beyond that the gradient estimate is a near-singular
    // Jacobian talking, not a colour edge.
    double tol = posTol;
    if (g > 0) tol = std::max(posTol / 8, std::min(posTol, colTol / g));

    // Second-derivative bounds of the position from the Bézier control net.
    const BezierPatch bz = toBezier(scaled);
    double mss = 0, mtt = 0, mst = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            if (a < 2) mss = std::max(mss, norm(bz.p[a + 2][b] - 2 * bz.p[a + 1][b] + bz.p[a][b]));
            if (b < 2) mtt = std::max(mtt, norm(bz.p[a][b + 2] - 2 * bz.p[a][b + 1] + bz.p[a][b]));
            if (a < 3 && b < 3)
                mst = std::max(
                    mst, norm(bz.p[a + 1][b + 1] - bz.p[a + 1][b] - bz.p[a][b + 1] + bz.p[a][b]));
        }
    mss *= 6;
    mtt *= 6;
    mst *= 9;
    ns = subdivisionsFor(mss + mst, tol);
    nt = subdivisionsFor(mtt + mst, tol);
}

PreparedMesh prepareMesh(const GradientMesh& mesh, const RenderOptions& options, int imageW,
                         int imageH) {
    PreparedMesh pm;
    const int C = mesh.columns(), R = mesh.rows();
    pm.columns = C;
    pm.rows = R;
    pm.patches.resize(static_cast<size_t>(C) * R);
    pm.horizontalCut.assign(static_cast<size_t>(C) * (R + 1), 0);
    for (const Slit& s : mesh.slits)
        for (int i = s.i0; i < s.i1; ++i) pm.horizontalCut[static_cast<size_t>(s.row) * C + i] = 1;

    bool any = false;
    for (int j = 0; j < R; ++j) {
        for (int i = 0; i < C; ++i) {
            PreparedPatch& P = pm.patches[static_cast<size_t>(j) * C + i];
            bool ok = false;
            P.hermite = scaledHermite(mesh, i, j, options.scale, ok);
            if (!ok) continue;
            const BezierPatch bz = toBezier(P.hermite);
            double x0 = bz.p[0][0].x, x1 = x0, y0 = bz.p[0][0].y, y1 = y0;
            for (const auto& row : bz.p)
                for (Vec2 q : row) {
                    x0 = std::min(x0, q.x);
                    x1 = std::max(x1, q.x);
                    y0 = std::min(y0, q.y);
                    y1 = std::max(y1, q.y);
                }
            if (!std::isfinite(x0 + x1 + y0 + y1)) continue;
            P.minX = x0;
            P.maxX = x1;
            P.minY = y0;
            P.maxY = y1;
            if (!any) {
                pm.minX = x0, pm.maxX = x1, pm.minY = y0, pm.maxY = y1;
                any = true;
            } else {
                pm.minX = std::min(pm.minX, x0);
                pm.maxX = std::max(pm.maxX, x1);
                pm.minY = std::min(pm.minY, y0);
                pm.maxY = std::max(pm.maxY, y1);
            }
            P.visible = x1 >= -1 && y1 >= -1 && x0 <= imageW + 1 && y0 <= imageH + 1;
            if (!P.visible) continue;
            chooseSubdivisions(P.hermite, options, P.ns, P.nt);
            P.x = powerForm([&](int a, int b) { return bz.p[a][b].x; });
            P.y = powerForm([&](int a, int b) { return bz.p[a][b].y; });
            for (int k = 0; k < 3; ++k) {
                const Poly2 c = powerForm([&](int a, int b) { return bz.c[a][b][k]; });
                for (int m = 0; m < 4; ++m)
                    for (int n = 0; n < 4; ++n) P.colour.k[m][n][k] = c.k[m][n];
            }
            for (auto& row : P.colour.k)
                for (auto& lanes : row) lanes[3] = 0;
        }
    }
    return pm;
}

namespace {

// Parameters along one patch edge: the patch's own a/n merged with the neighbour's k/m (m = 0:
// no neighbour). Both patches merge the same two sets of correctly rounded quotients, so they
// agree bit for bit.
struct EdgeParams {
    std::vector<double> params;
    std::vector<int> gridAt;  // gridAt[a]: index in params of a/n
    std::vector<int> vertex;  // vertex index of each param
};

void mergeParams(int n, int m, EdgeParams& e) {
    e.params.clear();
    e.gridAt.clear();
    int a = 0, k = 0;
    const double inf = std::numeric_limits<double>::infinity();
    while (a <= n) {
        const double pa = static_cast<double>(a) / n;
        const double pk = (m > 0 && k <= m) ? static_cast<double>(k) / m : inf;
        if (pk < pa) {
            e.params.push_back(pk);
            ++k;
            continue;
        }
        if (pk == pa) ++k;
        e.gridAt.push_back(static_cast<int>(e.params.size()));
        e.params.push_back(pa);
        ++a;
    }
}

int64_t snap(double v) {
    v *= kSubpixel;
    if (!(v == v)) v = 0;
    v = std::min(std::max(v, -kFixedLimit), kFixedLimit);
    return static_cast<int64_t>(std::llround(v));
}

// A point of the edge curve from p0 (derivative d0) to p1 (d1): a function of the edge data
// only, evaluated in one fixed order, so neighbours sharing the edge get identical bits.
Vec2 edgePoint(Vec2 p0, Vec2 p1, Vec2 d0, Vec2 d1, double tau) {
    double h[4];
    hermiteBasis(tau, h);
    return {h[0] * p0.x + h[1] * p1.x + h[2] * d0.x + h[3] * d1.x,
            h[0] * p0.y + h[1] * p1.y + h[2] * d0.y + h[3] * d1.y};
}

}  // namespace

namespace {

// Edges of a patch: 0 top (t=0), 1 bottom (t=1), both along s; 2 left (s=0), 3 right (s=1),
// along t.
using PatchEdges = EdgeParams[4];

// Each edge's parameters: the patch's own subdivisions merged with its neighbour's across that
// edge (none across a slit or the mesh border, or when the neighbour is not drawn).
void mergeEdgeParams(const PreparedMesh& pm, int i, int j, PatchEdges& edges) {
    const int C = pm.columns, R = pm.rows;
    const PreparedPatch& P = pm.patches[static_cast<size_t>(j) * C + i];
    auto countOf = [&](int ii, int jj, bool alongS) {
        const PreparedPatch& q = pm.patches[static_cast<size_t>(jj) * C + ii];
        return q.visible ? (alongS ? q.ns : q.nt) : 0;
    };
    const bool topShared = j > 0 && !pm.horizontalCut[static_cast<size_t>(j) * C + i];
    const bool bottomShared = j < R - 1 && !pm.horizontalCut[static_cast<size_t>(j + 1) * C + i];
    mergeParams(P.ns, topShared ? countOf(i, j - 1, true) : 0, edges[0]);
    mergeParams(P.ns, bottomShared ? countOf(i, j + 1, true) : 0, edges[1]);
    mergeParams(P.nt, i > 0 ? countOf(i - 1, j, false) : 0, edges[2]);
    mergeParams(P.nt, i < C - 1 ? countOf(i + 1, j, false) : 0, edges[3]);
}

// Tessellates one prepared patch: an (ns+1) x (nt+1) grid of vertices, the boundary ones on
// the edge curves (shared bit for bit with the neighbours), cells split in two triangles or,
// where a finer neighbour adds edge vertices, fanned around their centre.
class PatchTessellator {
public:
    PatchTessellator(const PreparedPatch& patch, PatchEdges& edges, Tessellation& out)
        : P_(patch), ns_(patch.ns), nt_(patch.nt), edges_(edges), out_(out) {}

    void run() {
        out_.vertices.assign(static_cast<size_t>(ns_ + 1) * (nt_ + 1), TessVertex{});
        out_.triangles.clear();
        interiorVertices();
        for (int e = 0; e < 4; ++e) edgeVertices(e);
        for (int b = 0; b < nt_; ++b)
            for (int a = 0; a < ns_; ++a) cell(a, b);
    }

private:
    int grid(int a, int b) const { return b * (ns_ + 1) + a; }

    TessVertex surfacePoint(double s, double t) const {
        return {snap(P_.x.eval(s, t)), snap(P_.y.eval(s, t)), s, t};
    }

    void interiorVertices() {
        for (int b = 1; b < nt_; ++b)
            for (int a = 1; a < ns_; ++a) {
                const double s = static_cast<double>(a) / ns_, t = static_cast<double>(b) / nt_;
                out_.vertices[grid(a, b)] = surfacePoint(s, t);
            }
    }

    // The vertices of edge e at its merged parameters, evaluated from the edge data alone: the
    // patch's own grid points take their grid slots, the neighbour's extra ones are appended.
    void edgeVertices(int e) {
        const auto& h = P_.hermite.corner;
        EdgeParams& ep = edges_[e];
        const bool alongS = e < 2;
        const int side = e & 1;  // 0: t=0 / s=0, 1: t=1 / s=1
        const HermiteCorner& c0 = alongS ? h[0][side] : h[side][0];
        const HermiteCorner& c1 = alongS ? h[1][side] : h[side][1];
        const Vec2 d0 = alongS ? c0.posS : c0.posT, d1 = alongS ? c1.posS : c1.posT;
        ep.vertex.assign(ep.params.size(), -1);
        const int n = alongS ? ns_ : nt_;
        for (int a = 0; a <= n; ++a)
            ep.vertex[static_cast<size_t>(ep.gridAt[a])] =
                alongS ? grid(a, side ? nt_ : 0) : grid(side ? ns_ : 0, a);
        for (size_t k = 0; k < ep.params.size(); ++k) {
            const double tau = ep.params[k];
            const Vec2 q = edgePoint(c0.pos, c1.pos, d0, d1, tau);
            TessVertex v{snap(q.x), snap(q.y), alongS ? tau : double(side),
                         alongS ? double(side) : tau};
            if (ep.vertex[k] < 0) {
                ep.vertex[k] = static_cast<int>(out_.vertices.size());
                out_.vertices.push_back(v);
            } else {
                out_.vertices[static_cast<size_t>(ep.vertex[k])] = v;
            }
        }
    }

    // Extra vertices from a finer neighbour on edge e within the cell `cell` along it.
    int extras(int e, int cell) const {
        return edges_[e].gridAt[cell + 1] - edges_[e].gridAt[cell] - 1;
    }

    void cell(int a, int b) {
        const bool top = b == 0 && extras(0, a) > 0;
        const bool bottom = b == nt_ - 1 && extras(1, a) > 0;
        const bool left = a == 0 && extras(2, b) > 0;
        const bool right = a == ns_ - 1 && extras(3, b) > 0;
        if (!top && !bottom && !left && !right)
            splitCell(a, b);
        else
            fanCell(a, b, top, bottom, left, right);
    }

    // Split along the shorter diagonal: better-shaped triangles follow the surface.
    void splitCell(int a, int b) {
        const int v00 = grid(a, b), v10 = grid(a + 1, b), v01 = grid(a, b + 1),
                  v11 = grid(a + 1, b + 1);
        const TessVertex &p00 = out_.vertices[v00], &p10 = out_.vertices[v10],
                         &p01 = out_.vertices[v01], &p11 = out_.vertices[v11];
        auto dist2 = [](const TessVertex& p, const TessVertex& q) {
            const double dx = double(p.X - q.X), dy = double(p.Y - q.Y);
            return dx * dx + dy * dy;
        };
        const double d1 = dist2(p11, p00), d2 = dist2(p10, p01);
        const int tri[6] = {v00, v10, v11, v00, v11, v01};
        const int alt[6] = {v00, v10, v01, v10, v11, v01};
        out_.triangles.insert(out_.triangles.end(), d1 <= d2 ? tri : alt,
                              (d1 <= d2 ? tri : alt) + 6);
    }

    // Appends the vertices of edge e within `cell` (without its last one) to the ring.
    void walk(std::vector<int>& ring, int e, int cell, bool forward) const {
        const EdgeParams& ep = edges_[e];
        const int lo = ep.gridAt[cell], hi = ep.gridAt[cell + 1];
        if (forward)
            for (int k = lo; k < hi; ++k) ring.push_back(ep.vertex[k]);
        else
            for (int k = hi; k > lo; --k) ring.push_back(ep.vertex[k]);
    }

    // A cell with extra edge vertices becomes a fan around its centre (the cell is convex in
    // parameter space, so the fan is a valid triangulation there).
    void fanCell(int a, int b, bool top, bool bottom, bool left, bool right) {
        static thread_local std::vector<int> ring;
        ring.clear();
        if (top)
            walk(ring, 0, a, true);
        else
            ring.push_back(grid(a, b));
        if (right)
            walk(ring, 3, b, true);
        else
            ring.push_back(grid(a + 1, b));
        if (bottom)
            walk(ring, 1, a, false);
        else
            ring.push_back(grid(a + 1, b + 1));
        if (left)
            walk(ring, 2, b, false);
        else
            ring.push_back(grid(a, b + 1));
        const double s = (a + 0.5) / ns_, t = (b + 0.5) / nt_;
        const int centre = static_cast<int>(out_.vertices.size());
        out_.vertices.push_back(surfacePoint(s, t));
        for (size_t k = 0; k < ring.size(); ++k) {
            out_.triangles.push_back(centre);
            out_.triangles.push_back(ring[k]);
            out_.triangles.push_back(ring[(k + 1) % ring.size()]);
        }
    }

    const PreparedPatch& P_;
    const int ns_, nt_;
    PatchEdges& edges_;
    Tessellation& out_;
};

}  // namespace

void tessellatePatch(const PreparedMesh& pm, int patch, Tessellation& out) {
    const int i = patch % pm.columns, j = patch / pm.columns;
    static thread_local EdgeParams edges[4];
    mergeEdgeParams(pm, i, j, edges);
    PatchTessellator(pm.patches[static_cast<size_t>(patch)], edges, out).run();
}

}  // namespace render_detail
}  // namespace gm
