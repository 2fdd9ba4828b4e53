// Node copies and derivative slots of a mesh, shared by the colour rule (color_rule.cpp) and the
// bicubic colour model (bicubic_colors.cpp): numbering, lookup, and which copy and u-slot each
// patch corner uses.
#pragma once

#include <cstddef>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {
namespace detail {

// Derivative slots. Node copies are numbered main nodes first (row-major, as in
// GradientMesh::nodes), then every slit's `below` copies in slit order. A u-slot is a node copy's
// colU, then the slit ends (two per slit: left, right), then the corner tangents. A v-slot is a
// node copy's colV and shares the node copy's number.
struct Layout {
    std::vector<size_t> belowBase;  // per slit: number of its first `below` copy
    size_t nodeCopies = 0;
    size_t slitEndBase = 0;
    size_t tangentBase = 0;
    size_t uSlots = 0;

    explicit Layout(const GradientMesh& mesh) {
        nodeCopies = mesh.nodes.size();
        for (const Slit& s : mesh.slits) {
            belowBase.push_back(nodeCopies);
            nodeCopies += s.below.size();
        }
        slitEndBase = nodeCopies;
        tangentBase = slitEndBase + 2 * mesh.slits.size();
        uSlots = tangentBase + mesh.tangents.size();
    }
};

inline const Node& nodeCopy(const GradientMesh& mesh, const Layout& layout, size_t k) {
    if (k < mesh.nodes.size()) return mesh.nodes[k];
    for (size_t s = mesh.slits.size(); s-- > 0;) {
        if (k >= layout.belowBase[s]) return mesh.slits[s].below[k - layout.belowBase[s]];
    }
    return mesh.nodes[0];  // unreachable for k < layout.nodeCopies
}

inline Node& nodeCopy(GradientMesh& mesh, const Layout& layout, size_t k) {
    return const_cast<Node&>(nodeCopy(static_cast<const GradientMesh&>(mesh), layout, k));
}

inline Vec3 slotU(const GradientMesh& mesh, const Layout& layout, size_t slot) {
    if (slot < layout.slitEndBase) return nodeCopy(mesh, layout, slot).colU;
    if (slot < layout.tangentBase) {
        const size_t k = slot - layout.slitEndBase;
        const Slit& s = mesh.slits[k / 2];
        return (k % 2 == 0) ? s.left.colU : s.right.colU;
    }
    return mesh.tangents[slot - layout.tangentBase].colU;
}

inline void setSlotU(GradientMesh& mesh, const Layout& layout, size_t slot, Vec3 value) {
    if (slot < layout.slitEndBase) {
        nodeCopy(mesh, layout, slot).colU = value;
    } else if (slot < layout.tangentBase) {
        const size_t k = slot - layout.slitEndBase;
        Slit& s = mesh.slits[k / 2];
        ((k % 2 == 0) ? s.left.colU : s.right.colU) = value;
    } else {
        mesh.tangents[slot - layout.tangentBase].colU = value;
    }
}

// What corner (a,b) of patch (i,j) uses: the node copy (position, colour, colV) and the u-slot
// with its sign. Mirrors patchHermite's resolution order: slits, then corner tangents.
struct CornerUse {
    size_t node = 0;
    size_t uSlot = 0;
    double uSign = 1.0;
};

inline CornerUse resolveCorner(const GradientMesh& mesh, const Layout& layout, int i, int j, int a,
                        int b) {
    const int col = i + a, row = j + b;
    CornerUse use;
    use.node = static_cast<size_t>(row) * static_cast<size_t>(mesh.columns() + 1) +
               static_cast<size_t>(col);
    use.uSlot = use.node;
    for (size_t k = 0; k < mesh.slits.size(); ++k) {
        const Slit& s = mesh.slits[k];
        if (s.row != row) continue;
        const bool below = (b == 0);  // the patch lies below the row
        if (col > s.i0 && col < s.i1 && below) {
            use.node = layout.belowBase[k] + static_cast<size_t>(col - s.i0 - 1);
            use.uSlot = use.node;
            use.uSign = 1.0;
        } else if (col == s.i0 && a == 0) {
            use.uSlot = layout.slitEndBase + 2 * k;
            use.uSign = below ? -1.0 : 1.0;
        } else if (col == s.i1 && a == 1) {
            use.uSlot = layout.slitEndBase + 2 * k + 1;
            use.uSign = below ? -1.0 : 1.0;
        }
    }
    for (size_t q = 0; q < mesh.tangents.size(); ++q) {
        const CornerTangent& t = mesh.tangents[q];
        if (t.i == i && t.j == j && t.a == a && t.b == b) {
            use.uSlot = layout.tangentBase + q;
            use.uSign = 1.0;
        }
    }
    return use;
}

}  // namespace detail
}  // namespace gm
