// Killed runs (issue 27, case 4): SIGINT and SIGTERM remove the run's temporaries; after a
// SIGKILL the next run removes them.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include "cli_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;
using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

TEST_CASE("case 4: SIGKILL leaves a recognisable temporary that the next run removes",
          "[output_safety][cli]") {
    const fs::path d = tmpDir("cli_sigkill");
    const std::vector<std::string> args = {"convert", kApple, "--mask", kAppleMask, "-o",
                                           (d / "out.gmb").string(), "--report",
                                           (d / "r.json").string()};
    Background run(args, d);
    const std::string temp = waitForEntry(d, ".out.gmb.gradmesh-tmp-", run);
    REQUIRE_FALSE(temp.empty());
    ::kill(run.pid(), SIGKILL);
    run.wait();
    CHECK(fs::exists(d / temp));  // a kill cannot be cleaned up at the time
    const Run again = gradmesh(convertApple(d / "out.gmb", (d / "r.json").string()), d);
    CHECK(again.code == 0);
    CHECK(temporaries(d).empty());
    CHECK(fs::exists(d / "out.gmb"));
}

TEST_CASE("case 4: SIGTERM and SIGINT remove the run's temporaries before it exits",
          "[output_safety][cli]") {
    for (int sig : {SIGTERM, SIGINT}) {
        INFO("signal " << sig);
        const fs::path d = tmpDir("cli_sig" + std::to_string(sig));
        spit(d / "out.gmb", "precious");
        Background run({"convert", kApple, "--mask", kAppleMask, "-o", (d / "out.gmb").string(),
                        "--report", (d / "r.json").string()},
                       d);
        const std::string temp = waitForEntry(d, ".out.gmb.gradmesh-tmp-", run);
        REQUIRE_FALSE(temp.empty());
        ::kill(run.pid(), sig);
        const int status = run.wait();
        CHECK(WIFSIGNALED(status));
        CHECK(WTERMSIG(status) == sig);
        for (const std::string& left : temporaries(d)) FAIL_CHECK("left behind: " << left);
        CHECK(slurp(d / "out.gmb") == "precious");
    }
}

