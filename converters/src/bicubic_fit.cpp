// Gauss–Newton colour fit through the bicubic rule; see bicubic_fit.h.
#include "bicubic_fit.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "meshcore/bicubic_colors.h"
#include "meshcore/evaluate.h"

namespace gm {
namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Rhs12 = Eigen::Matrix<double, 12, 3>;

// One patch's normal equations in its 12 local unknowns, shared by the channels: corner
// values, s-slopes, t-slopes, each in corner order k = 2a + b.
struct PatchNormals {
    int i = 0, j = 0;
    Mat12 M = Mat12::Zero();
    Rhs12 B = Rhs12::Zero();
};

std::vector<PatchNormals> patchNormals(const GradientMesh& mesh, const RgbaImage& image,
                                       const Region& region,
                                       const std::vector<PixelSample>& samples, int meshIndex) {
    const int C = mesh.columns();
    std::vector<int> slot(static_cast<size_t>(mesh.patchCount()), -1);
    std::vector<PatchNormals> out;
    for (size_t p = 0; p < samples.size(); ++p) {
        const PixelSample& ps = samples[p];
        if (!region.mask[p] || ps.mesh != meshIndex || ps.patch < 0) continue;
        int& k = slot[static_cast<size_t>(ps.patch)];
        if (k < 0) {
            k = static_cast<int>(out.size());
            out.emplace_back();
            out.back().i = ps.patch % C;
            out.back().j = ps.patch / C;
        }
        double hs[4], ht[4];
        hermiteBasis(ps.s, hs);
        hermiteBasis(ps.t, ht);
        Eigen::Matrix<double, 12, 1> c;
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) {
                c(2 * a + b) = hs[a] * ht[b];
                c(4 + 2 * a + b) = hs[2 + a] * ht[b];
                c(8 + 2 * a + b) = hs[a] * ht[2 + b];
            }
        const float* col = image.at(static_cast<int>(p % image.width),
                                    static_cast<int>(p / image.width));
        PatchNormals& n = out[static_cast<size_t>(k)];
        n.M.selfadjointView<Eigen::Upper>().rankUpdate(c);
        for (int ch = 0; ch < 3; ++ch) n.B.col(ch) += c * static_cast<double>(col[ch]);
    }
    for (PatchNormals& n : out) n.M = n.M.selfadjointView<Eigen::Upper>();
    return out;
}

// The 12 local unknowns of a patch as a linear map T of the node-copy colours of one channel:
// row r of T is Σ weight · e_copy; `copies` lists the columns used.
struct LocalMap {
    std::vector<int> copies;
    Eigen::Matrix<double, 12, Eigen::Dynamic> T;
};

int columnOf(LocalMap& m, int copy) {
    for (size_t k = 0; k < m.copies.size(); ++k)
        if (m.copies[k] == copy) return static_cast<int>(k);
    m.copies.push_back(copy);
    m.T.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(m.copies.size()));
    m.T.col(m.T.cols() - 1).setZero();
    return static_cast<int>(m.copies.size()) - 1;
}

LocalMap localMap(const PatchColorRule& rule, int ch) {
    LocalMap m;
    m.copies.reserve(16);
    m.T.resize(12, 0);
    auto addForm = [&](int row, const RuleSlope& f) {
        for (int k = 0; k < f.count; ++k) m.T(row, columnOf(m, f.copy[k])) += f.weight[k];
    };
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            const int k = 2 * a + b;
            m.T(k, columnOf(m, rule.copy[a][b])) += 1.0;
            addForm(4 + k, rule.s[ch][a][b]);
            addForm(8 + k, rule.t[ch][a][b]);
        }
    return m;
}

// Calls visit(node) for every node copy in the rule's numbering: the nodes, then every slit's
// `below` copies. `Mesh` is GradientMesh, const or not.
template <class Mesh, class Visit>
void forEachNodeCopy(Mesh& mesh, Visit visit) {
    for (auto& node : mesh.nodes) visit(node);
    for (auto& slit : mesh.slits)
        for (auto& node : slit.below) visit(node);
}

// The node-copy colours, one row each, and back.
Eigen::MatrixXd copyColors(const GradientMesh& mesh) {
    size_t n = 0;
    forEachNodeCopy(mesh, [&](const Node&) { ++n; });
    Eigen::MatrixXd c(static_cast<Eigen::Index>(n), 3);
    Eigen::Index k = 0;
    forEachNodeCopy(mesh, [&](const Node& node) {
        for (int ch = 0; ch < 3; ++ch) c(k, ch) = node.col[ch];
        ++k;
    });
    return c;
}

void setCopyColors(GradientMesh& mesh, const Eigen::MatrixXd& c) {
    Eigen::Index k = 0;
    forEachNodeCopy(mesh, [&](Node& node) {
        node.col = {c(k, 0), c(k, 1), c(k, 2)};
        ++k;
    });
}

