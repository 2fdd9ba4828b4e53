// Temporaries: recognisable, unpredictable names created exclusively in the output's directory;
// a planted symlink is never followed; new files get 0666 minus the umask.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <regex>

#include "formats/atomic_file.h"
#include "formats/file_io.h"
#include "formats/temp_file.h"
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

