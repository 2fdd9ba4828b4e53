// .gmb — the native binary format of gradmesh: the MeshFormat that the registry finds for
// ".gmb" files. It sniffs the magic number and hands the bytes to decodeGmb (gmb_read.cpp) and
// encodeGmb (gmb_write.cpp); with --legacy it writes every mesh as its hole-free pieces.
// The format itself (versions 1.0 to 1.5, 2.0 and 2.1, byte layouts, coding and reading limits) is
// specified in docs/formats.md, "gmb — the native binary format".
#include <algorithm>

#include "formats/input_file.h"
#include "formats/gmb.h"
#include "gmb_pvt.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"

namespace gm {

namespace {

class GmbFormat : public MeshFormat {
public:
    std::string name() const override { return "gmb"; }
    std::vector<std::string> extensions() const override { return {".gmb"}; }
    bool canRead() const override { return true; }
    bool canWrite() const override { return true; }

    bool sniff(const std::string& head) const override {
        return head.size() >= sizeof gmb::kMagic &&
               std::equal(head.begin(), head.begin() + sizeof gmb::kMagic, gmb::kMagic);
    }

    Document read(const std::string& path, const ReadOptions& options) const override {
        const std::string bytes = readWholeFile(path, options.limits.maxFileBytes);
        return decodeGmb(bytes, options.limits, path);
    }

    std::string encode(const Document& doc, const std::string& path,
                       const WriteOptions& options) const override {
        try {
            if (!options.legacy) return encodeGmb(doc, options.compact, options.compactLevel);
            Document pieces;
            pieces.width = doc.width;
            pieces.height = doc.height;
            std::vector<size_t> piecesBefore{0};  // per mesh index: the pieces of those before
            for (const GradientMesh& m : doc.meshes) {
                for (GradientMesh& piece : splitIntoLegacyMeshes(m))
                    pieces.meshes.push_back(std::move(piece));
                piecesBefore.push_back(pieces.meshes.size());
            }
            pieces.shapes = doc.shapes;
            for (FlatShape& s : pieces.shapes)
                s.layer = piecesBefore[std::min(s.layer, piecesBefore.size() - 1)];
            return encodeGmb(pieces, options.compact, options.compactLevel);
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error(e.reason(), path, e.where());
        }
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeGmbFormat() { return std::make_unique<GmbFormat>(); }

}  // namespace gm
