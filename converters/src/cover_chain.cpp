#include "cover_chain.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "meshcore/evaluate.h"

namespace gm {

double CoverChain::deviation(int k, Vec2 a, Vec2 da, Vec2 b, Vec2 db) const {
    std::vector<Vec2> c;
    for (int r = 0; r <= steps[k]; ++r) {
        double h[4];
        hermiteBasis(double(r) / steps[k], h);
        c.push_back(h[0] * a + h[1] * b + (delta[k] * h[2]) * da + (delta[k] * h[3]) * db);
    }
    return std::max(directedPolylineDistance(c, outline[k]).first,
                    directedPolylineDistance(outline[k], c).first);
}

namespace {

// Penalty weights (a least-squares sample weighs 1), the target of a covered point (half the
// cover inside the curve) and of a bounded one (a little within its bound), and how far past
// its target a penalised point must get before its penalty is dropped.
constexpr double kPenalty = 50.0, kBoundPenalty = 2000.0, kWithin = 0.85, kHysteresis = 0.25;
constexpr double kOffsetWeight = 1.0;  // an offset of 1 px costs as much as one sample 1 px off
constexpr int kRounds = 12;

// One round's normal equations over the 3(N+1) unknowns (D_k.x, D_k.y, s_k per node).
struct ChainSystem {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rhs;
};

class CoverChainFit {
public:
    CoverChainFit(const std::vector<Vec2>& P, const std::vector<double>& delta,
                  const std::function<Vec2(int, double)>& outline, const std::vector<Vec2>& inside,
                  const std::vector<double>& tau, double cover, double slack, double tangentLimit)
        : P_(P), delta_(delta), tau_(tau), N_(static_cast<int>(delta.size())), n_(3 * (N_ + 1)),
          cover_(cover), slack_(slack), tangentLimit_(tangentLimit) {
        orientNormals(inside);
        sampleEdges(outline);
        x_.assign(static_cast<size_t>(n_), 0.0);
        coverOn_.resize(static_cast<size_t>(N_));
        valleyOn_.resize(static_cast<size_t>(N_));
        bulgeOn_.resize(static_cast<size_t>(N_));
        longOn_.assign(static_cast<size_t>(N_ + 1), 0);
        for (int k = 0; k < N_; ++k) {
            coverOn_[k].assign(line_[k].size(), 0);
            valleyOn_[k].assign(line_[k].size(), 0);
            bulgeOn_[k].assign(static_cast<size_t>(curveSteps_[k]) + 1, 0);
        }
    }

    CoverChain run() {
        for (int round = 0; round < kRounds; ++round) {
            ChainSystem sys{{}, Eigen::VectorXd::Zero(n_)};
            addLeastSquares(sys, round);
            if (round > 0) {
                if (round == 1) fixPlainFit();
                bool any = false;
                for (int k = 0; k < N_; ++k) {  // in this order: the triplets' sums depend on it
                    if (addOutlinePenalties(sys, k)) any = true;
                    if (addBulgePenalties(sys, k)) any = true;
                }
                if (addTangentPenalties(sys)) any = true;
                if (!any) break;
            }
            if (!solve(sys)) {
                if (!plain_.empty()) x_ = plain_;
                break;
            }
        }
        if (plain_.empty()) plain_ = x_;  // the plain fit failed: nothing to blend back to
        return result(blendTowardPlain());
    }

private:
    static Vec2 perp(Vec2 t) { return Vec2{t.y, -t.x}; }

    // Which perpendicular points out of the region: the majority over the edges.
    void orientNormals(const std::vector<Vec2>& inside) {
        double vote = 0;
        for (int k = 0; k < N_; ++k)
            vote += dot(perp(P_[k + 1] - P_[k]), inside[k] - 0.5 * (P_[k] + P_[k + 1])) > 0 ? 1 : -1;
        sgn_ = vote > 0 ? -1.0 : 1.0;
        nu_.assign(static_cast<size_t>(N_ + 1), Vec2{});
        for (int k = 1; k < N_; ++k) nu_[k] = outward(P_[k + 1] - P_[k - 1]);
    }

    Vec2 outward(Vec2 t) const {
        const double len = norm(t);
        return len > 1e-12 ? (sgn_ / len) * perp(t) : Vec2{};
    }

