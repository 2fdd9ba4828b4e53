#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "formats/mesh_shading.h"
#include "formats/pdf.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

// Builds the file object by object, recording each one's byte offset for the xref table.
class PdfBuilder {
public:
    PdfBuilder() {
        // The binary comment tells transfer programs the file is binary.
        out_ = "%PDF-1.7\n%\xe2\xe3\xcf\xd3\n";
    }
    // Reserves the next object number.
    int reserve() {
        offsets_.push_back(0);
        return static_cast<int>(offsets_.size());
    }
    void object(int number, const std::string& body) {
        offsets_[static_cast<size_t>(number) - 1] = out_.size();
        out_ += std::to_string(number) + " 0 obj\n" + body + "\nendobj\n";
    }
    void stream(int number, const std::string& dict, const std::string& data) {
        object(number, "<< " + dict + " /Length " + std::to_string(data.size()) + " >>\nstream\n" +
                           data + "\nendstream");
    }
    std::string finish(int root) {
        const size_t xref = out_.size();
        const size_t count = offsets_.size() + 1;
        out_ += "xref\n0 " + std::to_string(count) + "\n";
        out_ += "0000000000 65535 f\r\n";  // each entry exactly 20 bytes
        for (size_t offset : offsets_) {
            char entry[32];
            std::snprintf(entry, sizeof entry, "%010zu 00000 n\r\n", offset);
            out_ += entry;
        }
        out_ += "trailer\n<< /Size " + std::to_string(count) + " /Root " + ref(root) + " >>\n";
        out_ += "startxref\n" + std::to_string(xref) + "\n%%EOF\n";
        return std::move(out_);
    }
    static std::string ref(int number) { return std::to_string(number) + " 0 R"; }

private:
    std::string out_;
    std::vector<size_t> offsets_;
};

// The page's content stream and the resources it names.
struct PageContent {
    std::string paint, shadings, states;
    size_t shadingCount = 0;
    // Names shading object `object` a resource of the page and paints it.
    void shading(int object) {
        const std::string name = "/Sh" + std::to_string(shadingCount++);
        shadings += name + " " + PdfBuilder::ref(object) + " ";
        paint += name + " sh\n";
    }
};

// A flat shape: an opaque fill as it is; anything else between q and Q, so that its graphics
// state (opacity, line width, caps, joins, clip) ends with it. A translucent shape's state of
// its own sets /ca, the fill's opacity (which a shading's painting uses too), or /CA, the
// stroke's. A graded shape clips to its outline and paints its axial shading there.
void paintShape(const FlatShape& shape, size_t index, PdfBuilder& pdf, PageContent& page) {
    if (shape.alpha >= 1 && !shape.stroked() && !shape.graded()) {
        page.paint += shapeFillOperators(shape, kPdfPathOperators);
        return;
    }
    page.paint += "q ";
    if (shape.alpha < 1) {
        const std::string name = "/GS" + std::to_string(index);
        page.states += name + (shape.stroked() ? " << /CA " : " << /ca ") +
                       formatDecimal(shape.alpha, 4) + " >> ";
        page.paint += name + " gs ";
    }
    if (shape.graded()) {
        const int object = pdf.reserve();
        pdf.object(object, "<< " + axialShadingEntries(shape.gradient) + " >>");
        page.paint += shapeClipOperators(shape, kPdfPathOperators);
        page.shading(object);
    } else {
        page.paint += shape.stroked() ? shapeStrokeOperators(shape, kPdfPathOperators)
                                      : shapeFillOperators(shape, kPdfPathOperators);
    }
    page.paint += "Q\n";
}

std::string pdfDocument(const Document& doc, const WriteOptions& options) {
    const std::vector<MeshShading> shadings = buildMeshShadings(doc, options);
    const std::string w = std::to_string(doc.width), h = std::to_string(doc.height);
    PdfBuilder pdf;
    const int catalog = pdf.reserve(), pages = pdf.reserve(), page = pdf.reserve(),
              contents = pdf.reserve();
    PageContent content;
    // Canvas y runs down, PDF y up.
    content.paint = "q 1 0 0 -1 0 " + h + " cm\n";
    // Flat shapes between the shadings in their paint order.
    size_t nextShape = 0;
    auto shapesUpTo = [&](size_t layer) {
        for (; nextShape < doc.shapes.size() && doc.shapes[nextShape].layer <= layer; ++nextShape)
            paintShape(doc.shapes[nextShape], nextShape, pdf, content);
    };
    for (const MeshShading& shading : shadings) {
        shapesUpTo(shading.source);
        const BinaryShading binary = encodeShadingBinary(shading);
        const int object = pdf.reserve();
        pdf.stream(object, binaryShadingEntries(binary) + " /Filter /FlateDecode",
                   deflateBytes(binary.data));
        content.shading(object);
    }
    shapesUpTo(SIZE_MAX);
    content.paint += "Q\n";
    pdf.object(catalog, "<< /Type /Catalog /Pages " + PdfBuilder::ref(pages) + " >>");
    pdf.object(pages, "<< /Type /Pages /Kids [" + PdfBuilder::ref(page) + "] /Count 1 >>");
    pdf.object(page, "<< /Type /Page /Parent " + PdfBuilder::ref(pages) + " /MediaBox [0 0 " + w +
                         " " + h + "] /Resources << /Shading << " + content.shadings + ">>" +
                         (content.states.empty() ? "" : " /ExtGState << " + content.states + ">>") +
                         " >> /Contents " + PdfBuilder::ref(contents) + " >>");
    pdf.stream(contents, "", content.paint);
    return pdf.finish(catalog);
}

class PdfFormat : public MeshFormat {
public:
    std::string name() const override { return "pdf"; }
    std::vector<std::string> extensions() const override { return {".pdf"}; }
    bool canWrite() const override { return true; }
    bool sniff(const std::string& head) const override { return head.rfind("%PDF-", 0) == 0; }
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
        return pdfDocument(doc, options);
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makePdfFormat() { return std::make_unique<PdfFormat>(); }

}  // namespace gm
