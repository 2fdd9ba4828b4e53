#include "converters/topology_map.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <string>

#include "meshcore/error.h"
#include "param_laplacian.h"

namespace gm {

namespace {

enum Side { kTop = 0, kRight = 1, kBottom = 2, kLeft = 3 };

std::string at(Vec2 p) {
    return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
}

// A convex-combination map squeezes a long thin part whose two flanks lie on one side of the
// rectangle exponentially (a leg or a tail between two corners): in double precision its
// triangles reach zero area, which the flip count does not see and no grid can follow.
void requireNoSqueezedTriangle(const TriMesh& mesh, const ParamMap& map) {
    const double tiny = 1e-12 * map.px * map.py;
    for (const auto& t : mesh.triangles) {
        const Vec2 a = map.uv[t[0]], b = map.uv[t[1]], c = map.uv[t[2]];
        if ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) <= tiny) {
            const Vec2 p = mesh.vertices[t[0]];
            throw SqueezeError("the parameterisation squeezes a thin part near (" +
                        std::to_string(static_cast<int>(p.x)) + ", " +
                        std::to_string(static_cast<int>(p.y)) +
                        ") to zero area (a long thin part with both flanks on one side of the "
                        "mesh rectangle is not supported yet)");
        }
    }
}

void checkMesh(const TriMesh& mesh, double px, double py) {
    if (!(px > 0) || !(py > 0) || !std::isfinite(px) || !std::isfinite(py))
        throw Error("topology map: rectangle " + std::to_string(px) + " x " + std::to_string(py) +
                    " is empty");
    const int nv = static_cast<int>(mesh.vertices.size());
    if (mesh.triangles.empty()) throw Error("topology map: the triangulation has no triangles");
    for (const auto& t : mesh.triangles)
        for (int k : t)
            if (k < 0 || k >= nv) throw Error("topology map: triangle vertex index out of range");
    const int n = static_cast<int>(mesh.outerLoop.size());
    if (n < 4) throw Error("topology map: the outer loop has fewer than 4 vertices");
    if (mesh.corner[0] != 0 || mesh.corner[1] <= 0 || mesh.corner[2] <= mesh.corner[1] ||
        mesh.corner[3] <= mesh.corner[2] || mesh.corner[3] >= n)
        throw Error("topology map: corners must be increasing loop positions starting at 0");
    std::vector<char> onLoop(nv, 0);
    auto mark = [&](const std::vector<int>& loop, const char* what) {
        for (int k : loop) {
            if (k < 0 || k >= nv)
                throw Error(std::string("topology map: ") + what + " vertex index out of range");
            if (onLoop[k])
                throw Error(std::string("topology map: vertex ") + std::to_string(k) +
                            " appears twice in the loops");
            onLoop[k] = 1;
        }
    };
    mark(mesh.outerLoop, "outer loop");
    for (const auto& h : mesh.holeLoops) {
        if (h.size() < 3) throw Error("topology map: a hole loop has fewer than 3 vertices");
        mark(h, "hole loop");
    }
}

// The outer loop's four sides in loop order, each from its first corner to the next (corners
// belong to both their sides).
std::array<std::vector<int>, 4> sidesOf(const TriMesh& mesh) {
    std::array<std::vector<int>, 4> sides;
    const int n = static_cast<int>(mesh.outerLoop.size());
    for (int s = 0; s < 4; ++s) {
        const int end = s == 3 ? n : mesh.corner[s + 1];
        for (int k = mesh.corner[s]; k <= end; ++k) sides[s].push_back(mesh.outerLoop[k % n]);
    }
    return sides;
}

// Cumulative image arc length along a chain, scaled to [0, 1].
std::vector<double> arcFractions(const TriMesh& mesh, const std::vector<int>& chain) {
    std::vector<double> s(chain.size(), 0.0);
    for (size_t k = 1; k < chain.size(); ++k)
        s[k] = s[k - 1] + norm(mesh.vertices[chain[k]] - mesh.vertices[chain[k - 1]]);
    const double total = s.back();
    if (!(total > 0)) throw Error("topology map: a side of the outer loop has zero length");
    for (double& x : s) x /= total;
    s.back() = 1.0;
    return s;
}

