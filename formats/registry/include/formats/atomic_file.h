// No partial output, and no output replaced by a run that failed: every output of a run is
// written whole to a temporary beside it (temp_file.h) and renamed into place only once all of
// them are written.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace gm {

class TempFile;

// The outputs of one run. reserve() each target as early as possible (a missing directory, a
// read-only one or /proc fails before any work is done), write() each, then commit(): the
// renames happen only after every temporary is completely written, synced and closed. Destroying
// the batch without commit() (an exception) removes every temporary; existing files at the
// targets are untouched.
class OutputBatch {
public:
    OutputBatch();
    ~OutputBatch();
    OutputBatch(const OutputBatch&) = delete;
    OutputBatch& operator=(const OutputBatch&) = delete;

    // Creates the temporary for `target`; throws gm::Error naming it on failure.
    void reserve(const std::string& target);
    // Writes a reserved target's content (reserving it first if needed); throws gm::Error naming
    // the target (disk full, I/O error).
    void write(const std::string& target, const std::string& bytes);
    // Moves every temporary into place, in the order reserved. Throws gm::Error when one is not
    // written or a rename fails.
    void commit();

private:
    TempFile* find(const std::string& target);
    std::vector<std::unique_ptr<TempFile>> files_;
};

// Writes `bytes` to `path` atomically; throws gm::Error naming `path` on failure (missing
// directory, no permission, disk full).
void writeFileAtomically(const std::string& path, const std::string& bytes);

// Throws Error naming `output` when it is the file `input` (the same file, whatever the
// spelling: links and relative paths included); `role` says what the input is ("input",
// "mask"). An output is never written over a file the command reads.
void refuseOverwritingInput(const std::string& input, const std::string& output,
                            const std::string& role = "input");

}  // namespace gm
