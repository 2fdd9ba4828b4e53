// gradmesh: raster images to topology-preserving gradient meshes, and the formats they are
// written in. One header for a program that uses the library:
//   find_package(gradmesh) + target_link_libraries(... gradmesh::gradmesh), or
//   pkg-config --cflags --libs gradmesh.
// examples/convert.cpp reads an image, converts it and writes an SVG.
#pragma once

// The representation: meshes with holes as slits, evaluation, rendering, validation.
#include "meshcore/bicubic_colors.h"
#include "meshcore/error.h"
#include "meshcore/evaluate.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"
#include "meshcore/render.h"
#include "meshcore/split_legacy.h"
#include "meshcore/validate.h"

// Reading and writing: the format registry and every built-in format.
#include "formats/eps.h"
#include "formats/gmb.h"
#include "formats/pdf.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "formats/svg.h"

// The conversion pipeline: object masks, one object's regions, whole images by segmentation.
#include "converters/bicubic_model.h"
#include "converters/compact_file.h"
#include "converters/conversion_report.h"
#include "converters/convert_image.h"
#include "converters/convert_segments.h"
#include "converters/foreground.h"
#include "converters/visible_colors.h"
