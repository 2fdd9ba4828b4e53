#include "std_streams.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <vector>

#include "formats/temp_registry.h"

namespace gm::cli {

const char* const kStdinName = "<stdin>";
const char* const kStdoutName = "<stdout>";

namespace {

constexpr uint64_t kMaxStdinBytes = uint64_t(4) << 30;

// The extension of an image readImage takes, from its first bytes; "" for anything else.
std::string imageExtension(const std::string& head) {
    auto starts = [&](const char* magic, size_t n) { return head.compare(0, n, magic, n) == 0; };
    if (starts("\x89PNG\r\n\x1a\n", 8)) return ".png";
    if (starts("\xFF\xD8\xFF", 3)) return ".jpg";
    if (starts("II*\0", 4) || starts("MM\0*", 4)) return ".tif";
    if (starts("\x76\x2f\x31\x01", 4)) return ".exr";
    return "";
}

std::string contentExtension(const std::string& head, const FormatRegistry& registry) {
    for (const MeshFormat* f : registry.all())
        if (f->canRead() && f->sniff(head)) return f->extensions().at(0);
    return imageExtension(head);
}

void writeAll(int fd, const char* data, size_t size, const std::string& name) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw Error(std::string("cannot write: ") + std::strerror(errno), name);
        data += n;
        size -= static_cast<size_t>(n);
    }
}

// Reads standard input to its end into the file `fd`, returning its first bytes.
std::string copyStandardInput(int fd, const std::string& spoolPath) {
    std::string head;
    std::vector<char> buffer(1 << 16);
    uint64_t total = 0;
    for (;;) {
        const ssize_t n = ::read(0, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw Error(std::string("cannot read: ") + std::strerror(errno), kStdinName);
        if (n == 0) return head;
        total += static_cast<uint64_t>(n);
        if (total > kMaxStdinBytes) throw Error("over 4 GiB; give the file's name instead", kStdinName);
        if (head.size() < 64) head.append(buffer.data(), std::min<size_t>(n, 64 - head.size()));
        writeAll(fd, buffer.data(), static_cast<size_t>(n), spoolPath);
    }
}

}  // namespace


std::string spoolStandardInput(PrivateDir& dir, const FormatRegistry& registry) {
    if (::isatty(0) == 1)
        throw Error("is a terminal: pipe a file into it (gradmesh convert - ... < IN)", kStdinName);
    const std::string raw = dir.file("stdin");
    const int fd = ::open(raw.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) throw Error(std::string("cannot spool: ") + std::strerror(errno), raw);
    std::string head;
    try {
        head = copyStandardInput(fd, raw);
    } catch (...) {
        ::close(fd);
        throw;
    }
    if (::close(fd) != 0) throw Error(std::string("cannot spool: ") + std::strerror(errno), raw);
    if (head.empty()) throw Error("empty (0 bytes)", kStdinName);
    const std::string extension = contentExtension(head, registry);
    if (extension.empty())
        throw Error("not an image or a mesh file (reads PNG, JPEG, TIFF, OpenEXR, .gmb, SVG)",
                    kStdinName);
    const std::string named = dir.file("stdin" + extension);
    if (::rename(raw.c_str(), named.c_str()) != 0)
        throw Error(std::string("cannot spool: ") + std::strerror(errno), named);
    return named;
}

void copyToStandardOutput(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(std::string("cannot read the output: ") + std::strerror(errno), kStdoutName);
    // A closed pipe is an error to report, not a signal that ends the run before its cleanup.
    struct sigaction ignore {}, old {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &old);
    std::vector<char> buffer(1 << 16);
    std::string failure;
    for (;;) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n < 0) failure = std::string("cannot read the output: ") + std::strerror(errno);
            break;
        }
        try {
            writeAll(1, buffer.data(), static_cast<size_t>(n), kStdoutName);
        } catch (const Error& e) {
            failure = e.reason();
            break;
        }
    }
    ::close(fd);
    sigaction(SIGPIPE, &old, nullptr);
    if (failure.empty() && std::fflush(stdout) != 0) failure = "cannot write";
    if (!failure.empty()) throw Error(failure, kStdoutName);
}

}  // namespace gm::cli
