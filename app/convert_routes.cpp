#include "convert_routes.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "meshcore/error.h"
#include "output_format.h"
#include "std_streams.h"
#include "verbosity.h"

namespace gm::cli {

namespace {

namespace fs = std::filesystem;

// Raster images are what render writes; what it reads must be a mesh file.
bool isRaster(const std::string& extension) {
    const MeshFormat* f = FormatRegistry::builtin().forPath("x" + extension);
    return f && f->name() == "raster";
}

// The extension of the format written to `out`: --to's (`to`), else out's own. A name whose
// extension says another format than --to is a usage error.
std::string outputFormat(const std::string& command, const std::string& out, const std::string& to) {
    const std::string own = lowerExtension(out);
    const MeshFormat* ownFormat = isStdStream(out) ? nullptr : FormatRegistry::builtin().forPath(out);
    if (to.empty()) {
        if (isStdStream(out))
            throw UsageError("-o - (standard output) needs --to FORMAT (" + writableFormatNames() + ")");
        FormatRegistry::builtin().writerFor(out);  // names the formats written when out's is none
    } else if (ownFormat && ownFormat->canWrite() && own != to) {
        throw UsageError("'" + out + "' names a " + own.substr(1) + " file but --to says " + to.substr(1));
    }
    const std::string format = to.empty() ? own : to;
    if (command == "render" && !isRaster(format))
        throw UsageError("render writes raster images (.png .jpg .tif .exr); use convert for '" + format + "'");
    return format;
}

// IN (or -) to OUT (or -) in the format `format`: through private files where a stream or a
// name without the format's extension stands for either.
void convertRouted(const std::string& in, const std::string& out, const std::string& format,
                   const Args& args, const ConvertFile& convertFile) {
    std::optional<PrivateDir> dir;
    std::string inPath = in, outPath = out;
    if (isStdStream(in)) {
        dir.emplace();
        inPath = spoolStandardInput(*dir, FormatRegistry::builtin());
    } else {
        requireRegularFile(in);
    }
    const bool toStdout = isStdStream(out);
    const bool spoolOut = toStdout || lowerExtension(out) != format;
    if (!toStdout) {
        if (!isStdStream(in)) refuseOverwritingInput(in, out);
        if (auto mask = args.values.find("--mask"); mask != args.values.end() && !mask->second.empty())
            refuseOverwritingInput(mask->second, out, "mask");
    }
    if (spoolOut) {
        if (!dir) dir.emplace();
        outPath = dir->file("output" + format);
        if (!toStdout) {  // fail before the work when the place cannot be written
            OutputBatch place;
            place.reserve(out);
        }
    }
    const MeshFormat& writer = FormatRegistry::builtin().writerFor("x" + format);
    withFileNamed(inPath, isStdStream(in) ? kStdinName : in, [&] {
        withFileNamed(outPath, toStdout ? kStdoutName : out,
                      [&] { convertFile(inPath, outPath, writer); });
    });
    if (!spoolOut) return;
    if (toStdout)
        copyToStandardOutput(outPath);
    else
        writeFileAtomically(out, readWholeFile(outPath, uint64_t(1) << 40));
}

// IN... --output-dir DIR: each input on its own, every failure reported; the exit code is the
// worst of them.
int convertSeveral(const std::string& command, const Args& args, const std::string& to,
                   const ConvertFile& convertFile) {
    if (args.values.count("--output"))
        throw UsageError("-o names one output: give one input, or --output-dir DIR for several");
    for (const char* perInput : {"--report", "--mask"})
        if (args.values.count(perInput))
            throw UsageError(std::string(perInput) + " is for one input; convert each on its own");
    const auto dirIt = args.values.find("--output-dir");
    if (dirIt == args.values.end() || dirIt->second.empty())
        throw UsageError("several inputs need --output-dir DIR");
    const std::string format = to.empty() ? (command == "render" ? ".png" : ".gmb") : to;
    std::map<std::string, std::string> outputs;  // output -> input
    std::vector<std::pair<std::string, std::string>> work;
    for (const std::string& in : args.positional) {
        if (isStdStream(in))
            throw UsageError("- (standard input) is one input: give it alone, with -o OUT");
        const std::string out = (fs::path(dirIt->second) / (fs::path(in).stem().string() + format)).string();
        if (auto [it, fresh] = outputs.emplace(out, in); !fresh)
            throw UsageError(it->second + " and " + in + " would both write " + out);
        work.emplace_back(in, out);
    }
    outputFormat(command, work.front().second, to.empty() ? format : to);
    std::error_code ec;
    fs::create_directories(dirIt->second, ec);
    if (ec) throw Error("cannot make the output directory: " + ec.message(), dirIt->second);
    int worst = 0, failed = 0;
    for (const auto& [in, out] : work) {
        const int code = runReportingErrors(command, [&] {
            convertRouted(in, out, format, args, convertFile);
            detail("gradmesh %s: %s -> %s\n", command.c_str(), in.c_str(), out.c_str());
            return 0;
        });
        worst = std::max(worst, code);
        failed += code != 0;
    }
    if (failed)
        note("gradmesh %s: %d of %zu inputs failed\n", command.c_str(), failed, work.size());
    return worst;
}

}  // namespace

int runConversions(const std::string& command, const Args& args, const ConvertFile& convertFile) {
    if (args.positional.empty()) throw UsageError("expects an input file (- for standard input)");
    std::string to;
    if (auto it = args.values.find("--to"); it != args.values.end()) {
        to = writableExtension(it->second);
        if (to.empty())
            throw UsageError("--to expects a format to write (" + writableFormatNames() + "), got '" +
                             it->second + "'");
    }
    if (args.positional.size() > 1 || args.values.count("--output-dir"))
        return convertSeveral(command, args, to, convertFile);
    auto out = args.values.find("--output");
    if (out == args.values.end() || out->second.empty()) throw UsageError("missing -o OUTPUT");
    convertRouted(args.positional[0], out->second, outputFormat(command, out->second, to), args,
                  convertFile);
    return 0;
}

}  // namespace gm::cli
