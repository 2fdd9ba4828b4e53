// The images of a batch: from directories, glob patterns, image files and manifests (CSV or
// JSON lines: image, optional mask, output name and options per line; docs/batch.md).
#pragma once

#include <string>
#include <vector>

namespace gm {

struct BatchItem {
    std::string input;
    std::string mask;                  // empty: none
    std::string outputName;            // empty: the input's stem
    std::vector<std::string> options;  // convert's options for this image alone
    std::string origin;                // where it was named: "m.csv:12", a directory, a pattern
};

// Each source in turn: a directory gives its raster files (by name, not recursive), a manifest
// (.csv, .jsonl, .ndjson, .json) its lines, a pattern with * ? [ its matching files (by name),
// anything else is an image file. Relative paths in a manifest are relative to its directory.
// Throws gm::Error naming the source: a missing one, a pattern that matches nothing, a bad
// manifest line.
std::vector<BatchItem> gatherBatchItems(const std::vector<std::string>& sources);

// Splits an options text ("--max-error 2 --colors 'hermite'") into words as a shell would:
// whitespace separates, single and double quotes group. Throws std::invalid_argument on an
// unclosed quote.
std::vector<std::string> splitOptionText(const std::string& text);

// The output's base name of an item: its output name, else its input's file stem.
std::string outputStem(const BatchItem& item);

}  // namespace gm
