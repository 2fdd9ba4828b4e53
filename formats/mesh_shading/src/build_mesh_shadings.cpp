#include <algorithm>

#include "formats/mesh_shading.h"
#include "meshcore/color_subdivision.h"
#include "meshcore/split_legacy.h"

namespace gm {

namespace {
void appendMesh(const GradientMesh& mesh, size_t source, double tolerance, double minPiece,
                std::vector<MeshShading>& out) {
    if (mesh.patchCount() == 0) return;
    MeshShading shading;
    shading.source = source;
    shading.patches.reserve(static_cast<size_t>(mesh.patchCount()));
    for (int j = 0; j < mesh.rows(); ++j) {
        for (int i = 0; i < mesh.columns(); ++i) {
            const BezierPatch patch = toBezier(mesh, i, j);
            const auto [ks, kt] = exactColorPieces(patch, tolerance, minPiece);
            if (ks == 1 && kt == 1) {
                shading.patches.push_back(patch);
            } else {
                for (const BezierPatch& piece : subdivideGrid(patch, ks, kt))
                    shading.patches.push_back(piece);
            }
        }
    }
    out.push_back(std::move(shading));
}
}  // namespace

std::vector<MeshShading> buildMeshShadings(const Document& doc, const WriteOptions& options) {
    // A tolerance below what 16-bit colour can carry would only multiply patches.
    const double tolerance = std::max(options.colorTolerance, 1.0 / 65535.0);
    std::vector<MeshShading> shadings;
    for (size_t m = 0; m < doc.meshes.size(); ++m) {
        const GradientMesh& mesh = doc.meshes[m];
        if (options.legacy) {
            for (const GradientMesh& piece : splitIntoLegacyMeshes(mesh))
                appendMesh(piece, m, tolerance, options.minPiece, shadings);
        } else {
            appendMesh(mesh, m, tolerance, options.minPiece, shadings);
        }
    }
    return shadings;
}

}  // namespace gm
