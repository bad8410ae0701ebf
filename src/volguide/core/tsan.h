#pragma once
// ThreadSanitizer's annotations, compiled only into a ThreadSanitizer build (gcc defines
// __SANITIZE_THREAD__, clang has __has_feature(thread_sanitizer)): VOLGUIDE_TSAN is 1 there, 0
// otherwise, and the functions below are no-ops. core/parallel.h uses them to tell TSan about the
// ordering TBB guarantees inside the uninstrumented libtbb (docs/reliability.md, "Sanitizers").
#if defined(__SANITIZE_THREAD__)
#define VOLGUIDE_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define VOLGUIDE_TSAN 1
#endif
#endif
#ifndef VOLGUIDE_TSAN
#define VOLGUIDE_TSAN 0
#endif

#if VOLGUIDE_TSAN
#include <sanitizer/tsan_interface.h>
// Part of the TSan runtime's interface (gcc's libtsan and clang's compiler-rt), not of its header.
extern "C" void __tsan_ignore_thread_begin();
extern "C" void __tsan_ignore_thread_end();
#endif

namespace volguide {

// A happens-before edge from every tsan_release(key) to every later tsan_acquire(key) with the same
// address, for hand-overs inside an uninstrumented library (e.g. Embree's BVH build calls volguide's
// bounds callback on TBB's threads: geometry/accel_embree.cpp).
inline void tsan_release(const void* key) {
#if VOLGUIDE_TSAN
    __tsan_release(const_cast<void*>(key));
#else
    (void)key;
#endif
}
inline void tsan_acquire(const void* key) {
#if VOLGUIDE_TSAN
    __tsan_acquire(const_cast<void*>(key));
#else
    (void)key;
#endif
}

// While one lives, ThreadSanitizer ignores this thread's memory accesses (and resets, rather than
// records, what it allocates and frees). For calls into an uninstrumented library that set up or tear
// down state the library later reads on threads of its own, through hand-overs TSan cannot see:
// Embree's device settings, written when the device is created and read by the BVH build on TBB's
// threads (geometry/accel_embree.cpp). Nothing of volguide's may run inside one.
class TsanIgnoredAccesses {
public:
#if VOLGUIDE_TSAN
    TsanIgnoredAccesses() { __tsan_ignore_thread_begin(); }
    ~TsanIgnoredAccesses() { __tsan_ignore_thread_end(); }
#else
    TsanIgnoredAccesses() = default;
#endif
    TsanIgnoredAccesses(const TsanIgnoredAccesses&) = delete;
    TsanIgnoredAccesses& operator=(const TsanIgnoredAccesses&) = delete;
};

}  // namespace volguide
