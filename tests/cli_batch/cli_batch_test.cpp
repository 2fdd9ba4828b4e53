// `gradmesh batch`: inputs from a directory, a glob and manifests; outputs byte for byte those
// of `convert`; the log; resuming after a deleted output and after SIGKILL; a bad image among
// good ones; --shard; the GNU parallel and Slurm recipes of docs/batch.md. The images are small
// crops of the samples, so that each conversion is quick.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "formats/raster.h"
#include "support/cli_run.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

fs::path tmpDir(const std::string& name) { return gmtest::scratchDir("cli_batch_", name); }

Run gradmesh(const std::string& args, const fs::path& dir) { return gmtest::runGradmesh(args, dir); }

void spit(const fs::path& p, const std::string& bytes) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f << bytes;
}

// A size x size crop of a sample at (x, y), transparent outside its inscribed disc (the object
// comes from the alpha channel), written to `to`.
void crop(const std::string& sample, int x, int y, int size, const fs::path& to) {
    const gm::RgbaImage src = gm::readImage(std::string(GRADMESH_SAMPLES) + "/" + sample);
    gm::RgbaImage out;
    out.width = out.height = size;
    out.pixels.resize(static_cast<size_t>(size) * size * 4);
    for (int r = 0; r < size; ++r)
        for (int c = 0; c < size; ++c) {
            const double dx = c + 0.5 - size / 2.0, dy = r + 0.5 - size / 2.0;
            const bool inside = dx * dx + dy * dy < 0.2 * size * size;
            for (int k = 0; k < 4; ++k)
                out.pixels[(static_cast<size_t>(r) * size + c) * 4 + k] =
                    k == 3 && !inside ? 0.f : src.pixels[(static_cast<size_t>(y + r) * src.width + x + c) * 4 + k];
        }
    gm::writeImage(out, to.string());
}

// Four small images in dir/in: a.png, b.png, c.PNG, d.png.
fs::path makeImages(const fs::path& dir) {
    const fs::path in = dir / "in";
    fs::create_directories(in);
    crop("pic1.png", 20, 20, 40, in / "a.png");
    crop("horse.png", 60, 40, 40, in / "b.png");
    crop("fruits.jpg", 100, 100, 40, in / "c.PNG");
    crop("HappyFish.jpg", 30, 30, 40, in / "d.png");
    return in;
}

std::vector<std::string> logLines(const fs::path& log) {
    std::vector<std::string> lines;
    std::istringstream s(slurp(log));
    for (std::string line; std::getline(s, line);) lines.push_back(line);
    return lines;
}

size_t countWith(const std::vector<std::string>& lines, const std::string& what) {
    return static_cast<size_t>(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) {
        return l.find(what) != std::string::npos;
    }));
}

// `convert IN -o OUT [options]` in dir/ref; the bytes of OUT.
std::string convertBytes(const fs::path& dir, const fs::path& in, const std::string& outName,
                         const std::string& options = "") {
    fs::create_directories(dir / "ref");
    const fs::path out = dir / "ref" / outName;
    const Run r = gradmesh("convert " + q(in) + " -o " + q(out) + " " + options, dir / "ref");
    INFO(r.err);
    REQUIRE(r.code == 0);
    return slurp(out);
}

std::set<std::string> temporaries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".gradmesh-tmp-") != std::string::npos)
            names.insert(e.path().string());
    return names;
}

}  // namespace

TEST_CASE("batch: a directory's images, the same bytes as convert, a record each") {
    const fs::path dir = tmpDir("directory");
    const fs::path in = makeImages(dir);
    const Run r = gradmesh("batch " + q(in) + " --output-dir " + q(dir / "out") + " --to gmb,svg", dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.empty());  // no progress on a pipe
    CHECK(r.out.empty());
    for (const char* stem : {"a", "b", "c", "d"}) {
        const fs::path image = in / (std::string(stem) + (stem == std::string("c") ? ".PNG" : ".png"));
        CHECK(slurp(dir / "out" / (std::string(stem) + ".gmb")) == convertBytes(dir, image, std::string(stem) + ".gmb"));
        CHECK(slurp(dir / "out" / (std::string(stem) + ".svg")) == convertBytes(dir, image, std::string(stem) + ".svg"));
    }
    const std::vector<std::string> log = logLines(dir / "out" / "gradmesh-batch.jsonl");
    REQUIRE(log.size() == 4);
    CHECK(countWith(log, "\"status\":\"ok\"") == 4);
    CHECK(countWith(log, "\"patches\":") == 4);
    CHECK(countWith(log, "\"E\":") == 4);
    CHECK(countWith(log, "\"error\":null") == 4);
    CHECK(temporaries(dir).empty());
}

