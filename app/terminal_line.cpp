#include "terminal_line.h"

#include <unistd.h>

#include <cstdio>

#include "verbosity.h"

namespace gm {

TerminalLine::TerminalLine()
    : enabled_(::isatty(2) == 1 && cli::verbosity() != cli::Verbosity::Quiet) {}

void TerminalLine::show(const std::string& text) {
    if (!enabled_) return;
    std::fputs(("\r" + text + "\x1b[K").c_str(), stderr);
    std::fflush(stderr);
    shown_ = true;
}

void TerminalLine::keep() {
    if (!shown_) return;
    std::fputs("\n", stderr);
    shown_ = false;
}

void TerminalLine::erase() {
    if (!shown_) return;
    std::fputs("\r\x1b[K", stderr);
    std::fflush(stderr);
    shown_ = false;
}

}  // namespace gm