// Positions of the outer loop on the rectangle by arc length along each side.
void placeOuterLoop(const TriMesh& mesh, const std::array<std::vector<int>, 4>& sides, double px,
                    double py, std::vector<Vec2>& uv) {
    for (int s = 0; s < 4; ++s) {
        const std::vector<double> f = arcFractions(mesh, sides[s]);
        for (size_t k = 0; k < sides[s].size(); ++k) {
            Vec2 p;
            switch (s) {
                case kTop: p = {px * f[k], 0}; break;
                case kRight: p = {px, py * f[k]}; break;
                case kBottom: p = {px * (1 - f[k]), py}; break;
                default: p = {0, py * (1 - f[k])}; break;
            }
            uv[sides[s][k]] = p;
        }
    }
}

using detail::VertexTriangles;

// Strictly increasing values along a chain with fixed ends: every step is at least
// floorFraction of the mean step, the others shrink in proportion. Returns whether any step
// was raised.
bool makeStrictlyIncreasing(std::vector<double>& x, double floorFraction) {
    const size_t steps = x.size() - 1;
    const double span = x.back() - x.front();
    const double floor = floorFraction * span / static_cast<double>(steps);
    std::vector<double> d(steps);
    double sum = 0;
    bool raised = false;
    for (size_t k = 0; k < steps; ++k) {
        d[k] = x[k + 1] - x[k];
        if (!(d[k] >= floor)) {
            d[k] = floor;
            raised = true;
        }
        sum += d[k];
    }
    if (!raised) return false;
    const double last = x.back(), scale = span / sum;
    for (size_t k = 0; k < steps; ++k) x[k + 1] = x[k] + d[k] * scale;
    x.back() = last;
    return true;
}

bool strictlyIncreasing(const std::vector<double>& x) {
    for (size_t k = 1; k < x.size(); ++k)
        if (!(x[k] > x[k - 1])) return false;
    return true;
}

// One coordinate (0 = u, 1 = v) of the uv values along a chain, optionally reversed.
std::vector<double> chainValues(const std::vector<Vec2>& uv, const std::vector<int>& chain,
                                int coord, bool reversed) {
    std::vector<double> x;
    x.reserve(chain.size());
    for (int i : chain) x.push_back(coord == 0 ? uv[i].x : uv[i].y);
    if (reversed) std::reverse(x.begin(), x.end());
    return x;
}

void setChainValues(std::vector<Vec2>& uv, const std::vector<int>& chain, int coord, bool reversed,
                    std::vector<double> x) {
    if (reversed) std::reverse(x.begin(), x.end());
    for (size_t k = 0; k < chain.size(); ++k) (coord == 0 ? uv[chain[k]].x : uv[chain[k]].y) = x[k];
}

// Maximises the smallest doubled area of the triangles around interior vertex i over its
// position (a 2-D linear programme: the optimum has three active constraints, and rings are
// small, so try every triple). Moves i only if that improves on its current smallest area.
bool untangleVertex(const TriMesh& mesh, const VertexTriangles& vt, int i, std::vector<Vec2>& uv) {
    struct Constraint {
        double a, gx, gy;  // doubled area = a + gx·p.x + gy·p.y, p relative to uv[i]
    };
    const Vec2 o = uv[i];
    std::vector<Constraint> cs;
    double current = INFINITY;
    for (int k = vt.start[i]; k < vt.start[i + 1]; ++k) {
        const auto& t = mesh.triangles[vt.tris[k]];
        const int r = t[0] == i ? 0 : (t[1] == i ? 1 : 2);
        const Vec2 b = uv[t[(r + 1) % 3]] - o, c = uv[t[(r + 2) % 3]] - o;
        cs.push_back({b.x * c.y - c.x * b.y, b.y - c.y, c.x - b.x});
        current = std::min(current, cs.back().a);
    }
    const size_t m = cs.size();
    double bestT = current;
    Vec2 bestP{0, 0};
    bool found = false;
    for (size_t p = 0; p < m; ++p)
        for (size_t q = p + 1; q < m; ++q)
            for (size_t r = q + 1; r < m; ++r) {
                // Solve gx·x + gy·y − t = −a for the three constraints (Cramer's rule).
                const Constraint* c3[3] = {&cs[p], &cs[q], &cs[r]};
                double M[3][3], rhs[3];
                for (int k = 0; k < 3; ++k) {
                    M[k][0] = c3[k]->gx;
                    M[k][1] = c3[k]->gy;
                    M[k][2] = -1;
                    rhs[k] = -c3[k]->a;
                }
                auto det3 = [](double A[3][3]) {
                    return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                           A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                           A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
                };
                const double det = det3(M);
                if (std::abs(det) < 1e-300) continue;
                double sol[3];
                for (int col = 0; col < 3; ++col) {
                    double Mc[3][3];
                    for (int a = 0; a < 3; ++a)
                        for (int b = 0; b < 3; ++b) Mc[a][b] = b == col ? rhs[a] : M[a][b];
                    sol[col] = det3(Mc) / det;
                }
                const double t = sol[2];
                if (!(t > bestT)) continue;
                bool feasible = true;
                for (const Constraint& c : cs)
                    if (c.a + c.gx * sol[0] + c.gy * sol[1] < t * (1 - 1e-9)) {
                        feasible = false;
                        break;
                    }
                if (!feasible) continue;
                bestT = t;
                bestP = {sol[0], sol[1]};
                found = true;
            }
    if (!found) return false;
    uv[i] = o + bestP;
    return true;
}

