#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "meshcore/render.h"
#include "meshcore/split_legacy.h"
#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"

using namespace gm;

namespace {
bool sameCorner(const HermiteCorner& a, const HermiteCorner& b) {
    return a.pos == b.pos && a.posS == b.posS && a.posT == b.posT && a.col == b.col &&
           a.colS == b.colS && a.colT == b.colT;
}
}  // namespace

TEST_CASE("a mesh without slits splits into itself", "[split]") {
    const GradientMesh m = makeCurvedMesh(4, 3, 0, 0, 50, 50);
    const auto pieces = splitIntoLegacyMeshes(m);
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0] == m);
    CHECK(legacyPieceCount(m) == 1);
}

TEST_CASE("split keeps every patch's Hermite data exactly", "[split]") {
    const GradientMesh m = makeHoledMesh(3, 10, 10, 240, 480);
    REQUIRE(m.holeCount() == 3);
    const auto pieces = splitIntoLegacyMeshes(m);
    REQUIRE(pieces.size() == 4);
    CHECK(legacyPieceCount(m) == 4);
    int row0 = 0, total = 0;
    for (const GradientMesh& p : pieces) {
        CHECK(validateMesh(p).empty());
        CHECK(p.slits.empty());
        CHECK(p.columns() == m.columns());
        for (int j = 0; j < p.rows(); ++j)
            for (int i = 0; i < p.columns(); ++i) {
                const PatchHermite a = patchHermite(p, i, j), b = patchHermite(m, i, row0 + j);
                for (int x = 0; x < 2; ++x)
                    for (int y = 0; y < 2; ++y) CHECK(sameCorner(a.corner[x][y], b.corner[x][y]));
                ++total;
            }
        row0 += p.rows();
    }
    CHECK(total == m.patchCount());
}

TEST_CASE("two slits on one row give one cut", "[split]") {
    GradientMesh m = makeCurvedMesh(9, 4, 0, 0, 90, 40, 0.2);
    for (int k = 0; k < 2; ++k) {
        Slit s;
        s.row = 2;
        s.i0 = 1 + 4 * k;
        s.i1 = s.i0 + 2;
        s.below.push_back(m.node(s.i0 + 1, 2));
        m.slits.push_back(s);
    }
    REQUIRE(validateMesh(m).empty());
    CHECK(splitIntoLegacyMeshes(m).size() == 2);
}

TEST_CASE("legacy pieces render identically to the whole", "[split][render]") {
    Document whole;
    whole.width = 260;
    whole.height = 500;
    whole.meshes.push_back(makeHoledMesh(3, 10, 10, 240, 480));
    Document split = whole;
    split.meshes = splitIntoLegacyMeshes(whole.meshes[0]);
    REQUIRE(split.meshes.size() == 4);
    RenderOptions opt;
    opt.antialias = false;  // pieces share cut lines: compare the patch interiors exactly
    const RgbaImage a = renderDocument(whole, opt).image;
    const RgbaImage b = renderDocument(split, opt).image;
    REQUIRE(a.width == b.width);
    double maxDiff = 0;
    size_t covered = 0;
    for (size_t k = 0; k < a.pixels.size(); ++k) maxDiff = std::max(maxDiff, double(std::fabs(a.pixels[k] - b.pixels[k])));
    for (size_t k = 3; k < a.pixels.size(); k += 4) covered += a.pixels[k] > 0.5f;
    CHECK(covered > 50000);
    CHECK(maxDiff <= 1.0 / 255.0);

    // With the anti-aliased outline too, the pieces only differ along the cut lines, where
    // each piece's outline is partly covered; away from them the pixels agree.
    const RgbaImage c = renderDocument(whole).image;
    const RgbaImage d = renderDocument(split).image;
    double sum = 0;
    for (size_t k = 0; k < c.pixels.size(); ++k) sum += std::fabs(c.pixels[k] - d.pixels[k]);
    CHECK(sum / c.pixels.size() < 0.5 / 255.0);
}
