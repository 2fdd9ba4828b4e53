#include "converters/grid.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <queue>
#include <string>

#include "meshcore/error.h"
#include "converters/unfold.h"
#include "cover_chain.h"
#include "meshcore/evaluate.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {


// Sorted, with values closer than `tol` merged (the first kept).
std::vector<double> uniqueSorted(std::vector<double> values, double tol) {
    std::sort(values.begin(), values.end());
    std::vector<double> out;
    for (double x : values)
        if (out.empty() || x - out.back() > tol) out.push_back(x);
    return out;
}

// Knots along one direction of extent `extent`: the required ones, then `count` intervals
// as uniform as possible (each required interval split evenly, the longest pieces first).
std::vector<double> knotsAlong(double extent, std::vector<double> required, int count,
                               const std::vector<double>& explicitKnots, const char* axis) {
    const double tol = 1e-9 * extent;
    std::vector<double> req{0.0, extent};
    for (double x : required)
        if (std::isfinite(x) && x > tol && x < extent - tol) req.push_back(x);
    req = uniqueSorted(req, tol);
    req.front() = 0.0;
    req.back() = extent;

    if (!explicitKnots.empty()) {
        if (explicitKnots.size() < 2 || std::abs(explicitKnots.front()) > tol ||
            std::abs(explicitKnots.back() - extent) > tol)
            throw Error(std::string("grid: explicit ") + axis + " knots do not span the rectangle");
        for (size_t k = 1; k < explicitKnots.size(); ++k)
            if (!(explicitKnots[k] > explicitKnots[k - 1]))
                throw Error(std::string("grid: explicit ") + axis +
                            " knots are not strictly increasing");
        // Required knots win over explicit ones that lie within the merge tolerance of them.
        std::vector<double> merged = req;
        for (double x : explicitKnots) {
            auto it = std::lower_bound(req.begin(), req.end(), x);
            bool near =
                (it != req.end() && *it - x <= tol) || (it != req.begin() && x - *(it - 1) <= tol);
            if (!near) merged.push_back(x);
        }
        std::sort(merged.begin(), merged.end());
        return merged;
    }

    const int nReq = static_cast<int>(req.size()) - 1;
    const int n = std::max(count, nReq);
    std::vector<int> pieces(static_cast<size_t>(nReq), 1);
    using Item = std::pair<double, int>;  // piece length, interval
    std::priority_queue<Item> queue;
    for (int k = 0; k < nReq; ++k) queue.push({req[k + 1] - req[k], k});
    for (int extra = n - nReq; extra > 0; --extra) {
        const int k = queue.top().second;
        queue.pop();
        ++pieces[k];
        queue.push({(req[k + 1] - req[k]) / pieces[k], k});
    }
    std::vector<double> knots;
    for (int k = 0; k < nReq; ++k)
        for (int p = 0; p < pieces[k]; ++p)
            knots.push_back(req[k] + (req[k + 1] - req[k]) * p / pieces[k]);
    knots.push_back(extent);
    return knots;
}

int nearestIndex(const std::vector<double>& knots, double x) {
    auto it = std::lower_bound(knots.begin(), knots.end(), x);
    if (it == knots.end()) return static_cast<int>(knots.size()) - 1;
    int k = static_cast<int>(it - knots.begin());
    if (k > 0 && x - knots[k - 1] < knots[k] - x) --k;
    return k;
}

}  // namespace

void chooseKnots(const ParamMap& map, const GridOptions& options, std::vector<double>& u,
                 std::vector<double>& v) {
    if (!(map.px > 0) || !(map.py > 0) || !std::isfinite(map.px) || !std::isfinite(map.py))
        throw Error("grid: the parameter rectangle is empty");
    std::vector<double> ru = options.extraU, rv = options.extraV;
    for (const GridSlit& s : options.slits) {
        if (!(s.u0 > 0 && s.u1 > s.u0 && s.u1 < map.px && s.v > 0 && s.v < map.py))
            throw Error("grid: a slit lies outside the parameter rectangle's interior");
        ru.push_back(s.u0);
        ru.push_back(s.u1);
        rv.push_back(s.v);
    }
    const double size = options.targetPatchSize > 0 ? options.targetPatchSize : 64.0;
    const int cols = options.columns > 0
                         ? options.columns
                         : std::max(1, static_cast<int>(std::lround(map.px / size)));
    const int rows =
        options.rows > 0 ? options.rows : std::max(1, static_cast<int>(std::lround(map.py / size)));
    u = knotsAlong(map.px, ru, cols, options.knotsU, "u");
    v = knotsAlong(map.py, rv, rows, options.knotsV, "v");
}

