// Work spread over threads with the workers' exceptions handed back to the caller. An exception
// that leaves a std::thread's function ends the process (std::terminate, SIGABRT): every pool in
// gradmesh runs through parallelFor, so that a failure on a worker (std::bad_alloc, gm::Error)
// reaches the command like one on the main thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace gm {

// Runs f(k, worker) for k in 0..count-1 on up to `threads` threads (this one included; worker
// numbers them from 0). After the first exception no new item starts; once every thread has
// stopped, that exception is rethrown here.
template <class F>
void parallelFor(int count, int threads, const F& f) {
    if (threads <= 1 || count <= 1) {
        for (int k = 0; k < count; ++k) f(k, 0);
        return;
    }
    std::atomic<int> next{0};
    std::exception_ptr failure;
    std::atomic<bool> failed{false};
    auto work = [&](int worker) {
        for (;;) {
            const int k = next.fetch_add(1);
            if (k >= count || failed.load()) return;
            try {
                f(k, worker);
            } catch (...) {
                if (!failed.exchange(true)) failure = std::current_exception();
            }
        }
    };
    const int n = std::min(threads, count);
    std::vector<std::thread> pool;
    try {
        pool.reserve(static_cast<size_t>(n) - 1);
        for (int t = 1; t < n; ++t) pool.emplace_back(work, t);
    } catch (...) {
        // No further thread could be started (no memory for its stack): those running and
        // this one share the work.
    }
    work(0);
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

// The number of threads `threads` asks for: itself when positive, else every hardware thread.
inline int threadsToUse(int threads) {
    return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace gm
