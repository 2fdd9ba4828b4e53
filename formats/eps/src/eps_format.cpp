#include <cstdint>
#include <string>

#include "formats/eps.h"
#include "formats/mesh_shading.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

// PostScript implementations may limit arrays to 65535 elements; a text patch has 45 numbers.
constexpr size_t kTextPatchesPerArray = 1000;

// A flat shape; a stroked one between gsave and grestore, so that its line width, caps and
// joins end with it; a graded one likewise, clipped to its outline, so that the clip ends with
// it, its axial shading painted within.
std::string shapeOperators(const FlatShape& shape) {
    if (shape.stroked())
        return "gsave " + shapeStrokeOperators(shape, kPostScriptPathOperators) + "grestore\n";
    if (shape.graded())
        return "gsave " + shapeClipOperators(shape, kPostScriptPathOperators) + "<< " +
               axialShadingEntries(shape.gradient) + " >> shfill grestore\n";
    return shapeFillOperators(shape, kPostScriptPathOperators);
}

std::string epsDocument(const Document& doc, const WriteOptions& options) {
    const std::string w = std::to_string(doc.width), h = std::to_string(doc.height);
    std::string ps;
    ps += "%!PS-Adobe-3.0 EPSF-3.0\n";
    ps += "%%Creator: gradmesh\n";
    ps += "%%BoundingBox: 0 0 " + w + " " + h + "\n";
    ps += "%%HiResBoundingBox: 0 0 " + w + " " + h + "\n";
    ps += "%%LanguageLevel: 3\n";
    ps += "%%Pages: 1\n";
    ps += "%%EndComments\n";
    ps += "%%Page: 1 1\n";
    ps += "save\n";
    ps += "4 dict begin\n";
    // Canvas y runs down, PostScript y up.
    ps += "0 " + h + " translate 1 -1 scale\n";
    // Flat shapes go between the shadings in their paint order.
    size_t nextShape = 0;
    auto shapesUpTo = [&](size_t layer) {
        for (; nextShape < doc.shapes.size() && doc.shapes[nextShape].layer <= layer; ++nextShape)
            ps += shapeOperators(doc.shapes[nextShape]);
    };
    for (const MeshShading& shading : buildMeshShadings(doc, options)) {
        shapesUpTo(shading.source);
        if (options.textShading) {
            for (size_t first = 0; first < shading.patches.size(); first += kTextPatchesPerArray) {
                ps += "<< /ShadingType 7 /ColorSpace /DeviceRGB /DataSource [\n";
                ps += encodeShadingText(shading, first, kTextPatchesPerArray);
                ps += "] >> shfill\n";
            }
        } else {
            const BinaryShading binary = encodeShadingBinary(shading);
            // The shading reads until the Flate stream ends, which may leave the ASCII85 end
            // marker unread; flushfile consumes it before the interpreter reads on. Both run
            // from one procedure so that the data starts right after `exec`.
            ps += "/gmSource currentfile /ASCII85Decode filter def\n";
            ps += "{ << " + binaryShadingEntries(binary) +
                  " /DataSource gmSource /FlateDecode filter >> shfill gmSource flushfile } exec\n";
            ps += ascii85Encode(deflateBytes(binary.data));
        }
    }
    shapesUpTo(SIZE_MAX);
    ps += "end\n";
    ps += "restore\n";
    ps += "showpage\n";
    ps += "%%Trailer\n";
    ps += "%%EOF\n";
    return ps;
}

class EpsFormat : public MeshFormat {
public:
    std::string name() const override { return "eps"; }
    std::vector<std::string> extensions() const override { return {".eps", ".epsf"}; }
    bool canWrite() const override { return true; }
    bool sniff(const std::string& head) const override { return head.rfind("%!PS", 0) == 0; }
    // A patch of the shading stream takes at least a flag, eight points (its edges shared
    // with the previous patch) in 2-byte coordinates and two colours.
    uint64_t leastBytes(const Document& doc, const WriteOptions&) const override {
        return 32 * documentPatches(doc);
    }
    std::string encode(const Document& doc, const std::string& path,
                       const WriteOptions& options) const override {
        requireOutputWithinLimit(leastBytes(doc, options), options, path);
        const std::string problem = validateDocument(doc);
        if (!problem.empty()) throw Error("cannot write an invalid document: " + problem, path);
        if (const std::string e = coordinateProblem(doc); !e.empty())
            throw Error("cannot write: " + e, path);
        for (size_t k = 0; k < doc.shapes.size(); ++k)
            if (doc.shapes[k].alpha < 1)
                throw Error("cannot write: shape " + std::to_string(k) +
                                " is translucent, which PostScript cannot paint (write PDF or SVG)",
                            path);
        return epsDocument(doc, options);
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeEpsFormat() { return std::make_unique<EpsFormat>(); }

}  // namespace gm