// ---------------------------------------------------------------------------------------------

struct GridBuilder::Impl {
    uint64_t id = 0;       // tells builders apart in the cover-chain cache (build())
    std::vector<Vec2> xy;  // image positions
    ParamMap map;          // uv per vertex
    std::vector<std::array<int, 3>> triangles;
    // Bucket grid over the uv bounding box; bucket b holds cellTris[cellStart[b]..[b+1]).
    double minU = 0, minV = 0, cellW = 1, cellH = 1;
    int nu = 1, nv = 1;
    std::vector<int> cellStart, cellTris;

    struct Hit {
        int tri = -1;
        double l[3] = {0, 0, 0};
    };

    int cellU(double u) const {
        return std::clamp(static_cast<int>(std::floor((u - minU) / cellW)), 0, nu - 1);
    }
    int cellV(double v) const {
        return std::clamp(static_cast<int>(std::floor((v - minV) / cellH)), 0, nv - 1);
    }

    bool barycentric(int t, Vec2 p, double l[3]) const {
        const auto& tri = triangles[t];
        const Vec2 a = map.uv[tri[0]], b = map.uv[tri[1]], c = map.uv[tri[2]];
        const double d = cross(b - a, c - a);
        if (d == 0 || !std::isfinite(d)) return false;
        l[1] = cross(p - a, c - a) / d;
        l[2] = cross(b - a, p - a) / d;
        l[0] = 1 - l[1] - l[2];
        return true;
    }

    // Closest point of triangle t to p, as barycentrics; returns the squared distance.
    double closest(int t, Vec2 p, double l[3]) const {
        const auto& tri = triangles[t];
        if (barycentric(t, p, l) && l[0] >= 0 && l[1] >= 0 && l[2] >= 0) return 0;
        double best = std::numeric_limits<double>::infinity();
        for (int e = 0; e < 3; ++e) {
            const Vec2 a = map.uv[tri[e]], b = map.uv[tri[(e + 1) % 3]];
            const double s = closestSegmentParameter(p, a, b);
            const Vec2 q = a + s * (b - a);
            const double d2 = dot(p - q, p - q);
            if (d2 < best) {
                best = d2;
                l[e] = 1 - s;
                l[(e + 1) % 3] = s;
                l[(e + 2) % 3] = 0;
            }
        }
        return best;
    }

    Hit locate(Vec2 p, int side) const {
        const double tol = 1e-10;
        Hit hit, preferred;
        // Points come in runs along grid lines: most fall in the triangle the previous one of
        // this thread fell in (the buckets hold a few triangles each; this is one test).
        // (Builders are told apart by id: a new one may live where a freed one did.)
        thread_local uint64_t lastOwner = 0;
        thread_local int lastTri = -1;
        if (side == 0 && lastOwner == id && barycentric(lastTri, p, hit.l) && hit.l[0] >= -tol &&
            hit.l[1] >= -tol && hit.l[2] >= -tol) {
            hit.tri = lastTri;
            return snapped(hit);
        }
        const int cu = cellU(p.x), cv = cellV(p.y);
        const int cell = cv * nu + cu;
        for (int k = cellStart[cell]; k < cellStart[cell + 1]; ++k) {
            const int t = cellTris[k];
            double l[3];
            if (!barycentric(t, p, l) || l[0] < -tol || l[1] < -tol || l[2] < -tol) continue;
            if (hit.tri < 0) {
                hit.tri = t;
                std::copy(l, l + 3, hit.l);
            }
            if (side == 0) break;
            const auto& tri = triangles[t];
            const double cvv = (map.uv[tri[0]].y + map.uv[tri[1]].y + map.uv[tri[2]].y) / 3;
            if ((side < 0 && cvv < p.y) || (side > 0 && cvv > p.y)) {
                preferred.tri = t;
                std::copy(l, l + 3, preferred.l);
                break;
            }
        }
        if (preferred.tri >= 0) hit = preferred;
        if (hit.tri < 0) {
            // A hair outside (or in a gap of) the domain: the nearest triangle, searched ring by
            // ring until no closer one can exist.
            double best = std::numeric_limits<double>::infinity();
            const int maxRing = std::max(nu, nv);
            for (int r = 0; r <= maxRing; ++r) {
                const double ringDist = (r - 1) * std::min(cellW, cellH);
                if (r > 0 && ringDist > 0 && ringDist * ringDist > best) break;
                for (int y = cv - r; y <= cv + r; ++y) {
                    if (y < 0 || y >= nv) continue;
                    for (int x = cu - r; x <= cu + r; ++x) {
                        if (x < 0 || x >= nu) continue;
                        if (std::max(std::abs(x - cu), std::abs(y - cv)) != r) continue;
                        const int c = y * nu + x;
                        for (int k = cellStart[c]; k < cellStart[c + 1]; ++k) {
                            double l[3] = {0, 0, 0};
                            const double d2 = closest(cellTris[k], p, l);
                            if (d2 < best) {
                                best = d2;
                                hit.tri = cellTris[k];
                                std::copy(l, l + 3, hit.l);
                            }
                        }
                    }
                }
            }
        }
        assert(hit.tri >= 0);
        lastOwner = id;
        lastTri = hit.tri;
        return snapped(hit);
    }

