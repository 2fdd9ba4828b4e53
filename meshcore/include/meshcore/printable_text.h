// Text from an input (a file name, an SVG id, an attribute value) made safe to print on a
// terminal: a message that repeats it must not carry escape sequences that retitle the window,
// clear the screen or rewrite what was printed before.
#pragma once

#include <string>

namespace gm {

// Control characters become visible escapes: C0 (ESC, BEL, CR, LF, ...) and DEL as \xNN, C1
// (U+0080–U+009F, as UTF-8) as \u00NN, bytes that are not UTF-8 (a lone 0x9B is CSI on some
// terminals) as \xNN. Everything else, printable UTF-8 included, is unchanged.
std::string printableText(const std::string& text);

// A message on one line: its lines trimmed, the empty ones and those another line already holds
// left out, the rest joined by "; " (libraries' messages, OpenImageIO's, may hold several lines,
// often repeated).
std::string oneLine(const std::string& message);

}  // namespace gm
