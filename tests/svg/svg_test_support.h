// Shared by the SVG tests: the three test meshes, temporary paths, rendering over white.
#pragma once

#include <array>
#include <string>
#include <sys/stat.h>

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

}  // namespace svgtest