    // Snap: a point on an edge (the domain boundary, a slit) interpolates that edge only.
    static Hit snapped(Hit hit) {
        double sum = 0;
        for (double& x : hit.l) {
            if (x < 1e-12) x = 0;
            sum += x;
        }
        for (double& x : hit.l) x /= sum;
        return hit;
    }

    Vec2 position(double u, double v, int side) const {
        const Hit h = locate({u, v}, side);
        const auto& tri = triangles[h.tri];
        return h.l[0] * xy[tri[0]] + h.l[1] * xy[tri[1]] + h.l[2] * xy[tri[2]];
    }
};

GridBuilder::GridBuilder(const TriMesh& mesh, const ParamMap& map) : impl_(new Impl) {
    Impl& m = *impl_;
    static std::atomic<uint64_t> nextId{1};
    m.id = nextId++;
    if (map.uv.size() != mesh.vertices.size())
        throw Error("grid: the parameter map does not match the triangulation's vertices");
    if (mesh.triangles.empty()) throw Error("grid: the triangulation has no triangles");
    if (!(map.px > 0) || !(map.py > 0) || !std::isfinite(map.px) || !std::isfinite(map.py))
        throw Error("grid: the parameter rectangle is empty");
    const int nVert = static_cast<int>(mesh.vertices.size());
    for (const auto& t : mesh.triangles)
        for (int k : t)
            if (k < 0 || k >= nVert) throw Error("grid: a triangle names a missing vertex");
    m.xy = mesh.vertices;
    m.map = map;
    m.triangles = mesh.triangles;

    double maxU = -std::numeric_limits<double>::infinity(), maxV = maxU;
    m.minU = m.minV = std::numeric_limits<double>::infinity();
    for (const Vec2& p : map.uv) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw Error("grid: the parameter map has a non-finite value");
        m.minU = std::min(m.minU, p.x);
        m.minV = std::min(m.minV, p.y);
        maxU = std::max(maxU, p.x);
        maxV = std::max(maxV, p.y);
    }
    // About two triangles per bucket, buckets roughly square in parameter space.
    const double w = std::max(maxU - m.minU, 1e-12), h = std::max(maxV - m.minV, 1e-12);
    const double cells = std::max(1.0, static_cast<double>(m.triangles.size()) / 2.0);
    const double side = std::sqrt(w * h / cells);
    m.nu = std::clamp(static_cast<int>(std::ceil(w / side)), 1, 4096);
    m.nv = std::clamp(static_cast<int>(std::ceil(h / side)), 1, 4096);
    m.cellW = w / m.nu;
    m.cellH = h / m.nv;

    const size_t nCells = static_cast<size_t>(m.nu) * m.nv;
    std::vector<int> count(nCells + 1, 0);
    auto forCells = [&](const std::array<int, 3>& t, auto&& fn) {
        const Vec2 a = map.uv[t[0]], b = map.uv[t[1]], c = map.uv[t[2]];
        const int x0 = m.cellU(std::min({a.x, b.x, c.x})), x1 = m.cellU(std::max({a.x, b.x, c.x}));
        const int y0 = m.cellV(std::min({a.y, b.y, c.y})), y1 = m.cellV(std::max({a.y, b.y, c.y}));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) fn(y * m.nu + x);
    };
    for (const auto& t : m.triangles) forCells(t, [&](int c) { ++count[c + 1]; });
    for (size_t c = 0; c < nCells; ++c) count[c + 1] += count[c];
    m.cellStart = count;
    m.cellTris.resize(static_cast<size_t>(count[nCells]));
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int k = 0; k < static_cast<int>(m.triangles.size()); ++k)
        forCells(m.triangles[k], [&](int c) { m.cellTris[fill[c]++] = k; });
}

