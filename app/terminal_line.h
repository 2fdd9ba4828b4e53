// One status line on standard error, redrawn in place (\r) while a command runs, when standard
// error is a terminal and the run is not --quiet; nothing at all otherwise (a pipe or a log
// file gets no progress).
#pragma once

#include <string>

namespace gm {

class TerminalLine {
public:
    TerminalLine();
    bool enabled() const { return enabled_; }
    // Replaces the line with `text`.
    void show(const std::string& text);
    // Leaves the line as it is and moves on to the next one.
    void keep();
    // Removes the line, leaving the cursor where it started.
    void erase();

private:
    bool enabled_, shown_ = false;
};

}  // namespace gm
