// The built-in formats that read meshes, without the raster library (registry.h).
#include "formats/gmb.h"
#include "formats/registry.h"
#include "formats/svg.h"

namespace gm {

const FormatRegistry& FormatRegistry::meshReaders() {
    static const FormatRegistry registry = [] {
        FormatRegistry r;
        r.add(makeGmbFormat());
        r.add(makeSvgFormat());  // reads only: no fallback encoder needed
        return r;
    }();
    return registry;
}

}  // namespace gm
