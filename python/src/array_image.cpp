#include "array_image.h"

#include <OpenImageIO/fmath.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace py = pybind11;

namespace gmpy {

namespace {

float clampedFloat(double v) {
    if (!std::isfinite(v)) return 0.f;
    return static_cast<float>(std::clamp(v, 0.0, 1.0));
}

// Each sample as a float 0–1, by dtype.
template <class T>
float sampleToFloat(const void* p) {
    const T v = *static_cast<const T*>(p);
    if constexpr (std::is_same_v<T, bool>) {
        return v ? 1.f : 0.f;
    } else if constexpr (std::is_integral_v<T>) {
        float f;
        OIIO::convert_type<T, float>(&v, &f, 1);
        return f;
    } else {
        return clampedFloat(static_cast<double>(v));
    }
}

std::string shapeText(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// Walks the array through its strides: no contiguous copy is made first.
template <class T>
void fillImage(const py::array& a, int channels, gm::RgbaImage& img) {
    const auto* base = static_cast<const char*>(a.data());
    const py::ssize_t sy = a.strides(0), sx = a.strides(1), sc = a.ndim() == 3 ? a.strides(2) : 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const char* p = base + y * sy + x * sx;
            float s[4];
            for (int c = 0; c < channels; ++c) s[c] = sampleToFloat<T>(p + c * sc);
            float* d = img.at(x, y);
            const bool grey = channels < 3;
            d[0] = s[0];
            d[1] = grey ? s[0] : s[1];
            d[2] = grey ? s[0] : s[2];
            d[3] = channels == 2 ? s[1] : channels == 4 ? s[3] : 1.f;
        }
}

}  // namespace

gm::RgbaImage arrayToImage(const py::array& a, const std::string& what, uint64_t maxPixels) {
    const int channels = a.ndim() == 2 ? 1 : a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 0;
    if (channels < 1 || channels > 4)
        throw py::value_error(what + " must be an HxW, HxWx1, HxWx2, HxWx3 or HxWx4 array, got shape " +
                              shapeText(a));
    if (a.shape(0) < 1 || a.shape(1) < 1) throw py::value_error(what + " is empty: shape " + shapeText(a));
    const double pixels = static_cast<double>(a.shape(0)) * a.shape(1);
    if (pixels > static_cast<double>(maxPixels) || a.shape(0) > (1 << 30) || a.shape(1) > (1 << 30))
        throw py::value_error(what + " is " + std::to_string(a.shape(1)) + "x" +
                              std::to_string(a.shape(0)) + ", over the limit of " +
                              std::to_string(maxPixels) + " pixels (raise it with max_pixels)");
    gm::RgbaImage img(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
    const char kind = a.dtype().kind();
    const auto size = a.dtype().itemsize();
    if (kind == 'b') fillImage<bool>(a, channels, img);
    else if (kind == 'u' && size == 1) fillImage<uint8_t>(a, channels, img);
    else if (kind == 'u' && size == 2) fillImage<uint16_t>(a, channels, img);
    else if (kind == 'f' && size == 4) fillImage<float>(a, channels, img);
    else if (kind == 'f' && size == 8) fillImage<double>(a, channels, img);
    else
        throw py::value_error(what + " must be uint8, uint16, bool, float32 or float64, got " +
                              std::string(py::str(a.dtype())));
    return img;
}

py::array_t<float> imageToFloatArray(gm::RgbaImage&& image) {
    auto* pixels = new std::vector<float>(std::move(image.pixels));
    py::capsule owner(pixels, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    const py::ssize_t w = image.width, h = image.height, f = sizeof(float);
    return py::array_t<float>({h, w, py::ssize_t(4)}, {w * 4 * f, 4 * f, f}, pixels->data(), owner);
}

py::array_t<uint8_t> imageToByteArray(const gm::RgbaImage& image) {
    py::array_t<uint8_t> out({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(4)});
    uint8_t* d = out.mutable_data();
    const size_t n = image.pixels.size();
    {
        py::gil_scoped_release release;
        for (size_t k = 0; k < n; ++k) {
            const float v = std::clamp(image.pixels[k], 0.f, 1.f);
            OIIO::convert_type<float, uint8_t>(&v, &d[k], 1);
        }
    }
    return out;
}

}  // namespace gmpy
