#include "converters/compact_file.h"

#include "converters/convert_image.h"
#include "converters/visible_colors.h"
#include "meshcore/render.h"

namespace gm {

CompactFile compactFileAt(const Document& doc, int level, const CompactTarget& target,
                          const CompactCodec& codec) {
    const auto quantise = [&](const Document& d) { return codec.decode(codec.encode(d, level)); };
    QuantisedColors q = colorsForQuantisation(doc, target.image, target.measured, target.colors,
                                              quantise, target.threads, &target.meshError);
    CompactFile c;
    c.level = level;
    c.bytes = codec.encode(q.doc, level);
    c.error = q.error;
    c.doc = std::move(q.doc);
    c.refit = std::move(q.how);
    return c;
}

CompactFile coarsestCompactFile(const Document& doc, int maxLevel, const CompactTarget& target,
                                const CompactCodec& codec) {
    const double bound = 1.05 * target.meshError.meanAbs + 0.02;
    CompactFile c;
    for (int level = maxLevel; level >= 0; --level) {
        const Document quantised = codec.decode(codec.encode(doc, level));
        const double plainE =
            compareOverMask(target.image, renderDocument(quantised, RenderOptions{}).image,
                            target.measured)
                .meanAbs;
        if (plainE > 1.25 * bound && level > 0) continue;
        c = compactFileAt(doc, level, target, codec);
        if (c.error.meanAbs <= bound) break;
    }
    return c;
}

}  // namespace gm