// Moves interior vertices near folded triangles until none is folded, growing the region of
// movable vertices ring by ring. Returns the number of vertices moved.
int untangle(const TriMesh& mesh, const VertexTriangles& vt, const std::vector<char>& movable,
             std::vector<Vec2>& uv) {
    std::vector<char> inRegion(mesh.vertices.size(), 0);
    std::vector<int> region;
    std::vector<char> moved(mesh.vertices.size(), 0);
    int movedCount = 0;
    for (int round = 0; round < 12; ++round) {
        const std::vector<int> flipped = detail::flippedTriangles(mesh, uv);
        if (flipped.empty()) break;
        if (round == 0) {
            for (int t : flipped)
                for (int k : mesh.triangles[t])
                    if (!inRegion[k]) inRegion[k] = 1, region.push_back(k);
        } else {
            const std::vector<int> ring = region;
            for (int i : ring)
                for (int k = vt.start[i]; k < vt.start[i + 1]; ++k)
                    for (int j : mesh.triangles[vt.tris[k]])
                        if (!inRegion[j]) inRegion[j] = 1, region.push_back(j);
        }
        for (int sweep = 0; sweep < 20; ++sweep) {
            bool any = false;
            for (int i : region)
                if (movable[i] && untangleVertex(mesh, vt, i, uv)) {
                    any = true;
                    if (!moved[i]) moved[i] = 1, ++movedCount;
                }
            if (!any || detail::flippedTriangles(mesh, uv).empty()) break;
        }
    }
    return movedCount;
}

// Solves a symmetric positive definite Laplacian system (cotangent weights): a direct
// factorisation is faster than conjugate gradients at the sizes of our triangulations.
Eigen::MatrixXd solveSymmetric(const detail::LaplacianSystem& sys, const char* what) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(sys.A);
    if (solver.info() != Eigen::Success)
        throw Error(std::string("slit map: the ") + what + " system could not be factorised");
    Eigen::MatrixXd x = solver.solve(sys.rhs);
    if (solver.info() != Eigen::Success || !x.allFinite())
        throw Error(std::string("slit map: the ") + what + " system could not be solved");
    return x;
}

struct SlitMapBuilder {
    const TriMesh& mesh;
    double px, py;
    int nv;
    std::array<std::vector<int>, 4> sides;
    std::vector<int> sideMask, holeOf;
    detail::WeightMatrix W;
    std::vector<Vec2> uv;
    VertexTriangles vt;

    SlitMapBuilder(const TriMesh& m, double px_, double py_)
        : mesh(m), px(px_), py(py_), nv(static_cast<int>(m.vertices.size())), sides(sidesOf(m)),
          sideMask(nv, 0), holeOf(nv, -1), uv(nv), vt(m) {
        for (int s = 0; s < 4; ++s)
            for (int i : sides[s]) sideMask[i] |= 1 << s;
        for (size_t h = 0; h < mesh.holeLoops.size(); ++h)
            for (int i : mesh.holeLoops[h]) holeOf[i] = static_cast<int>(h);
    }

