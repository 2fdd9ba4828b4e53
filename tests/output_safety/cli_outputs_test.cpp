// The command line's outputs (issue 27, cases 1-3): an existing output survives any failed run,
// a full disk leaves no truncated file, and temporaries cannot be hijacked by planted symlinks.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include "cli_support.h"

using namespace safetytest;
using Catch::Matchers::Contains;
using gmtest::q;
using gmtest::Run;
using gmtest::slurp;

TEST_CASE("case 1: an existing output survives a report that cannot be written",
          "[output_safety][cli]") {
    const fs::path d = tmpDir("cli_late_failure");
    spit(d / "out.gmb", "precious");
    Run r = gradmesh(convertApple(d / "out.gmb", "/proc/r.json"), d);
    checkFailedCleanly(r, "r.json");
    CHECK(slurp(d / "out.gmb") == "precious");
    CHECK(temporaries(d).empty());

    // A report into a read-only directory: a read-only mount (root ignores a directory's mode).
    const fs::path ro = d / "readonly";
    fs::create_directories(ro);
    SmallTmpfs mount(ro, 4096, /*readOnly=*/true);
    if (!mount.mounted()) {
        if (::geteuid() == 0) {
            WARN("cannot mount a read-only tmpfs and root writes anywhere: read-only case skipped");
            return;
        }
        fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    }
    r = gradmesh(convertApple(d / "out.gmb", (ro / "r.json").string()), d);
    checkFailedCleanly(r, "r.json");
    CHECK(slurp(d / "out.gmb") == "precious");
    CHECK(temporaries(d).empty());
}

TEST_CASE("case 2: a full disk leaves neither a truncated output nor a temporary",
          "[output_safety][cli]") {
    const fs::path d = tmpDir("cli_disk_full");
    REQUIRE(gradmesh("sample " + q(d / "s.gmb"), d).code == 0);
    // The kernel refusing writes past a file size limit, as a full disk does: runs everywhere.
    spit(d / "render.png", "precious");
    Run r = gradmesh("render " + q(d / "s.gmb") + " -o " + q(d / "render.png"), d);
    REQUIRE(r.code == 0);
    const std::string good = slurp(d / "render.png");
    spit(d / "render.png", "precious");
    r.code = gmtest::runCommand("prlimit --fsize=4096 " + std::string(GRADMESH_EXE) + " render " +
                                q(d / "s.gmb") + " -o " + q(d / "render.png") + " 2>" +
                                q(d / "stderr.txt"));
    r.err = slurp(d / "stderr.txt");
    checkFailedCleanly(r, "render.png");
    CHECK_THAT(r.err, Contains("File too large"));
    CHECK(slurp(d / "render.png") == "precious");
    CHECK(temporaries(d).empty());

    // A really full filesystem, where the test may mount one.
    const fs::path full = d / "full";
    fs::create_directories(full);
    SmallTmpfs small(full, 64 * 1024);
    if (!small.mounted()) {
        WARN("cannot mount a tmpfs here: the file size limit above stands in for a full disk");
        return;
    }
    spit(full / "render.png", "precious");
    r = gradmesh("render " + q(d / "s.gmb") + " -o " + q(full / "render.png") + " --scale 2", d);
    checkFailedCleanly(r, "render.png");
    CHECK_THAT(r.err, Contains("No space left on device"));
    CHECK(slurp(full / "render.png") == "precious");
    CHECK(entries(full) == std::set<std::string>{"render.png"});
    CHECK(good.size() > 4096);
}

TEST_CASE("case 3: symlinks planted at the old temporary names are not followed",
          "[output_safety][cli]") {
    const fs::path d = tmpDir("cli_symlinks");
    spit(d / "victim", "unrelated");
    // `exec` keeps the shell's PID, so the names gradmesh used to predict are known here.
    const std::string plant = "cd " + q(d) +
                              " && ln -s victim .s.gmb.tmp$$-0.gmb"
                              " && ln -s victim .out.gmb.tmp$$-0.gmb"
                              " && ln -s victim r.json.tmp$$ && exec ";
    CHECK(gmtest::runCommand(plant + GRADMESH_EXE + " sample s.gmb") == 0);
    CHECK(gmtest::runCommand(plant + GRADMESH_EXE + " " + convertApple("out.gmb", "r.json") +
                             " 2>/dev/null") == 0);
    CHECK(slurp(d / "victim") == "unrelated");
    CHECK(fs::is_regular_file(fs::symlink_status(d / "s.gmb")));
    CHECK(fs::is_regular_file(fs::symlink_status(d / "out.gmb")));
    CHECK(fs::is_regular_file(fs::symlink_status(d / "r.json")));

    // An output that is itself a symlink is replaced, not written through.
    fs::create_symlink(d / "victim", d / "link.svg");
    CHECK(gradmesh("convert " + q(d / "s.gmb") + " -o " + q(d / "link.svg"), d).code == 0);
    CHECK(slurp(d / "victim") == "unrelated");
    CHECK(fs::is_regular_file(fs::symlink_status(d / "link.svg")));

    // Outputs are new files: 0666 minus the umask.
    CHECK(gmtest::runCommand("umask 027 && " + std::string(GRADMESH_EXE) + " sample " +
                             q(d / "mode.gmb")) == 0);
    struct stat st {};
    REQUIRE(::stat((d / "mode.gmb").c_str(), &st) == 0);
    CHECK((st.st_mode & 07777) == 0640);
}

