#include <cctype>

#include "formats/atomic_file.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

class SvgFormat : public MeshFormat {
public:
    std::string name() const override { return "svg"; }
    std::vector<std::string> extensions() const override { return {".svg"}; }
    bool canRead() const override { return true; }
    bool canWrite() const override { return true; }

    // An XML declaration, a comment, a doctype or the <svg> element first (after a BOM).
    bool sniff(const std::string& head) const override {
        size_t p = 0;
        if (head.compare(0, 3, "\xEF\xBB\xBF") == 0) p = 3;
        while (p < head.size() && std::isspace(static_cast<unsigned char>(head[p]))) ++p;
        const std::string rest = head.substr(p);
        return rest.compare(0, 5, "<?xml") == 0 || rest.compare(0, 4, "<svg") == 0 ||
               rest.compare(0, 9, "<!DOCTYPE") == 0 || rest.compare(0, 4, "<!--") == 0;
    }

    Document read(const std::string& path, const ReadOptions& options) const override {
        const uint64_t limit =
            std::min<uint64_t>(options.limits.maxFileBytes, SvgReadLimits::maxFileBytes);
        return decodeSvg(readWholeFile(path, limit), options.limits, path);
    }

    // A meshpatch of the editable mode takes ~80 bytes (two stops with a path and a colour);
    // exact colours split patches into more.
    uint64_t leastBytes(const Document& doc, const WriteOptions&) const override {
        return 60 * documentPatches(doc);
    }

    void write(const Document& doc, const std::string& path,
               const WriteOptions& options) const override {
        requireOutputWithinLimit(leastBytes(doc, options), options, path);
        if (const std::string e = coordinateProblem(doc); !e.empty())
            throw Error("cannot write: " + e, path);
        std::string bytes;
        try {
            bytes = encodeSvg(doc, options);
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error(e.reason(), path, e.where());
        }
        writeFileAtomically(path, bytes);
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeSvgFormat() { return std::make_unique<SvgFormat>(); }

}  // namespace gm
