// libFuzzer target for the SVG reader: any input must either decode to a valid document or
// throw gm::Error — never crash, hang or allocate without bound. A decoded document then goes
// through every writer in memory (SVG exact and editable, .gmb lossless and compact, EPS, PDF),
// which must succeed or throw gm::Error, and its lossless .gmb must read back as the same document.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "formats/eps.h"
#include "formats/gmb.h"
#include "formats/pdf.h"
#include "formats/svg.h"
#include "meshcore/error.h"

namespace {

gm::ReadLimits fuzzLimits() {
    gm::ReadLimits l;
    l.maxFileBytes = uint64_t(1) << 20;
    l.maxNodesPerMesh = uint64_t(1) << 12;
    l.maxGridSide = 256;
    l.maxSlitsPerMesh = 64;
    l.maxMeshes = 16;
    l.maxCanvasSide = 4096;
    return l;
}

// Exact colours split a patch into up to 64×64 pieces; past this many patches the exact writers
// would spend the fuzzer's time on output size, not on new paths.
constexpr int kExactWritersMaxPatches = 64;

[[noreturn]] void die(const char* what, const std::string& detail) {
    std::fprintf(stderr, "svg_fuzzer: %s: %s\n", what, detail.c_str());
    std::abort();
}

int patchCount(const gm::Document& doc) {
    int n = 0;
    for (const gm::GradientMesh& m : doc.meshes) n += m.patchCount();
    return n;
}

// Every writer on the document; gm::Error is an allowed answer (an invalid document for EPS/PDF).
void writeAll(const gm::Document& doc) {
    gm::WriteOptions editable;
    editable.svgColors = "editable";
    gm::WriteOptions exact;
    exact.colorTolerance = 4.0 / 255.0;
    exact.minPiece = 8.0;
    const bool exactToo = patchCount(doc) <= kExactWritersMaxPatches;
    static const auto eps = gm::makeEpsFormat();
    static const auto pdf = gm::makePdfFormat();
    const auto attempt = [](auto&& write) {
        try {
            write();
        } catch (const gm::Error&) {
        }
    };
    attempt([&] { gm::encodeSvg(doc, editable); });
    attempt([&] { gm::encodeGmb(doc, true); });
    if (!exactToo) return;
    attempt([&] { gm::encodeSvg(doc, exact); });
    attempt([&] { eps->encode(doc, "fuzz.eps", exact); });
    attempt([&] { pdf->encode(doc, "fuzz.pdf", exact); });
}

void check(const std::string& input) {
    gm::Document doc;
    try {
        doc = gm::decodeSvg(input, fuzzLimits(), "fuzz");
    } catch (const gm::Error&) {
        return;  // the expected outcome for nearly every input
    }
    try {
        gm::ReadLimits roomy = fuzzLimits();
        roomy.maxFileBytes = uint64_t(1) << 30;
        const gm::Document back = gm::decodeGmb(gm::encodeGmb(doc, false), roomy, "lossless");
        if (!(back == doc)) die("the lossless .gmb of a decoded SVG reads back different", "");
    } catch (const gm::Error& e) {
        die("a decoded SVG document failed the lossless .gmb round trip", e.what());
    }
    writeAll(doc);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    check(std::string(reinterpret_cast<const char*>(data), size));
    return 0;
}
