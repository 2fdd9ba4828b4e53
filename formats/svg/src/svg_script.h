// The mesh script an SVG carries for browsers, which implement no <meshgradient>
// (docs/browsers.md): formats/svg/script/mesh_polyfill.js, minified at build time.
#pragma once

#include <string>

#include "mesh_polyfill_script.h"

namespace gm {

// Appends the script as a <script> element whose text is one CDATA section. The build refuses
// a script holding "]]>"; should one ever get through, it is split across two sections so that
// the document stays well-formed.
inline void appendMeshScript(std::string& out) {
    std::string text = kMeshPolyfillScript;
    for (size_t at = text.find("]]>"); at != std::string::npos; at = text.find("]]>", at + 15))
        text.replace(at, 3, "]]]]><![CDATA[>");
    out += "<script type=\"text/javascript\"><![CDATA[";
    out += text;
    out += "]]></script>\n";
}

}  // namespace gm
