// How a rendered vector file scores against its image, over every pixel, and where it spills:
//
//   stray_pixels IMAGE RENDER [--max-error 48] [--edge 40] [--distance 2] [--map OUT.png]
//
// Both images are composited over white and compared at 8 bits per channel. Prints one JSON
// object: E (mean absolute error per channel, 0-255), PSNR over all channels, and the stray
// pixels: pixels whose largest channel error exceeds --max-error and that lie more than
// --distance px from a strong image edge. A strong edge is a pixel whose morphological gradient
// (5×5 dilation minus 5×5 erosion, largest over the channels) is at least --edge. Errors near
// edges are expected of any vector file (a border a pixel off); errors far from them are paint
// where the image has none, which a viewer sees as a stray shape. --map writes the stray pixels
// in red over a dimmed copy of the image.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <opencv2/imgproc.hpp>

namespace {

struct Options {
    std::string image, render, map;
    int maxError = 48;
    int edge = 40;
    int distance = 2;
};

// The file as 8-bit RGB composited over white, `width`×`height` (0: the file's own size).
cv::Mat readOverWhite(const std::string& path, int width, int height) {
    OIIO::ImageBuf source(path);
    if (!source.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        throw std::runtime_error(path + ": cannot read: " + source.geterror());
    const OIIO::ImageSpec& spec = source.spec();
    if ((width && spec.width != width) || (height && spec.height != height))
        throw std::runtime_error(path + ": size " + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) + " differs from the image's");
    const int channels = spec.nchannels;
    cv::Mat rgb(spec.height, spec.width, CV_8UC3);
    for (int y = 0; y < spec.height; ++y) {
        for (int x = 0; x < spec.width; ++x) {
            float pixel[4] = {0, 0, 0, 1};
            source.getpixel(x, y, pixel, std::min(channels, 4));
            if (channels < 3) pixel[1] = pixel[2] = pixel[0];
            if (channels == 2) pixel[3] = pixel[1];
            const float alpha = (channels == 2 || channels >= 4) ? pixel[3] : 1.0f;
            for (int c = 0; c < 3; ++c) {
                // OpenImageIO hands back associated (premultiplied) colour.
                const float value = pixel[c] + (1.0f - alpha);
                rgb.at<cv::Vec3b>(y, x)[c] =
                    static_cast<unsigned char>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255));
            }
        }
    }
    return rgb;
}

// Pixels within `distance` px of a strong edge of `image`.
cv::Mat nearStrongEdge(const cv::Mat& image, int edgeThreshold, int distance) {
    const cv::Mat box = cv::getStructuringElement(cv::MORPH_RECT, {5, 5});
    cv::Mat gradient;
    cv::morphologyEx(image, gradient, cv::MORPH_GRADIENT, box);
    cv::Mat channels[3];
    cv::split(gradient, channels);
    cv::Mat strongest = cv::max(cv::max(channels[0], channels[1]), channels[2]);
    cv::Mat strong = strongest >= edgeThreshold;
    cv::Mat near;
    const int size = 2 * distance + 1;
    cv::dilate(strong, near, cv::getStructuringElement(cv::MORPH_RECT, {size, size}));
    return near;
}

Options parseOptions(int argc, char** argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "--max-error") options.maxError = std::stoi(value());
        else if (arg == "--edge") options.edge = std::stoi(value());
        else if (arg == "--distance") options.distance = std::stoi(value());
        else if (arg == "--map") options.map = value();
        else if (options.image.empty()) options.image = arg;
        else if (options.render.empty()) options.render = arg;
        else throw std::runtime_error("unexpected argument " + arg);
    }
    if (options.render.empty())
        throw std::runtime_error("usage: stray_pixels IMAGE RENDER [--max-error N] [--edge N] "
                                 "[--distance N] [--map OUT.png]");
    return options;
}

void writeMap(const std::string& path, const cv::Mat& image, const cv::Mat& stray) {
    OIIO::ImageBuf map(OIIO::ImageSpec(image.cols, image.rows, 3, OIIO::TypeDesc::UINT8));
    for (int y = 0; y < image.rows; ++y) {
        for (int x = 0; x < image.cols; ++x) {
            const cv::Vec3b& p = image.at<cv::Vec3b>(y, x);
            float out[3];
            for (int c = 0; c < 3; ++c) out[c] = (128 + p[c] / 2) / 255.0f;
            if (stray.at<unsigned char>(y, x)) out[0] = 1, out[1] = out[2] = 0;
            map.setpixel(x, y, out, 3);
        }
    }
    if (!map.write(path)) throw std::runtime_error(path + ": cannot write: " + map.geterror());
}

}  // namespace

int main(int argc, char** argv) try {
    const Options options = parseOptions(argc, argv);
    const cv::Mat image = readOverWhite(options.image, 0, 0);
    const cv::Mat render = readOverWhite(options.render, image.cols, image.rows);
    cv::Mat difference;
    cv::absdiff(image, render, difference);
    const double meanError = cv::mean(difference.reshape(1))[0];
    cv::Mat squared;
    difference.convertTo(squared, CV_64F);
    const cv::Mat squaredError = squared.mul(squared);
    const double mse = cv::mean(squaredError.reshape(1))[0];
    const double psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;

    cv::Mat channels[3];
    cv::split(difference, channels);
    const cv::Mat largest = cv::max(cv::max(channels[0], channels[1]), channels[2]);
    const cv::Mat stray = (largest > options.maxError) &
                          ~nearStrongEdge(image, options.edge, options.distance);
    const int strayCount = cv::countNonZero(stray);
    if (!options.map.empty()) writeMap(options.map, image, stray);
    std::printf("{\"pixels\": %d, \"E\": %.4f, \"psnr\": %.3f, \"stray\": %d, "
                "\"stray_fraction\": %.6f}\n",
                image.rows * image.cols, meanError, psnr, strayCount,
                static_cast<double>(strayCount) / (image.rows * image.cols));
    return 0;
} catch (const std::exception& error) {
    std::fprintf(stderr, "stray_pixels: %s\n", error.what());
    return 1;
}