GridBuilder::~GridBuilder() = default;
GridBuilder::GridBuilder(GridBuilder&&) noexcept = default;
GridBuilder& GridBuilder::operator=(GridBuilder&&) noexcept = default;

const ParamMap& GridBuilder::map() const { return impl_->map; }

Vec2 GridBuilder::imagePosition(double u, double v, int side) const {
    return impl_->position(u, v, side);
}

namespace {

// Least-squares fit of the derivative slots of a family of grid lines: each patch edge
// contributes samples q(τ) of the iso-curve, modelled by the Hermite cubic
// h0·Pa + h1·Pb + h2·Δ·σa·Da + h3·Δ·σb·Db; D are the unknown slots (pixels per global unit).
//
// With a tangent limit L > 0, each solved slot is then shortened, where needed, so that on every
// edge it belongs to the end tangent (slot × Δ) is at most L times the edge's chord: one
// derivative shared by a short interval and a long one (knots bunch where the map is uneven)
// would otherwise make the short edge overshoot into a loop, and its patches fold.
class DerivativeFit {
public:
    DerivativeFit(int slots, double tangentLimit)
        : slots_(slots), tangentLimit_(tangentLimit), rhsX_(slots, 0.0), rhsY_(slots, 0.0),
          limit_(static_cast<size_t>(slots), INFINITY) {}

    // One patch edge of parameter length `delta` from Pa to Pb, with interior samples q at
    // local parameters tau.
    void addEdge(int slotA, double signA, int slotB, double signB, double delta, Vec2 pa, Vec2 pb,
                 const std::vector<double>& tau, const std::vector<Vec2>& q) {
        double aa = 0, ab = 0, bb = 0;
        Vec2 ra, rb;
        for (size_t k = 0; k < tau.size(); ++k) {
            double h[4];
            hermiteBasis(tau[k], h);
            const double ca = h[2] * delta * signA, cb = h[3] * delta * signB;
            const Vec2 r = q[k] - h[0] * pa - h[1] * pb;
            aa += ca * ca;
            ab += ca * cb;
            bb += cb * cb;
            ra = ra + ca * r;
            rb = rb + cb * r;
        }
        // A weak pull toward the chord keeps every slot determined (e.g. degenerate edges)
        // without biasing straight edges, whose chord is the exact derivative.
        const double w = 1e-4 * delta * delta;
        const Vec2 chord = (1.0 / delta) * (pb - pa);
        aa += w;
        bb += w;
        ra = ra + (w * signA) * chord;
        rb = rb + (w * signB) * chord;
        if (tangentLimit_ > 0) {
            const double cap = tangentLimit_ * norm(pb - pa) / delta;
            limit_[slotA] = std::min(limit_[slotA], cap);
            limit_[slotB] = std::min(limit_[slotB], cap);
        }
        triplets_.emplace_back(slotA, slotA, aa);
        triplets_.emplace_back(slotB, slotB, bb);
        triplets_.emplace_back(slotA, slotB, ab);
        triplets_.emplace_back(slotB, slotA, ab);
        rhsX_[slotA] += ra.x;
        rhsY_[slotA] += ra.y;
        rhsX_[slotB] += rb.x;
        rhsY_[slotB] += rb.y;
    }