TEST_CASE("batch: a glob pattern takes the files it matches") {
    const fs::path dir = tmpDir("glob");
    const fs::path in = makeImages(dir);
    const Run r = gradmesh("batch " + q((in / "*.png").string()) + " --output-dir " + q(dir / "out") +
                               " --log " + q(dir / "log.jsonl"),
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(fs::exists(dir / "out" / "a.gmb"));
    CHECK(fs::exists(dir / "out" / "d.gmb"));
    CHECK_FALSE(fs::exists(dir / "out" / "c.gmb"));  // c.PNG does not match
    CHECK(logLines(dir / "log.jsonl").size() == 3);
    const Run none = gradmesh("batch " + q((in / "*.tif").string()) + " --output-dir " + q(dir / "out"), dir);
    CHECK(none.code == 1);
    CHECK_THAT(none.err, Contains("matches no file"));
}

TEST_CASE("batch: a CSV manifest gives masks, options and output names") {
    const fs::path dir = tmpDir("csv");
    const fs::path in = makeImages(dir);
    const std::string mask = std::string(GRADMESH_SAMPLES) + "/apple_mask.png";
    fs::copy_file(std::string(GRADMESH_SAMPLES) + "/apple.jpg", in / "apple.jpg");
    spit(dir / "m.csv",
         "image,mask,options,output\n"
         "# a comment\n"
         "in/a.png,,--max-error 8,first\n"
         "in/apple.jpg," + mask + ",\"--max-patches 30 --colors hermite\",\n"
         "\"in/b.png\",,,\n");
    const Run r = gradmesh("batch " + q(dir / "m.csv") + " --output-dir " + q(dir / "out"), dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(slurp(dir / "out" / "first.gmb") == convertBytes(dir, in / "a.png", "first.gmb", "--max-error 8"));
    CHECK(slurp(dir / "out" / "apple.gmb") ==
          convertBytes(dir, in / "apple.jpg", "apple.gmb", "--mask " + q(mask) + " --max-patches 30 --colors hermite"));
    CHECK(slurp(dir / "out" / "b.gmb") == convertBytes(dir, in / "b.png", "b.gmb"));
    const std::string log = slurp(dir / "out" / "gradmesh-batch.jsonl");
    CHECK_THAT(log, Contains("\"mask\":\"" + mask + "\""));
    CHECK_THAT(log, Contains("--max-error=8"));
}

TEST_CASE("batch: a JSON-lines manifest, the command's options under each line's") {
    const fs::path dir = tmpDir("jsonl");
    makeImages(dir);
    spit(dir / "m.jsonl",
         "{\"image\": \"in/a.png\", \"options\": \"--max-error 8\"}\n"
         "\n"
         "{\"image\": \"in/c.PNG\", \"output\": \"sub/cee\", \"options\": [\"--max-patches\", \"20\"]}\n");
    const Run r = gradmesh("batch " + q(dir / "m.jsonl") + " --output-dir " + q(dir / "out") +
                               " --max-patches 50 --to svg",
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(slurp(dir / "out" / "a.svg") ==
          convertBytes(dir, dir / "in" / "a.png", "a.svg", "--max-patches 50 --max-error 8"));
    CHECK(slurp(dir / "out" / "sub" / "cee.svg") ==
          convertBytes(dir, dir / "in" / "c.PNG", "cee.svg", "--max-patches 20"));

    spit(dir / "bad.jsonl", "{\"image\": \"in/a.png\"}\n{\"image\": 3}\n");
    const Run bad = gradmesh("batch " + q(dir / "bad.jsonl") + " --output-dir " + q(dir / "out2"), dir);
    CHECK(bad.code == 1);
    CHECK_THAT(bad.err, Contains("bad.jsonl: line 2"));
    CHECK_FALSE(fs::exists(dir / "out2"));
}

TEST_CASE("batch: a rerun skips what is done and redoes a deleted output") {
    const fs::path dir = tmpDir("resume");
    const fs::path in = makeImages(dir);
    const std::string args = "batch " + q(in) + " --output-dir " + q(dir / "out") + " --to gmb,svg";
    REQUIRE(gradmesh(args, dir).code == 0);
    const std::string b = slurp(dir / "out" / "b.svg");
    const auto aTime = fs::last_write_time(dir / "out" / "a.gmb");
    fs::remove(dir / "out" / "b.svg");
    const Run again = gradmesh(args, dir);
    INFO(again.err);
    REQUIRE(again.code == 0);
    const std::vector<std::string> log = logLines(dir / "out" / "gradmesh-batch.jsonl");
    REQUIRE(log.size() == 8);
    const std::vector<std::string> second(log.begin() + 4, log.end());
    CHECK(countWith(second, "\"status\":\"skipped\"") == 3);
    CHECK(countWith(second, "\"status\":\"ok\"") == 1);
    CHECK(countWith(second, "b.svg\"],\"status\":\"ok\"") == 1);
    CHECK(slurp(dir / "out" / "b.svg") == b);
    CHECK(fs::last_write_time(dir / "out" / "a.gmb") == aTime);
    // Other options are another conversion: redone.
    const Run other = gradmesh(args + " --max-error 9", dir);
    REQUIRE(other.code == 0);
    CHECK(countWith(logLines(dir / "out" / "gradmesh-batch.jsonl"), "\"status\":\"ok\"") == 4 + 1 + 4);
}

TEST_CASE("batch: killed with SIGKILL mid-batch, a rerun completes it") {
    const fs::path dir = tmpDir("sigkill");
    const fs::path in = dir / "in";
    fs::create_directories(in);
    // Crops large enough that the batch takes seconds: the kill must come before its end.
    for (int k = 0; k < 8; ++k) crop("horse.png", 10 + 20 * k, 30, 160, in / ("h" + std::to_string(k) + ".png"));
    const fs::path out = dir / "out", log = out / "gradmesh-batch.jsonl";
    const std::string batch = std::string(GRADMESH_EXE) + " batch " + q(in) + " --output-dir " + q(out) +
                              " --to gmb,svg --jobs 2";
    // Killed once two images are logged: the others are being converted or not started.
    const std::string script = batch + " 2>/dev/null & pid=$!; for i in $(seq 600); do "
                               "[ \"$(cat " + q(log) + " 2>/dev/null | wc -l)\" -ge 2 ] && break; sleep 0.1; done; "
                               "kill -9 $pid; wait $pid; sleep 1";
    gmtest::runCommand("bash -c " + gmtest::quote(script));
    const size_t before = logLines(log).size();
    REQUIRE(before >= 2);
    REQUIRE(before < 8);
    const Run again = gradmesh("batch " + q(in) + " --output-dir " + q(out) + " --to gmb,svg", dir);
    INFO(again.err);
    REQUIRE(again.code == 0);
    const std::vector<std::string> all = logLines(log);
    const std::vector<std::string> second(all.begin() + static_cast<long>(before), all.end());
    CHECK(countWith(second, "\"status\":\"skipped\"") == before);  // nothing finished is lost
    CHECK(countWith(second, "\"status\":\"ok\"") == 8 - before);
    CHECK(temporaries(dir).empty());
    for (int k = 0; k < 8; ++k) {
        const std::string stem = "h" + std::to_string(k);
        CHECK(slurp(out / (stem + ".svg")) == convertBytes(dir, in / (stem + ".png"), stem + ".svg"));
    }
}

TEST_CASE("batch: a bad image among good ones is a record, the batch goes on") {
    const fs::path dir = tmpDir("bad_image");
    const fs::path in = makeImages(dir);
    spit(in / "corrupt.png", "\x89PNG\r\n\x1a\n not really");
    spit(dir / "m.csv", "in/a.png\nin/corrupt.png\nin/b.png,in/no_such_mask.png\nin/c.PNG,,--max-error x\nin/d.png\n");
    const Run r = gradmesh("batch " + q(dir / "m.csv") + " --output-dir " + q(dir / "out"), dir);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("3 of 5 images failed"));
    const std::vector<std::string> log = logLines(dir / "out" / "gradmesh-batch.jsonl");
    REQUIRE(log.size() == 5);
    CHECK(countWith(log, "\"status\":\"ok\"") == 2);
    CHECK(countWith(log, "\"status\":\"error\"") == 3);
    CHECK(countWith(log, "\"error\":\"" + (dir / "in" / "corrupt.png").lexically_normal().string()) == 1);
    CHECK(countWith(log, "no_such_mask.png") == 1);
    CHECK(countWith(log, "--max-error expects a number") == 1);
    CHECK(fs::exists(dir / "out" / "a.gmb"));
    CHECK(fs::exists(dir / "out" / "d.gmb"));
    CHECK_FALSE(fs::exists(dir / "out" / "corrupt.gmb"));
    CHECK(temporaries(dir).empty());
}

namespace {

// The file names of the images in a --dry-run's plan ("convert DIR/a.png -> ...").
std::vector<std::string> plannedImages(const std::string& plan) {
    std::vector<std::string> images;
    std::istringstream s(plan);
    for (std::string line; std::getline(s, line);) {
        const std::string image = line.substr(line.find(' ') + 1, line.find(" ->") - line.find(' ') - 1);
        images.push_back(fs::path(image).filename().string());
    }
    return images;
}

// The images `batch --dry-run --shard SHARD` would convert.
std::vector<std::string> shardImages(const fs::path& dir, const std::string& manifest, const std::string& shard) {
    const Run r = gradmesh("batch " + q(dir / manifest) + " --output-dir " + q(dir / "out") + " --dry-run --shard " + shard, dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return plannedImages(r.out);
}

std::string manifestOf(int n) {
    std::string m;
    for (int k = 0; k < n; ++k) m += "img" + std::to_string(k) + ".png\n";
    return m;
}

}  // namespace

TEST_CASE("batch: --shard i/n splits a manifest into disjoint parts that make the whole") {
    const fs::path dir = tmpDir("shard");
    spit(dir / "m.csv", manifestOf(23));
    const std::vector<std::string> whole = shardImages(dir, "m.csv", "0/1");
    REQUIRE(whole.size() == 23);
    CHECK(shardImages(dir, "m.csv", "1/3") == shardImages(dir, "m.csv", "1/3"));  // deterministic
    for (int n : {3, 7}) {
        std::multiset<std::string> together;
        for (int i = 0; i < n; ++i) {
            const std::vector<std::string> part = shardImages(dir, "m.csv", std::to_string(i) + "/" + std::to_string(n));
            CHECK(part.size() <= 23 / n + 1);
            together.insert(part.begin(), part.end());
        }
        CHECK(together == std::multiset<std::string>(whole.begin(), whole.end()));
    }
    CHECK(shardImages(dir, "m.csv", "25/30").empty());
    for (const char* bad : {"2/2", "1/0", "a/b", "1/2/3"}) {
        const Run r = gradmesh("batch " + q(dir / "m.csv") + " --output-dir " + q(dir / "out") + " --shard " + bad, dir);
        CHECK(r.code == 2);
        CHECK_THAT(r.err, Contains("--shard"));
    }
}

TEST_CASE("batch: the GNU parallel recipe converts every shard") {
    const fs::path dir = tmpDir("parallel");
    if (gmtest::runCommand("command -v parallel >/dev/null") != 0) {
        WARN("GNU parallel is not installed (scripts/install-deps.sh installs it)");
        return;
    }
    const fs::path in = makeImages(dir);
    spit(dir / "m.csv", "in/a.png\nin/b.png\nin/c.PNG\nin/d.png\n");
    // docs/batch.md's recipe, two shards on this machine.
    const std::string recipe = "cd " + q(dir) + " && parallel --halt never " + std::string(GRADMESH_EXE) +
                               " batch m.csv --output-dir out --jobs 1 --shard {}/2 --log out/log-{}.jsonl ::: 0 1";
    REQUIRE(gmtest::runCommand("bash -c " + gmtest::quote(recipe) + " >/dev/null 2>&1") == 0);
    CHECK(logLines(dir / "out" / "log-0.jsonl").size() == 2);
    CHECK(logLines(dir / "out" / "log-1.jsonl").size() == 2);
    for (const char* image : {"a.png", "b.png", "c.PNG", "d.png"}) {
        const std::string stem = fs::path(image).stem().string();
        CHECK(slurp(dir / "out" / (stem + ".gmb")) == convertBytes(dir, in / image, stem + ".gmb"));
    }
}

TEST_CASE("batch: the Slurm array script gives task k shard k of n") {
    const fs::path dir = tmpDir("slurm");
    spit(dir / "m.csv", manifestOf(10));
    const std::string script = std::string(GRADMESH_RECIPES) + "/gradmesh_array.sbatch";
    // --array=0-3, --array=1-4 and --array=0-6:2: four tasks each.
    for (const auto& [first, step] : std::vector<std::pair<int, int>>{{0, 1}, {1, 1}, {0, 2}}) {
        std::multiset<std::string> together;
        for (int t = 0; t < 4; ++t) {
            const int id = first + t * step;
            const std::string env = "SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " SLURM_ARRAY_TASK_COUNT=4 SLURM_ARRAY_TASK_MIN=" +
                                    std::to_string(first) + " SLURM_ARRAY_TASK_STEP=" + std::to_string(step) +
                                    " GRADMESH=" + std::string(GRADMESH_EXE);
            const fs::path outFile = dir / "task.txt";
            const int rc = gmtest::runCommand("cd " + q(dir) + " && env " + env + " bash " + gmtest::quote(script) +
                                              " m.csv out --dry-run >" + q(outFile) + " 2>&1");
            INFO(slurp(outFile));
            REQUIRE(rc == 0);
            const std::vector<std::string> part = plannedImages(slurp(outFile));
            CHECK(part == shardImages(dir, "m.csv", std::to_string(t) + "/4"));
            together.insert(part.begin(), part.end());
        }
        CHECK(together.size() == 10);
        CHECK(std::set<std::string>(together.begin(), together.end()).size() == 10);
    }
    CHECK(gmtest::runCommand("bash " + gmtest::quote(script) + " m.csv out >/dev/null 2>&1") != 0);  // not an array task
}

TEST_CASE("batch: usage errors") {
    const fs::path dir = tmpDir("usage");
    const fs::path in = makeImages(dir);
    for (const std::string& args :
         {std::string("batch ") + q(in), "batch " + q(in) + " --output-dir o -o x.gmb", "batch " + q(in) + " --output-dir o --to doc",
          "batch " + q(in) + " --output-dir o --mask m.png", "batch " + q(in) + " --output-dir o --jobs 0",
          "batch " + q(in) + " --output-dir o --max-error x", std::string("batch --output-dir o")}) {
        const Run r = gradmesh(args, dir);
        INFO(args << ": " << r.err);
        CHECK(r.code == 2);
        CHECK(gmtest::lineCount(r.err) == 1);
        CHECK_FALSE(fs::exists(dir / "o"));
    }
    spit(dir / "m.csv", "in/a.png\nin/a.png\n");
    const Run clash = gradmesh("batch " + q(dir / "m.csv") + " --output-dir o", dir);
    CHECK(clash.code == 2);
    CHECK_THAT(clash.err, Contains("would both write"));
}

TEST_CASE("batch: an output that would overwrite its input is refused") {
    const fs::path dir = tmpDir("overwrite");
    const fs::path in = dir / "in";
    fs::create_directories(in);
    crop("pic1.png", 20, 20, 40, in / "a.png");
    const std::string before = slurp(in / "a.png");
    const Run r = gradmesh("batch " + q(in) + " --output-dir " + q(in) + " --to png --log " + q(dir / "log.jsonl"), dir);
    CHECK(r.code == 1);
    CHECK(slurp(in / "a.png") == before);
    CHECK_THAT(slurp(dir / "log.jsonl"), Contains("would overwrite an input"));
}
