// Test support for output safety: scratch directories, what a directory holds, a temporary
// filesystem when the test may mount one, and gradmesh started in the background.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "support/cli_run.h"

namespace safetytest {

namespace fs = std::filesystem;

inline fs::path tmpDir(const std::string& name) { return gmtest::scratchDir("safety_", name); }

inline void spit(const fs::path& p, const std::string& bytes) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The directory's entries, the captured stdout/stderr excepted.
inline std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n != "stdout.txt" && n != "stderr.txt") names.insert(n);
    }
    return names;
}

// Entries that look like a temporary of any writer (ours: ".NAME.gradmesh-tmp-...", the old
// ".NAME.tmpPID-N.EXT" and "NAME.tmpPID").
inline std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> found;
    for (const std::string& n : entries(dir))
        if (n.find(".gradmesh-tmp-") != std::string::npos || n.find(".tmp") != std::string::npos)
            found.push_back(n);
    return found;
}

// A tmpfs of `bytes` mounted on `dir` while alive, when this process may mount (root, and a
// container that allows it); mounted() says whether it is.
class SmallTmpfs {
public:
    SmallTmpfs(const fs::path& dir, size_t bytes, bool readOnly = false) : dir_(dir) {
        const std::string options = "size=" + std::to_string(bytes);
        unsigned long flags = readOnly ? MS_RDONLY : 0;
        mounted_ = ::mount("tmpfs", dir.c_str(), "tmpfs", flags, options.c_str()) == 0;
    }
    ~SmallTmpfs() {
        if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
    }
    bool mounted() const { return mounted_; }

private:
    fs::path dir_;
    bool mounted_ = false;
};

// gradmesh started in the background with stdout/stderr in dir; wait() gives its raw status.
class Background {
public:
    Background(const std::vector<std::string>& args, const fs::path& dir) {
        pid_ = ::fork();
        if (pid_ == 0) {
            const int flags = O_WRONLY | O_CREAT | O_TRUNC;
            const int out = ::open((dir / "stdout.txt").c_str(), flags, 0644);
            const int err = ::open((dir / "stderr.txt").c_str(), flags, 0644);
            ::dup2(out, 1);
            ::dup2(err, 2);
            // A shell starts background jobs with SIGINT ignored, and gradmesh keeps an inherited
            // SIG_IGN: the signal tests need the default.
            for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::signal(sig, SIG_DFL);
            std::vector<std::string> all = {GRADMESH_EXE};
            all.insert(all.end(), args.begin(), args.end());
            std::vector<char*> argv;
            for (std::string& a : all) argv.push_back(a.data());
            argv.push_back(nullptr);
            ::execv(GRADMESH_EXE, argv.data());
            ::_exit(127);
        }
    }
    ~Background() {
        if (pid_ > 0 && !reaped_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
    }
    pid_t pid() const { return pid_; }
    int wait() {
        if (!reaped_) ::waitpid(pid_, &status_, 0);
        reaped_ = true;
        return status_;
    }
    bool running() {
        if (reaped_) return false;
        if (::waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
        return !reaped_;
    }

private:
    pid_t pid_ = -1;
    bool reaped_ = false;
    int status_ = 0;
};

// Waits (up to 60 s) until a name starting with `prefix` shows in dir while `run` is alive;
// "" when the run ended first.
inline std::string waitForEntry(const fs::path& dir, const std::string& prefix, Background& run) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < until && run.running()) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(dir, ec)) {
            const std::string n = e.path().filename().string();
            if (n.compare(0, prefix.size(), prefix) == 0) return n;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return {};
}

}  // namespace safetytest
