// Test support for the SVG raster fallback: the sample meshes, converted once per run, and
// images compared as the suite compares renderers.
#pragma once

#include <unistd.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "formats/raster.h"
#include "support/cli_run.h"
#include "support/compare.h"

namespace fallbacktest {

namespace fs = std::filesystem;
using gmtest::q;

inline fs::path tmpDir(const std::string& name) { return gmtest::scratchDir("fallback_", name); }

inline void checkSuccess(const gmtest::Run& r) {
    INFO("exit " << r.code << ", stderr: " << r.err);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
}

struct Sample {
    std::string name;     // apple, pic1, fish
    std::string convert;  // the gradmesh arguments that convert its image
};

// A masked object, an object with 7 holes, a whole image (--segment).
inline const Sample kSamples[] = {
    {"apple", "convert " + q(fs::path(GRADMESH_SAMPLES) / "apple.jpg") + " --mask " +
                  q(fs::path(GRADMESH_SAMPLES) / "apple_mask.png")},
    {"pic1", "convert " + q(fs::path(GRADMESH_SAMPLES) / "pic1.png")},
    {"fish", "convert " + q(fs::path(GRADMESH_SAMPLES) / "HappyFish.jpg") + " --segment"},
};

// The sample's .gmb, converted on first use and kept for the process's other tests. The folder
// is the process's own: ctest runs test cases as parallel processes.
inline fs::path sampleGmb(const Sample& s) {
    static std::map<std::string, fs::path> done;
    if (auto it = done.find(s.name); it != done.end()) return it->second;
    const fs::path d = tmpDir("sample_" + s.name + "_" + std::to_string(::getpid())),
                   gmb = d / (s.name + ".gmb");
    const gmtest::Run r = gmtest::runGradmesh(s.convert + " -o " + q(gmb), d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return done[s.name] = gmb;
}

// Mean error (0-255) of `theirs` against `ours` over ours' interior eroded 1 px, both composited
// over white first (a browser's page is white).
inline gmtest::DiffStats interiorError(const fs::path& ours, const fs::path& theirs) {
    gm::RgbaImage a = gm::readImage(ours.string()), b = gm::readImage(theirs.string());
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    gm::RgbaImage opaqueA = a;
    gm::compositeOver(opaqueA, {1, 1, 1, 1});
    gm::compositeOver(b, {1, 1, 1, 1});
    // The interior is where ours is opaque: compareInterior reads it from the alpha of its
    // first image, so the composited colours go in with ours' alpha.
    for (size_t p = 0; p < a.pixels.size(); p += 4)
        for (int c = 0; c < 3; ++c) a.pixels[p + c] = opaqueA.pixels[p + c];
    return gmtest::compareInterior(a, b, 1);
}

}  // namespace fallbacktest
