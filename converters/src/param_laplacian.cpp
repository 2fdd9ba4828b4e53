#include "param_laplacian.h"

#include <cmath>
#include <string>

#include "meshcore/error.h"
#include "meshcore/geometry.h"

namespace gm::detail {

namespace {

using Triplet = Eigen::Triplet<double>;

[[noreturn]] void throwDegenerate(const TriMesh& mesh, const std::vector<Vec2>& pos, size_t t,
                                  const char* stage) {
    const Vec2 p = pos[mesh.triangles[t][0]];
    throw Error(std::string(stage) + ": triangle " + std::to_string(t) + " near (" +
                std::to_string(p.x) + ", " + std::to_string(p.y) + ") is degenerate");
}

}  // namespace

WeightMatrix meanValueWeights(const TriMesh& mesh, const std::vector<Vec2>& pos) {
    std::vector<Triplet> entries;
    entries.reserve(mesh.triangles.size() * 6);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
            const Vec2 a = pos[j] - pos[i], b = pos[l] - pos[i];
            const double la = norm(a), lb = norm(b);
            const double sine = cross(a, b), d = dot(a, b);
            // tan(θ/2) = sin θ / (1 + cos θ), scaled by |a||b| on both sides.
            const double denom = la * lb + d;
            if (!(sine > 0) || !(denom > 0) || !(la > 0) || !(lb > 0))
                throwDegenerate(mesh, pos, t, "mean-value weights");
            const double tanHalf = sine / denom;
            entries.emplace_back(i, j, tanHalf / la);
            entries.emplace_back(i, l, tanHalf / lb);
        }
    }
    const int n = static_cast<int>(pos.size());
    WeightMatrix W(n, n);
    W.setFromTriplets(entries.begin(), entries.end());
    return W;
}

WeightMatrix cotangentWeights(const TriMesh& mesh, const std::vector<Vec2>& pos, double floor,
                              int* clamped) {
    std::vector<Triplet> entries;
    entries.reserve(mesh.triangles.size() * 6);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
            const Vec2 a = pos[j] - pos[i], b = pos[l] - pos[i];
            const double sine = cross(a, b);
            if (!(sine > 0)) throwDegenerate(mesh, pos, t, "cotangent weights");
            const double halfCot = 0.5 * dot(a, b) / sine;  // angle at i faces edge j–l
            entries.emplace_back(j, l, halfCot);
            entries.emplace_back(l, j, halfCot);
        }
    }
    const int n = static_cast<int>(pos.size());
    WeightMatrix W(n, n);
    W.setFromTriplets(entries.begin(), entries.end());
    int count = 0;
    for (int i = 0; i < W.outerSize(); ++i)
        for (WeightMatrix::InnerIterator it(W, i); it; ++it)
            if (it.value() < -1e-9) {
                it.valueRef() = floor;
                if (it.col() > i) ++count;
            } else if (it.value() < 0) {
                it.valueRef() = 0;  // rounding of a right angle's zero cotangent
            }
    if (clamped) *clamped = count;
    return W;
}

LaplacianSystem assembleLaplacian(const WeightMatrix& W, const std::vector<int>& unknown,
                                  int unknownCount, const Eigen::MatrixXd& fixedValues) {
    LaplacianSystem sys;
    sys.rhs = Eigen::MatrixXd::Zero(unknownCount, fixedValues.cols());
    Eigen::VectorXd diag = Eigen::VectorXd::Zero(unknownCount);
    std::vector<Triplet> entries;
    entries.reserve(W.nonZeros() + unknownCount);
    for (int i = 0; i < W.outerSize(); ++i) {
        const int r = unknown[i];
        if (r < 0) continue;
        for (WeightMatrix::InnerIterator it(W, i); it; ++it) {
            const int c = unknown[it.col()];
            if (c == r) continue;  // both ends on one floating potential: no flux between them
            diag[r] += it.value();
            if (c >= 0)
                entries.emplace_back(r, c, -it.value());
            else
                sys.rhs.row(r) += it.value() * fixedValues.row(it.col());
        }
    }
    for (int r = 0; r < unknownCount; ++r) {
        if (!(diag[r] > 0))
            throw Error("parameterisation: unknown " + std::to_string(r) +
                        " has no neighbour outside itself (a vertex in no triangle, or a hole "
                        "whose vertices only touch each other)");
        entries.emplace_back(r, r, diag[r]);
    }
    sys.A.resize(unknownCount, unknownCount);
    sys.A.setFromTriplets(entries.begin(), entries.end());
    sys.A.makeCompressed();
    return sys;
}

std::vector<int> flippedTriangles(const TriMesh& mesh, const std::vector<Vec2>& uv) {
    std::vector<int> out;
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        if (!(twiceSignedArea(mesh, uv, t) > 0)) out.push_back(static_cast<int>(t));
    return out;
}

}  // namespace gm::detail
