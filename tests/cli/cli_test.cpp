// The command line: exit codes, one-line errors, and never a partial or clobbered file.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "formats/raster.h"
#include "support/cli_run.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {
using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

fs::path tmpDir(const std::string& name) { return gmtest::scratchDir("cli_", name); }
Run gradmesh(const std::string& args, const fs::path& dir) { return gmtest::runGradmesh(args, dir); }
size_t lines(const std::string& s) { return gmtest::lineCount(s); }
}  // namespace

TEST_CASE("no arguments and unknown commands are usage errors", "[cli]") {
    const fs::path d = tmpDir("usage");
    CHECK(gradmesh("", d).code == 2);
    Run r = gradmesh("frobnicate", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("unknown command"));
    CHECK(lines(r.err) == 1);
}

TEST_CASE("every command has --help", "[cli]") {
    const fs::path d = tmpDir("help");
    for (const char* c : {"convert", "render", "info", "compare", "sample"}) {
        Run r = gradmesh(std::string(c) + " --help", d);
        CHECK(r.code == 0);
        CHECK_THAT(r.out, Contains(std::string("usage: gradmesh ") + c));
    }
    CHECK(gradmesh("--help", d).code == 0);
}

TEST_CASE("bad arguments get one clear line and exit 2", "[cli]") {
    const fs::path d = tmpDir("badargs");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    Run r = gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "x.png") + " --scale banana", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("--scale"));
    CHECK(lines(r.err) == 1);
    r = gradmesh("render " + q(d / "s.gmb"), d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("-o"));
    r = gradmesh("convert " + q(d / "s.gmb") + " -o " + q(d / "x.gmb") + " --bogus", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("--bogus"));
    r = gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "x.png") + " --background pink", d);
    CHECK(r.code == 2);
    CHECK_FALSE(fs::exists(d / "x.png"));
    CHECK_FALSE(fs::exists(d / "x.gmb"));
}

TEST_CASE("a missing input file is named in the error", "[cli]") {
    const fs::path d = tmpDir("missing");
    Run r = gradmesh("render " + q(d / "nope.gmb") + " -o " + q(d / "x.png"), d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("nope.gmb") && Contains("no such file"));
    CHECK(lines(r.err) == 1);
    CHECK_FALSE(fs::exists(d / "x.png"));
    r = gradmesh("info " + q(d / "nope.gmb"), d);
    CHECK(r.code == 1);
    r = gradmesh("compare " + q(d / "a.png") + " " + q(d / "b.png"), d);
    CHECK(r.code == 1);
}

TEST_CASE("an output path in a missing directory fails cleanly", "[cli]") {
    const fs::path d = tmpDir("nodir");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    for (const char* name : {"x.png", "x.gmb"}) {
        Run r = gradmesh("convert " + q(d / "s.gmb") + " -o " + q(d / "no" / "such" / name), d);
        CHECK(r.code == 1);
        CHECK_THAT(r.err, Contains("does not exist"));
    }
    CHECK_FALSE(fs::exists(d / "no"));
}

TEST_CASE("output equal to input is refused and the input survives", "[cli]") {
    const fs::path d = tmpDir("same");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    const std::string before = slurp((d / "s.gmb").string());
    Run r = gradmesh("convert " + q(d / "s.gmb") + " -o " + q(d / "." / "s.gmb") + " --compact", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("input"));
    CHECK(slurp((d / "s.gmb").string()) == before);
}

TEST_CASE("a corrupt input leaves no output behind", "[cli][malformed]") {
    const fs::path d = tmpDir("corrupt");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    std::string bytes = slurp((d / "s.gmb").string());
    bytes.resize(bytes.size() / 2);
    std::ofstream(d / "half.gmb", std::ios::binary) << bytes;
    Run r = gradmesh("convert " + q(d / "half.gmb") + " -o " + q(d / "out.png"), d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("half.gmb"));
    CHECK(lines(r.err) == 1);
    for (const auto& e : fs::directory_iterator(d)) {
        const std::string name = e.path().filename().string();
        if (name == "stdout.txt" || name == "stderr.txt") continue;
        CHECK_THAT(name, !Contains("out") && !Contains(".tmp"));
    }
    // Not a mesh file at all.
    std::ofstream(d / "text.gmb") << "hello, I am text\n";
    r = gradmesh("info " + q(d / "text.gmb"), d);
    CHECK(r.code == 1);
}

TEST_CASE("render, convert, info and compare work end to end", "[cli]") {
    const fs::path d = tmpDir("happy");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    Run r = gradmesh("info " + q(d / "s.gmb"), d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Contains("meshes: 2") && Contains("holes: 3") && Contains("legacy pieces: 5"));

    REQUIRE(gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "a.png"), d).code == 0);
    REQUIRE(gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "b.png") + " --scale 2 --background white", d).code == 0);
    const gm::RgbaImage a = gm::readImage((d / "a.png").string());
    const gm::RgbaImage b = gm::readImage((d / "b.png").string());
    CHECK(a.width == 512);
    CHECK(b.width == 1024);
    CHECK(b.at(2, 2)[3] == 1.0f);  // white background, opaque
    CHECK(a.at(2, 2)[3] == 0.0f);  // transparent outside the meshes
    // Mesh lines over the render: some pixels change, the size does not.
    REQUIRE(gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "l.png") + " --mesh-lines '#ff00ff'", d).code == 0);
    const gm::RgbaImage l = gm::readImage((d / "l.png").string());
    REQUIRE(l.width == a.width);
    size_t changed = 0;
    for (size_t k = 0; k < l.pixels.size(); ++k) changed += l.pixels[k] != a.pixels[k];
    CHECK(changed > 1000);
    CHECK(gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "m.png") + " --mesh-lines none", d).code == 2);

    REQUIRE(gradmesh("convert " + q(d / "s.gmb") + " -o " + q(d / "c.gmb") + " --compact", d).code == 0);
    REQUIRE(gradmesh("render " + q(d / "c.gmb") + " -o " + q(d / "c.png"), d).code == 0);
    r = gradmesh("compare " + q(d / "a.png") + " " + q(d / "c.png"), d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Contains("E: ") && Contains("PSNR: ") && Contains("uncovered: "));

    r = gradmesh("compare " + q(d / "a.png") + " " + q(d / "a.png"), d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Contains("E: 0.0000") && Contains("max: 0.00"));

    r = gradmesh("compare " + q(d / "a.png") + " " + q(d / "b.png"), d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("differs"));

    r = gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "x.svg"), d);
    CHECK(r.code == 2);
}
