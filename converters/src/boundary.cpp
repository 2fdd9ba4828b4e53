#include "converters/boundary.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "meshcore/evaluate.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {

// One boundary edge: a patch, which of its sides, and the map parameters under it.
struct BoundaryEdge {
    int i = 0, j = 0;      // patch
    bool alongS = true;    // the edge runs along s (t fixed) or along t (s fixed)
    double fixed = 0;      // the fixed local parameter, 0 or 1
    int side = 0;          // inverse-map side for points on a slit
    bool splitsU = true;   // which knot interval lies under it
    int interval = 0;
};

std::vector<BoundaryEdge> boundaryEdges(const GradientMesh& m) {
    const int C = m.columns(), R = m.rows();
    std::vector<BoundaryEdge> e;
    for (int i = 0; i < C; ++i) {
        e.push_back({i, 0, true, 0.0, 0, true, i});
        e.push_back({i, R - 1, true, 1.0, 0, true, i});
    }
    for (int j = 0; j < R; ++j) {
        e.push_back({0, j, false, 0.0, 0, false, j});
        e.push_back({C - 1, j, false, 1.0, 0, false, j});
    }
    for (const Slit& s : m.slits)
        for (int i = s.i0; i < s.i1; ++i) {
            e.push_back({i, s.row - 1, true, 1.0, -1, true, i});
            e.push_back({i, s.row, true, 0.0, 1, true, i});
        }
    return e;
}

// Hausdorff distance between the edge's cubic and the outline under it, both sampled densely,
// and where along the edge (local parameter 0–1) the worst point is.
struct EdgeDeviation {
    double distance = 0;
    double where = 0.5;
};

EdgeDeviation edgeDeviation(const GridBuilder& grid, const GradientMesh& m, const BoundaryEdge& e) {
    const PatchHermite h = patchHermite(m, e.i, e.j);
    auto curveAt = [&](double a) {
        return (e.alongS ? evaluatePatch(h, a, e.fixed) : evaluatePatch(h, e.fixed, a)).pos;
    };
    auto outlineAt = [&](double a) {
        const double u = e.alongS ? m.u[e.i] + a * (m.u[e.i + 1] - m.u[e.i]) : m.u[e.i + (e.fixed > 0.5)];
        const double v = e.alongS ? m.v[e.j + (e.fixed > 0.5)] : m.v[e.j] + a * (m.v[e.j + 1] - m.v[e.j]);
        return grid.imagePosition(u, v, e.side);
    };
    const double chord = norm(curveAt(1) - curveAt(0));
    const int n = std::clamp(static_cast<int>(std::ceil(chord / 1.5)), 8, 64);
    std::vector<Vec2> curve(static_cast<size_t>(n) + 1), outline(static_cast<size_t>(4 * n) + 1);
    for (int k = 0; k <= n; ++k) curve[static_cast<size_t>(k)] = curveAt(double(k) / n);
    for (int k = 0; k <= 4 * n; ++k) outline[static_cast<size_t>(k)] = outlineAt(double(k) / (4 * n));
    const auto [dc, ic] = directedPolylineDistance(curve, outline);
    const auto [dout, io] = directedPolylineDistance(outline, curve);
    // The outline's parameter is the map's, the one a knot is placed in.
    if (dout >= dc) return {dout, double(io) / (4 * n)};
    return {dc, double(ic) / n};
}

}  // namespace

double outlineDeviation(const GridBuilder& grid, const GradientMesh& mesh) {
    double worst = 0;
    for (const BoundaryEdge& e : boundaryEdges(mesh))
        worst = std::max(worst, edgeDeviation(grid, mesh, e).distance);
    return worst;
}

BoundaryFitResult fitBoundary(const GridBuilder& grid, GridOptions& options,
                              const BoundaryFitOptions& fit) {
    BoundaryFitResult result;
    // Intervals are split however small in parameter units (a map may crowd many pixels of
    // outline into a tiny interval), down to where knots would merge.
    const double minU = 1e-6 * grid.map().px, minV = 1e-6 * grid.map().py;
    long cap = fit.maxPatches;
    for (;;) {
        const GradientMesh m = grid.build(options);
        const int C = m.columns(), R = m.rows();
        // Slits alone may need more patches than the budget (a row and two columns each): the
        // outline then still gets half as many again.
        if (result.rounds == 0) cap = std::max<long>(cap, 3L * C * R / 2);
        // Worst deviation per knot interval.
        std::vector<EdgeDeviation> devU(static_cast<size_t>(C)), devV(static_cast<size_t>(R));
        result.maxDeviation = 0;
        double worstScaled = 0;  // deviations in units of each edge's own tolerance × tolerance
        for (const BoundaryEdge& e : boundaryEdges(m)) {
            EdgeDeviation d = edgeDeviation(grid, m, e);
            result.maxDeviation = std::max(result.maxDeviation, d.distance);
            // Hole outlines are held to their own (tighter) tolerance: a small hole loses a
            // large share of its pixels to a half-pixel stray.
            if (e.side != 0) d.distance *= fit.tolerance / std::max(1e-3, fit.holeTolerance);
            worstScaled = std::max(worstScaled, d.distance);
            EdgeDeviation& slot = e.splitsU ? devU[static_cast<size_t>(e.interval)]
                                            : devV[static_cast<size_t>(e.interval)];
            if (d.distance > slot.distance) slot = d;
        }
        if (worstScaled <= fit.tolerance || result.rounds >= fit.maxRounds) break;
        struct Split {
            double dev;
            bool alongU;
            int interval;
            double knot;
        };
        // The new knot goes where the edge strays most (kept within the interval's middle
        // part so that neither half becomes a sliver): one knot where the outline needs it
        // does what several halvings would.
        auto knotAt = [&](const std::vector<double>& k, int i, double where) {
            return k[i] + std::clamp(where, fit.knotMargin, 1 - fit.knotMargin) * (k[i + 1] - k[i]);
        };
        std::vector<Split> splits;
        for (int i = 0; i < C; ++i)
            if (devU[i].distance > fit.tolerance && m.u[i + 1] - m.u[i] >= 2 * minU)
                splits.push_back({devU[i].distance, true, i, knotAt(m.u, i, devU[i].where)});
        for (int j = 0; j < R; ++j)
            if (devV[j].distance > fit.tolerance && m.v[j + 1] - m.v[j] >= 2 * minV)
                splits.push_back({devV[j].distance, false, j, knotAt(m.v, j, devV[j].where)});
        std::stable_sort(splits.begin(), splits.end(),
                         [](const Split& a, const Split& b) { return a.dev > b.dev; });
        // From here on the knots are explicit, so that the uniform ones do not move.
        options.knotsU = m.u;
        options.knotsV = m.v;
        long nu = 0, nv = 0;
        bool any = false;
        for (const Split& s : splits) {
            if (s.dev < fit.roundFraction * splits.front().dev) break;
            const long patches = (C + nu + s.alongU) * (R + nv + !s.alongU);
            if (patches > cap) continue;
            if (s.alongU) {
                options.knotsU.push_back(s.knot);
                ++nu;
            } else {
                options.knotsV.push_back(s.knot);
                ++nv;
            }
            any = true;
        }
        if (!any) break;
        std::sort(options.knotsU.begin(), options.knotsU.end());
        std::sort(options.knotsV.begin(), options.knotsV.end());
        result.addedU += static_cast<int>(nu);
        result.addedV += static_cast<int>(nv);
        ++result.rounds;
    }
    return result;
}

}  // namespace gm
