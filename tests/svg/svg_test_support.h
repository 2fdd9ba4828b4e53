// Shared by the SVG tests (and the browsers'): the three test meshes, temporary paths, rendering
// over white, comparing renders away from flat shapes' outlines.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <sys/stat.h>
#include <vector>

#include "formats/raster.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"

namespace svgtest {

inline std::string tmpPath(const std::string& name) {
    const std::string dir = std::string(GRADMESH_TMP) + "/svg";
    mkdir(GRADMESH_TMP, 0755);
    mkdir(dir.c_str(), 0755);
    return dir + "/" + name;
}

// ≥ 3 holes.
inline gm::Document holedDocument() {
    gm::Document d;
    d.width = 340;
    d.height = 260;
    d.meshes.push_back(gm::makeHoledMesh(3, 20, 20, 300, 220));
    return d;
}

// Strongly curved patches.
inline gm::Document curvedDocument() {
    gm::Document d;
    d.width = 320;
    d.height = 260;
    d.meshes.push_back(gm::makeCurvedMesh(5, 4, 20, 20, 280, 220, 1.0, 7));
    return d;
}

// ≥ 400 patches.
inline gm::Document largeDocument() {
    gm::Document d;
    d.width = 500;
    d.height = 420;
    d.meshes.push_back(gm::makeCurvedMesh(24, 20, 10, 10, 480, 400, 0.6, 3));
    return d;
}

// Our render with its coverage in alpha: the `ours` side of gmtest::compareInterior, whose
// mask comes from that alpha. `fine`: tessellation far below the default tolerances, to compare
// two meshes to 1/255.
inline gm::RgbaImage renderOurs(const gm::Document& doc, bool fine = false) {
    gm::RenderOptions o;
    if (fine) {
        o.positionTolerance = 0.01;
        o.colorTolerance = 0.1 / 255;
    }
    return gm::renderDocument(doc, o).image;
}

// The `theirs` side when it is our renderer too: opaque, over white as the consumers render.
inline gm::RgbaImage renderOverWhite(const gm::Document& doc, bool fine = false) {
    gm::RenderOptions o;
    if (fine) {
        o.positionTolerance = 0.01;
        o.colorTolerance = 0.1 / 255;
    }
    gm::RgbaImage img = gm::renderDocument(doc, o).image;
    gm::compositeOver(img, {1, 1, 1, 1});
    return img;
}

// Clears in `away` the pixels within `reach` (Chebyshev distance) of a pixel that `part` (a
// document of one shape or one mesh) covers differently, or covers partly.
inline void clearNearOutline(const gm::Document& part, int reach, std::vector<char>& away) {
    const gm::RgbaImage cover = gm::renderDocument(part).image;
    const int W = part.width, H = part.height;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float a = cover.at(x, y)[3];
            bool uniform = a == 0.0f || a == 1.0f;
            for (int dy = -reach; dy <= reach && uniform; ++dy)
                for (int dx = -reach; dx <= reach && uniform; ++dx)
                    uniform = cover.at(std::clamp(x + dx, 0, W - 1),
                                       std::clamp(y + dy, 0, H - 1))[3] == a;
            if (!uniform) away[static_cast<size_t>(y) * W + x] = 0;
        }
}

// Pixels at least `reach` px from the outline of every shape and mesh of `doc`.
inline std::vector<char> awayFromOutlines(const gm::Document& doc, int reach = 2) {
    std::vector<char> away(static_cast<size_t>(doc.width) * doc.height, 1);
    gm::Document part;
    part.width = doc.width;
    part.height = doc.height;
    for (const gm::FlatShape& shape : doc.shapes) {
        part.shapes = {shape};
        part.shapes[0].alpha = 1;
        part.shapes[0].layer = 0;
        clearNearOutline(part, reach, away);
    }
    part.shapes.clear();
    for (const gm::GradientMesh& mesh : doc.meshes) {
        part.meshes = {mesh};
        clearNearOutline(part, reach, away);
    }
    return away;
}

// E: the mean absolute difference over the pixels `mask` holds (all when empty) and every
// channel, 0–255 units (both images opaque).
inline double meanAbs(const gm::RgbaImage& a, const gm::RgbaImage& b,
                      const std::vector<char>& mask = {}) {
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k < a.pixels.size() / 4; ++k) {
        if (!mask.empty() && !mask[k]) continue;
        for (int c = 0; c < 3; ++c) sum += std::fabs(a.pixels[4 * k + c] - b.pixels[4 * k + c]);
        ++n;
    }
    return 255 * sum / (3.0 * double(n));
}

// The largest distance between corresponding points of two shapes of the same layout.
inline double largestPointDistance(const gm::FlatShape& a, const gm::FlatShape& b) {
    double worst = 0;
    for (size_t s = 0; s < a.subpaths.size(); ++s)
        for (size_t k = 0; k < a.subpaths[s].size(); ++k)
            worst = std::max(worst, gm::norm(a.subpaths[s][k] - b.subpaths[s][k]));
    return worst;
}

}  // namespace svgtest