    // Per edge: least-squares samples, dense outline points (the penalties' and the deviation
    // measure's; as boundary.cpp measures it: the curve at `curveSteps` points, the outline at
    // four times as many).
    void sampleEdges(const std::function<Vec2(int, double)>& outline) {
        q_.resize(static_cast<size_t>(N_));
        line_.resize(static_cast<size_t>(N_));
        curveSteps_.resize(static_cast<size_t>(N_));
        for (int k = 0; k < N_; ++k) {
            for (double t : tau_) q_[k].push_back(outline(k, t));
            const double chord = norm(P_[k + 1] - P_[k]);
            curveSteps_[k] = std::clamp(static_cast<int>(std::ceil(chord / 1.5)), 8, 64);
            const int M = 4 * curveSteps_[k];
            for (int m = 0; m <= M; ++m)
                line_[k].push_back(m == 0 ? P_[k] : m == M ? P_[k + 1] : outline(k, double(m) / M));
        }
    }

    Vec2 nodePos(const std::vector<double>& v, int k) const { return P_[k] + v[3 * k + 2] * nu_[k]; }
    static Vec2 nodeDer(const std::vector<double>& v, int k) { return Vec2{v[3 * k], v[3 * k + 1]}; }

    // Edge k of the chain v at t, and its derivative in *d1 when d1 is not null.
    Vec2 curve(const std::vector<double>& v, int k, double t, Vec2* d1) const {
        double h[4], dh[4];
        hermiteBasis(t, h);
        const Vec2 a = nodePos(v, k), b = nodePos(v, k + 1), da = nodeDer(v, k), db = nodeDer(v, k + 1);
        if (d1) {
            hermiteBasisDerivative(t, dh);
            *d1 = dh[0] * a + dh[1] * b + (delta_[k] * dh[2]) * da + (delta_[k] * dh[3]) * db;
        }
        return h[0] * a + h[1] * b + (delta_[k] * h[2]) * da + (delta_[k] * h[3]) * db;
    }

    // The largest length node k's derivative may have (INFINITY when there is no limit).
    double derivativeCap(const std::vector<double>& v, int k) const {
        double cap = INFINITY;
        if (k > 0) cap = std::min(cap, tangentLimit_ * norm(nodePos(v, k) - nodePos(v, k - 1)) / delta_[k - 1]);
        if (k < N_) cap = std::min(cap, tangentLimit_ * norm(nodePos(v, k + 1) - nodePos(v, k)) / delta_[k]);
        return cap;
    }

    // The tangent limit of DerivativeFit, applied to the derivatives of v.
    std::vector<double> limited(std::vector<double> v) const {
        if (tangentLimit_ <= 0) return v;
        for (int k = 0; k <= N_; ++k) {
            const double cap = derivativeCap(v, k);
            const double len = norm(nodeDer(v, k));
            if (len > cap) v[3 * k] *= cap / len, v[3 * k + 1] *= cap / len;
        }
        return v;
    }

    double deviation(const std::vector<double>& v, int k) const {
        std::vector<Vec2> c;
        for (int r = 0; r <= curveSteps_[k]; ++r) c.push_back(curve(v, k, double(r) / curveSteps_[k], nullptr));
        return std::max(directedPolylineDistance(c, line_[k]).first,
                        directedPolylineDistance(line_[k], c).first);
    }

    // Adds w·(a·c_k(t) − value)² (a linear function of edge k's six unknowns).
    void addRow(ChainSystem& sys, int k, double t, Vec2 a, double w, double value) const {
        double h[4];
        hermiteBasis(t, h);
        const int idx[6] = {3 * k, 3 * k + 1, 3 * k + 2, 3 * k + 3, 3 * k + 4, 3 * k + 5};
        const double g[6] = {a.x * h[2] * delta_[k], a.y * h[2] * delta_[k], h[0] * dot(a, nu_[k]),
                             a.x * h[3] * delta_[k], a.y * h[3] * delta_[k], h[1] * dot(a, nu_[k + 1])};
        const double rest = value - h[0] * dot(a, P_[k]) - h[1] * dot(a, P_[k + 1]);
        for (int r = 0; r < 6; ++r) {
            if (g[r] == 0) continue;
            sys.rhs[idx[r]] += w * g[r] * rest;
            for (int c = 0; c < 6; ++c)
                if (g[c] != 0) sys.trip.emplace_back(idx[r], idx[c], w * g[r] * g[c]);
        }
    }

