// The one place that names the built-in formats.
#include "formats/registry.h"

#include "formats/eps.h"
#include "formats/gmb.h"
#include "formats/pdf.h"
#include "formats/raster.h"
#include "formats/svg.h"

namespace gm {

const FormatRegistry& FormatRegistry::builtin() {
    static const FormatRegistry registry = [] {
        FormatRegistry r;
        r.add(makeGmbFormat());
        r.add(makeRasterFormat());
        r.add(makeSvgFormat(encodeFallbackImage));  // formats/raster renders SVG fallbacks
        r.add(makeEpsFormat());
        r.add(makePdfFormat());
        return r;
    }();
    return registry;
}

}  // namespace gm
