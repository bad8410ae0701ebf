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
//   join: every task body happens before everything the calling thread does after the call.
// Fork and join are two sync objects, so task bodies are not ordered with one another (TBB does not
// order them either): a conflict between two iterations is still reported.
//
// tbb::enumerable_thread_specific needs no wrapper: its table is in TBB's headers (instrumented
// atomics), and its elements are combined after the parallel_for that wrote them has joined.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <utility>

#include "volguide/core/tsan.h"

namespace volguide {

namespace parallel_detail {

#if VOLGUIDE_TSAN
// The happens-before edges of one fork/join. Its two bytes are only addresses for TSan's sync
// objects (on the caller's stack: only the calling thread releases `fork`, and it acquires `join`
// after every call, so a sync object left at a reused address carries no edge that is not real).
class ForkJoin {
  public:
    ForkJoin() { __tsan_release(&fork_); }   // the caller's past, before any task starts
    ~ForkJoin() { __tsan_acquire(&join_); }  // after the join (also when a task threw)
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
    parallel_detail::ForkJoin fj;
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
    parallel_detail::ForkJoin fj;
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
    parallel_detail::ForkJoin fj;
    return arena.execute([&]() -> decltype(auto) {
        parallel_detail::ForkJoin::Task task(fj);
        return f();
    });
#else
    return arena.execute(std::forward<F>(f));
#endif
}

}  // namespace volguide
