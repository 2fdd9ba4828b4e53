// The temporaries this process has open, for a signal handler to remove: SIGINT, SIGTERM or
// SIGHUP must not leave half-written files beside the outputs. Everything the handler touches is
// a fixed array of atomics and paths, so it stays async-signal-safe.
#pragma once

#include <string>

namespace gm {

// Records a live temporary (a file, or an empty directory of temporaries); returns its slot, or -1 when the path is too long or every slot is
// taken (that temporary is then only removed by its owner or by the next run's stale cleanup).
int registerTemporary(const std::string& path);

// Forgets a slot from registerTemporary (-1 is ignored). Call after the file is renamed or removed.
void unregisterTemporary(int slot);

// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every registered temporary (files
// first, then directories), then re-raise the signal with its default action (so the exit
// status still says which signal).
// A signal the process inherited as ignored stays ignored. Call once, from main.
void removeTemporariesOnSignals();

}  // namespace gm
