// The batch log: one JSON line per image and run, appended (docs/batch.md). It is also what a
// rerun reads to know which images are done.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace gm {

struct BatchRecord {
    std::string input, mask;
    std::vector<std::string> outputs;
    std::string status;   // ok, error or skipped
    std::string options;  // the image's conversion options, canonical (batch_command.cpp)
    uint64_t patches = 0;
    double meanAbs = -1, psnr = -1;  // negative: none
    double seconds = -1, cpuSeconds = -1, peakRssMb = -1;
    std::string error, messages;
};

// The record as one JSON line (with its newline).
std::string batchRecordJson(const BatchRecord& r);

// What identifies an image's conversion in the log: its input, mask, outputs and options.
std::string batchRecordKey(const BatchRecord& r);

// The keys of the records with status ok in the log at `path` (none when it does not exist).
// Lines that are not records (a foreign line, a torn one) are passed over.
std::set<std::string> finishedBatchKeys(const std::string& path);

// The log file, opened for appending; each record is one write(2), so that records of
// processes sharing the file do not interleave.
class BatchLog {
public:
    // Throws gm::Error naming the file when it cannot be opened.
    explicit BatchLog(const std::string& path);
    ~BatchLog();
    BatchLog(const BatchLog&) = delete;
    BatchLog& operator=(const BatchLog&) = delete;
    // Throws gm::Error on a failed write.
    void append(const BatchRecord& r);

private:
    std::string path_;
    int fd_ = -1;
};

}  // namespace gm
