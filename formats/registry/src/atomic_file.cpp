#include "formats/atomic_file.h"

#include <filesystem>
#include <system_error>

#include "formats/temp_file.h"
#include "meshcore/error.h"

namespace gm {

OutputBatch::OutputBatch() = default;
OutputBatch::~OutputBatch() = default;

TempFile* OutputBatch::find(const std::string& target) {
    for (const auto& f : files_)
        if (f->target() == target) return f.get();
    return nullptr;
}

void OutputBatch::reserve(const std::string& target) {
    if (!find(target)) files_.push_back(std::make_unique<TempFile>(target));
}

void OutputBatch::write(const std::string& target, const std::string& bytes) {
    reserve(target);
    find(target)->write(bytes);
}

void OutputBatch::commit() {
    for (const auto& f : files_)
        if (!f->written())
            throw Error("internal: an output was reserved but not written", f->target());
    for (const auto& f : files_) f->moveIntoPlace();
    files_.clear();
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    OutputBatch out;
    out.write(path, bytes);
    out.commit();
}

void refuseOverwritingInput(const std::string& input, const std::string& output,
                            const std::string& role) {
    std::error_code ec;
    if (!input.empty() && std::filesystem::exists(output, ec) &&
        std::filesystem::equivalent(input, output, ec))
        throw Error("output is the " + role + " file; refusing to overwrite it", output);
}

}  // namespace gm
