// The view page (`gradmesh view`, `convert --report R.html`): one self-contained HTML file that
// shows a document's render, its mesh lines, the source image and an error heat map, with zoom
// and pan, and the conversion's figures. The markup, style and script are the template in
// view_page.html; this fills it in.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "formats/registry.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

// What the caller knows about the document beyond its meshes.
struct ViewFigures {
    std::string title;       // the file the page is about, as the header names it
    std::string sourceName;  // the source image's file name ("" when there is none)
    std::string colorModel;  // "" : said from the meshes (bicubic, hermite or both)
    // The conversion's own error figures; when absent and a source image is given, the page
    // measures them from the render (over the pixels both paint).
    bool haveError = false;
    double meanAbs = 0, psnr = 0;
    std::string errorOver;  // which pixels they are over, in words
    std::vector<std::pair<std::string, double>> seconds;     // stage, seconds
    std::vector<std::pair<std::string, std::string>> facts;  // further rows: label, value
};

// An inline SVG (for zooming the mesh itself) is left out of the page above this size; the
// zoom then scales the render.
constexpr size_t kMaxInlineSvgBytes = size_t(8) << 20;

// Above this many patches the mesh lines are left out: a browser draws such an overlay slowly,
// and its path data takes about 40 bytes a patch.
constexpr uint64_t kMaxMeshLinePatches = 100000;

// The page for `doc` (rendered at 1x here), with `source` (the same size as the canvas) when
// given. The byte figures are the writers' in-memory encodings under `options` (its output
// limit included). The time spent building the page joins the figures.
std::string buildViewPage(const Document& doc, const RgbaImage* source, ViewFigures figures,
                          const WriteOptions& options);

}  // namespace gm