    // One coordinate (0 = u, 1 = v), harmonic, with the vertices of fixedMask at their current
    // values; with floatingHoles each hole's vertices share one unknown.
    void solveCoord(int coord, const std::vector<char>& fixedMask, bool floatingHoles) {
        std::vector<int> unknown(nv, -1);
        Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(nv, 1);
        std::vector<int> holeUnknown(mesh.holeLoops.size(), -1);
        int count = 0;
        for (int i = 0; i < nv; ++i) {
            if (fixedMask[i]) {
                fixed(i, 0) = coord ? uv[i].y : uv[i].x;
            } else if (floatingHoles && holeOf[i] >= 0) {
                int& h = holeUnknown[holeOf[i]];
                if (h < 0) h = count++;
                unknown[i] = h;
            } else {
                unknown[i] = count++;
            }
        }
        const Eigen::MatrixXd x = solveSymmetric(
            detail::assembleLaplacian(W, unknown, count, fixed), coord ? "v" : "u");
        for (int i = 0; i < nv; ++i)
            if (unknown[i] >= 0) (coord ? uv[i].y : uv[i].x) = x(unknown[i], 0);
    }

    std::vector<char> onSides(int mask) const {
        std::vector<char> out(nv, 0);
        for (int i = 0; i < nv; ++i) out[i] = (sideMask[i] & mask) != 0;
        return out;
    }

    // Places the interior neighbours of slit end `e` evenly around it, on a circle of their
    // mean current distance, from just past one arc round to the other: the harmonic u and v
    // are least accurate at slit ends (the map is singular there), and this fan is valid by
    // construction. `leftEnd`: the slit extends to the right of e. Returns the placed vertices.
    std::vector<int> placeEndFan(int e, bool leftEnd) {
        // Successor of each neighbour around e in positive orientation.
        std::vector<std::pair<int, int>> next;
        for (int q = vt.start[e]; q < vt.start[e + 1]; ++q) {
            const auto& t = mesh.triangles[vt.tris[q]];
            const int r = t[0] == e ? 0 : (t[1] == e ? 1 : 2);
            next.push_back({t[(r + 1) % 3], t[(r + 2) % 3]});
        }
        int start = -1;
        for (const auto& [a, b0] : next) {
            (void)b0;
            bool hasPred = false;
            for (const auto& [c, d] : next) hasPred = hasPred || d == a, (void)c;
            if (!hasPred) start = a;
        }
        std::vector<int> chain;
        for (int cur = start; cur >= 0 && chain.size() <= next.size();) {
            chain.push_back(cur);
            int succ = -1;
            for (const auto& [a, b0] : next)
                if (a == cur) succ = b0;
            cur = succ;
        }
        std::vector<int> fan;
        if (start < 0 || chain.size() != next.size() + 1) return fan;  // not a simple fan
        const Vec2 o = uv[e];
        double radius = 0;
        for (size_t k = 1; k + 1 < chain.size(); ++k) {
            if (holeOf[chain[k]] >= 0 || sideMask[chain[k]]) return {};
            radius += norm(uv[chain[k]] - o);
            fan.push_back(chain[k]);
        }
        if (fan.empty()) return fan;
        // Not farther than halfway to the rectangle's sides.
        radius = std::min(radius / static_cast<double>(fan.size()),
                          0.5 * std::min({o.x, px - o.x, o.y, py - o.y}));
        // Angles atan2(v, u) grow in positive orientation; the arcs leave e at angle π (right
        // end) or 0 (left end).
        const double first = leftEnd ? 0.0 : 3.14159265358979323846;
        for (size_t k = 0; k < fan.size(); ++k) {
            const double a = first + 2 * 3.14159265358979323846 * static_cast<double>(k + 1) /
                                         static_cast<double>(fan.size() + 1);
            uv[fan[k]] = o + radius * Vec2{std::cos(a), std::sin(a)};
        }
        return fan;
    }