    std::vector<Vec2> solve() {
        Eigen::SparseMatrix<double> A(slots_, slots_);
        A.setFromTriplets(triplets_.begin(), triplets_.end());
        for (int k = 0; k < slots_; ++k)
            if (A.coeff(k, k) == 0) A.coeffRef(k, k) = 1;  // a slot no edge uses stays 0
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
        std::vector<Vec2> out(static_cast<size_t>(slots_));
        if (ldlt.info() != Eigen::Success) return out;
        Eigen::VectorXd bx = Eigen::Map<Eigen::VectorXd>(rhsX_.data(), slots_);
        Eigen::VectorXd by = Eigen::Map<Eigen::VectorXd>(rhsY_.data(), slots_);
        const Eigen::VectorXd x = ldlt.solve(bx), y = ldlt.solve(by);
        for (int k = 0; k < slots_; ++k) {
            out[k] = {x[k], y[k]};
            const double len = norm(out[k]);
            if (len > limit_[k]) out[k] = (limit_[k] / len) * out[k];
        }
        return out;
    }

private:
    int slots_;
    double tangentLimit_;
    std::vector<Eigen::Triplet<double>> triplets_;
    std::vector<double> rhsX_, rhsY_;
    std::vector<double> limit_;  // per slot: the largest length its edges allow
};

// What one side's cover chain depends on: the builder (its map), the side, the knots along it,
// the fixed parameter and the inward offset of the other direction, and the fit's settings.
struct CoverKey {
    uint64_t builder = 0;
    int side = 0;
    std::vector<double> knots;
    double fixed = 0, inward = 0, cover = 0, slack = 0, tangentLimit = 0;
    int samples = 0;
    bool operator==(const CoverKey& o) const {
        return builder == o.builder && side == o.side && fixed == o.fixed && inward == o.inward &&
               cover == o.cover && slack == o.slack && tangentLimit == o.tangentLimit &&
               samples == o.samples && knots == o.knots;
    }
};

// The last few cover chains fitted on this thread. Refinement rebuilds the grid for every
// trial split, and a split along u leaves the left and right sides' chains as they were (one
// along v the top and bottom): those are not fitted again. Per thread, so that regions
// converted in parallel need no lock.
const CoverChain& cachedCoverChain(CoverKey key, const std::function<CoverChain()>& fit) {
    constexpr size_t kEntries = 16;
    thread_local std::deque<std::pair<CoverKey, CoverChain>> cache;
    for (auto it = cache.begin(); it != cache.end(); ++it)
        if (it->first == key) {
            if (it != cache.begin()) {
                auto entry = std::move(*it);
                cache.erase(it);
                cache.push_front(std::move(entry));
            }
            return cache.front().second;
        }
    CoverChain chain = fit();
    if (cache.size() >= kEntries) cache.pop_back();
    cache.emplace_front(std::move(key), std::move(chain));
    return cache.front().second;
}

}  // namespace

// The steps of GridBuilder::build: knots, slits, node positions, the rectangle's sides fitted
// one-sided, position derivatives by least squares along every grid line, then the sides
// blended back where they would fold a patch.
class GridAssembly {
public:
    GridAssembly(const GridBuilder::Impl& map, const GridOptions& options)
        : m_(map), options_(options) {}

    GradientMesh run() {
        chooseKnots(m_.map, options_, mesh_.u, mesh_.v);
        C_ = mesh_.columns();
        R_ = mesh_.rows();
        mesh_.nodes.assign(static_cast<size_t>(C_ + 1) * (R_ + 1), Node{});
        placeSlits();
        placeNodes();
        const int nSamples = std::max(2, options_.samplesPerEdge);
        tau_.resize(static_cast<size_t>(nSamples));
        for (int k = 0; k < nSamples; ++k) tau_[k] = (k + 1.0) / (nSamples + 1.0);
        std::vector<CoverChain> cover;
        if (options_.outlineCover >= 0)
            for (int side = 0; side < 4; ++side) cover.push_back(sideCover(side));
        layoutSlots();
        storeDerivatives(fitAlongRows(), fitAlongColumns());
        if (!cover.empty()) blendSidesWhereTheyFold(cover);
        if (options_.unfold) unfoldPatches(mesh_);
        return std::move(mesh_);
    }

private:
    // Slits onto knot indices; slitOfNode_ marks their interior nodes, slitRow_ their rows.
    void placeSlits() {
        slitOfNode_.assign(static_cast<size_t>(C_ + 1) * (R_ + 1), -1);
        for (const GridSlit& gs : options_.slits) {
            Slit s;
            s.row = nearestIndex(mesh_.v, gs.v);
            s.i0 = nearestIndex(mesh_.u, gs.u0);
            s.i1 = nearestIndex(mesh_.u, gs.u1);
            if (s.row <= 0 || s.row >= R_ || s.i0 <= 0 || s.i1 >= C_ || s.i1 <= s.i0)
                throw Error("grid: a slit does not lie on interior grid lines");
            for (const Slit& o : mesh_.slits)
                if (o.row == s.row && s.i0 <= o.i1 && o.i0 <= s.i1)
                    throw Error("grid: two slits touch on one row");
            s.below.resize(static_cast<size_t>(s.i1 - s.i0 - 1));
            for (int i = s.i0 + 1; i < s.i1; ++i)
                slitOfNode_[static_cast<size_t>(s.row) * (C_ + 1) + i] =
                    static_cast<int>(mesh_.slits.size());
            mesh_.slits.push_back(std::move(s));
        }
        slitRow_.assign(static_cast<size_t>(R_ + 1), 0);
        for (const Slit& s : mesh_.slits) slitRow_[s.row] = 1;
    }

