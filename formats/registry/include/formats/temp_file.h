// A temporary file beside an output, for writing it whole before it takes the output's name.
//
// Its name is recognisable and unpredictable: ".NAME.gradmesh-tmp-PID-XXXXXX" in the output's
// directory (NAME the output's file name, PID this process, XXXXXX random). It is created with
// O_CREAT|O_EXCL|O_NOFOLLOW, so a file or symlink planted at that name is never opened or
// followed, and with mode 0666 minus the umask, like any file a program creates: an output's
// permissions are those of a new file, whatever the input's or a replaced output's were.
#pragma once

#include <string>

namespace gm {

class TempFile {
public:
    // Creates the temporary for `target` (after removing stale temporaries of the same target,
    // see removeStaleTemporaries). Throws gm::Error naming `target` when the directory is
    // missing, not writable, or `target` is a directory.
    explicit TempFile(const std::string& target);
    // Removes the temporary unless moveIntoPlace() succeeded.
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    const std::string& target() const { return target_; }
    const std::string& path() const { return path_; }
    bool written() const { return written_; }

    // Writes the whole content, fsyncs and closes, every step checked; once only.
    void write(const std::string& bytes);
    // Renames the written temporary onto the target (replacing a symlink there, never following
    // it). Throws gm::Error naming the target on failure.
    void moveIntoPlace();

private:
    void discard();

    std::string target_, path_;
    int fd_ = -1;
    int slot_ = -1;  // temp_registry.h
    bool written_ = false, moved_ = false;
};

// The name prefix of target's temporaries: ".NAME.gradmesh-tmp-" (NAME cut to 200 bytes).
std::string temporaryPrefix(const std::string& targetFileName);

// Removes temporaries of `target` left by runs that were killed: names with its prefix whose PID
// is no longer running, or that were last modified more than a day ago (the PID may have been
// reused). Another run's live temporary is left alone. Errors are ignored: this is tidying.
void removeStaleTemporaries(const std::string& target);

}  // namespace gm
