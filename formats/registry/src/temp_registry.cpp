#include "formats/temp_registry.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>

namespace gm {

namespace {

enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2 };

struct Slot {
    std::atomic<int> state{kFree};
    char path[PATH_MAX];
};

constexpr int kSlots = 64;
Slot g_slots[kSlots];

static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads these atomics");

extern "C" void removeTemporariesAndReraise(int sig) {
    const int savedErrno = errno;
    for (Slot& s : g_slots)
        if (s.state.load() == kLive) ::unlink(s.path);
    // Then the private directories, emptied by the first pass.
    for (Slot& s : g_slots)
        if (s.state.load() == kLive) ::rmdir(s.path);
    // Default action on re-raise: the signal is blocked while this runs and is delivered when
    // the handler returns.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    errno = savedErrno;
}

}  // namespace

int registerTemporary(const std::string& path) {
    if (path.size() + 1 > sizeof g_slots[0].path) return -1;
    for (int k = 0; k < kSlots; ++k) {
        int expected = kFree;
        if (!g_slots[k].state.compare_exchange_strong(expected, kFilling)) continue;
        std::memcpy(g_slots[k].path, path.c_str(), path.size() + 1);
        g_slots[k].state.store(kLive);
        return k;
    }
    return -1;
}

void unregisterTemporary(int slot) {
    if (slot < 0 || slot >= kSlots) return;
    g_slots[slot].state.store(kFree);
}

void removeTemporariesOnSignals() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old {};
        if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        struct sigaction sa {};
        sa.sa_handler = removeTemporariesAndReraise;
        sigemptyset(&sa.sa_mask);
        for (int other : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, other);
        sigaction(sig, &sa, nullptr);
    }
}

}  // namespace gm
