// Hostile inputs at the command line (issue 27, cases 5-6): messages cannot drive the terminal,
// and special files are refused instead of read.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include "cli_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;
using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

TEST_CASE("case 5: escape sequences from the input are escaped in error messages",
          "[output_safety][cli][malformed]") {
    const fs::path d = tmpDir("cli_escapes");
    const std::string hostile = "\x1b]0;title\x07\x1b[2J";
    spit(d / "evil.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + hostile +
                             "\" viewBox=\"0 0 0 0\"/>\n");
    Run r = gradmesh("info " + q(d / "evil.svg"), d);
    checkFailedCleanly(r, "\\x1b]0;title\\x07\\x1b[2J");
    CHECK(r.err.find('\x1b') == std::string::npos);
    CHECK(r.err.find('\x07') == std::string::npos);

    // The same in a file name, and in an unknown command.
    r = gradmesh("info " + q((d / ("no" + hostile + ".svg")).string()), d);
    checkFailedCleanly(r, "no\\x1b]0;title");
    CHECK(r.err.find('\x1b') == std::string::npos);
    r = gradmesh(q(hostile), d);
    CHECK(r.code == 2);
    CHECK(r.err.find('\x1b') == std::string::npos);
}

TEST_CASE("case 6: a FIFO or a device is refused at once, not read", "[output_safety][cli]") {
    const fs::path d = tmpDir("cli_fifo");
    REQUIRE(::mkfifo((d / "fifo.svg").c_str(), 0600) == 0);
    REQUIRE(::mkfifo((d / "fifo.png").c_str(), 0600) == 0);
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    const std::vector<std::pair<std::string, std::string>> runs = {
        {"info " + q(d / "fifo.svg"), "FIFO"},
        {"convert " + q(d / "fifo.png") + " -o " + q(d / "x.gmb"), "FIFO"},
        {"convert " + q(kApple) + " --mask " + q(d / "fifo.png") + " -o " + q(d / "x.gmb"), "FIFO"},
        {"render " + q(d / "fifo.svg") + " -o " + q(d / "x.png"), "FIFO"},
        {"compare " + q(d / "fifo.png") + " " + q(kApple), "FIFO"},
        {"info /dev/zero", "character device"},
        {"convert /dev/zero -o " + q(d / "x.gmb"), "character device"},
        {"info " + q(d), "directory"},
    };
    for (const auto& [args, what] : runs) {
        INFO(args);
        const Run r = gradmesh(args, d);  // a hang would show as exit 124 after 60 s
        checkFailedCleanly(r, what);
        CHECK_THAT(r.err, Contains("not a regular file"));
    }
    CHECK_FALSE(fs::exists(d / "x.gmb"));
    CHECK_FALSE(fs::exists(d / "x.png"));
}