    // The slit (if any) whose run [i0, i1] holds column i on row j, ends included.
    const Slit* slitAt(int i, int j) const {
        if (!slitRow_[j]) return nullptr;
        for (const Slit& s : mesh_.slits)
            if (s.row == j && i >= s.i0 && i <= s.i1) return &s;
        return nullptr;
    }

    // Node positions (nodes on a slit: the main copy from above, the below copy from below).
    void placeNodes() {
        for (int j = 0; j <= R_; ++j) {
            for (int i = 0; i <= C_; ++i) {
                const bool onSlit = slitAt(i, j) != nullptr;
                mesh_.node(i, j).pos = m_.position(mesh_.u[i], mesh_.v[j], onSlit ? -1 : 0);
            }
        }
        for (Slit& s : mesh_.slits)
            for (int i = s.i0 + 1; i < s.i1; ++i)
                s.below[static_cast<size_t>(i - s.i0 - 1)].pos =
                    m_.position(mesh_.u[i], mesh_.v[s.row], 1);
    }

    // One side of the rectangle fitted one-sided (its nodes may move outward): 0 top, 1 bottom
    // (derivatives along u), 2 left, 3 right (along v).
    CoverChain sideCover(int side) const {
        const bool alongU = side < 2;
        const int fixedIndex = side == 0 || side == 2 ? 0 : (alongU ? R_ : C_);
        const std::vector<double>& k = alongU ? mesh_.u : mesh_.v;
        const std::vector<double>& other = alongU ? mesh_.v : mesh_.u;
        const double fixed = other[fixedIndex];
        const double inward = fixedIndex == 0 ? 0.5 * (other[1] - other[0])
                                              : -0.5 * (other[fixedIndex] - other[fixedIndex - 1]);
        const int N = static_cast<int>(k.size()) - 1;
        auto fit = [&]() {
            std::vector<Vec2> P, inside;
            std::vector<double> delta;
            for (int a = 0; a <= N; ++a)
                P.push_back(alongU ? mesh_.node(a, fixedIndex).pos : mesh_.node(fixedIndex, a).pos);
            for (int a = 0; a < N; ++a) {
                delta.push_back(k[a + 1] - k[a]);
                const double mid = 0.5 * (k[a] + k[a + 1]);
                inside.push_back(alongU ? m_.position(mid, fixed + inward, 0)
                                        : m_.position(fixed + inward, mid, 0));
            }
            auto outlineAt = [&](int a, double t) {
                const double p = k[a] + t * (k[a + 1] - k[a]);
                return alongU ? m_.position(p, fixed, 0) : m_.position(fixed, p, 0);
            };
            return fitCoverChain(P, delta, outlineAt, inside, tau_, options_.outlineCover,
                                 options_.outlineSlack, options_.tangentLimit);
        };
        const int nSamples = static_cast<int>(tau_.size());
        return cachedCoverChain({m_.id, side, k, fixed, inward, options_.outlineCover,
                                 options_.outlineSlack, options_.tangentLimit, nSamples},
                                fit);
    }

    // Slot numbering of the derivative fits: nodes, then below copies; for u also the slit
    // ends' (left, right).
    void layoutSlots() {
        nNodes_ = (C_ + 1) * (R_ + 1);
        int nBelow = 0;
        for (const Slit& s : mesh_.slits) {
            belowBase_.push_back(nNodes_ + nBelow);
            nBelow += s.i1 - s.i0 - 1;
        }
        endBase_ = nNodes_ + nBelow;
        nSlotsU_ = endBase_ + 2 * static_cast<int>(mesh_.slits.size());
        nSlotsV_ = nNodes_ + nBelow;
    }

    int slitIndex(const Slit* s) const { return static_cast<int>(s - mesh_.slits.data()); }

    // Node copy used by a patch on side `below` of row j at column i: slot and position.
    int copySlot(int i, int j, bool below) const {
        const int sl = slitOfNode_[static_cast<size_t>(j) * (C_ + 1) + i];
        if (below && sl >= 0) return belowBase_[sl] + (i - mesh_.slits[sl].i0 - 1);
        return j * (C_ + 1) + i;
    }
    Vec2 copyPos(int i, int j, bool below) const {
        const int sl = slitOfNode_[static_cast<size_t>(j) * (C_ + 1) + i];
        if (below && sl >= 0) return mesh_.slits[sl].below[i - mesh_.slits[sl].i0 - 1].pos;
        return mesh_.node(i, j).pos;
    }

