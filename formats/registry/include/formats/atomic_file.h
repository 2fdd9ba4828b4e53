// No partial output ever: write to a temporary file beside the target, rename on success.
#pragma once

#include <string>

namespace gm {

// A temporary path in the target's directory (keeping its extension, so libraries that pick a
// format by extension still work). The destructor removes the temporary unless commit() ran.
class AtomicOutput {
public:
    explicit AtomicOutput(const std::string& target);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::string& tempPath() const { return temp_; }
    const std::string& target() const { return target_; }
    // Renames the temporary onto the target; throws gm::Error on failure.
    void commit();

private:
    std::string target_, temp_;
    bool committed_ = false;
};

// Writes `bytes` to `path` atomically; throws gm::Error naming `path` on failure (missing
// directory, no permission, disk full).
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace gm
