#include "converters/tri_mesh.h"

#include <cassert>

namespace gm {

int countFlippedTriangles(const TriMesh& mesh, const ParamMap& map) {
    assert(map.uv.size() == mesh.vertices.size());
    int flipped = 0;
    for (const auto& t : mesh.triangles) {
        const Vec2 a = map.uv[t[0]], b = map.uv[t[1]], c = map.uv[t[2]];
        const double twiceArea = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        // NaN compares false, so a map with non-finite entries counts as flipped too.
        if (!(twiceArea > 0)) ++flipped;
    }
    return flipped;
}

}  // namespace gm
