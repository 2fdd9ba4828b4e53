#include "info_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "converters/bicubic_model.h"
#include "meshcore/printable_text.h"
#include "meshcore/split_legacy.h"

namespace gm::cli {

namespace {

void printMesh(size_t k, const GradientMesh& m) {
    std::printf("mesh %zu: %s, grid %d x %d, %d patches, %d holes, %d legacy pieces", k,
                m.colorModel == ColorModel::Bicubic ? "bicubic" : "hermite", m.columns(),
                m.rows(), m.patchCount(), m.holeCount(), legacyPieceCount(m));
    if (!m.tangents.empty()) std::printf(", %zu tangent breaks", m.tangents.size());
    std::printf("\n");
}

void printShape(size_t k, const FlatShape& s) {
    size_t segments = 0;
    for (const std::vector<Vec2>& path : s.subpaths) segments += path.size() / 3;
    std::printf("shape %zu: ", k);
    if (s.stroked())
        std::printf("stroke %.3g px wide", s.strokeWidth);
    else if (s.graded())
        std::printf("linear gradient, %zu stops, mean", s.gradient.stops.size());
    else
        std::printf("flat");
    std::printf(" #%02lx%02lx%02lx, opacity %.3g, %zu %s, %zu segments, above %zu meshes\n",
                std::lround(s.col.r * 255), std::lround(s.col.g * 255), std::lround(s.col.b * 255),
                s.alpha, s.subpaths.size(), s.stroked() ? "centrelines" : "subpaths", segments,
                s.layer);
}

}  // namespace

int infoCommand(const Args& a, const FormatRegistry& registry, const std::string& shownName) {
    if (a.positional.size() != 1) throw UsageError("expects exactly one input file");
    const std::string in = a.positional[0];
    const Document doc = readDocument(registry, in);
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(in, ec);
    int patches = 0, holes = 0, pieces = 0;
    for (const GradientMesh& m : doc.meshes) {
        patches += m.patchCount();
        holes += m.holeCount();
        pieces += legacyPieceCount(m);
    }
    std::printf("file: %s\nformat: %s\nbytes: %llu\ncanvas: %d x %d\nmeshes: %zu\npatches: %d\n"
                "holes: %d\nlegacy pieces: %d\n",
                printableText(shownName.empty() ? in : shownName).c_str(), readerFor(registry, in)->name().c_str(),
                static_cast<unsigned long long>(bytes), doc.width, doc.height, doc.meshes.size(),
                patches, holes, pieces);
    if (!doc.shapes.empty()) std::printf("flat shapes: %zu\n", doc.shapes.size());
    for (size_t k = 0; k < doc.meshes.size(); ++k) printMesh(k, doc.meshes[k]);
    for (size_t k = 0; k < doc.shapes.size(); ++k) printShape(k, doc.shapes[k]);
    // A Hermite mesh's colour slopes are its own; the SVG carries the bicubic rule's, so
    // convert refits its colours: say how close that comes.
    if (hasHermiteMeshes(doc)) {
        const BicubicConversion c = toBicubicModel(doc);
        std::printf("bicubic refit (svg): %d hermite mesh(es), E %.2f, PSNR %.2f dB, max %.0f/255 "
                    "from the hermite render\n",
                    c.refitted, c.error.meanAbs, c.error.psnr, c.error.maxAbs);
    }
    return 0;
}

}  // namespace gm::cli
