#include "formats/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "meshcore/error.h"

namespace gm {

namespace {

std::string kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

[[noreturn]] void refuse(mode_t mode, const std::string& path) {
    throw Error("is " + kindOf(mode) + ", not a regular file; refusing to read it", path);
}

// An fd on a regular file: O_NONBLOCK so that opening a FIFO does not wait for a writer, then
// fstat on what was opened (not a second lookup that could find another file).
int openRegular(const std::string& path, struct stat& st) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        const int err = errno;
        throw Error(std::string("cannot open: ") + std::strerror(err), path);
    }
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        refuse(st.st_mode, path);
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

// Reads up to `size` bytes; fewer only at the end of the file.
size_t readUpTo(int fd, char* data, size_t size) {
    size_t got = 0;
    while (got < size) {
        const ssize_t n = ::read(fd, data + got, size - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += static_cast<size_t>(n);
    }
    return got;
}

}  // namespace

void requireRegularFile(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        const int err = errno;
        throw Error(err == ENOENT ? std::string("no such file")
                                  : std::string("cannot open: ") + std::strerror(err),
                    path);
    }
    if (!S_ISREG(st.st_mode)) refuse(st.st_mode, path);
}

std::string readWholeFile(const std::string& path, uint64_t maxBytes) {
    struct stat st {};
    const int fd = openRegular(path, st);
    if (static_cast<uint64_t>(st.st_size) > maxBytes) {
        ::close(fd);
        throw Error("file is " + std::to_string(st.st_size) + " bytes, over the limit of " +
                        std::to_string(maxBytes),
                    path);
    }
    std::string data(static_cast<size_t>(st.st_size), '\0');
    const size_t got = readUpTo(fd, &data[0], data.size());
    ::close(fd);
    if (got != data.size()) throw Error("read failed", path);
    return data;
}

std::string readFileHead(const std::string& path, size_t bytes) {
    struct stat st {};
    int fd = -1;
    try {
        fd = openRegular(path, st);
    } catch (const Error&) {
        return {};
    }
    std::string head(bytes, '\0');
    head.resize(readUpTo(fd, &head[0], head.size()));
    ::close(fd);
    return head;
}

}  // namespace gm
