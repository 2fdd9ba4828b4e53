// Hostile inputs at the command line (issue 27, case 6): special files are refused instead of
// read.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include "cli_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;
using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

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
