// The writer's own I/O layer: every output of a run is written whole before any takes its name;
// a write, fsync or close that fails (a full disk) leaves no file and the old one as it was.
#include <catch2/catch.hpp>

#include <cerrno>

#include "formats/atomic_file.h"
#include "formats/file_io.h"
#include "meshcore/error.h"
#include "output_safety_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;

namespace {

// Fails every write after this many bytes with ENOSPC, as a full disk does.
size_t g_bytesLeft = 0;
ssize_t writeUntilFull(int fd, const void* data, size_t size) {
    if (g_bytesLeft == 0) {
        errno = ENOSPC;
        return -1;
    }
    const size_t n = std::min(size, g_bytesLeft);
    g_bytesLeft -= n;
    return ::write(fd, data, n);
}
int fsyncFails(int) {
    errno = EIO;
    return -1;
}
int closeFails(int fd) {
    ::close(fd);
    errno = EIO;
    return -1;
}

}  // namespace

TEST_CASE("a batch whose second output cannot be created leaves the first target untouched",
          "[output_safety]") {
    const fs::path d = tmpDir("batch_reserve");
    spit(d / "out.gmb", "precious");
    gm::OutputBatch batch;
    batch.reserve((d / "out.gmb").string());
    CHECK_THROWS_AS(batch.reserve("/proc/gradmesh-test-report.json"), gm::Error);
    CHECK(gmtest::slurp(d / "out.gmb") == "precious");
}

TEST_CASE("a batch failing at its last write renames nothing and removes every temporary",
          "[output_safety]") {
    const fs::path d = tmpDir("batch_late");
    spit(d / "out.gmb", "precious");
    spit(d / "r.json", "old report");
    {
        gm::OutputBatch batch;
        batch.write((d / "out.gmb").string(), std::string(10000, 'x'));
        g_bytesLeft = 100;
        gm::ScopedFileIo io({&writeUntilFull, &::fsync, &::close});
        CHECK_THROWS_WITH(batch.write((d / "r.json").string(), std::string(5000, 'y')),
                          Contains("r.json") && Contains("No space left on device"));
    }
    CHECK(gmtest::slurp(d / "out.gmb") == "precious");
    CHECK(gmtest::slurp(d / "r.json") == "old report");
    CHECK(temporaries(d).empty());
}

TEST_CASE("a full disk, a failing fsync or close: no file at the target, the old one kept",
          "[output_safety]") {
    const fs::path d = tmpDir("failing_io");
    const std::string target = (d / "out.png").string();
    spit(target, "precious");
    SECTION("write") {
        g_bytesLeft = 4096;  // the truncated PNG was 4,096 bytes
        gm::ScopedFileIo io({&writeUntilFull, &::fsync, &::close});
        CHECK_THROWS_WITH(gm::writeFileAtomically(target, std::string(100000, 'p')),
                          Contains("out.png") && Contains("No space left"));
    }
    SECTION("fsync") {
        gm::ScopedFileIo io({&::write, &fsyncFails, &::close});
        CHECK_THROWS_WITH(gm::writeFileAtomically(target, "new"), Contains("fsync"));
    }
    SECTION("close") {
        gm::ScopedFileIo io({&::write, &::fsync, &closeFails});
        CHECK_THROWS_WITH(gm::writeFileAtomically(target, "new"), Contains("close"));
    }
    CHECK(gmtest::slurp(target) == "precious");
    CHECK(entries(d) == std::set<std::string>{"out.png"});
}

TEST_CASE("a really full filesystem (a small tmpfs) fails the write cleanly", "[output_safety]") {
    const fs::path d = tmpDir("tmpfs_full");
    SmallTmpfs small(d, 64 * 1024);
    if (!small.mounted()) {
        WARN("cannot mount a tmpfs here; the injected failures above stand in for it");
        return;
    }
    const std::string target = (d / "out.gmb").string();
    spit(target, "precious");
    CHECK_THROWS_WITH(gm::writeFileAtomically(target, std::string(200 * 1024, 'z')),
                      Contains("out.gmb") && Contains("No space left"));
    CHECK(gmtest::slurp(target) == "precious");
    CHECK(entries(d) == std::set<std::string>{"out.gmb"});
}
