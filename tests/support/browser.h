// Test support: screenshots of a page (an .svg or .html file) in the real browsers users open
// our files in, Debian's headless Chromium and Firefox ESR, and the console messages it printed.
#pragma once

#include <filesystem>
#include <string>

#include "support/cli_run.h"

namespace gmtest {

enum class Browser { Chromium, Firefox };

inline const char* browserName(Browser b) { return b == Browser::Chromium ? "chromium" : "firefox"; }

inline bool browserAvailable(Browser b) {
    const std::string exe = b == Browser::Chromium ? "chromium" : "firefox-esr";
    return runCommand("command -v " + exe + " >/dev/null 2>&1") == 0;
}

struct BrowserShot {
    int code = -1;        // the browser's exit status (124: it hung and was stopped)
    std::string console;  // Chromium: the page's console messages ("CONSOLE" lines); Firefox: ""
};

// Loads `page` (a local file) in a window of width×height CSS pixels at device scale 1 and
// writes what it shows to `png`. Scripts run; Chromium waits for them (virtual time) and draws
// WebGL with its software rasteriser. Pages should set `margin:0` on their body to line up
// with an image of the same size. `work` is a scratch directory (profile, logs).
inline BrowserShot browserScreenshot(Browser b, const std::filesystem::path& page, int width,
                                     int height, const std::filesystem::path& png,
                                     const std::filesystem::path& work) {
    namespace fs = std::filesystem;
    fs::create_directories(work);
    const std::string url = "file://" + fs::absolute(page).string();
    const std::string size = std::to_string(width) + "," + std::to_string(height);
    const std::string log = (work / (std::string(browserName(b)) + ".log")).string();
    std::string command;
    if (b == Browser::Chromium) {
        command = "timeout -k 5 120 chromium --headless --no-sandbox --disable-gpu-sandbox"
                  " --use-angle=swiftshader --enable-unsafe-swiftshader --hide-scrollbars"
                  " --force-device-scale-factor=1 --no-first-run --disable-extensions"
                  " --user-data-dir=" + quote(fs::absolute(work / "chromium-profile").string()) +
                  " --enable-logging=stderr --v=0 --virtual-time-budget=20000"
                  " --window-size=" + size + " --screenshot=" + quote(png.string()) + " " +
                  quote(url);
    } else {
        const fs::path profile = fs::absolute(work / "firefox-profile");  // Firefox hangs on a relative one
        fs::create_directories(profile);
        command = "HOME=" + quote(fs::absolute(work).string()) +
                  " MOZ_HEADLESS=1 timeout -k 5 120 firefox-esr --headless --no-remote"
                  " --profile " + quote(profile.string()) + " --window-size " + size +
                  " --screenshot " + quote(fs::absolute(png).string()) + " " + quote(url);
    }
    BrowserShot shot;
    shot.code = runCommand(command + " >" + quote(log) + " 2>&1 </dev/null");
    if (b == Browser::Chromium) {
        const std::string all = slurp(log);
        size_t start = 0;
        while (start < all.size()) {
            size_t end = all.find('\n', start);
            if (end == std::string::npos) end = all.size();
            const std::string line = all.substr(start, end - start);
            if (line.find("CONSOLE") != std::string::npos) shot.console += line + "\n";
            start = end + 1;
        }
    }
    return shot;
}

}  // namespace gmtest