    // u: the patch edges along each row. On a slit run there are two edges (above, below).
    std::vector<Vec2> fitAlongRows() const {
        std::vector<Vec2> q(tau_.size());
        DerivativeFit fitU(nSlotsU_, options_.tangentLimit);
        for (int j = 0; j <= R_; ++j) {
            for (int i = 0; i < C_; ++i) {
                const double du = mesh_.u[i + 1] - mesh_.u[i];
                const Slit* run = nullptr;
                if (slitRow_[j])
                    for (const Slit& s : mesh_.slits)
                        if (s.row == j && i >= s.i0 && i < s.i1) run = &s;
                for (int pass = 0; pass < (run ? 2 : 1); ++pass) {
                    const bool below = pass == 1;
                    const int side = run ? (below ? 1 : -1) : 0;
                    for (size_t k = 0; k < tau_.size(); ++k)
                        q[k] = m_.position(mesh_.u[i] + tau_[k] * du, mesh_.v[j], side);
                    int slotA = copySlot(i, j, below), slotB = copySlot(i + 1, j, below);
                    const double sign = below ? -1.0 : 1.0;
                    double signA = 1, signB = 1;
                    if (run && i == run->i0) {
                        slotA = endBase_ + 2 * slitIndex(run);
                        signA = sign;
                    }
                    if (run && i + 1 == run->i1) {
                        slotB = endBase_ + 2 * slitIndex(run) + 1;
                        signB = sign;
                    }
                    fitU.addEdge(slotA, signA, slotB, signB, du, copyPos(i, j, below),
                                 copyPos(i + 1, j, below), tau_, q);
                }
            }
        }
        return fitU.solve();
    }

    // v: the patch edges along each column; an edge leaving a slit row downward starts at the
    // below copy.
    std::vector<Vec2> fitAlongColumns() const {
        std::vector<Vec2> q(tau_.size());
        DerivativeFit fitV(nSlotsV_, options_.tangentLimit);
        for (int i = 0; i <= C_; ++i) {
            for (int j = 0; j < R_; ++j) {
                const double dv = mesh_.v[j + 1] - mesh_.v[j];
                for (size_t k = 0; k < tau_.size(); ++k)
                    q[k] = m_.position(mesh_.u[i], mesh_.v[j] + tau_[k] * dv, 0);
                fitV.addEdge(copySlot(i, j, true), 1, copySlot(i, j + 1, false), 1, dv,
                             copyPos(i, j, true), copyPos(i, j + 1, false), tau_, q);
            }
        }
        return fitV.solve();
    }

    void storeDerivatives(const std::vector<Vec2>& dU, const std::vector<Vec2>& dV) {
        for (int k = 0; k < nNodes_; ++k) {
            mesh_.nodes[k].posU = dU[k];
            mesh_.nodes[k].posV = dV[k];
        }
        for (size_t s = 0; s < mesh_.slits.size(); ++s) {
            Slit& sl = mesh_.slits[s];
            for (size_t k = 0; k < sl.below.size(); ++k) {
                sl.below[k].posU = dU[belowBase_[s] + k];
                sl.below[k].posV = dV[belowBase_[s] + k];
            }
            sl.left.posU = dU[endBase_ + 2 * s];
            sl.right.posU = dU[endBase_ + 2 * s + 1];
        }
    }

    // The sides' nodes, each blended between the plain fit (0) and the one-sided one (1): by
    // `all` when it is not negative, else by its own mix.
    void applySideMix(const std::vector<CoverChain>& cover,
                      const std::vector<std::vector<double>>& mix, double all) {
        for (int side = 0; side < 4; ++side) {
            const bool alongU = side < 2;
            const int fixedIndex = side == 0 || side == 2 ? 0 : (alongU ? R_ : C_);
            const CoverChain& cc = cover[side];
            for (size_t a = 0; a < cc.pos.size(); ++a) {
                const double f = all >= 0 ? all : mix[side][a];
                const int ia = static_cast<int>(a);
                Node& nd = alongU ? mesh_.node(ia, fixedIndex) : mesh_.node(fixedIndex, ia);
                nd.pos = cc.plainPos[a] + f * (cc.pos[a] - cc.plainPos[a]);
                (alongU ? nd.posU : nd.posV) =
                    cc.plainDerivative[a] + f * (cc.derivative[a] - cc.plainDerivative[a]);
            }
        }
    }

