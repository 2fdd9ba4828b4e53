// Batch's workers: each image is converted in a child process of its own, at most `workers` at
// once. A child shares nothing mutable with the others (convert's code silences and restores
// the process's stderr, libraries keep process-wide state), its crash or out-of-memory kill is
// that image's failure only, and its peak memory and CPU time are measured apart.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace gm {

struct ChildOutcome {
    bool ok = false;
    std::string text;      // what the work returned, or the error's message
    std::string messages;  // what the child printed on stderr
    double seconds = 0, cpuSeconds = 0, peakRssMb = 0;
};

// Runs work(k) for each k of `order` in a child process, `workers` at a time, in that order.
// work returns its result text or throws (the message becomes the outcome's text). done(k, ...)
// is called in this process as each child ends; tick() about twice a second meanwhile. A child
// gets SIGTERM if this process dies. This process must not be running other threads.
void runInChildProcesses(const std::vector<int>& order, int workers,
                         const std::function<std::string(int)>& work,
                         const std::function<void(int, const ChildOutcome&)>& done,
                         const std::function<void()>& tick);

}  // namespace gm
