#include "meshcore/gradient_mesh.h"

#include <algorithm>
#include <cassert>

#include "meshcore/bicubic_colors.h"

namespace gm {

GradientMesh::GradientMesh(int columns, int rows) {
    assert(columns > 0 && rows > 0);
    u.resize(static_cast<size_t>(columns) + 1);
    v.resize(static_cast<size_t>(rows) + 1);
    for (int i = 0; i <= columns; ++i) u[i] = i;
    for (int j = 0; j <= rows; ++j) v[j] = j;
    nodes.resize((static_cast<size_t>(columns) + 1) * (static_cast<size_t>(rows) + 1));
}

bool operator==(const Slit& a, const Slit& b) {
    return a.row == b.row && a.i0 == b.i0 && a.i1 == b.i1 && a.below == b.below &&
           a.left.posU == b.left.posU && a.left.colU == b.left.colU &&
           a.right.posU == b.right.posU && a.right.colU == b.right.colU;
}

bool operator==(const CornerTangent& a, const CornerTangent& b) {
    return a.i == b.i && a.j == b.j && a.a == b.a && a.b == b.b && a.posU == b.posU &&
           a.colU == b.colU;
}

bool operator==(const GradientMesh& a, const GradientMesh& b) {
    return a.u == b.u && a.v == b.v && a.nodes == b.nodes && a.slits == b.slits &&
           a.tangents == b.tangents && a.colorModel == b.colorModel;
}

bool operator==(const GradientStop& a, const GradientStop& b) {
    return a.offset == b.offset && a.col == b.col;
}

bool operator==(const LinearGradient& a, const LinearGradient& b) {
    return a.from == b.from && a.to == b.to && a.stops == b.stops;
}

Vec3 LinearGradient::colourAt(Vec2 p) const {
    if (stops.empty()) return {};
    const Vec2 axis = to - from;
    const double length2 = dot(axis, axis);
    const double t = length2 > 0 ? std::clamp(dot(p - from, axis) / length2, 0.0, 1.0) : 0.0;
    size_t k = 1;
    while (k + 1 < stops.size() && stops[k].offset < t) ++k;
    if (k >= stops.size()) return stops.front().col;
    const GradientStop& a = stops[k - 1];
    const GradientStop& b = stops[k];
    const double span = b.offset - a.offset;
    const double s = span > 0 ? std::clamp((t - a.offset) / span, 0.0, 1.0) : 0.0;
    return a.col + s * (b.col - a.col);
}

bool operator==(const FlatShape& a, const FlatShape& b) {
    return a.col == b.col && a.alpha == b.alpha && a.subpaths == b.subpaths && a.layer == b.layer &&
           a.strokeWidth == b.strokeWidth && a.gradient == b.gradient;
}

std::vector<Vec2> polygonAsCubics(const std::vector<Vec2>& polygon) {
    std::vector<Vec2> path;
    for (size_t k = 0; k < polygon.size(); ++k) {
        const Vec2 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
        path.insert(path.end(), {a, a + (1.0 / 3) * (b - a), a + (2.0 / 3) * (b - a)});
    }
    return path;
}

bool operator==(const Document& a, const Document& b) {
    return a.width == b.width && a.height == b.height && a.meshes == b.meshes &&
           a.shapes == b.shapes;
}

PatchHermite patchHermite(const GradientMesh& mesh, int i, int j) {
    assert(i >= 0 && i < mesh.columns() && j >= 0 && j < mesh.rows());
    const double du = mesh.u[i + 1] - mesh.u[i];
    const double dv = mesh.v[j + 1] - mesh.v[j];
    PatchHermite h;
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            const int col = i + a, row = j + b;
            const Node* n = &mesh.node(col, row);
            Vec2 posU = n->posU;
            Vec3 colU = n->colU;
            for (const Slit& s : mesh.slits) {
                if (s.row != row) continue;
                // b == 0: the node is on the patch's top edge, so the patch lies below the row.
                const bool below = (b == 0);
                if (col > s.i0 && col < s.i1 && below) {
                    n = &s.below[static_cast<size_t>(col - s.i0 - 1)];
                    posU = n->posU;
                    colU = n->colU;
                } else if (col == s.i0 && a == 0) {  // patch to the right of the left end
                    const double sign = below ? -1.0 : 1.0;
                    posU = sign * s.left.posU;
                    colU = sign * s.left.colU;
                } else if (col == s.i1 && a == 1) {  // patch to the left of the right end
                    const double sign = below ? -1.0 : 1.0;
                    posU = sign * s.right.posU;
                    colU = sign * s.right.colU;
                }
            }
            for (const CornerTangent& t : mesh.tangents) {
                if (t.i == i && t.j == j && t.a == a && t.b == b) {
                    posU = t.posU;
                    colU = t.colU;
                }
            }
            HermiteCorner& c = h.corner[a][b];
            c.pos = n->pos;
            c.col = n->col;
            c.posS = du * posU;
            c.colS = du * colU;
            c.posT = dv * n->posV;
            c.colT = dv * n->colV;
        }
    }
    if (mesh.colorModel == ColorModel::Bicubic) {
        Vec3 colS[2][2], colT[2][2];
        bicubicPatchSlopes(mesh, i, j, colS, colT);
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) {
                h.corner[a][b].colS = colS[a][b];
                h.corner[a][b].colT = colT[a][b];
            }
    }
    return h;
}

}  // namespace gm
