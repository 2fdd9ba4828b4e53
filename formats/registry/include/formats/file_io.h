// The system calls every output goes through, checked by their callers: one place where a test
// can make a write, an fsync or a close fail (a full disk, an I/O error) without a full disk.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace gm {

struct FileIo {
    ssize_t (*write)(int fd, const void* data, size_t size);
    int (*fsync)(int fd);
    int (*close)(int fd);
};

// The calls in use: ::write, ::fsync, ::close unless a test replaced them (ScopedFileIo).
const FileIo& fileIo();

// Replaces the calls while alive (tests only; not thread-safe against concurrent writers).
class ScopedFileIo {
public:
    explicit ScopedFileIo(const FileIo& replacement);
    ~ScopedFileIo();
    ScopedFileIo(const ScopedFileIo&) = delete;
    ScopedFileIo& operator=(const ScopedFileIo&) = delete;

private:
    FileIo saved_;
};

// Writes all of `bytes` to fd (retrying short writes and EINTR), then fsyncs it. Throws gm::Error
// naming `fileName` with the system's reason (ENOSPC: "No space left on device") on failure.
void writeAllAndSync(int fd, const std::string& bytes, const std::string& fileName);

}  // namespace gm
