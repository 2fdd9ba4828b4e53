#include "cli_common.h"

#include <malloc.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <system_error>

#include "formats/input_file.h"
#include "formats/temp_registry.h"
#include "meshcore/error.h"
#include "meshcore/printable_text.h"
#include "meshcore/validate.h"
#include "verbosity.h"

namespace gm::cli {

namespace {

// An argument that is an option: "-x..." but not a negative number ("-3", "-.5").
bool isOption(const std::string& s) {
    return s.size() > 1 && s[0] == '-' &&
           !(std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.');
}

// What an error prints: one line, input text in it (file names, SVG ids, attribute values)
// with its control characters escaped.
std::string messageLine(const std::string& message) { return printableText(oneLine(message)); }

// A thread that cannot start (std::thread's system_error EAGAIN, TBB's "pthread_create has
// failed") means the process has no memory left for the thread's stack.
bool isThreadStartFailure(const std::exception& e) {
    if (std::string(e.what()).find("pthread_create") != std::string::npos) return true;
    const auto* system = dynamic_cast<const std::system_error*>(&e);
    return system && system->code() == std::errc::resource_unavailable_try_again;
}

}  // namespace

Args parseArgs(const std::string& command, int argc, char** argv,
               const std::set<std::string>& valued, const std::set<std::string>& flagNames) {
    Args a;
    for (int k = 2; k < argc; ++k) {
        std::string s = argv[k];
        if (s == "-o") s = "--output";
        if (!isOption(s)) {
            a.positional.push_back(s);
            continue;
        }
        std::string value;
        const size_t eq = s.find('=');
        const bool hasValue = eq != std::string::npos;
        if (hasValue) {
            value = s.substr(eq + 1);
            s = s.substr(0, eq);
        }
        if (valued.count(s)) {
            if (!hasValue) {
                if (k + 1 >= argc) throw UsageError(s + " needs a value");
                value = argv[++k];
            }
            a.values[s] = value;
        } else if (flagNames.count(s) && !hasValue) {
            a.flags.insert(s);
        } else {
            throw UsageError("unknown option '" + s + "' for '" + command + "'");
        }
    }
    return a;
}

double parseNumber(const std::string& option, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        char range[64];
        std::snprintf(range, sizeof range, "%g to %g", lo, hi);
        throw UsageError(option + " expects a number from " + range + ", got '" + text + "'");
    }
    return v;
}

void requireInputFile(const std::string& path) { requireRegularFile(path); }

const MeshFormat* readerFor(const FormatRegistry& registry, const std::string& path) {
    const MeshFormat* f = registry.forReading(path);
    if (!f || !f->canRead()) {
        throw Error(f ? "cannot read meshes from " + f->name() + " files"
                      : "unknown file type '" + lowerExtension(path) + "'",
                    path);
    }
    return f;
}

Document readDocument(const FormatRegistry& registry, const std::string& path,
                      const ReadOptions& options) {
    requireInputFile(path);
    Document doc = readerFor(registry, path)->read(path, options);
    if (std::string e = validateDocument(doc); !e.empty()) throw Error("invalid mesh: " + e, path);
    return doc;
}

void prepareProcess() {
    // Refinement allocates and frees the same image-sized buffers (render samples, the fit's
    // system) on every step; glibc hands blocks over its mmap threshold back to the kernel and
    // the next step faults them in again, a large share of a long conversion's time.
    // Blocks up to 32 MB stay in the heap, which is trimmed only above 256 MB of free space.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    // Interrupted or terminated, the run removes its temporaries before it dies; over a file
    // size limit (ulimit -f), a write fails with an error instead of killing the run.
    removeTemporariesOnSignals();
    std::signal(SIGXFSZ, SIG_IGN);
}

int runReportingErrors(const std::string& command, const std::function<int()>& run) {
    try {
        const auto start = std::chrono::steady_clock::now();
        const int code = run();
        detail("gradmesh %s: %.3f s\n", command.c_str(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        return code;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "gradmesh %s: %s (see gradmesh %s --help)\n", command.c_str(),
                     messageLine(e.what()).c_str(), command.c_str());
        return 2;
    } catch (const Error& e) {
        std::fprintf(stderr, "gradmesh %s: %s\n", command.c_str(), messageLine(e.what()).c_str());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "gradmesh %s: out of memory\n", command.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gradmesh %s: %s%s\n", command.c_str(),
                     isThreadStartFailure(e) ? "out of memory: cannot start a thread: " : "",
                     messageLine(e.what()).c_str());
        return 1;
    }
}

}  // namespace gm::cli