    // The plain fit's terms: the outline samples, a slight pull of each derivative toward its
    // edge's chord, and the offsets held (at 0 in round 0 and at the corners; softly after).
    void addLeastSquares(ChainSystem& sys, int round) const {
        for (int k = 0; k < N_; ++k) {
            for (size_t s = 0; s < tau_.size(); ++s) {
                addRow(sys, k, tau_[s], {1, 0}, 1.0, q_[k][s].x);
                addRow(sys, k, tau_[s], {0, 1}, 1.0, q_[k][s].y);
            }
            const double w = 1e-4 * delta_[k] * delta_[k];
            const Vec2 chord = (1.0 / delta_[k]) * (P_[k + 1] - P_[k]);
            for (int e : {3 * k, 3 * k + 3}) {
                sys.trip.emplace_back(e, e, w);
                sys.trip.emplace_back(e + 1, e + 1, w);
                sys.rhs[e] += w * chord.x;
                sys.rhs[e + 1] += w * chord.y;
            }
        }
        for (int k = 0; k <= N_; ++k)
            sys.trip.emplace_back(3 * k + 2, 3 * k + 2,
                                  k == 0 || k == N_ || round == 0 ? 1e12 : kOffsetWeight);
    }

    // After round 0: the plain fit and each edge's deviation bound.
    void fixPlainFit() {
        plain_ = x_;
        const std::vector<double> plainLimited = limited(plain_);
        for (int k = 0; k < N_; ++k) bound_.push_back(std::max(slack_, deviation(plainLimited, k)));
    }

    // Outline points of edge k against the curve's nearest point (Gauss–Newton from the point's
    // own parameter): too far outside it (cover) or inside it (valley). True when any is added.
    bool addOutlinePenalties(ChainSystem& sys, int k) {
        bool any = false;
        const double target = 0.5 * cover_;
        const int M = static_cast<int>(line_[k].size()) - 1;
        for (int m = 0; m <= M; ++m) {
            const Vec2 o = line_[k][m];
            double t = double(m) / M;
            Vec2 d1;
            for (int it = 0; it < 4; ++it) {
                const Vec2 c = curve(x_, k, t, &d1);
                const double dd = dot(d1, d1);
                if (dd < 1e-18) break;
                t = std::clamp(t - dot(c - o, d1) / dd, 0.0, 1.0);
            }
            const Vec2 c = curve(x_, k, t, &d1);
            const Vec2 nrm = outward(d1);
            if (nrm.x == 0 && nrm.y == 0) continue;
            const double out = dot(nrm, o - c), dist = norm(o - c);
            if (out > cover_) coverOn_[k][m] = 1;
            if (out < 0 && dist > bound_[k]) valleyOn_[k][m] = 1;
            if (coverOn_[k][m] && out > target - kHysteresis) {
                addRow(sys, k, t, nrm, kPenalty, dot(nrm, o) - target);
                any = true;
            } else if (valleyOn_[k][m] && out < 0 && dist > kWithin * bound_[k] - kHysteresis) {
                const Vec2 dir = (1.0 / dist) * (c - o);
                addRow(sys, k, t, dir, kBoundPenalty, dot(dir, o) + kWithin * bound_[k]);
                any = true;
            }
        }
        return any;
    }

    // Curve points of edge k too far outside the outline (bulge). True when any is added.
    bool addBulgePenalties(ChainSystem& sys, int k) {
        bool any = false;
        for (int r = 0; r <= curveSteps_[k]; ++r) {
            const double t = double(r) / curveSteps_[k];
            Vec2 d1;
            const Vec2 c = curve(x_, k, t, &d1);
            const Vec2 nrm = outward(d1);
            // The nearest outline point, searched within a quarter of the edge of the point at
            // the same parameter.
            Vec2 nearest = line_[k][0];
            double best = INFINITY;
            const int M = static_cast<int>(line_[k].size()) - 1, at = 4 * r;
            const int from = std::max(0, at - M / 4), to = std::min(M, at + M / 4);
            for (int s = from; s < to; ++s) {
                const Vec2 a = line_[k][s], b = line_[k][s + 1];
                const Vec2 p = a + closestSegmentParameter(c, a, b) * (b - a);
                if (norm(p - c) < best) best = norm(p - c), nearest = p;
            }
            if (dot(nrm, c - nearest) <= 0 || best < 1e-9) continue;
            if (best > bound_[k]) bulgeOn_[k][r] = 1;
            if (!bulgeOn_[k][r] || best < kWithin * bound_[k] - kHysteresis) continue;
            const Vec2 dir = (1.0 / best) * (c - nearest);
            addRow(sys, k, t, dir, kBoundPenalty, dot(dir, nearest) + kWithin * bound_[k]);
            any = true;
        }
        return any;
    }

