#include "batch_inputs.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "batch_json.h"
#include "formats/registry.h"
#include "meshcore/error.h"

namespace gm {

namespace fs = std::filesystem;

namespace {

bool isRasterPath(const std::string& path) {
    const MeshFormat* f = FormatRegistry::builtin().forReading(path);
    return f && f->name() == "raster";
}

bool isManifestPath(const std::string& path) {
    const std::string e = lowerExtension(path);
    return e == ".csv" || e == ".jsonl" || e == ".ndjson" || e == ".json";
}

std::vector<BatchItem> directoryItems(const std::string& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file(ec) && isRasterPath(e.path().string())) names.push_back(e.path().string());
    if (ec) throw Error("cannot list the directory: " + ec.message(), dir);
    std::sort(names.begin(), names.end());
    std::vector<BatchItem> items;
    for (const std::string& n : names) items.push_back({n, "", "", {}, dir});
    return items;
}

std::vector<BatchItem> globItems(const std::string& pattern) {
    glob_t g{};
    const int rc = ::glob(pattern.c_str(), 0, nullptr, &g);
    std::vector<BatchItem> items;
    if (rc == 0)
        for (size_t k = 0; k < g.gl_pathc; ++k) items.push_back({g.gl_pathv[k], "", "", {}, pattern});
    ::globfree(&g);
    if (items.empty()) throw Error("the pattern matches no file", pattern);
    return items;  // glob sorts its matches
}

// One CSV record's fields (RFC 4180 quoting; unquoted fields trimmed).
std::vector<std::string> csvFields(const std::string& line) {
    std::vector<std::string> fields;
    size_t k = 0;
    for (;;) {
        std::string f;
        while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
        if (k < line.size() && line[k] == '"') {
            for (++k;; ++k) {
                if (k >= line.size()) throw std::invalid_argument("unclosed quote");
                if (line[k] == '"') {
                    if (k + 1 < line.size() && line[k + 1] == '"') f += line[++k];
                    else break;
                } else {
                    f += line[k];
                }
            }
            ++k;
            while (k < line.size() && line[k] != ',') ++k;
        } else {
            while (k < line.size() && line[k] != ',') f += line[k++];
            f.erase(f.find_last_not_of(" \t\r") + 1);
        }
        fields.push_back(f);
        if (k >= line.size()) return fields;
        ++k;  // the comma
    }
}

const std::vector<std::string> kColumns = {"image", "mask", "options", "output"};

// A CSV manifest: a header naming the columns (image, mask, options, output) or none, when the
// columns are image, mask, options, output in that order.
BatchItem csvItem(const std::vector<std::string>& fields, const std::vector<std::string>& columns) {
    BatchItem item;
    if (fields.size() > columns.size()) throw std::invalid_argument("more fields than columns");
    for (size_t k = 0; k < fields.size(); ++k) {
        if (columns[k] == "image") item.input = fields[k];
        else if (columns[k] == "mask") item.mask = fields[k];
        else if (columns[k] == "output") item.outputName = fields[k];
        else if (columns[k] == "options") item.options = splitOptionText(fields[k]);
    }
    return item;
}

BatchItem jsonItem(const std::string& line) {
    BatchItem item;
    for (const auto& [key, v] : parseJsonObjectLine(line)) {
        const bool text = v.kind == JsonValue::String;
        if (key == "image" && text) item.input = v.text;
        else if (key == "mask" && (text || v.kind == JsonValue::Null)) item.mask = v.text;
        else if (key == "output" && (text || v.kind == JsonValue::Null)) item.outputName = v.text;
        else if (key == "options" && text) item.options = splitOptionText(v.text);
        else if (key == "options" && v.kind == JsonValue::Array) item.options = v.items;
        else if (key == "image" || key == "mask" || key == "output" || key == "options")
            throw std::invalid_argument("\"" + key + "\" has a value of the wrong type");
        else throw std::invalid_argument("unknown key \"" + key + "\" (image, mask, output, options)");
    }
    return item;
}

std::string besideManifest(const fs::path& manifestDir, const std::string& path) {
    if (path.empty() || fs::path(path).is_absolute()) return path;
    return (manifestDir / path).lexically_normal().string();
}

std::vector<BatchItem> manifestItems(const std::string& manifest) {
    std::ifstream f(manifest, std::ios::binary);
    if (!f) throw Error("cannot read the manifest", manifest);
    const bool csv = lowerExtension(manifest) == ".csv";
    const fs::path dir = fs::path(manifest).parent_path();
    std::vector<std::string> columns = kColumns;
    std::vector<BatchItem> items;
    std::string line;
    for (int number = 1; std::getline(f, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::string origin = manifest + ":" + std::to_string(number);
        try {
            BatchItem item;
            if (csv) {
                const std::vector<std::string> fields = csvFields(line);
                if (items.empty() && columns == kColumns && fields[0] == "image") {  // a header
                    for (const std::string& c : fields)
                        if (std::find(kColumns.begin(), kColumns.end(), c) == kColumns.end())
                            throw std::invalid_argument("unknown column '" + c + "' (image, mask, options, output)");
                    columns = fields;
                    continue;
                }
                item = csvItem(fields, columns);
            } else {
                item = jsonItem(line.substr(first));
            }
            if (item.input.empty()) throw std::invalid_argument("no image");
            item.input = besideManifest(dir, item.input);
            item.mask = besideManifest(dir, item.mask);
            item.origin = origin;
            items.push_back(std::move(item));
        } catch (const std::invalid_argument& e) {
            throw Error(std::string("line ") + std::to_string(number) + ": " + e.what(), manifest);
        }
    }
    return items;
}

}  // namespace

std::vector<BatchItem> gatherBatchItems(const std::vector<std::string>& sources) {
    std::vector<BatchItem> items;
    for (const std::string& source : sources) {
        std::error_code ec;
        std::vector<BatchItem> more;
        if (fs::is_directory(source, ec)) more = directoryItems(source);
        else if (fs::exists(source, ec) && isManifestPath(source)) more = manifestItems(source);
        else if (!fs::exists(source, ec) && source.find_first_of("*?[") != std::string::npos)
            more = globItems(source);
        else if (fs::exists(source, ec)) more = {{source, "", "", {}, source}};
        else throw Error("no such file or directory", source);
        items.insert(items.end(), more.begin(), more.end());
    }
    return items;
}

std::vector<std::string> splitOptionText(const std::string& text) {
    std::vector<std::string> words;
    std::string word;
    bool inWord = false;
    char quote = 0;
    for (const char c : text) {
        if (quote) {
            if (c == quote) quote = 0;
            else word += c;
        } else if (c == '\'' || c == '"') {
            quote = c;
            inWord = true;
        } else if (c == ' ' || c == '\t') {
            if (inWord) words.push_back(word);
            word.clear();
            inWord = false;
        } else {
            word += c;
            inWord = true;
        }
    }
    if (quote) throw std::invalid_argument("unclosed quote in the options");
    if (inWord) words.push_back(word);
    return words;
}

std::string outputStem(const BatchItem& item) {
    return item.outputName.empty() ? fs::path(item.input).stem().string() : item.outputName;
}

}  // namespace gm