std::vector<Vec2> copyPositions(const GradientMesh& mesh) {
    std::vector<Vec2> out;
    forEachNodeCopy(mesh, [&](const Node& node) { out.push_back(node.pos); });
    return out;
}

// Inkscape's (cairo's) mesh rasteriser takes a pixel's colour from a point that may lie anywhere
// in the pixel, not at its centre, so a colour that changes within a pixel is drawn differently
// from our render by about that change. A thin row of patches along a region's outline can pack
// a steep colour step into a sliver; pulling the ends of each edge shorter than a pixel toward
// one colour (by `pull` times 1 − its length) spreads the step over wider patches.
struct ShortEdge {
    int a = 0, b = 0;  // node copies
    double weight = 0;
};

std::vector<ShortEdge> subPixelEdges(const GradientMesh& mesh, double pull) {
    std::vector<ShortEdge> out;
    if (pull <= 0) return out;
    const std::vector<Vec2> pos = copyPositions(mesh);
    std::set<std::pair<int, int>> seen;
    for (int j = 0; j < mesh.rows(); ++j)
        for (int i = 0; i < mesh.columns(); ++i) {
            const PatchColorRule r = bicubicPatchRule(mesh, i, j);
            const int sides[4][2] = {{r.copy[0][0], r.copy[1][0]}, {r.copy[0][1], r.copy[1][1]},
                                     {r.copy[0][0], r.copy[0][1]}, {r.copy[1][0], r.copy[1][1]}};
            for (const auto& side : sides) {
                const int a = std::min(side[0], side[1]), b = std::max(side[0], side[1]);
                if (a == b || !seen.insert({a, b}).second) continue;
                const double length = norm(pos[static_cast<size_t>(a)] - pos[static_cast<size_t>(b)]);
                if (length < 1.0) out.push_back({a, b, pull * (1.0 - length)});
            }
        }
    return out;
}

// The normal-equation terms of the edges' pulls: weight · (c_a − c_b)² each.
Eigen::SparseMatrix<double> edgePulls(const std::vector<ShortEdge>& edges, Eigen::Index n,
                                      double pixelWeight) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(edges.size() * 4);
    for (const ShortEdge& e : edges) {
        const double w = e.weight * pixelWeight;
        entries.emplace_back(e.a, e.a, w);
        entries.emplace_back(e.b, e.b, w);
        entries.emplace_back(e.a, e.b, -w);
        entries.emplace_back(e.b, e.a, -w);
    }
    Eigen::SparseMatrix<double> S(n, n);
    S.setFromTriplets(entries.begin(), entries.end());
    return S;
}

std::vector<PatchColorRule> rulesOf(const GradientMesh& mesh,
                                    const std::vector<PatchNormals>& normals) {
    std::vector<PatchColorRule> rules;
    rules.reserve(normals.size());
    for (const PatchNormals& n : normals) rules.push_back(bicubicPatchRule(mesh, n.i, n.j));
    return rules;
}

// The fit's true cost at colours c (rules taken at c), up to the constant Σ target².
double cost(const std::vector<PatchNormals>& normals, const std::vector<PatchColorRule>& rules,
            const Eigen::MatrixXd& c, const Eigen::MatrixXd& c0, const Eigen::Vector3d& lambda,
            const std::vector<ShortEdge>& edges, const Eigen::Vector3d& pixelWeight) {
    double f = 0;
    for (const ShortEdge& e : edges)
        for (int ch = 0; ch < 3; ++ch)
            f += e.weight * pixelWeight(ch) * std::pow(c(e.a, ch) - c(e.b, ch), 2);
    for (size_t p = 0; p < normals.size(); ++p)
        for (int ch = 0; ch < 3; ++ch) {
            const LocalMap m = localMap(rules[p], ch);
            Eigen::VectorXd x(m.copies.size());
            for (size_t k = 0; k < m.copies.size(); ++k) x(k) = c(m.copies[k], ch);
            const Eigen::Matrix<double, 12, 1> y = m.T * x;
            f += y.dot(normals[p].M * y) - 2 * y.dot(normals[p].B.col(ch));
        }
    for (int ch = 0; ch < 3; ++ch) f += lambda(ch) * (c.col(ch) - c0.col(ch)).squaredNorm();
    return f;
}

