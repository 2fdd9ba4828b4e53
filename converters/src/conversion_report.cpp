#include "converters/conversion_report.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace gm {

namespace {

std::string num(double v) { return jsonNumber(v); }

std::string errorJson(const FitError& e) {
    std::ostringstream s;
    s << "{\"E\": " << num(e.meanAbs) << ", \"rmse\": " << num(e.rmse)
      << ", \"psnr\": " << num(e.psnr) << ", \"max\": " << num(e.maxAbs)
      << ", \"uncovered\": " << num(e.uncovered) << ", \"pixels\": " << e.pixels << "}";
    return s.str();
}

std::string secondsJson(const StageSeconds& t) {
    std::ostringstream s;
    s << "{\"regions\": " << num(t.regions) << ", \"corners\": " << num(t.corners)
      << ", \"triangulate\": " << num(t.triangulate) << ", \"topology\": " << num(t.topology)
      << ", \"feature\": " << num(t.feature) << ", \"mesh\": " << num(t.mesh)
      << ", \"T\": " << num(t.triangulationStages()) << ", \"P\": " << num(t.mapStages())
      << ", \"M\": " << num(t.meshStages())
      << ", \"total\": " << num(t.total()) << "}";
    return s.str();
}

// The "segments" object of a whole-image conversion.
void writeSegmentsJson(std::ostringstream& s, const SegmentConvertReport& report, int totalPatches) {
    const ConvertReport& convertReport = report.convert;
    const SegmentStats& segmentation = report.segmentation;
    s << ",\n  \"segments\": {\"count\": " << convertReport.regions.size()
      << ", \"graph_regions\": " << segmentation.fhRegions
      << ", \"grabcut_changed\": " << segmentation.grabCutChanged
      << ", \"border_refined\": " << segmentation.borderRefined
      << ", \"grown\": " << segmentation.grown << ", \"merged\": " << segmentation.merged
      << ", \"failed\": " << report.failedRegions << ", \"holes_filled\": " << report.filledRegions
      << ", \"thin_parts_apart\": " << report.trimmedRegions
      << ", \"split_at_necks\": " << report.splitRegions << ", \"flat\": " << report.flatRegions
      << ", \"finer_segments\": " << report.finerSegments
      << ", \"thin_structures\": " << segmentation.thinStructures
      << ", \"thin_grown\": " << segmentation.thinGrown
      << ", \"ink_lines\": " << segmentation.inkLines
      << ", \"base_patches\": " << report.basePatches
      << ", \"flat_backdrop\": " << (report.flatBackdrop ? "true" : "false")
      << ", \"merged_into_backdrop\": " << report.mergedIntoBackdrop
      << ", \"residue_regions\": " << report.residueRegions
      << ", \"lifted_thin\": " << report.liftedThin
      << ", \"merged_across_thin\": " << report.mergedAcrossThin
      << ", \"region_uncovered\": " << num(report.regionUncovered)
      << ", \"total_patches\": " << totalPatches << ", \"conversions\": " << report.conversions
      << ",\n    \"seconds\": {\"segmentation\": " << num(report.segmentSeconds)
      << ", \"graph\": " << num(segmentation.fhSeconds)
      << ", \"grabcut\": " << num(segmentation.grabCutSeconds)
      << ", \"grow\": " << num(segmentation.growSeconds)
      << ", \"merge\": " << num(segmentation.mergeSeconds)
      << ", \"ink\": " << num(segmentation.inkSeconds)
      << ", \"regions\": " << num(report.regionsSeconds)
      << ", \"convert_wall\": " << num(report.convertSeconds)
      << ", \"measure\": " << num(report.measureSeconds)
      << ", \"total_wall\": " << num(report.totalSeconds) << "}"
      << ",\n    \"border_error\": " << errorJson(report.border)
      << ",\n    \"interior_error\": " << errorJson(report.interior) << "}";
}

// Region k's entry of "regions".
void writeRegionJson(std::ostringstream& s, const SegmentConvertReport& report, bool segment, size_t k) {
    const ConvertReport& convertReport = report.convert;
    const RegionReport& r = convertReport.regions[k];
    s << (k ? "," : "") << "\n    {\"pixels\": " << r.pixels << ", \"holes\": " << r.holes;
    if (segment)
        s << ", \"label\": " << report.regionLabels[k]
          << ", \"fallback\": " << jsonString(report.fallbacks[k]);
    if (segment && k < report.keptBudget.size())
        s << ", \"largest_budget\": " << report.largestBudget[k]
          << ", \"budget\": " << report.keptBudget[k]
          << ", \"spill_sse\": " << num(report.keptSpill[k]);
    s
      << ", \"triangles\": " << r.triangles << ", \"vertices\": " << r.vertices
      << ", \"map_refined_vertices\": " << r.mapRefinedVertices
      << ", \"tip_corners\": " << (r.tipCorners ? "true" : "false")
      << ", \"part\": " << jsonString(r.part)
      << ", \"flipped_triangles\": " << r.flippedTriangles << ", \"grid\": [" << r.columns
      << ", " << r.rows << "], \"patches\": " << r.patches
      << ", \"feature_solves\": " << r.featureSolves
      << ", \"outline_deviation\": " << r.outlineDeviation
      << ", \"outline_knots\": " << r.outlineKnots
      << ", \"hole_pixels\": " << r.holePixels << ", \"hole_pixels_painted\": " << r.holePixelsPainted
      << ", \"feature_map\": " << (r.featureMapUsed ? "true" : "false")
      << ", \"folded_patches\": " << r.foldedPatches
      << ",\n     \"seconds\": " << secondsJson(r.seconds)
      << ",\n     \"error\": " << errorJson(r.error) << ",\n     \"refinement\": [";
    for (size_t j = 0; j < r.refinement.size(); ++j) {
        const RefineStep& st = r.refinement[j];
        s << (j ? ", " : "") << "\n       {\"grid\": [" << st.columns << ", " << st.rows
          << "], \"patches\": " << st.patches << ", \"E\": " << num(st.meanAbs)
          << ", \"psnr\": " << num(st.psnr) << ", \"axis\": "
          << (st.axis ? jsonString(std::string(1, st.axis)) : "null")
          << ", \"knot\": " << num(st.knot) << ", \"seconds\": " << num(st.seconds) << "}";
    }
    s << "]}";
}

}  // namespace

