// convert and render as the tools users script take them (potrace, ImageMagick): `-` for
// standard input and standard output, --to FORMAT, several inputs into --output-dir, --quiet,
// --verbose and the progress line on a terminal (and none on a pipe).
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "formats/raster.h"
#include "support/cli_run.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

fs::path scratch(const std::string& name) { return gmtest::scratchDir("cli_streams_", name); }

// A shaded disc on a transparent background: one small region, converted in a fraction of a
// second.
fs::path writeDisc(const fs::path& dir, const std::string& name = "disc.png") {
    const int w = 48, h = 40;
    gm::RgbaImage img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.at(x, y);
            const double dx = (x + 0.5 - w / 2.0) / (0.4 * w), dy = (y + 0.5 - h / 2.0) / (0.4 * h);
            p[0] = 0.2f + 0.6f * x / w;
            p[1] = 0.3f + 0.5f * y / h;
            p[2] = 0.5f;
            p[3] = dx * dx + dy * dy <= 1.0 ? 1.f : 0.f;
        }
    const fs::path path = dir / name;
    gm::writeImage(img, path.string());
    return path;
}

// `gradmesh ARGS` in `dir`, standard input from `in` (/dev/null when empty), standard output
// and error captured.
Run gradmeshWithInput(const std::string& args, const fs::path& dir, const std::string& in = "") {
    const fs::path out = dir / "stdout.bin", err = dir / "stderr.txt";
    Run r;
    r.code = gmtest::runCommand("cd " + q(dir) + " && timeout -k 5 60 " + GRADMESH_EXE + " " + args +
                                " <" + (in.empty() ? std::string("/dev/null") : q(in)) + " >" + q(out) +
                                " 2>" + q(err));
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

// No temporary of ours is left in `tmp` (the run's TMPDIR).
void checkNoTemporaries(const fs::path& tmp) {
    for (const auto& e : fs::directory_iterator(tmp)) FAIL("left behind: " << e.path());
}

}  // namespace

TEST_CASE("convert - -o - --to F gives the bytes of the file route: svg, pdf, gmb, svgz, eps, png") {
    const fs::path dir = scratch("stdio");
    const fs::path disc = writeDisc(dir);
    // An image on standard input.
    for (const std::string format : {"svg", "pdf", "gmb"}) {
        INFO(format);
        REQUIRE(gradmeshWithInput("convert disc.png -o file." + format, dir).code == 0);
        const Run streamed = gradmeshWithInput("convert - -o - --to " + format, dir, disc.string());
        INFO(streamed.err);
        CHECK(streamed.code == 0);
        CHECK(streamed.out == slurp(dir / ("file." + format)));
    }
    // A mesh file on standard input.
    const std::string gmb = (dir / "file.gmb").string();
    for (const std::string format : {"svgz", "eps"}) {
        INFO(format);
        REQUIRE(gradmeshWithInput("convert file.gmb -o mesh." + format, dir).code == 0);
        const Run streamed = gradmeshWithInput("convert - -o - --to " + format, dir, gmb);
        CHECK(streamed.code == 0);
        CHECK(streamed.out == slurp(dir / ("mesh." + format)));
    }
    const Run render = gradmeshWithInput("render - -o - --to png", dir, gmb);
    CHECK(render.code == 0);
    REQUIRE(gradmeshWithInput("render file.gmb -o render.png", dir).code == 0);
    CHECK(render.out == slurp(dir / "render.png"));
    const Run info = gradmeshWithInput("info -", dir, gmb);
    CHECK(info.code == 0);
    CHECK_THAT(info.out, Contains("file: <stdin>") && Contains("format: gmb"));
    // --to for a name without the format's extension; not against the name's own format.
    REQUIRE(gradmeshWithInput("convert file.gmb -o noext --to eps", dir).code == 0);
    CHECK(slurp(dir / "noext") == slurp(dir / "mesh.eps"));
    const Run clash = gradmeshWithInput("convert file.gmb -o x.png --to svg", dir);
    CHECK(clash.code == 2);
    CHECK_THAT(clash.err, Contains("--to says svg"));
}

TEST_CASE("streams: no temporary is left in TMPDIR, on success or failure") {
    const fs::path dir = scratch("tmpdir");
    const fs::path tmp = dir / "tmp";
    fs::create_directories(tmp);
    const fs::path disc = writeDisc(dir);
    const std::string env = "env TMPDIR=" + q(tmp) + " ";
    const int bad = gmtest::runCommand("cd " + q(dir) + " && " + env + GRADMESH_EXE +
                                       " convert - -o - --to svg --max-error x <" + q(disc) +
                                       " >/dev/null 2>&1");
    CHECK(bad == 2);
    const int good = gmtest::runCommand("cd " + q(dir) + " && " + env + GRADMESH_EXE +
                                        " convert - -o - --to svg <" + q(disc) + " >out.svg 2>/dev/null");
    CHECK(good == 0);
    CHECK(fs::file_size(dir / "out.svg") > 0);
    // Interrupted while converting: SIGTERM removes the spooled input, the output's temporary
    // and their directory (a run that ends first leaves nothing either).
    const std::string pic = (fs::path(GRADMESH_SAMPLES) / "pic1.png").string();
    gmtest::runCommand("cd " + q(dir) + " && " + env + GRADMESH_EXE + " convert - -o - --to svg --segment <" +
                       q(pic) + " >/dev/null 2>&1 & p=$!; sleep 1; kill -TERM $p; wait $p");
    checkNoTemporaries(tmp);
}

