// Limits on what a document may make the readers build and the writers produce (registry.h).
#include <cstdio>
#include <string>

#include "formats/registry.h"
#include "meshcore/error.h"

namespace gm {

namespace {
std::string megabytes(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MB", static_cast<double>(bytes) / 1e6);
    return text;
}
}  // namespace

uint64_t documentPatches(const Document& doc) {
    uint64_t patches = 0;
    for (const GradientMesh& m : doc.meshes) patches += static_cast<uint64_t>(m.patchCount());
    return patches;
}

std::string tooManyPatchesMessage(uint64_t patches, uint64_t limit) {
    return "document has " + std::to_string(patches) + " patches, over the limit of " +
           std::to_string(limit) + " (raise it with --max-document-patches)";
}

void requireOutputWithinLimit(uint64_t leastBytes, const WriteOptions& options,
                              const std::string& path) {
    if (leastBytes <= options.maxOutputBytes) return;
    throw Error("output would take at least " + megabytes(leastBytes) + ", over the limit of " +
                    megabytes(options.maxOutputBytes) + " (raise it with --max-output-bytes)",
                path);
}

}  // namespace gm
