#include "formats/file_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "meshcore/error.h"

namespace gm {

namespace {
FileIo& current() {
    static FileIo io{&::write, &::fsync, &::close};
    return io;
}
}  // namespace

const FileIo& fileIo() { return current(); }

ScopedFileIo::ScopedFileIo(const FileIo& replacement) : saved_(current()) {
    current() = replacement;
}

ScopedFileIo::~ScopedFileIo() { current() = saved_; }

void writeAllAndSync(int fd, const std::string& bytes, const std::string& fileName) {
    const char* p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = fileIo().write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int err = n < 0 ? errno : ENOSPC;  // a write of 0 bytes makes no progress
            throw Error(std::string("cannot write the output: ") + std::strerror(err), fileName);
        }
        p += n;
        left -= static_cast<size_t>(n);
    }
    // Without it a full disk or a failing device may only show after the rename, on a file that
    // is already in place.
    if (fileIo().fsync(fd) != 0 && errno != EINVAL)
        throw Error(std::string("cannot write the output (fsync): ") + std::strerror(errno),
                    fileName);
}

}  // namespace gm