const char* colorModeName(ColorMode mode) {
    switch (mode) {
        case ColorMode::Fit: return "hermite";
        case ColorMode::Sampled: return "sampled";
        default: return "bicubic";
    }
}

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '<' || static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string jsonNumber(double v) {
    if (std::isnan(v)) return "null";
    if (std::isinf(v)) return v > 0 ? "1e308" : "-1e308";
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

std::string conversionReportJson(const ReportFacts& facts, const SegmentConvertReport& report,
                                 const CompactFile& compact) {
    const ConvertReport& convertReport = report.convert;
    std::ostringstream s;
    s << "{\n  \"input\": " << jsonString(facts.input)
      << ",\n  \"output\": " << jsonString(facts.output) << ",\n  \"width\": " << facts.width
      << ",\n  \"height\": " << facts.height
      << ",\n  \"mask_source\": " << jsonString(convertReport.maskSource)
      << ",\n  \"colors\": " << jsonString(colorModeName(facts.colors))
      << ",\n  \"max_error\": " << num(facts.maxError)
      << ",\n  \"max_patches\": " << facts.maxPatches
      << ",\n  \"seconds\": " << secondsJson(convertReport.seconds)
      << ",\n  \"io_seconds\": {\"read\": " << num(facts.readSeconds)
      << ", \"mask\": " << num(facts.maskSeconds) << ", \"write\": " << num(facts.writeSeconds)
      << ", \"end_to_end\": " << num(facts.endToEndSeconds) << "}"
      << ",\n  \"meshes\": " << facts.meshes << ",\n  \"patches\": " << convertReport.patches
      << ",\n  \"error\": " << errorJson(convertReport.error)
      << ",\n  \"bytes\": {\"output\": " << facts.outputBytes
      << ", \"gmb_lossless\": " << facts.gmbLosslessBytes
      << ", \"gmb_compact\": " << compact.bytes.size() << ", \"svg\": ";
    if (facts.exactSvgBytes)
        s << *facts.exactSvgBytes << "}";
    else
        s << "null}";
    s << ",\n  \"compact\": {\"level\": " << compact.level << ", \"auto\": " << (facts.compactAuto ? "true" : "false")
      << ", \"bytes\": " << compact.bytes.size() << ", \"colors_refit\": " << jsonString(compact.refit)
      << ", \"error\": " << errorJson(compact.error) << "}";
    if (facts.segment) writeSegmentsJson(s, report, facts.totalPatches);
    s << ",\n  \"regions\": [";
    for (size_t k = 0; k < convertReport.regions.size(); ++k)
        writeRegionJson(s, report, facts.segment, k);
    s << "\n  ]\n}\n";
    return s.str();
}

}  // namespace gm
