// The one place that names the built-in formats.
#include "formats/registry.h"

#include "formats/gmb.h"
#include "formats/raster.h"

namespace gm {

const FormatRegistry& FormatRegistry::builtin() {
    static const FormatRegistry registry = [] {
        FormatRegistry r;
        r.add(makeGmbFormat());
        r.add(makeRasterFormat());
        return r;
    }();
    return registry;
}

}  // namespace gm