// One Gauss–Newton step per channel at the rules' branches: the least-squares colours of the
// linearised problem with the edges' pulls, or false when a solve fails. `pixelWeight` returns
// the mean diagonal of the pixels' normal equations per channel, the unit of every pull.
// `held` (optional, per copy and channel): colours held at their value in c0 by a pull far
// stronger than any pixel's.
bool solveLinearised(const std::vector<PatchNormals>& normals,
                     const std::vector<PatchColorRule>& rules, const Eigen::MatrixXd& c0,
                     double regularization, Eigen::MatrixXd& c, Eigen::Vector3d& lambda,
                     const std::vector<ShortEdge>& edges, Eigen::Vector3d& pixelWeight,
                     const Eigen::MatrixXd* held = nullptr) {
    const Eigen::Index n = c0.rows();
    for (int ch = 0; ch < 3; ++ch) {
        std::vector<Eigen::Triplet<double>> entries;
        entries.reserve(normals.size() * 256);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
        for (size_t p = 0; p < normals.size(); ++p) {
            const LocalMap m = localMap(rules[p], ch);
            const Eigen::MatrixXd K = m.T.transpose() * normals[p].M * m.T;
            const Eigen::VectorXd r = m.T.transpose() * normals[p].B.col(ch);
            for (size_t a = 0; a < m.copies.size(); ++a) {
                rhs(m.copies[a]) += r(a);
                for (size_t b = 0; b < m.copies.size(); ++b)
                    entries.emplace_back(m.copies[a], m.copies[b], K(a, b));
            }
        }
        Eigen::SparseMatrix<double> A(n, n);
        A.setFromTriplets(entries.begin(), entries.end());
        double sum = 0;
        int used = 0;
        for (Eigen::Index k = 0; k < n; ++k)
            if (const double d = A.coeff(k, k); d > 0) {
                sum += d;
                ++used;
            }
        lambda(ch) = std::max(regularization, 1e-12) * (used > 0 ? sum / used : 1.0);
        pixelWeight(ch) = used > 0 ? sum / used : 1.0;
        if (!edges.empty()) A += edgePulls(edges, n, pixelWeight(ch));
        Eigen::VectorXd pull = Eigen::VectorXd::Constant(n, lambda(ch));
        if (held) pull += (1e6 * (sum / std::max(used, 1))) * held->col(ch);
        Eigen::SparseMatrix<double> P(n, n);
        std::vector<Eigen::Triplet<double>> diagonal;
        for (Eigen::Index k = 0; k < n; ++k) diagonal.emplace_back(k, k, pull(k));
        P.setFromTriplets(diagonal.begin(), diagonal.end());
        A += P;
        rhs += pull.cwiseProduct(c0.col(ch));
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
        if (ldlt.info() != Eigen::Success) return false;
        c.col(ch) = ldlt.solve(rhs);
        if (ldlt.info() != Eigen::Success || !c.col(ch).allFinite()) return false;
    }
    return true;
}

// Colours a file can hold: 0–1. Colours the fit put outside are clamped and held there, and
// the others refitted around them (one linearised solve at the rules' branches), then
// clamped once more.
Eigen::MatrixXd keepInRange(const std::vector<PatchNormals>& normals, GradientMesh& mesh,
                            const Eigen::MatrixXd& colors, double regularization,
                            const std::vector<ShortEdge>& edges) {
    const Eigen::MatrixXd clamped = colors.cwiseMax(0.0).cwiseMin(1.0);
    const Eigen::MatrixXd held = (clamped - colors).cwiseAbs().unaryExpr(
        [](double d) { return d > 0 ? 1.0 : 0.0; });
    if (held.sum() == 0) return colors;
    setCopyColors(mesh, clamped);
    Eigen::MatrixXd c = clamped;
    Eigen::Vector3d unused, unusedWeight;
    if (!solveLinearised(normals, rulesOf(mesh, normals), clamped, regularization, c, unused,
                         edges, unusedWeight, &held))
        return clamped;
    return c.cwiseMax(0.0).cwiseMin(1.0);
}

}  // namespace

void fitBicubicColors(GradientMesh& mesh, const RgbaImage& image, const Region& region,
                      const std::vector<PixelSample>& samples, int meshIndex,
                      double regularization, double subPixelEdgePull) {
    const std::vector<PatchNormals> normals =
        patchNormals(mesh, image, region, samples, meshIndex);
    if (normals.empty()) return;
    const Eigen::MatrixXd c0 = copyColors(mesh);
    std::vector<PatchColorRule> rules = rulesOf(mesh, normals);
    Eigen::MatrixXd c = c0;
    Eigen::Vector3d lambda, pixelWeight;
    const std::vector<ShortEdge> edges = subPixelEdges(mesh, subPixelEdgePull);
    if (!solveLinearised(normals, rules, c0, regularization, c, lambda, edges, pixelWeight))
        return;
    double best = cost(normals, rules, c0, c0, lambda, edges, pixelWeight);
    Eigen::MatrixXd bestColors = c0;
    constexpr int kRounds = 4;
    for (int round = 0; round < kRounds; ++round) {
        setCopyColors(mesh, c);
        rules = rulesOf(mesh, normals);
        const double f = cost(normals, rules, c, c0, lambda, edges, pixelWeight);
        if (f < best) {
            best = f;
            bestColors = c;
        } else if (round > 0) {
            break;  // the branches moved against us twice in a row: keep the best
        }
        if (round + 1 == kRounds) break;
        Eigen::Vector3d unused;
        Eigen::Vector3d unusedWeight;
        if (!solveLinearised(normals, rules, c0, regularization, c, unused, edges, unusedWeight))
            break;
    }
    setCopyColors(mesh, keepInRange(normals, mesh, bestColors, regularization, edges));
}

}  // namespace gm
