#include "formats/temp_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <ctime>
#include <random>

#include "formats/file_io.h"
#include "formats/temp_registry.h"
#include "meshcore/error.h"

namespace gm {

namespace {

constexpr size_t kMaxNameInPrefix = 200;  // keeps the whole name under NAME_MAX (255)
constexpr int kRandomChars = 6;
constexpr time_t kStaleAfterSeconds = 24 * 3600;

std::string directoryOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

std::string fileNameOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string joinPath(const std::string& dir, const std::string& name) {
    return dir == "/" ? "/" + name : dir + "/" + name;
}

std::string randomChars() {
    static const char kAlphabet[] =
        "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    unsigned char raw[kRandomChars];
    if (getrandom(raw, sizeof raw, 0) != static_cast<ssize_t>(sizeof raw)) {
        // No kernel entropy: O_EXCL still makes a guessed name harmless, only a retry.
        std::random_device rd;
        for (unsigned char& c : raw) c = static_cast<unsigned char>(rd());
    }
    std::string s;
    for (unsigned char c : raw) s += kAlphabet[c % (sizeof kAlphabet - 1)];
    return s;
}

// The PID in a temporary's name after the prefix ("PID-XXXXXX"), or -1 when it is not one of ours.
long pidInTemporaryName(const std::string& rest) {
    const size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || dash > 10) return -1;
    if (rest.size() != dash + 1 + kRandomChars) return -1;
    long pid = 0;
    for (size_t k = 0; k < dash; ++k) {
        if (rest[k] < '0' || rest[k] > '9') return -1;
        pid = pid * 10 + (rest[k] - '0');
    }
    return pid <= INT_MAX ? pid : -1;  // a larger one would be a negative pid_t: a process group
}

bool processIsGone(long pid) { return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

}  // namespace

std::string temporaryPrefix(const std::string& targetFileName) {
    return "." + targetFileName.substr(0, kMaxNameInPrefix) + ".gradmesh-tmp-";
}

void removeStaleTemporaries(const std::string& target) {
    const std::string dir = directoryOf(target);
    const std::string prefix = temporaryPrefix(fileNameOf(target));
    DIR* d = ::opendir(dir.c_str());
    if (!d) return;
    const time_t now = std::time(nullptr);
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        const long pid = pidInTemporaryName(name.substr(prefix.size()));
        if (pid <= 0 || pid == static_cast<long>(getpid())) continue;
        const std::string path = joinPath(dir, name);
        struct stat st {};
        if (::lstat(path.c_str(), &st) != 0) continue;
        if (processIsGone(pid) || now - st.st_mtime > kStaleAfterSeconds) ::unlink(path.c_str());
    }
    ::closedir(d);
}

TempFile::TempFile(const std::string& target) : target_(target) {
    const std::string dir = directoryOf(target);
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw Error("output directory '" + dir + "' does not exist", target);
    if (::stat(target.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        throw Error("output path is a directory", target);
    removeStaleTemporaries(target);
    const std::string prefix =
        joinPath(dir, temporaryPrefix(fileNameOf(target)) + std::to_string(getpid()) + "-");
    for (int attempt = 0; attempt < 100; ++attempt) {
        path_ = prefix + randomChars();
        // Registered before it exists: a signal right after the open must find it (any thread
        // may take the signal, so blocking it here would not close that gap). Were the name
        // taken (EEXIST), a signal before the unregister would remove a file planted at our
        // own random, PID-stamped name: harmless.
        slot_ = registerTemporary(path_);
        fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd_ >= 0) return;
        const int err = errno;
        unregisterTemporary(slot_);
        slot_ = -1;
        path_.clear();
        if (err != EEXIST)
            throw Error(std::string("cannot create a file in the output's directory: ") +
                            std::strerror(err),
                        target);
    }
    throw Error("cannot create a temporary file in the output's directory (100 names taken)",
                target);
}

TempFile::~TempFile() {
    if (!moved_) discard();
}

void TempFile::discard() {
    if (fd_ >= 0) fileIo().close(fd_);
    fd_ = -1;
    if (!path_.empty()) ::unlink(path_.c_str());
    unregisterTemporary(slot_);
    slot_ = -1;
}

void TempFile::write(const std::string& bytes) {
    if (written_ || fd_ < 0) throw Error("internal: temporary written twice", target_);
    writeAllAndSync(fd_, bytes, target_);
    const int fd = fd_;
    fd_ = -1;
    if (fileIo().close(fd) != 0)
        throw Error(std::string("cannot write the output (close): ") + std::strerror(errno),
                    target_);
    written_ = true;
}

void TempFile::moveIntoPlace() {
    if (!written_ || moved_) throw Error("internal: temporary not written", target_);
    if (::rename(path_.c_str(), target_.c_str()) != 0) {
        const int err = errno;
        throw Error(std::string("cannot move the finished file into place: ") + std::strerror(err),
                    target_);
    }
    moved_ = true;
    unregisterTemporary(slot_);
    slot_ = -1;
    // Best effort: makes the rename itself durable; the file is in place either way.
    const int dirFd = ::open(directoryOf(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
}

}  // namespace gm
