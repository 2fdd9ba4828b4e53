// NumPy arrays in and out: an image array (HxW grey, HxWx1/2/3/4; uint8, uint16, bool, float32
// or float64; any strides) read into the library's float RGBA image in one pass, and rendered
// images handed to NumPy without a copy (float32) or quantised as the PNG writer does (uint8).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include "meshcore/image.h"

namespace gmpy {

// Straight-alpha float RGBA, sRGB 0–1, as readImage makes from a file with the same samples:
// integers scaled as OpenImageIO scales them (so an 8-bit array converts exactly as the
// 8-bit file it came from), floats clamped to 0–1 (NaN: 0), grey copied to R, G, B, a
// missing alpha 1. Throws pybind11::value_error naming `what` for another shape or dtype, an
// empty array, or one over maxPixels.
gm::RgbaImage arrayToImage(const pybind11::array& array, const std::string& what, uint64_t maxPixels);

// An HxWx4 float32 array that owns the image's pixels (moved, not copied).
pybind11::array_t<float> imageToFloatArray(gm::RgbaImage&& image);

// An HxWx4 uint8 array: each channel clamped to 0–1 and scaled as the PNG writer does.
pybind11::array_t<uint8_t> imageToByteArray(const gm::RgbaImage& image);

}  // namespace gmpy