TEST_CASE("streams: bad standard input and -o - without --to are clear errors") {
    const fs::path dir = scratch("bad");
    const fs::path text = dir / "notes.txt";
    std::ofstream(text) << "hello, not an image\n";
    Run r = gradmeshWithInput("convert - -o out.svg", dir, text.string());
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("<stdin>: not an image"));
    CHECK(gmtest::lineCount(r.err) == 1);
    CHECK_FALSE(fs::exists(dir / "out.svg"));
    r = gradmeshWithInput("convert - -o - --to svg", dir);  // empty
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("<stdin>: empty"));
    CHECK(r.out.empty());
    const fs::path disc = writeDisc(dir);
    r = gradmeshWithInput("convert - -o -", dir, disc.string());
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("needs --to"));
    CHECK(r.out.empty());
    // A PNG cut short: the decoder's complaint names <stdin>, nothing on standard output.
    const std::string bytes = slurp(disc);
    std::ofstream(dir / "cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    r = gradmeshWithInput("convert - -o - --to svg", dir, (dir / "cut.png").string());
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("<stdin>"));
    CHECK(r.out.empty());
}

TEST_CASE("convert IN... --output-dir: each as alone, a bad one does not stop the others") {
    const fs::path dir = scratch("several");
    writeDisc(dir, "a.png");
    writeDisc(dir, "b.png");
    std::ofstream(dir / "bad.png") << "not a png";
    REQUIRE(gradmeshWithInput("convert a.png -o alone.svg", dir).code == 0);
    const Run r = gradmeshWithInput("convert a.png bad.png b.png --output-dir out --to svg", dir);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("bad.png"));
    CHECK(slurp(dir / "out/a.svg") == slurp(dir / "alone.svg"));
    CHECK(slurp(dir / "out/b.svg") == slurp(dir / "alone.svg"));
    CHECK_FALSE(fs::exists(dir / "out/bad.svg"));
    // Two inputs that would write the same output: refused before any work.
    fs::create_directories(dir / "sub");
    writeDisc(dir / "sub", "a.png");
    CHECK(gradmeshWithInput("convert a.png sub/a.png --output-dir clash", dir).code == 2);
    CHECK_FALSE(fs::exists(dir / "clash"));
}

TEST_CASE("verbosity: --quiet prints nothing on success, --verbose prints the stages") {
    const fs::path dir = scratch("verbosity");
    writeDisc(dir);
    Run r = gradmeshWithInput("convert disc.png -o q.svg --colors hermite --quiet", dir);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    r = gradmeshWithInput("convert disc.png -o n.svg --colors hermite", dir);
    CHECK_THAT(r.err, Contains("refitted"));  // the note --quiet silenced
    r = gradmeshWithInput("convert disc.png -o v.svg --verbose", dir);
    CHECK(r.code == 0);
    for (const char* stage : {"read", "mask", "regions", "mesh", "write", "end to end", "patches"})
        CHECK_THAT(r.err, Contains(stage));
    r = gradmeshWithInput("info q.svg --quiet", dir);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains("meshes:"));
    r = gradmeshWithInput("render q.svg -o r.png --verbose", dir);
    CHECK_THAT(r.err, Contains("render"));
}

TEST_CASE("progress: a line on a terminal for a run over a second, none on a pipe") {
    const fs::path dir = scratch("progress");
    const std::string run = std::string(GRADMESH_EXE) + " convert " + q(fs::path(GRADMESH_SAMPLES) / "pic1.png") +
                            " -o " + q(dir / "pic1.gmb") + " --segment --threads 1";
    // script(1) gives the run a pseudo-terminal; its output is the terminal's.
    const auto start = std::chrono::steady_clock::now();
    REQUIRE(gmtest::runCommand("script -qfec " + q(run) + " /dev/null >" + q(dir / "tty.txt")) == 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string tty = slurp(dir / "tty.txt");
    if (seconds > 1.5) {  // else the run was too short to show any
        CHECK_THAT(tty, Contains("\rgradmesh convert pic1.png: regions ") && Contains("/"));
        CHECK_THAT(tty, Contains("\r\x1b[K"));  // erased at the end
    } else {
        WARN("the conversion took " << seconds << " s: too short to check the progress line");
    }
    REQUIRE(gmtest::runCommand(run + " 2>" + q(dir / "pipe.txt")) == 0);
    CHECK(slurp(dir / "pipe.txt").empty());
    // --quiet: no progress on a terminal either.
    REQUIRE(gmtest::runCommand("script -qfec " + q(run + " --quiet") + " /dev/null >" + q(dir / "quiet.txt")) == 0);
    CHECK(slurp(dir / "quiet.txt").empty());
}
