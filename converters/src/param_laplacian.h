// Sparse linear systems shared by the topology map and the feature map (docs/design.md §3,
// steps 4–5): per-edge weights of a triangulation and the "each free vertex is a weighted
// average of its neighbours" system built from them. Internal to converters_pipeline.
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "converters/tri_mesh.h"
#include "meshcore/geometry.h"

namespace gm::detail {

// Vertex → incident triangles, compressed: the triangles of vertex i are
// tris[start[i] .. start[i+1]).
struct VertexTriangles {
    std::vector<int> start, tris;
    explicit VertexTriangles(const TriMesh& mesh) : start(mesh.vertices.size() + 1, 0) {
        for (const auto& t : mesh.triangles)
            for (int k : t) ++start[k + 1];
        for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
        tris.resize(start.back());
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int k : mesh.triangles[t]) tris[fill[k]++] = static_cast<int>(t);
    }
};

// W(i, j) is the weight of neighbour j in vertex i's equation  Σ_j W(i,j)·(x_i − x_j) = 0.
using WeightMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Floater's mean-value weights tan(α/2 + β/2)/|p_j − p_i| of the triangulation laid out at
// `pos` (image or parameter positions). Positive wherever the triangles incident to a vertex
// have positive area. Throws gm::Error on a degenerate triangle.
WeightMatrix meanValueWeights(const TriMesh& mesh, const std::vector<Vec2>& pos);

// Cotangent weights (cot α + cot β)/2, symmetric. Negative edge weights (from obtuse angles: at
// boundary edges, or inside a non-Delaunay triangulation) are raised to `floor`; *clamped counts
// those edges. Throws gm::Error on a degenerate triangle.
WeightMatrix cotangentWeights(const TriMesh& mesh, const std::vector<Vec2>& pos, double floor,
                              int* clamped);

// The system for the free values. unknown[i] is vertex i's unknown, or −1 when its value is
// fixed to fixedValues.row(i); vertices sharing an unknown act as one (a floating potential:
// the unknown's row sums their equations, which is the zero-total-flux condition). One rhs
// column per column of fixedValues. Throws gm::Error when an unknown has no equation weight
// (a vertex in no triangle, or a hole whose vertices only touch each other).
struct LaplacianSystem {
    Eigen::SparseMatrix<double> A;
    Eigen::MatrixXd rhs;
};
LaplacianSystem assembleLaplacian(const WeightMatrix& W, const std::vector<int>& unknown,
                                  int unknownCount, const Eigen::MatrixXd& fixedValues);

// Twice the signed area of triangle t in `uv` (positive for an unfolded triangle).
inline double twiceSignedArea(const TriMesh& mesh, const std::vector<Vec2>& uv, size_t t) {
    const auto& tri = mesh.triangles[t];
    const Vec2 a = uv[tri[0]], b = uv[tri[1]], c = uv[tri[2]];
    return cross(b - a, c - a);
}

// Indices of the triangles whose signed area in `uv` is not positive (same rule as
// countFlippedTriangles).
std::vector<int> flippedTriangles(const TriMesh& mesh, const std::vector<Vec2>& uv);

}  // namespace gm::detail
