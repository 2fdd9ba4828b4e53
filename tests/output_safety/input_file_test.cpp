// Inputs are regular files: a FIFO, a device or a directory is refused before it is read, with
// a message that says what it is, and without waiting for a writer that never comes.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include "formats/input_file.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "meshcore/error.h"
#include "output_safety_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;

TEST_CASE("a FIFO, /dev/zero and a directory are refused by every reading path",
          "[output_safety][malformed]") {
    const fs::path d = tmpDir("fifo_unit");
    const std::string fifo = (d / "fifo.svg").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    for (const std::string& path : {fifo, std::string("/dev/zero"), d.string()}) {
        INFO(path);
        CHECK_THROWS_WITH(gm::requireRegularFile(path), Contains("not a regular file"));
        CHECK_THROWS_WITH(gm::readWholeFile(path, 1 << 20), Contains("not a regular file"));
        CHECK_THROWS_AS(gm::readImage(path), gm::Error);
        CHECK(gm::readFileHead(path, 64).empty());
        // The registry's sniff reads nothing from it (it would block on the FIFO).
        gm::FormatRegistry::builtin().forReading(path);
    }
    CHECK_THROWS_WITH(gm::readWholeFile(fifo, 1 << 20), Contains("FIFO"));
    CHECK_THROWS_WITH(gm::readWholeFile("/dev/zero", 1 << 20), Contains("character device"));
}

TEST_CASE("a regular file, also through a symlink, is read whole", "[output_safety]") {
    const fs::path d = tmpDir("regular");
    spit(d / "a.txt", "hello");
    fs::create_symlink(d / "a.txt", d / "link.txt");
    CHECK(gm::readWholeFile((d / "link.txt").string(), 100) == "hello");
    CHECK(gm::readFileHead((d / "a.txt").string(), 3) == "hel");
    CHECK_THROWS_WITH(gm::readWholeFile((d / "a.txt").string(), 4), Contains("over the limit"));
    CHECK_THROWS_WITH(gm::readWholeFile((d / "none").string(), 4), Contains("none"));
}
