#include "formats/atomic_file.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "meshcore/error.h"

namespace gm {

namespace {
std::string tempNameFor(const std::string& target) {
    static std::atomic<unsigned> counter{0};
    size_t slash = target.find_last_of('/');
    std::string dir = slash == std::string::npos ? std::string() : target.substr(0, slash + 1);
    std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
    std::string ext;
    size_t dot = base.find_last_of('.');
    if (dot != std::string::npos && dot > 0) ext = base.substr(dot);
    return dir + "." + base + ".tmp" + std::to_string(getpid()) + "-" +
           std::to_string(counter++) + ext;
}

std::string directoryOf(const std::string& path) {
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}
}  // namespace

AtomicOutput::AtomicOutput(const std::string& target) : target_(target) {
    struct stat st {};
    const std::string dir = directoryOf(target);
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw Error("output directory '" + dir + "' does not exist", target);
    if (stat(target.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        throw Error("output path is a directory", target);
    temp_ = tempNameFor(target);
}

AtomicOutput::~AtomicOutput() {
    if (!committed_) std::remove(temp_.c_str());
}

void AtomicOutput::commit() {
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
        const int err = errno;
        std::remove(temp_.c_str());
        committed_ = true;
        throw Error(std::string("cannot move the finished file into place: ") + std::strerror(err),
                    target_);
    }
    committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    AtomicOutput out(path);
    {
        std::ofstream f(out.tempPath(), std::ios::binary | std::ios::trunc);
        if (!f) throw Error(std::string("cannot create output file: ") + std::strerror(errno), path);
        f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        f.flush();
        if (!f) throw Error("write failed (disk full?)", path);
    }
    out.commit();
}

}  // namespace gm
