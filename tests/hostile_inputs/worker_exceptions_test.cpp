// Exceptions on worker threads reach the caller: an exception leaving a std::thread's function
// would end the process with SIGABRT.
#include <catch2/catch.hpp>

#include <atomic>
#include <new>
#include <string>

#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "support/cli_run.h"

using namespace gm;

TEST_CASE("parallelFor rethrows a worker's exception on the caller", "[hostile][threads]") {
    std::atomic<int> ran{0};
    // Item 5 throws on whichever thread takes it; the others may still run.
    CHECK_THROWS_AS(parallelFor(64, 4,
                                [&](int k, int) {
                                    ++ran;
                                    if (k == 5) throw std::bad_alloc();
                                }),
                    std::bad_alloc);
    CHECK(ran >= 1);
    CHECK_THROWS_WITH(parallelFor(8, 3, [](int k, int) {
                          if (k % 2) throw Error("worker " + std::to_string(k) + " failed");
                      }),
                      Catch::Contains("failed"));
    int sum = 0;
    parallelFor(10, 1, [&](int k, int) { sum += k; });  // one thread: in order, here
    CHECK(sum == 45);
}

TEST_CASE("out of memory on a worker is a clean error, never an abort", "[hostile][threads][cli]") {
    // Under an address-space limit GrabCut's allocations on the segmentation's workers fail
    // now and then; whatever fails, the command must exit 0 or 1 with a message.
    const auto dir = gmtest::scratchDir("hostile_", "worker_oom");
    const std::string in = std::string(GRADMESH_SAMPLES) + "/fruits.jpg";
    int failedCleanly = 0;
    for (const int megabytes : {480, 520, 560, 640, 800}) {
        const long kilobytes = megabytes * 1024L;
        // Below ~460 MB the shared libraries' own start-up (thread pools made before main)
        // already fails: such a limit tests nothing of ours.
        if (gmtest::runCommand("ulimit -v " + std::to_string(kilobytes) + " && exec " +
                               GRADMESH_EXE + " --version >/dev/null 2>&1") != 0)
            continue;
        const auto out = dir / "out.gmb";
        const std::string err = (dir / "stderr.txt").string();
        // The shell's ulimit -v (kB) rather than prlimit, which cannot run in some containers.
        const int code = gmtest::runCommand(
            std::string("ulimit -v ") + std::to_string(kilobytes) + " && exec timeout -k 5 120 " +
            GRADMESH_EXE + " convert " + gmtest::q(in) + " --segment --threads 4 -o " +
            gmtest::q(out) + " 2>" + gmtest::quote(err) + " </dev/null >/dev/null");
        const std::string message = gmtest::slurp(err);
        INFO(megabytes << " MB: exit " << code << ": " << message);
        CHECK((code == 0 || code == 1));
        CHECK(message.find("terminate called") == std::string::npos);
        if (code == 1) {
            CHECK(message.find("out of memory") != std::string::npos);
            CHECK(!std::filesystem::exists(out));
            ++failedCleanly;
        }
    }
    WARN(failedCleanly << " of the limits ran out of memory");
}
