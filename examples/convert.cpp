// gradmesh as a library: an image in, a gradient-mesh SVG out.
//   convert IMAGE OUT.svg
// The object is the image's alpha, else what foreground extraction finds; every region becomes
// one mesh (holes included), fitted in the SVG bicubic colour model that Inkscape draws.
#include <gradmesh/gradmesh.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s IMAGE OUT.svg\n", argv[0]);
        return 2;
    }
    try {
        const gm::RgbaImage image = gm::readImage(argv[1]);
        const gm::ObjectMask mask = gm::objectMask(image, nullptr, argv[1], "");
        gm::ConvertReport report;
        const gm::Document doc = gm::convertImage(image, mask, gm::ConvertOptions{}, argv[1], &report);
        gm::FormatRegistry::builtin().forPath(argv[2])->write(doc, argv[2], gm::WriteOptions{});
        std::printf("%d patches, E %.2f\n", report.patches, report.error.meanAbs);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
