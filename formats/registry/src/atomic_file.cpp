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

std::string readWholeFile(const std::string& path, uint64_t maxBytes) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0)
        throw Error(std::string("cannot open: ") + std::strerror(errno), path);
    if (S_ISDIR(st.st_mode)) throw Error("is a directory, not a file", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(std::string("cannot open: ") + std::strerror(errno), path);
    if (static_cast<uint64_t>(st.st_size) > maxBytes)
        throw Error("file is " + std::to_string(st.st_size) + " bytes, over the limit of " +
                        std::to_string(maxBytes),
                    path);
    std::string data(static_cast<size_t>(st.st_size), '\0');
    in.read(&data[0], static_cast<std::streamsize>(data.size()));
    if (static_cast<uint64_t>(in.gcount()) != data.size()) throw Error("read failed", path);
    return data;
}

}  // namespace gm
