// The raster fallback of an SVG (WriteOptions::svgFallback): our render of the document as an
// <image> in a locked Inkscape layer beneath the mesh shapes. Viewers that draw no meshes
// (browsers, librsvg) show the image, since the shapes' paint falls back to none; Inkscape draws
// the meshes over it and leaves the layer alone while the meshes are edited.
#pragma once

#include <string>

#include "formats/svg.h"

namespace gm {

// Namespace declarations the layer needs on the root <svg> (xlink, inkscape, sodipodi), each
// after a space.
const char* svgFallbackNamespaces();

// The layer with `image` stretched over the canvas, width × height user units.
void appendSvgFallbackLayer(std::string& out, const SvgFallbackImage& image, int width, int height);

}  // namespace gm
