#include "batch_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "batch_json.h"
#include "converters/conversion_report.h"  // jsonString, jsonNumber
#include "meshcore/error.h"

namespace gm {

namespace {

std::string optionalNumber(double v) { return v < 0 ? "null" : jsonNumber(v); }

std::string optionalString(const std::string& s) { return s.empty() ? "null" : jsonString(s); }

}  // namespace

std::string batchRecordJson(const BatchRecord& r) {
    std::string outputs;
    for (const std::string& o : r.outputs) outputs += (outputs.empty() ? "" : ",") + jsonString(o);
    const bool ok = r.status == "ok";
    std::string line = "{\"input\":" + jsonString(r.input) + ",\"mask\":" + optionalString(r.mask) +
                       ",\"outputs\":[" + outputs + "],\"status\":" + jsonString(r.status) +
                       ",\"patches\":" + (ok ? std::to_string(r.patches) : "null") +
                       ",\"E\":" + optionalNumber(r.meanAbs) + ",\"PSNR\":" + optionalNumber(r.psnr) +
                       ",\"seconds\":" + optionalNumber(r.seconds) +
                       ",\"cpu_seconds\":" + optionalNumber(r.cpuSeconds) +
                       ",\"peak_rss_mb\":" + optionalNumber(r.peakRssMb) +
                       ",\"error\":" + optionalString(r.error) +
                       ",\"messages\":" + optionalString(r.messages) +
                       ",\"options\":" + jsonString(r.options) + "}\n";
    return line;
}

std::string batchRecordKey(const BatchRecord& r) {
    std::string key = r.input + '\n' + r.mask + '\n' + r.options;
    for (const std::string& o : r.outputs) key += '\n' + o;
    return key;
}

std::set<std::string> finishedBatchKeys(const std::string& path) {
    std::set<std::string> keys;
    std::ifstream f(path, std::ios::binary);
    std::string line;
    while (std::getline(f, line)) {
        try {
            const auto fields = parseJsonObjectLine(line);
            auto text = [&](const char* key) {
                auto it = fields.find(key);
                return it == fields.end() || it->second.kind != JsonValue::String ? std::string()
                                                                                  : it->second.text;
            };
            if (text("status") != "ok" || !fields.count("outputs")) continue;
            BatchRecord r;
            r.input = text("input");
            r.mask = text("mask");
            r.options = text("options");
            r.outputs = fields.at("outputs").items;
            keys.insert(batchRecordKey(r));
        } catch (const std::invalid_argument&) {
            // not a record of ours: passed over
        }
    }
    return keys;
}

BatchLog::BatchLog(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0666);
    if (fd_ < 0) throw Error(std::string("cannot open the log: ") + std::strerror(errno), path);
}

BatchLog::~BatchLog() {
    if (fd_ >= 0) ::close(fd_);
}

void BatchLog::append(const BatchRecord& r) {
    const std::string line = batchRecordJson(r);
    size_t done = 0;
    while (done < line.size()) {
        const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw Error(std::string("cannot write the log: ") + std::strerror(errno), path_);
        done += static_cast<size_t>(n);
    }
}

}  // namespace gm
