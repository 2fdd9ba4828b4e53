// What one <meshgradient> holds, as plain data shared by the writer and the reader: a regular
// grid of cubic Bézier patches with corner colours. Rows run down (v), columns right (u).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

struct SvgPatchGrid {
    int columns = 0, rows = 0;
    std::vector<Vec2> corner;                // (rows+1)(columns+1), row-major
    std::vector<std::array<Vec2, 2>> hEdge;  // (rows+1)*columns: handles, left corner first
    std::vector<std::array<Vec2, 2>> vEdge;  // rows*(columns+1): handles, top corner first
    // Interior control points of each patch in Inkscape's order: near the top-left, top-right,
    // bottom-right, bottom-left corner. Only meaningful where tensorSet is true.
    std::vector<std::array<Vec2, 4>> tensor;  // rows*columns
    std::vector<char> tensorSet;
    std::vector<Vec3> color;  // per corner
    bool bicubic = false;

    void resize(int c, int r) {
        columns = c;
        rows = r;
        const size_t nc = static_cast<size_t>(c) + 1, nr = static_cast<size_t>(r) + 1;
        corner.assign(nc * nr, Vec2{});
        hEdge.assign(nr * static_cast<size_t>(c), {});
        vEdge.assign(static_cast<size_t>(r) * nc, {});
        tensor.assign(static_cast<size_t>(r) * static_cast<size_t>(c), {});
        tensorSet.assign(static_cast<size_t>(r) * static_cast<size_t>(c), 0);
        color.assign(nc * nr, Vec3{});
    }
    Vec2& P(int c, int r) { return corner[static_cast<size_t>(r) * (columns + 1) + c]; }
    const Vec2& P(int c, int r) const { return corner[static_cast<size_t>(r) * (columns + 1) + c]; }
    Vec3& C(int c, int r) { return color[static_cast<size_t>(r) * (columns + 1) + c]; }
    const Vec3& C(int c, int r) const { return color[static_cast<size_t>(r) * (columns + 1) + c]; }
    // Horizontal edge from corner (c, r) to (c+1, r).
    std::array<Vec2, 2>& H(int c, int r) { return hEdge[static_cast<size_t>(r) * columns + c]; }
    const std::array<Vec2, 2>& H(int c, int r) const {
        return hEdge[static_cast<size_t>(r) * columns + c];
    }
    // Vertical edge from corner (c, r) to (c, r+1).
    std::array<Vec2, 2>& V(int c, int r) { return vEdge[static_cast<size_t>(r) * (columns + 1) + c]; }
    const std::array<Vec2, 2>& V(int c, int r) const {
        return vEdge[static_cast<size_t>(r) * (columns + 1) + c];
    }
    size_t patchIndex(int c, int r) const { return static_cast<size_t>(r) * columns + c; }
};

// Builds the Ferguson mesh from a grid (the recovery described in formats/svg.h). `where`
// names the element for error messages.
GradientMesh meshFromPatchGrid(const SvgPatchGrid& grid, const std::string& fileName,
                               const std::string& where);

}  // namespace gm