    bool patchFolds(int i, int j) const {
        const PatchHermite h = patchHermite(mesh_, i, j);
        for (int n : {6, 8})
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    const PatchPoint p = evaluatePatch(h, (a + 0.5) / n, (b + 0.5) / n);
                    if (cross(p.posS, p.posT) <= 0) return true;
                }
        return false;
    }

    // An edge between nodes blended unequally may stray past its bound: both ends back to the
    // plain fit. True when any was.
    bool unblendStrayEdges(const std::vector<CoverChain>& cover, std::vector<std::vector<double>>& mix) const {
        bool any = false;
        for (int side = 0; side < 4; ++side) {
            const CoverChain& cc = cover[side];
            auto node = [&](int a) -> const Node& {
                return side < 2 ? mesh_.node(a, side == 0 ? 0 : R_) : mesh_.node(side == 2 ? 0 : C_, a);
            };
            for (size_t k = 0; k < cc.delta.size(); ++k) {
                const int a = static_cast<int>(k);
                if (mix[side][k] == mix[side][k + 1] && (mix[side][k] == 0 || mix[side][k] == 1))
                    continue;  // the plain or the one-sided edge: within its bound
                const Node &na = node(a), &nb = node(a + 1);
                const Vec2 da = side < 2 ? na.posU : na.posV, db = side < 2 ? nb.posU : nb.posV;
                if (cc.deviation(a, na.pos, da, nb.pos, db) > cc.bound[k] + 1e-3) {
                    mix[side][k] = mix[side][k + 1] = 0;
                    any = true;
                }
            }
        }
        return any;
    }

    // A patch along a side that folds where the plain fit's does not (the side's derivatives
    // turned too far from the grid lines crossing it) gets its side's nodes blended back toward
    // the plain fit until it does not.
    void blendSidesWhereTheyFold(const std::vector<CoverChain>& cover) {
        std::vector<std::vector<double>> mix(4);
        for (int side = 0; side < 4; ++side) mix[side].assign(cover[side].pos.size(), 1.0);
        struct SidePatch {
            int side, a, i, j;  // side, index along it, the patch
        };
        std::vector<SidePatch> along;
        for (int i = 0; i < C_; ++i) along.push_back({0, i, i, 0}), along.push_back({1, i, i, R_ - 1});
        for (int j = 0; j < R_; ++j) along.push_back({2, j, 0, j}), along.push_back({3, j, C_ - 1, j});
        applySideMix(cover, mix, 0.0);
        std::vector<uint8_t> plainFolds(along.size());
        for (size_t p = 0; p < along.size(); ++p) plainFolds[p] = patchFolds(along[p].i, along[p].j);
        bool settled = false;
        for (int pass = 0; pass < 12 && !settled; ++pass) {
            applySideMix(cover, mix, -1);
            settled = true;
            for (size_t p = 0; p < along.size(); ++p) {
                if (plainFolds[p] || !patchFolds(along[p].i, along[p].j)) continue;
                const double f = pass < 6 ? 0.5 : 0.0;
                mix[along[p].side][along[p].a] *= f;
                mix[along[p].side][along[p].a + 1] *= f;
                settled = false;
            }
            if (unblendStrayEdges(cover, mix)) settled = false;
        }
        if (!settled) applySideMix(cover, mix, 0.0);
    }

    const GridBuilder::Impl& m_;
    const GridOptions& options_;
    GradientMesh mesh_;
    int C_ = 0, R_ = 0;
    std::vector<int> slitOfNode_;  // per node: the slit it is inside of, or -1
    std::vector<uint8_t> slitRow_;  // per row: it holds a slit
    std::vector<double> tau_;       // sample parameters along every edge
    std::vector<int> belowBase_;    // per slit: the slot of its first below copy
    int nNodes_ = 0, endBase_ = 0, nSlotsU_ = 0, nSlotsV_ = 0;
};

GradientMesh GridBuilder::build(const GridOptions& options) const {
    return GridAssembly(*impl_, options).run();
}

GradientMesh buildGrid(const TriMesh& mesh, const ParamMap& map, const GridOptions& options) {
    return GridBuilder(mesh, map).build(options);
}

}  // namespace gm