    // The hole's arcs between its extreme-u vertices; which one is upper follows from the side
    // the domain's triangles lie on, not from the (possibly folded) values.
    SlitInfo arcs(int h) const {
        const std::vector<int>& loop = mesh.holeLoops[h];
        const int m = static_cast<int>(loop.size());
        // A slit end is surrounded by the domain on all sides but the slit's zero angle, so its
        // triangles must reach above, beyond and below the slit: at least three of them. A
        // vertex with two (one interior neighbour, joined to both arcs) would fold one.
        int lo = -1, hi = -1;
        for (int k = 0; k < m; ++k) {
            const int i = loop[k];
            if (vt.start[i + 1] - vt.start[i] < 3) continue;
            if (lo < 0 || uv[i].x < uv[loop[lo]].x) lo = k;
            if (hi < 0 || uv[i].x > uv[loop[hi]].x) hi = k;
        }
        if (lo < 0 || lo == hi)
            throw Error("slit map: hole " + std::to_string(h) + " near " + at(mesh.vertices[loop[0]]) +
                        " has fewer than two vertices with three or more triangles to end its slit");
        // Does a triangle hold the directed edge loop[0] → loop[1]? Then, walking the loop
        // forward with u increasing, the domain lies at larger v: the forward arc is the lower.
        const int a = loop[0], b = loop[1];
        int forward = -1;
        for (int q = vt.start[a]; q < vt.start[a + 1]; ++q)
            for (int k = 0; k < 3; ++k) {
                const auto& t = mesh.triangles[vt.tris[q]];
                if (t[k] == a && t[(k + 1) % 3] == b) forward = 1;
                if (t[k] == b && t[(k + 1) % 3] == a) forward = 0;
            }
        if (forward < 0)
            throw Error("slit map: hole " + std::to_string(h) + " loop edge at " +
                        at(mesh.vertices[a]) + " is in no triangle");
        std::vector<int> fwd, bwd;
        for (int k = lo;; k = (k + 1) % m) {
            fwd.push_back(loop[k]);
            if (k == hi) break;
        }
        for (int k = lo;; k = (k + m - 1) % m) {
            bwd.push_back(loop[k]);
            if (k == hi) break;
        }
        SlitInfo s;
        s.u0 = uv[loop[lo]].x;
        s.u1 = uv[loop[hi]].x;
        s.v = uv[loop[lo]].y;
        s.lowerArc = forward ? fwd : bwd;
        s.upperArc = forward ? bwd : fwd;
        return s;
    }

    // Each chain whose values must increase strictly: the sides as (chain, coordinate, reversed)
    // and the arcs of every slit.
    template <class F>
    void forEachChain(const std::vector<SlitInfo>& slits, F f) {
        f(sides[kTop], 0, false);
        f(sides[kBottom], 0, true);
        f(sides[kRight], 1, false);
        f(sides[kLeft], 1, true);
        for (const SlitInfo& s : slits) {
            f(s.upperArc, 0, false);
            f(s.lowerArc, 0, false);
        }
    }
};

}  // namespace

std::vector<std::array<int, 2>> dividingEdges(const TriMesh& mesh) {
    const int nv = static_cast<int>(mesh.vertices.size());
    std::vector<int> sideMask(nv, 0), loopId(nv, -1), loopPos(nv, -1);
    if (mesh.outerLoop.size() >= 4) {
        const auto sides = sidesOf(mesh);
        for (int s = 0; s < 4; ++s)
            for (int i : sides[s]) sideMask[i] |= 1 << s;
    }
    auto mark = [&](const std::vector<int>& loop, int id) {
        for (size_t k = 0; k < loop.size(); ++k) loopId[loop[k]] = id, loopPos[loop[k]] = static_cast<int>(k);
    };
    mark(mesh.outerLoop, 0);
    for (size_t h = 0; h < mesh.holeLoops.size(); ++h) mark(mesh.holeLoops[h], static_cast<int>(h) + 1);
    auto loopSize = [&](int id) {
        return static_cast<int>(id == 0 ? mesh.outerLoop.size() : mesh.holeLoops[id - 1].size());
    };
    std::vector<std::array<int, 2>> out;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            if (a > b || loopId[a] < 0 || loopId[a] != loopId[b]) continue;  // each edge once
            const int n = loopSize(loopId[a]), d = std::abs(loopPos[a] - loopPos[b]);
            if (d == 1 || d == n - 1) continue;  // a loop edge
            if (loopId[a] > 0 || (sideMask[a] & sideMask[b])) out.push_back({a, b});
        }
    return out;
}

