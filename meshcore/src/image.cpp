#include "meshcore/image.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace gm {

void adviseHugePages(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    if (bytes < 2 * kHuge) return;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

RgbaImage::RgbaImage(int w, int h) : width(w), height(h) {
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h) * 4;
    pixels.reserve(n);  // fresh, untouched pages for a large buffer
    adviseHugePages(pixels.data(), n * sizeof(float));
    pixels.resize(n, 0.f);
}

}  // namespace gm
