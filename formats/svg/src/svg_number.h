// Number text for SVG output: 1e-4 px steps, shortest form. Positions on canvases up to 1e7 px
// stay within 5e-5 px of the value (%.6g would lose 1e-3 px above a few hundred pixels).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace gm {

// Decimals written: 4 (1e-4 px) by default; the compact mesh syntax writes 2 (1/100 px).
constexpr int kSvgDecimalsExact = 4;
constexpr int kSvgDecimalsCompact = 2;

inline double svgStepsPerUnit(int decimals) { return decimals == 2 ? 1e2 : 1e4; }

// Values from this magnitude on (and non-finite ones) are written in exponent form: their
// 1e-4 steps would not fit a long long. The reader and the writer refuse such coordinates
// (SvgReadLimits::maxCoordinate, coordinateProblem) long before; the formatter stays defined
// for every double all the same.
constexpr double kSvgStepsLimit = 1e14;

inline bool svgNumberInSteps(double v) { return std::fabs(v) < kSvgStepsLimit; }

// The value a reader gets back from the text appendSvgNumber writes for v.
inline long long svgNumberSteps(double v, int decimals = kSvgDecimalsExact) {
    return std::llround(v * svgStepsPerUnit(decimals));
}
inline double svgPrintedValue(double v, int decimals = kSvgDecimalsExact) {
    return svgNumberInSteps(v)
               ? static_cast<double>(svgNumberSteps(v, decimals)) / svgStepsPerUnit(decimals)
               : v;
}

// "12.5", "-.25", "0", "3": no trailing zeros, no leading zero before the point when
// `dropLeadingZero` (path and tensor data; attribute lengths keep it).
inline void appendSvgNumber(std::string& out, double v, bool dropLeadingZero = true,
                            int decimals = kSvgDecimalsExact) {
    if (!svgNumberInSteps(v)) {  // includes NaN and infinities
        char text[32];
        std::snprintf(text, sizeof text, "%.17g", v);
        out += text;
        return;
    }
    long long q = svgNumberSteps(v, decimals);
    if (q == 0) {
        out += '0';
        return;
    }
    if (q < 0) {
        out += '-';
        q = -q;
    }
    const long long unit = static_cast<long long>(svgStepsPerUnit(decimals));
    const long long whole = q / unit;
    long long frac = q % unit;
    if (whole != 0 || !dropLeadingZero || frac == 0) out += std::to_string(whole);
    if (frac != 0) {
        char digits[5] = {'0', '0', '0', '0', 0};
        for (int k = decimals - 1; k >= 0; --k) {
            digits[k] = static_cast<char>('0' + frac % 10);
            frac /= 10;
        }
        int len = decimals;
        while (len > 0 && digits[len - 1] == '0') --len;
        out += '.';
        out.append(digits, static_cast<size_t>(len));
    }
}

}  // namespace gm