TopologyMap buildSlitMapOrFolds(const TriMesh& mesh, double px, double py) {
    checkMesh(mesh, px, py);
    if (const auto bad = dividingEdges(mesh); !bad.empty())
        throw Error("topology map: " + std::to_string(bad.size()) +
                    " edge(s) join two non-adjacent vertices of one side or hole, first " +
                    at(mesh.vertices[bad[0][0]]) + "–" + at(mesh.vertices[bad[0][1]]) +
                    "; no unfolded map exists, the triangulation must split them");
    SlitMapBuilder b(mesh, px, py);
    TopologyMap result;
    // Negative weights (obtuse angles facing an edge from both sides, or facing a loop edge) are
    // raised to this floor; cotangent weights are dimensionless, typically about 0.5.
    b.W = detail::cotangentWeights(mesh, mesh.vertices, 1e-3, &result.stats.clampedWeights);
    // Why v is free on the left and right sides and u on the top and bottom (the paper's
    // choice): v fixed on every side (left and right by arc length) straightens sides near
    // holes but lets patches bulge into small holes, leaving them painted over; fixing u on the
    // top and bottom too folds triangles between a hole and a side.
    for (int i = 0; i < b.nv; ++i) {
        if (b.sideMask[i] & (1 << kTop)) b.uv[i].y = 0;
        if (b.sideMask[i] & (1 << kBottom)) b.uv[i].y = py;
        if (b.sideMask[i] & (1 << kLeft)) b.uv[i].x = 0;
        if (b.sideMask[i] & (1 << kRight)) b.uv[i].x = px;
    }
    b.solveCoord(1, b.onSides((1 << kTop) | (1 << kBottom)), true);
    b.solveCoord(0, b.onSides((1 << kLeft) | (1 << kRight)), false);

    std::vector<SlitInfo> slits;
    for (size_t h = 0; h < mesh.holeLoops.size(); ++h) slits.push_back(b.arcs(static_cast<int>(h)));
    bool monotone = true;
    b.forEachChain(slits, [&](const std::vector<int>& chain, int coord, bool rev) {
        monotone = monotone && strictlyIncreasing(chainValues(b.uv, chain, coord, rev));
    });
    result.stats.flipsBeforeRepair = static_cast<int>(detail::flippedTriangles(mesh, b.uv).size());

    if (result.stats.flipsBeforeRepair > 0 || !monotone) {
        // Every loop keeps its (now monotone) values, the slit ends' fans are laid out by hand,
        // and u and v are solved again around them.
        result.stats.repaired = true;
        b.forEachChain(slits, [&](const std::vector<int>& chain, int coord, bool rev) {
            std::vector<double> x = chainValues(b.uv, chain, coord, rev);
            if (makeStrictlyIncreasing(x, 0.1)) setChainValues(b.uv, chain, coord, rev, x);
        });
        std::vector<char> fixedMask = b.onSides(15);
        for (int i = 0; i < b.nv; ++i) fixedMask[i] = fixedMask[i] || b.holeOf[i] >= 0;
        for (const SlitInfo& s : slits)
            for (const bool left : {true, false})
                for (int i : b.placeEndFan(left ? s.upperArc.front() : s.upperArc.back(), left))
                    fixedMask[i] = 1;
        b.solveCoord(1, fixedMask, false);
        b.solveCoord(0, fixedMask, false);
        if (!detail::flippedTriangles(mesh, b.uv).empty()) {
            std::vector<char> movable(b.nv, 0);
            for (int i = 0; i < b.nv; ++i) movable[i] = !fixedMask[i];
            result.stats.untangledVertices = untangle(mesh, b.vt, movable, b.uv);
        }
    }
    result.map = ParamMap{px, py, std::move(b.uv)};
    result.folded = detail::flippedTriangles(mesh, result.map.uv);
    for (SlitInfo& s : slits) {
        s.v = result.map.uv[s.upperArc.front()].y;
        s.u0 = result.map.uv[s.upperArc.front()].x;
        s.u1 = result.map.uv[s.upperArc.back()].x;
    }
    result.slits = std::move(slits);
    return result;
}

namespace {
// The checks every slit map passes before it leaves this stage: no fold left (MapError naming
// where, and the rounds of refinement tried), no triangle squeezed to zero area.
void requireUsableSlitMap(const TriMesh& mesh, const TopologyMap& result) {
    if (!result.folded.empty()) {
        const int rounds = result.stats.refineRounds;
        throw MapError("the slit map of " + std::to_string(mesh.holeLoops.size()) +
                       " hole(s) cannot be unfolded near " +
                       at(mesh.vertices[mesh.triangles[result.folded[0]][0]]) + " (" +
                       std::to_string(result.folded.size()) + " triangles" +
                       (rounds > 0 ? " after " + std::to_string(rounds) + " rounds of refinement"
                                   : std::string()) +
                       "): holes lie too close to each other or to the outline; "
                       "--min-hole N fills holes under N pixels");
    }
    requireNoSqueezedTriangle(mesh, result.map);
}
}  // namespace

