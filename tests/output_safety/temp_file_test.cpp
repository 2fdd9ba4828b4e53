// Temporaries: recognisable, unpredictable names created exclusively in the output's directory;
// a planted symlink is never followed; new files get 0666 minus the umask; temporaries of runs
// that died are removed by the next run; SIGTERM removes the live ones.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <regex>

#include "formats/atomic_file.h"
#include "formats/file_io.h"
#include "formats/temp_file.h"
#include "formats/temp_registry.h"
#include "meshcore/error.h"
#include "output_safety_support.h"

using namespace safetytest;

namespace {

// The directory's entries seen from inside a write, while the temporary exists.
std::set<std::string> g_seen;
fs::path g_watched;
ssize_t writeAndLook(int fd, const void* data, size_t size) {
    g_seen = entries(g_watched);
    return ::write(fd, data, size);
}

// A PID that no process has: a child that has exited and been reaped.
pid_t deadPid() {
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    ::waitpid(pid, nullptr, 0);
    return pid;
}

}  // namespace

TEST_CASE("a temporary is named .NAME.gradmesh-tmp-PID-XXXXXX beside its target",
          "[output_safety]") {
    g_watched = tmpDir("names");
    gm::ScopedFileIo io({&writeAndLook, &::fsync, &::close});
    gm::writeFileAtomically((g_watched / "out.gmb").string(), "bytes");
    REQUIRE(g_seen.size() == 1);
    const std::regex pattern("\\.out\\.gmb\\.gradmesh-tmp-" + std::to_string(::getpid()) +
                             "-[A-Za-z0-9]{6}");
    CHECK(std::regex_match(*g_seen.begin(), pattern));
    CHECK(entries(g_watched) == std::set<std::string>{"out.gmb"});
}

TEST_CASE("two temporaries of one target get different names", "[output_safety]") {
    const fs::path d = tmpDir("unique");
    gm::TempFile a((d / "x.svg").string()), b((d / "x.svg").string());
    CHECK(a.path() != b.path());
    CHECK(fs::exists(a.path()));
    CHECK(fs::exists(b.path()));
}

TEST_CASE("a symlink at the target is replaced, its target never written", "[output_safety]") {
    const fs::path d = tmpDir("symlink_target");
    spit(d / "victim", "unrelated");
    fs::create_symlink(d / "victim", d / "out.gmb");
    gm::writeFileAtomically((d / "out.gmb").string(), "new");
    CHECK(gmtest::slurp(d / "victim") == "unrelated");
    CHECK(fs::is_regular_file(fs::symlink_status(d / "out.gmb")));
    CHECK(gmtest::slurp(d / "out.gmb") == "new");
}

TEST_CASE("a new output's mode is 0666 minus the umask", "[output_safety]") {
    const fs::path d = tmpDir("mode");
    spit(d / "old.gmb", "old");
    fs::permissions(d / "old.gmb", fs::perms::owner_read | fs::perms::owner_write);
    const mode_t saved = ::umask(027);
    gm::writeFileAtomically((d / "new.gmb").string(), "new");
    gm::writeFileAtomically((d / "old.gmb").string(), "replaced");
    ::umask(saved);
    struct stat st {};
    REQUIRE(::stat((d / "new.gmb").c_str(), &st) == 0);
    CHECK((st.st_mode & 07777) == 0640);
    REQUIRE(::stat((d / "old.gmb").c_str(), &st) == 0);
    CHECK((st.st_mode & 07777) == 0640);  // a new file, not the replaced one's 0600
}

TEST_CASE("stale temporaries of the same target are removed, others kept", "[output_safety]") {
    const fs::path d = tmpDir("stale");
    const std::string dead = std::to_string(deadPid());
    const std::string alive = std::to_string(::getppid());
    const std::string staleName = ".out.gmb.gradmesh-tmp-" + dead + "-AbC123";
    const std::string liveName = ".out.gmb.gradmesh-tmp-" + alive + "-AbC123";
    const std::string otherTarget = ".other.gmb.gradmesh-tmp-" + dead + "-AbC123";
    const std::string notOurs = ".out.gmb.gradmesh-tmp-" + dead + "-toolong";
    for (const std::string& n : {staleName, liveName, otherTarget, notOurs}) spit(d / n, "x");
    gm::writeFileAtomically((d / "out.gmb").string(), "new");
    CHECK(entries(d) == std::set<std::string>{"out.gmb", liveName, otherTarget, notOurs});
}

TEST_CASE("SIGTERM removes the live temporaries before the process dies", "[output_safety]") {
    const fs::path d = tmpDir("sigterm");
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    const pid_t child = ::fork();
    if (child == 0) {
        // Only async-signal-safe exits from here: the child must never return into Catch.
        ::close(fds[0]);
        ::signal(SIGTERM, SIG_DFL);  // as a shell may have left it ignored
        gm::removeTemporariesOnSignals();
        try {
            gm::TempFile a((d / "a.gmb").string()), b((d / "b.png").string());
            if (::write(fds[1], "1", 1) != 1) ::_exit(3);
            ::pause();  // the parent's SIGTERM arrives here, with both temporaries open
        } catch (...) {
        }
        ::_exit(4);
    }
    ::close(fds[1]);
    char ready = 0;
    REQUIRE(::read(fds[0], &ready, 1) == 1);
    ::close(fds[0]);
    CHECK(temporaries(d).size() == 2);
    ::kill(child, SIGTERM);
    int status = 0;
    ::waitpid(child, &status, 0);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGTERM);
    CHECK(temporaries(d).empty());
}
