#include "converters/tri_mesh.h"

#include <algorithm>
#include <cassert>
#include <map>

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

namespace {
using Edge = std::pair<int, int>;
Edge key(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// Inserts the midpoints of split loop edges into a closed loop.
std::vector<int> withMidpoints(const std::vector<int>& loop, const std::map<Edge, int>& mid) {
    std::vector<int> out;
    const size_t n = loop.size();
    for (size_t k = 0; k < n; ++k) {
        out.push_back(loop[k]);
        if (auto it = mid.find(key(loop[k], loop[(k + 1) % n])); it != mid.end())
            out.push_back(it->second);
    }
    return out;
}
}  // namespace

int refineTriangles(TriMesh& mesh, const std::vector<int>& triangles) {
    const size_t nt = mesh.triangles.size();
    std::vector<char> red(nt, 0);
    std::map<Edge, int> mid;  // split edges; the midpoint's index once made
    auto markRed = [&](size_t t) {
        red[t] = 1;
        const auto& tr = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) mid.emplace(key(tr[k], tr[(k + 1) % 3]), -1);
    };
    for (int t : triangles)
        if (t >= 0 && static_cast<size_t>(t) < nt) markRed(static_cast<size_t>(t));
    // Closure: a triangle with two or more split edges becomes red.
    for (bool changed = true; changed;) {
        changed = false;
        for (size_t t = 0; t < nt; ++t) {
            if (red[t]) continue;
            const auto& tr = mesh.triangles[t];
            int split = 0;
            for (int k = 0; k < 3; ++k) split += mid.count(key(tr[k], tr[(k + 1) % 3])) ? 1 : 0;
            if (split >= 2) markRed(t), changed = true;
        }
    }
    const int before = static_cast<int>(mesh.vertices.size());
    for (auto& [e, m] : mid) {
        m = static_cast<int>(mesh.vertices.size());
        mesh.vertices.push_back(0.5 * (mesh.vertices[e.first] + mesh.vertices[e.second]));
    }
    std::vector<std::array<int, 3>> out;
    out.reserve(nt + 3 * mid.size());
    for (size_t t = 0; t < nt; ++t) {
        const auto tr = mesh.triangles[t];
        if (red[t]) {
            const int ab = mid.at(key(tr[0], tr[1])), bc = mid.at(key(tr[1], tr[2])),
                      ca = mid.at(key(tr[2], tr[0]));
            out.push_back({tr[0], ab, ca});
            out.push_back({ab, tr[1], bc});
            out.push_back({ca, bc, tr[2]});
            out.push_back({ab, bc, ca});
            continue;
        }
        int k = 0;
        while (k < 3 && !mid.count(key(tr[k], tr[(k + 1) % 3]))) ++k;
        if (k == 3) {
            out.push_back(tr);
            continue;
        }
        const int a = tr[k], b = tr[(k + 1) % 3], c = tr[(k + 2) % 3], m = mid.at(key(a, b));
        out.push_back({a, m, c});
        out.push_back({m, b, c});
    }
    mesh.triangles = std::move(out);
    std::array<int, 4> cornerVertex{};
    for (int k = 0; k < 4; ++k) cornerVertex[k] = mesh.outerLoop[mesh.corner[k]];
    mesh.outerLoop = withMidpoints(mesh.outerLoop, mid);
    for (int k = 0; k < 4; ++k)
        mesh.corner[k] = static_cast<int>(
            std::find(mesh.outerLoop.begin(), mesh.outerLoop.end(), cornerVertex[k]) -
            mesh.outerLoop.begin());
    for (auto& loop : mesh.holeLoops) loop = withMidpoints(loop, mid);
    return static_cast<int>(mesh.vertices.size()) - before;
}

}  // namespace gm
