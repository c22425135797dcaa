// ThreadSanitizer cannot see TBB's own fork and join (libtbb is not instrumented), so the
// parallel loops state them explicitly (tests/sanitize.sh thread): RELEASE before the fork
// and at the end of each task, ACQUIRE at the start of each task and after the join, all on
// one address per loop.
#pragma once

#if defined(__SANITIZE_THREAD__)
#define RG_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define RG_TSAN 1
#endif
#endif
#ifdef RG_TSAN
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#define RG_TSAN_ACQUIRE(p) __tsan_acquire(p)
#define RG_TSAN_RELEASE(p) __tsan_release(p)
#else
#define RG_TSAN_ACQUIRE(p) ((void)0)
#define RG_TSAN_RELEASE(p) ((void)0)
#endif
