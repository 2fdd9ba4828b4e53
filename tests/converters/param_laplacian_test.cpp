// The weights and systems behind the topology and feature maps (param_laplacian.h).
#include <catch2/catch.hpp>

#include <cmath>

#include "meshcore/error.h"
#include "param_laplacian.h"
#include "converters/test_meshes.h"

using namespace gm;
using namespace gm::detail;

namespace {

// A regular hexagon of radius r around a centre vertex 0: six equilateral triangles.
TriMesh hexagonFan(double r) {
    TriMesh m;
    m.vertices.push_back({0, 0});
    for (int k = 0; k < 6; ++k)
        m.vertices.push_back({r * std::cos(k * gm::test::kPi / 3), r * std::sin(k * gm::test::kPi / 3)});
    for (int k = 0; k < 6; ++k) gm::test::addOriented(m, 0, 1 + k, 1 + (k + 1) % 6);
    return m;
}

double weight(const WeightMatrix& W, int i, int j) { return W.coeff(i, j); }

}  // namespace

TEST_CASE("mean-value and cotangent weights of a regular fan are equal and as the formulas say",
          "[param_laplacian]") {
    const TriMesh m = hexagonFan(2.0);
    const WeightMatrix mv = meanValueWeights(m, m.vertices);
    int clamped = -1;
    const WeightMatrix cot = cotangentWeights(m, m.vertices, 0.0, &clamped);
    CHECK(clamped == 0);
    // Angles of 60° on both sides of every spoke: tan(30°) twice over the spoke's length, and
    // (cot 60° + cot 60°)/2.
    const double tan30 = std::tan(gm::test::kPi / 6), cot60 = 1 / std::tan(gm::test::kPi / 3);
    for (int j = 1; j <= 6; ++j) {
        CHECK(weight(mv, 0, j) == Approx(2 * tan30 / 2.0));
        CHECK(weight(cot, 0, j) == Approx(cot60));
        CHECK(weight(cot, j, 0) == Approx(weight(cot, 0, j)));  // symmetric
    }
}

TEST_CASE("mean-value weights reproduce positions: a vertex solved from its neighbours is where it was",
          "[param_laplacian]") {
    // Mean-value coordinates have linear precision: with the outline fixed at the image
    // positions, the free vertices solve to their own positions.
    const TriMesh m = gm::test::squareGrid(7, 60.0, 0.3);
    const WeightMatrix W = meanValueWeights(m, m.vertices);
    std::vector<char> onLoop(m.vertices.size(), 0);
    for (int v : m.outerLoop) onLoop[v] = 1;
    std::vector<int> unknown(m.vertices.size(), -1);
    int count = 0;
    Eigen::MatrixXd fixed(static_cast<Eigen::Index>(m.vertices.size()), 2);
    for (size_t v = 0; v < m.vertices.size(); ++v) {
        fixed(static_cast<Eigen::Index>(v), 0) = m.vertices[v].x;
        fixed(static_cast<Eigen::Index>(v), 1) = m.vertices[v].y;
        if (!onLoop[v]) unknown[v] = count++;
    }
    REQUIRE(count > 10);
    const LaplacianSystem sys = assembleLaplacian(W, unknown, count, fixed);
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(sys.A);
    REQUIRE(lu.info() == Eigen::Success);
    const Eigen::MatrixXd x = lu.solve(sys.rhs);
    for (size_t v = 0; v < m.vertices.size(); ++v) {
        if (unknown[v] < 0) continue;
        CHECK(x(unknown[v], 0) == Approx(m.vertices[v].x).margin(1e-9));
        CHECK(x(unknown[v], 1) == Approx(m.vertices[v].y).margin(1e-9));
    }
}

TEST_CASE("an obtuse angle's negative cotangent weight is raised to the floor and counted",
          "[param_laplacian]") {
    // Two triangles on the edge (0,1), both with an obtuse angle opposite it: the weight
    // (cot α + cot β)/2 is negative.
    TriMesh m;
    m.vertices = {{0, 0}, {10, 0}, {5, 1}, {5, -1}};
    gm::test::addOriented(m, 0, 1, 2);
    gm::test::addOriented(m, 0, 3, 1);
    int clamped = 0;
    const WeightMatrix floored = cotangentWeights(m, m.vertices, 1e-3, &clamped);
    CHECK(weight(floored, 0, 1) == Approx(1e-3));
    CHECK(weight(floored, 1, 0) == Approx(1e-3));
    CHECK(weight(floored, 0, 2) > 0);
    CHECK(clamped == 1);  // the edge (0,1), once
}

TEST_CASE("degenerate triangles and vertices without equations are errors, folds are found",
          "[param_laplacian]") {
    TriMesh flat;
    flat.vertices = {{0, 0}, {1, 0}, {2, 0}};
    flat.triangles.push_back({0, 1, 2});
    CHECK_THROWS_AS(meanValueWeights(flat, flat.vertices), Error);
    int clamped = 0;
    CHECK_THROWS_AS(cotangentWeights(flat, flat.vertices, 0.0, &clamped), Error);

    // Vertex 3 is in no triangle: as an unknown it has no equation.
    TriMesh m = hexagonFan(1.0);
    m.vertices.push_back({5, 5});
    const WeightMatrix W = meanValueWeights(m, m.vertices);
    std::vector<int> unknown(m.vertices.size(), -1);
    unknown.back() = 0;
    CHECK_THROWS_AS(assembleLaplacian(W, unknown, 1, Eigen::MatrixXd::Zero(8, 1)), Error);

    // Mirrored positions fold every triangle.
    std::vector<Vec2> mirrored = m.vertices;
    for (Vec2& p : mirrored) p.x = -p.x;
    CHECK(flippedTriangles(m, m.vertices).empty());
    CHECK(flippedTriangles(m, mirrored).size() == m.triangles.size());
}