TopologyMap buildSlitMap(const TriMesh& mesh, double px, double py) {
    TopologyMap result = buildSlitMapOrFolds(mesh, px, py);
    requireUsableSlitMap(mesh, result);
    return result;
}

TopologyMap buildTopologyMapRefining(TriMesh& mesh, double px, double py, int maxRounds) {
    if (mesh.holeLoops.empty()) return buildTopologyMap(mesh, px, py);
    TopologyMap result = buildSlitMapOrFolds(mesh, px, py);
    for (int round = 0; round < maxRounds && !result.folded.empty(); ++round) {
        // The folds and the triangles sharing a vertex with them, split in image space.
        std::vector<char> near(mesh.vertices.size(), 0);
        for (int t : result.folded)
            for (int k : mesh.triangles[t]) near[k] = 1;
        std::vector<int> chosen;
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const auto& tr = mesh.triangles[t];
            if (near[tr[0]] || near[tr[1]] || near[tr[2]]) chosen.push_back(static_cast<int>(t));
        }
        const TopologyMapStats previous = result.stats;
        const int added = refineTriangles(mesh, chosen);
        result = buildSlitMapOrFolds(mesh, px, py);
        result.stats.refineRounds = previous.refineRounds + 1;
        result.stats.refinedVertices = previous.refinedVertices + added;
    }
    requireUsableSlitMap(mesh, result);
    return result;
}

TopologyMap buildTopologyMap(const TriMesh& mesh, double px, double py) {
    if (!mesh.holeLoops.empty()) return buildSlitMap(mesh, px, py);
    checkMesh(mesh, px, py);
    if (const auto bad = dividingEdges(mesh); !bad.empty())
        throw Error("topology map: " + std::to_string(bad.size()) +
                    " edge(s) join two non-adjacent vertices of one side, first " +
                    at(mesh.vertices[bad[0][0]]) + "–" + at(mesh.vertices[bad[0][1]]) +
                    "; no unfolded map exists, the triangulation must split them");
    const int nv = static_cast<int>(mesh.vertices.size());
    std::vector<Vec2> uv(nv);
    placeOuterLoop(mesh, sidesOf(mesh), px, py, uv);
    std::vector<int> unknown(nv, 0);
    for (int i : mesh.outerLoop) unknown[i] = -1;
    int count = 0;
    Eigen::MatrixXd fixed(nv, 2);
    for (int i = 0; i < nv; ++i) {
        if (unknown[i] == 0) unknown[i] = count++;
        fixed(i, 0) = uv[i].x;
        fixed(i, 1) = uv[i].y;
    }
    const detail::LaplacianSystem sys =
        detail::assembleLaplacian(detail::meanValueWeights(mesh, mesh.vertices), unknown, count, fixed);
    // One factorisation for both coordinates: SparseLU is faster here than BiCGSTAB with an
    // incomplete-LU preconditioner.
    if (count > 0) {  // a small region may have every vertex on its outline
        Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
        solver.compute(sys.A);
        if (solver.info() != Eigen::Success)
            throw Error("topology map: the mean-value system could not be factorised");
        const Eigen::MatrixXd x = solver.solve(sys.rhs);
        if (!x.allFinite()) throw Error("topology map: the mean-value system could not be solved");
        for (int i = 0; i < nv; ++i)
            if (unknown[i] >= 0) uv[i] = {x(unknown[i], 0), x(unknown[i], 1)};
    }
    TopologyMap result;
    result.map = ParamMap{px, py, std::move(uv)};
    if (const int flips = countFlippedTriangles(mesh, result.map); flips > 0)
        // In exact arithmetic it cannot (convex boundary, positive weights): the folds are
        // round-off where a thin part is squeezed, as below.
        throw SqueezeError("topology map: the mean-value map folds " + std::to_string(flips) +
                           " triangle(s) (a thin part squeezed below round-off, or a "
                           "triangulation of negative orientation)");
    requireNoSqueezedTriangle(mesh, result.map);
    return result;
}

}  // namespace gm
