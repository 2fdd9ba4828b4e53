#include "batch_command.h"

#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "batch_inputs.h"
#include "batch_log.h"
#include "batch_pool.h"
#include "batch_progress.h"
#include "batch_shard.h"
#include "converters/conversion_report.h"  // jsonNumber
#include "formats/input_file.h"
#include "image_command.h"
#include "meshcore/error.h"
#include "meshcore/printable_text.h"
#include "output_format.h"

namespace gm {

namespace {

namespace fs = std::filesystem;

const std::set<std::string> kBatchValued = {"--output-dir", "--to", "--jobs", "--log", "--shard"};
const std::set<std::string> kBatchFlags = {"--force", "--dry-run"};
// Options of convert that name one file: a batch has one per image, given in a manifest.
const std::set<std::string> kPerImageOnly = {"--output", "--mask", "--report"};

std::string perImageOnly(const std::string& option) {
    if (option == "--mask") return "--mask is per image: give it in a manifest's mask column";
    if (option == "--report") return "batch takes no --report: its log (--log) has each image's figures";
    return "batch writes DIR/<stem>.<ext>: give --output-dir (and a manifest's output column for a name)";
}

struct ParsedOptions {
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;
    std::set<std::string> flags;
};

// Words as convert's command line takes them: --name value, --name=value, flags; anything not
// starting with '-' (or a negative number) is positional.
ParsedOptions parseOptions(const std::vector<std::string>& words, const std::set<std::string>& valued,
                           const std::set<std::string>& flags, const std::string& where) {
    ParsedOptions p;
    for (size_t k = 0; k < words.size(); ++k) {
        std::string w = words[k] == "-o" ? "--output" : words[k];
        const bool option = w.size() > 1 && w[0] == '-' && !std::isdigit(static_cast<unsigned char>(w[1])) && w[1] != '.';
        if (!option) {
            p.positional.push_back(w);
            continue;
        }
        std::string value;
        const size_t eq = w.find('=');
        const bool hasValue = eq != std::string::npos;
        if (hasValue) {
            value = w.substr(eq + 1);
            w = w.substr(0, eq);
        }
        if (kPerImageOnly.count(w)) throw std::invalid_argument(perImageOnly(w) + where);
        if (valued.count(w)) {
            if (!hasValue && k + 1 >= words.size()) throw std::invalid_argument(w + " needs a value" + where);
            p.values[w] = hasValue ? value : words[++k];
        } else if (flags.count(w) && !hasValue) {
            p.flags.insert(w);
        } else {
            throw std::invalid_argument("unknown option '" + w + "' for 'batch'" + where);
        }
    }
    return p;
}

// The cores this process may run on (taskset, a Slurm allocation), else the machine's.
int usableCores() {
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

struct BatchSettings {
    std::vector<std::string> sources;
    std::string outputDir, logPath;
    std::vector<std::string> extensions;  // ".gmb", ".svg"
    int workers = 1;
    Shard shard;
    bool force = false, dryRun = false;
    std::map<std::string, std::string> values;  // convert's options for every image
    std::set<std::string> flags;
};

BatchSettings parseSettings(const std::vector<std::string>& args, const ConvertSyntax& convert) {
    std::set<std::string> valued = convert.valued, flags = convert.flags;
    valued.insert(kBatchValued.begin(), kBatchValued.end());
    flags.insert(kBatchFlags.begin(), kBatchFlags.end());
    ParsedOptions p = parseOptions(args, valued, flags, "");
    BatchSettings s;
    s.sources = p.positional;
    if (s.sources.empty()) throw std::invalid_argument("expects inputs: directories, patterns, images or manifests");
    auto take = [&](const char* name, std::string fallback) {
        auto it = p.values.find(name);
        if (it == p.values.end()) return fallback;
        std::string v = it->second;
        p.values.erase(it);
        return v;
    };
    s.outputDir = take("--output-dir", "");
    if (s.outputDir.empty()) throw std::invalid_argument("missing --output-dir DIR");
    s.extensions = outputExtensions(take("--to", "gmb"));
    s.logPath = take("--log", (fs::path(s.outputDir) / "gradmesh-batch.jsonl").string());
    s.shard = parseShard(take("--shard", "0/1"));
    const std::string jobs = take("--jobs", std::to_string(usableCores()));
    if (jobs.empty() || jobs.size() > 4 || jobs.find_first_not_of("0123456789") != std::string::npos || std::stoi(jobs) < 1)
        throw std::invalid_argument("--jobs expects a number of processes from 1, got '" + jobs + "'");
    s.workers = std::stoi(jobs);
    s.force = p.flags.erase("--force") > 0;
    s.dryRun = p.flags.erase("--dry-run") > 0;
    s.values = p.values;
    s.flags = p.flags;
    return s;
}

// One image of the batch, as its child process converts it.
struct BatchJob {
    BatchRecord record;  // input, mask, outputs, options
    std::map<std::string, std::string> values;
    std::set<std::string> flags;
    std::string problem;  // found before converting (bad options in its manifest line)
};

// The options that decide an image's outputs, in a fixed order (--threads does not).
std::string canonicalOptions(const std::map<std::string, std::string>& values, const std::set<std::string>& flags) {
    std::string text;
    for (const auto& [name, value] : values)
        if (name != "--threads" && name != "--mask") text += (text.empty() ? "" : " ") + name + "=" + value;
    for (const std::string& f : flags) text += (text.empty() ? "" : " ") + f;
    return text;
}

// Every image's job: its outputs, its options (the command's, then its manifest line's).
// Two images writing the same output is a usage error.
std::vector<BatchJob> makeJobs(const std::vector<BatchItem>& items, const BatchSettings& s,
                               const ConvertSyntax& convert) {
    std::vector<BatchJob> jobs;
    std::map<std::string, std::string> writers;  // output -> the input writing it
    for (const BatchItem& item : items) {
        BatchJob job;
        job.record.input = item.input;
        job.record.mask = item.mask;
        for (const std::string& ext : s.extensions) {
            const std::string out = (fs::path(s.outputDir) / (outputStem(item) + ext)).string();
            auto [it, fresh] = writers.emplace(out, item.input);
            if (!fresh)
                throw std::invalid_argument(it->second + " and " + item.input + " would both write " + out +
                                            " (name their outputs in a manifest's output column)");
            job.record.outputs.push_back(out);
        }
        job.values = s.values;
        job.flags = s.flags;
        try {
            const ParsedOptions own = parseOptions(item.options, convert.valued, convert.flags, " (in " + item.origin + ")");
            if (!own.positional.empty())
                throw std::invalid_argument("unexpected '" + own.positional[0] + "' in the options of " + item.origin);
            for (const auto& [k, v] : own.values) job.values[k] = v;
            job.flags.insert(own.flags.begin(), own.flags.end());
        } catch (const std::invalid_argument& e) {
            job.problem = e.what();
        }
        if (!item.mask.empty()) job.values["--mask"] = item.mask;
        job.record.options = canonicalOptions(job.values, job.flags);
        jobs.push_back(std::move(job));
    }
    return jobs;
}

// The image's options as convert's conversion reads them: the valued ones and the image flags.
std::map<std::string, std::string> conversionValues(const BatchJob& job) {
    std::map<std::string, std::string> values = job.values;
    for (const std::string& f : kImageFlagOptions)
        if (job.flags.count(f)) values[f] = "1";
    return values;
}

// In the child: the conversion of one image, as convert does it. Returns its figures.
std::string convertJob(const BatchJob& job, const ConvertSyntax& convert) {
    if (!job.problem.empty()) throw std::invalid_argument(job.problem);
    const std::string& in = job.record.input;
    requireRegularFile(in);
    const MeshFormat* reader = FormatRegistry::builtin().forReading(in);
    if (!reader || reader->name() != "raster")
        throw Error("not a raster image (batch converts images: .png .jpg .tif .exr ...)", in);
    if (!job.record.mask.empty()) requireRegularFile(job.record.mask);
    std::vector<ImageTarget> targets;
    for (const std::string& out : job.record.outputs) {
        std::error_code ec;
        if (fs::exists(out, ec) && (fs::equivalent(in, out, ec) ||
                                    (!job.record.mask.empty() && fs::equivalent(job.record.mask, out, ec))))
            throw Error("the output would overwrite an input; refusing", out);
        fs::create_directories(fs::path(out).parent_path());
        targets.push_back({out, FormatRegistry::builtin().forPath(out)});
    }
    const WriteOptions wo = convert.writeOptions(job.values, job.flags);
    const ImageFigures f = convertImageToTargets(in, targets, wo, conversionValues(job));
    return std::to_string(f.patches) + " " + jsonNumber(f.meanAbs) + " " + jsonNumber(f.psnr);
}

// An error message as convert prints it: one line, control characters escaped.
std::string oneLineMessage(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return printableText(text);
}

void recordOutcome(BatchRecord& r, const ChildOutcome& o) {
    r.status = o.ok ? "ok" : "error";
    r.seconds = o.seconds;
    r.cpuSeconds = o.cpuSeconds;
    r.peakRssMb = o.peakRssMb;
    r.messages = oneLineMessage(o.messages);
    if (!o.ok) {
        r.error = oneLineMessage(o.text);
        return;
    }
    unsigned long long patches = 0;
    double e = -1, psnr = -1;
    if (std::sscanf(o.text.c_str(), "%llu %lf %lf", &patches, &e, &psnr) == 3) {
        r.patches = patches;
        r.meanAbs = e;
        r.psnr = psnr;
    }
}

bool outputsExist(const BatchRecord& r) {
    std::error_code ec;
    for (const std::string& o : r.outputs)
        if (!fs::is_regular_file(o, ec)) return false;
    return true;
}

}  // namespace

namespace {

// The images of this shard not yet done (all with --force), largest file first: a large image
// started last would leave the other workers idle at the end.
std::vector<int> imagesToConvert(const std::vector<BatchJob>& jobs, const BatchSettings& s,
                                 std::vector<int>& skipped) {
    const std::set<std::string> finished = s.force ? std::set<std::string>() : finishedBatchKeys(s.logPath);
    std::vector<int> todo;
    for (size_t k = 0; k < jobs.size(); ++k) {
        if (!s.shard.owns(k)) continue;
        const BatchRecord& r = jobs[k].record;
        const bool done = finished.count(batchRecordKey(r)) && outputsExist(r);
        (done ? skipped : todo).push_back(static_cast<int>(k));
    }
    std::vector<uintmax_t> bytes(jobs.size(), 0);
    for (int k : todo) {
        std::error_code ec;
        const uintmax_t b = fs::file_size(jobs[k].record.input, ec);
        bytes[k] = ec ? 0 : b;
    }
    std::stable_sort(todo.begin(), todo.end(), [&](int a, int b) { return bytes[a] > bytes[b]; });
    return todo;
}

void printPlan(const std::vector<BatchJob>& jobs, const std::vector<int>& todo, const std::vector<int>& skipped) {
    std::vector<int> all = todo;
    all.insert(all.end(), skipped.begin(), skipped.end());
    std::sort(all.begin(), all.end());
    for (int k : all) {
        const bool skip = std::find(skipped.begin(), skipped.end(), k) != skipped.end();
        std::string line = (skip ? "skip " : "convert ") + printableText(jobs[k].record.input) + " ->";
        for (const std::string& o : jobs[k].record.outputs) line += " " + printableText(o);
        std::puts(line.c_str());
    }
}

}  // namespace

int batchCommand(const std::vector<std::string>& args, const ConvertSyntax& convert) {
    BatchSettings s = parseSettings(args, convert);
    // The options every image shares are checked before any work, as convert checks them.
    convert.writeOptions(s.values, s.flags);
    BatchJob shared;
    shared.values = s.values;
    shared.flags = s.flags;
    checkImageOptions(conversionValues(shared));

    // The whole list, every shard alike: the same images, outputs and clashes on every machine.
    std::vector<BatchJob> jobs = makeJobs(gatherBatchItems(s.sources), s, convert);
    std::vector<int> skipped;
    const std::vector<int> todo = imagesToConvert(jobs, s, skipped);
    if (s.dryRun) {
        printPlan(jobs, todo, skipped);
        return 0;
    }
    std::error_code ec;
    fs::create_directories(s.outputDir, ec);
    if (ec) throw Error("cannot make the output directory: " + ec.message(), s.outputDir);
    BatchLog log(s.logPath);
    for (int k : skipped) {
        BatchRecord r = jobs[k].record;
        r.status = "skipped";
        log.append(r);
    }
    // One thread per image while there are images enough for every worker; a lone image gets
    // the cores. The outputs do not depend on it.
    const int workers = std::max(1, std::min<int>(s.workers, static_cast<int>(todo.size())));
    const int threadsPerImage = std::max(1, usableCores() / workers);
    for (int k : todo)
        if (!jobs[k].values.count("--threads")) jobs[k].values["--threads"] = std::to_string(threadsPerImage);

    BatchProgress progress(static_cast<int>(todo.size()), static_cast<int>(skipped.size()));
    int failed = 0;
    runInChildProcesses(
        todo, workers, [&](int k) { return convertJob(jobs[k], convert); },
        [&](int k, const ChildOutcome& outcome) {
            BatchRecord r = jobs[k].record;
            recordOutcome(r, outcome);
            log.append(r);
            failed += outcome.ok ? 0 : 1;
            progress.imageDone(outcome.ok);
        },
        [&] { progress.redraw(); });
    progress.finish();
    if (failed > 0)
        std::fprintf(stderr, "gradmesh batch: %d of %zu images failed (their records in %s say why)\n",
                     failed, todo.size(), printableText(s.logPath).c_str());
    return failed > 0 ? 1 : 0;
}

}  // namespace gm
