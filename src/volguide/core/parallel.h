#pragma once
// volguide's parallel constructs: thin wrappers over TBB's, used everywhere instead of TBB's own
// (tests/unit/test_parallel.cpp checks that src/ and apps/ call no tbb::parallel_for directly).
//
// In a normal build each wrapper is the TBB call it wraps, with the same arguments: the same
// partitioning and grain, so the same images. In a ThreadSanitizer build (docs/reliability.md,
// "Sanitizers") they also tell TSan about the ordering TBB guarantees and TSan cannot see, because
// Debian's libtbb is not built with -fsanitize=thread (the hand-over of a task to a worker and the
// join happen on atomics inside libtbb):
//   fork: everything the calling thread did before the call happens before every task body;
//   join: every task body happens before everything the calling thread does after the call, and so
//         does TBB's own bookkeeping on the caller's stack after the last body (acquire_tbb_frames).
// Fork and join are two sync objects, so task bodies are not ordered with one another (TBB does not
// order them either): a conflict between two iterations is still reported.
//
// tbb::enumerable_thread_specific needs no wrapper: its table is in TBB's headers (instrumented
// atomics), and its elements are combined after the parallel_for that wrote them has joined.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstdint>
#include <utility>

#include "volguide/core/tsan.h"

namespace volguide {

namespace parallel_detail {

#if VOLGUIDE_TSAN
// How far below the calling frame the frames of the TBB call may reach (TBB's run functions hold its
// wait node and task group context a few hundred bytes down; the margin is generous because a
// lookup of an address with no sync object costs TSan almost nothing).
inline constexpr uintptr_t kTbbFramesBytes = 16384;

// After TBB's algorithm has returned: acquire every sync object from `frame` (the top of the frame
// that called TBB, where TBB's inlined run function keeps its locals) down through the dead frames
// below this function's. The last thread to finish a task keeps using TBB's wait node on the
// caller's stack after its task body ended (TBB's fold_tree decrements the node's count, reads its
// parent, then decrements its wait context, a release), and the caller's wait acquires that
// decrement inside libtbb, where TSan cannot see it. Without this edge a later write of the caller
// to the reused stack is reported against that read; the report is suppressed by `race:fold_tree`
// only while the worker's history still holds the read's stack, and CI saw it without
// (tests/unit/test_parallel.cpp, TbbBookkeepingOnTheCallersStackIsOrderedBeforeItsReuse). Only
// the caller acquires, after the join, what other threads released before: task bodies stay
// unordered with one another.
[[gnu::noinline]] inline void acquire_tbb_frames(const void* frame) {
    const char here = 0;
    const auto top = reinterpret_cast<uintptr_t>(frame) & ~uintptr_t(7);
    const auto bottom = reinterpret_cast<uintptr_t>(&here) - kTbbFramesBytes;
    for (uintptr_t a = top; a > bottom; a -= 8) __tsan_acquire(reinterpret_cast<void*>(a));
}

// The happens-before edges of one fork/join. Its two bytes are only addresses for TSan's sync
// objects (on the caller's stack: only the calling thread releases `fork`, and it acquires `join`
// after every call, so a sync object left at a reused address carries no edge that is not real).
class ForkJoin {
  public:
    // `frame`: __builtin_frame_address(0) of the function that calls TBB.
    explicit ForkJoin(const void* frame) : frame_(frame) {
        __tsan_release(&fork_);  // the caller's past, before any task starts
    }
    ~ForkJoin() {  // after the join (also when a task threw)
        __tsan_acquire(&join_);
        acquire_tbb_frames(frame_);
    }
    ForkJoin(const ForkJoin&) = delete;
    ForkJoin& operator=(const ForkJoin&) = delete;

    // One task body: it sees the caller's past, and the caller sees it after the join (also when it
    // throws: TBB rethrows in the caller).
    class Task {
      public:
        explicit Task(const ForkJoin& fj) : fj_(fj) { __tsan_acquire(const_cast<char*>(&fj_.fork_)); }
        ~Task() { __tsan_release(const_cast<char*>(&fj_.join_)); }
        Task(const Task&) = delete;
        Task& operator=(const Task&) = delete;

      private:
        const ForkJoin& fj_;
    };

  private:
    const void* frame_;
    char fork_ = 0, join_ = 0;
};

// The body TBB copies and calls: the caller's function by reference, inside a Task.
template <typename F>
struct Annotated {
    const F* f;
    const ForkJoin* fj;
    template <typename... Args>
    void operator()(Args&&... args) const {
        ForkJoin::Task task(*fj);
        (*f)(std::forward<Args>(args)...);
    }
};
#endif

}  // namespace parallel_detail

// tbb::parallel_for(first, last, f): f(i) for every i in [first, last), TBB's default partitioner.
template <typename Index, typename F>
void parallel_for(Index first, Index last, const F& f) {
#if VOLGUIDE_TSAN
    parallel_detail::ForkJoin fj(__builtin_frame_address(0));
    tbb::parallel_for(first, last, parallel_detail::Annotated<F>{&f, &fj});
#else
    tbb::parallel_for(first, last, f);
#endif
}

// tbb::parallel_for(range, body): body(subrange) over subranges of `range` (its grain size),
// TBB's default partitioner. (More specialised than TBB's parallel_for(const Range&, const Body&),
// so an unqualified call with a blocked_range, which also finds TBB's by argument-dependent lookup,
// still comes here.)
template <typename Value, typename Body>
void parallel_for(const tbb::blocked_range<Value>& range, const Body& body) {
#if VOLGUIDE_TSAN
    parallel_detail::ForkJoin fj(__builtin_frame_address(0));
    tbb::parallel_for(range, parallel_detail::Annotated<Body>{&body, &fj});
#else
    tbb::parallel_for(range, body);
#endif
}

// arena.execute(f). The calling thread normally runs f itself, but TBB may hand f to one of the
// arena's threads (when no slot is free for the caller) and wait for it.
template <typename F>
decltype(auto) arena_execute(tbb::task_arena& arena, F&& f) {
#if VOLGUIDE_TSAN
    parallel_detail::ForkJoin fj(__builtin_frame_address(0));
    return arena.execute([&]() -> decltype(auto) {
        parallel_detail::ForkJoin::Task task(fj);
        return f();
    });
#else
    return arena.execute(std::forward<F>(f));
#endif
}

}  // namespace volguide
