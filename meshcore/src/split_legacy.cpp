#include "meshcore/split_legacy.h"

#include <algorithm>
#include <set>

namespace gm {

namespace {
std::vector<int> cutRows(const GradientMesh& mesh) {
    std::set<int> rows;
    for (const Slit& s : mesh.slits) rows.insert(s.row);
    return {rows.begin(), rows.end()};
}

// The piece between grid lines top and bottom (top < bottom).
GradientMesh piece(const GradientMesh& mesh, int top, int bottom) {
    const int C = mesh.columns();
    GradientMesh p;
    p.colorModel = mesh.colorModel;
    p.u = mesh.u;
    p.v.assign(mesh.v.begin() + top, mesh.v.begin() + bottom + 1);
    p.nodes.reserve((static_cast<size_t>(C) + 1) * (bottom - top + 1));
    for (int j = top; j <= bottom; ++j)
        for (int i = 0; i <= C; ++i) p.nodes.push_back(mesh.node(i, j));
    const int lastRow = bottom - top - 1;
    for (const Slit& s : mesh.slits) {
        if (s.row == top) {
            // The piece lies below this slit: its top line takes the lower copies and the
            // slit side's −d tangents.
            for (int i = s.i0 + 1; i < s.i1; ++i) p.node(i, 0) = s.below[static_cast<size_t>(i - s.i0 - 1)];
            p.tangents.push_back({s.i0, 0, 0, 0, -s.left.posU, -s.left.colU});
            p.tangents.push_back({s.i1 - 1, 0, 1, 0, -s.right.posU, -s.right.colU});
        } else if (s.row == bottom) {
            p.tangents.push_back({s.i0, lastRow, 0, 1, s.left.posU, s.left.colU});
            p.tangents.push_back({s.i1 - 1, lastRow, 1, 1, s.right.posU, s.right.colU});
        }
    }
    // The whole mesh's own breaks win over slit ends, as in patchHermite.
    for (const CornerTangent& t : mesh.tangents) {
        if (t.j >= top && t.j < bottom) {
            CornerTangent moved = t;
            moved.j -= top;
            p.tangents.push_back(moved);
        }
    }
    return p;
}
}  // namespace

int legacyPieceCount(const GradientMesh& mesh) {
    return static_cast<int>(cutRows(mesh).size()) + 1;
}

std::vector<GradientMesh> splitIntoLegacyMeshes(const GradientMesh& mesh) {
    if (mesh.slits.empty()) return {mesh};
    std::vector<int> lines = cutRows(mesh);
    lines.insert(lines.begin(), 0);
    lines.push_back(mesh.rows());
    std::vector<GradientMesh> pieces;
    for (size_t k = 0; k + 1 < lines.size(); ++k) pieces.push_back(piece(mesh, lines[k], lines[k + 1]));
    return pieces;
}

}  // namespace gm
