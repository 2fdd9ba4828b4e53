#include <algorithm>

#include "formats/svg.h"
#include "meshcore/color_rule.h"

namespace gm {

SvgEditableDeviation svgEditableDeviation(const Document& doc) {
    SvgEditableDeviation out;
    for (const GradientMesh& mesh : doc.meshes) {
        if (mesh.colorModel == ColorModel::Bicubic) continue;  // the file's rule is the mesh's
        out.ruleDeviation = std::max(out.ruleDeviation, colorRuleDeviation(mesh));
        out.slopeDeviation = std::max(out.slopeDeviation, bicubicExportDeviation(mesh));
    }
    out.maxColorDifference = 0.5 * out.slopeDeviation;
    return out;
}

}  // namespace gm