    // The tangent limit, as a penalty on each too long derivative's length.
    bool addTangentPenalties(ChainSystem& sys) {
        if (tangentLimit_ <= 0) return false;
        bool any = false;
        for (int k = 0; k <= N_; ++k) {
            double scale = 0;
            if (k > 0) scale = std::max(scale, delta_[k - 1]);
            if (k < N_) scale = std::max(scale, delta_[k]);
            const double cap = derivativeCap(x_, k);
            const Vec2 d = nodeDer(x_, k);
            const double len = norm(d);
            if (len > cap) longOn_[k] = 1;
            if (!longOn_[k] || len < 0.98 * cap - kHysteresis / scale || len < 1e-12) continue;
            const Vec2 u = (1.0 / len) * d;
            const double w = kBoundPenalty * scale * scale;
            sys.trip.emplace_back(3 * k, 3 * k, w * u.x * u.x);
            sys.trip.emplace_back(3 * k, 3 * k + 1, w * u.x * u.y);
            sys.trip.emplace_back(3 * k + 1, 3 * k, w * u.x * u.y);
            sys.trip.emplace_back(3 * k + 1, 3 * k + 1, w * u.y * u.y);
            sys.rhs[3 * k] += w * u.x * 0.98 * cap;
            sys.rhs[3 * k + 1] += w * u.y * 0.98 * cap;
            any = true;
        }
        return any;
    }

    // Solves the round's system into x_; false when the factorisation fails.
    bool solve(const ChainSystem& sys) {
        Eigen::SparseMatrix<double> A(n_, n_);
        A.setFromTriplets(sys.trip.begin(), sys.trip.end());
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
        if (ldlt.info() != Eigen::Success) return false;
        const Eigen::VectorXd sol = ldlt.solve(sys.rhs);
        for (int k = 0; k < n_; ++k) x_[k] = sol[k];
        return true;
    }

    // Nodes blended back toward the plain fit wherever an edge strays past its bound: halving
    // a few times, then all the way (an edge between two plain nodes is within its bound).
    std::vector<double> blendTowardPlain() const {
        std::vector<double> lambda(static_cast<size_t>(N_ + 1), 1.0), v;
        for (int pass = 0;; ++pass) {
            v = x_;
            for (int k = 0; k <= N_; ++k)
                for (int c = 0; c < 3; ++c)
                    v[3 * k + c] = plain_[3 * k + c] + lambda[k] * (x_[3 * k + c] - plain_[3 * k + c]);
            v = limited(v);
            if (bound_.empty()) break;
            bool ok = true;
            for (int k = 0; k < N_; ++k)
                if ((lambda[k] > 0 || lambda[k + 1] > 0) && deviation(v, k) > bound_[k] + 1e-3) {
                    const double f = pass < 6 ? 0.5 : 0.0;
                    lambda[k] *= f;
                    lambda[k + 1] *= f;
                    ok = false;
                }
            if (ok) break;
        }
        return v;
    }

    CoverChain result(const std::vector<double>& v) const {
        CoverChain result;
        const std::vector<double> plainLimited = limited(plain_);
        for (int k = 0; k <= N_; ++k) {
            result.pos.push_back(k == 0 || k == N_ ? P_[k] : nodePos(v, k));
            result.derivative.push_back(nodeDer(v, k));
            result.plainPos.push_back(P_[k]);
            result.plainDerivative.push_back(nodeDer(plainLimited, k));
        }
        result.delta = delta_;
        result.outline = line_;
        result.steps = curveSteps_;
        result.bound = bound_;
        if (result.bound.empty())
            for (int k = 0; k < N_; ++k)
                result.bound.push_back(std::max(slack_, deviation(plainLimited, k)));
        return result;
    }

    const std::vector<Vec2>& P_;
    const std::vector<double>& delta_;
    const std::vector<double>& tau_;
    const int N_, n_;
    const double cover_, slack_, tangentLimit_;
    double sgn_ = 1;
    std::vector<Vec2> nu_;                           // per node: the outward normal
    std::vector<std::vector<Vec2>> q_, line_;        // per edge: samples, dense outline
    std::vector<int> curveSteps_;                    // per edge: the deviation's curve samples
    std::vector<double> x_, plain_, bound_;          // the unknowns, the plain fit, the bounds
    // Penalties once switched on stay on (with hysteresis) until the point is past its target.
    std::vector<std::vector<uint8_t>> coverOn_, valleyOn_, bulgeOn_;
    std::vector<uint8_t> longOn_;
};

}  // namespace

CoverChain fitCoverChain(const std::vector<Vec2>& P, const std::vector<double>& delta,
                         const std::function<Vec2(int, double)>& outline,
                         const std::vector<Vec2>& inside, const std::vector<double>& tau,
                         double cover, double slack, double tangentLimit) {
    return CoverChainFit(P, delta, outline, inside, tau, cover, slack, tangentLimit).run();
}

}  // namespace gm
