/* A steady clock for recording programs that animate by wall time (real_programs.rs, issue
 * 21). Preloaded into a program being traced, it makes every reading of the clock on the
 * program's main thread 16,667 us later than the one before (a 60th of a second, in whole
 * microseconds for gettimeofday), however long the frame really took, so frame N of the
 * recording shows the same moment of the animation on a fast machine and on a loaded one
 * (glmark2 and glxgears read the clock once a frame: they run at a steady 60 frames per
 * second of their own time). The clocks start from fixed times in the past (2020 for the
 * wall clock, 1 s for the monotonic ones): the same readings on every run, bit for bit, and
 * a deadline computed from them is never later than a real one, so nothing that waits is
 * made to wait longer. Other threads (the driver's, the tracer's) see the real clock.
 *
 * Built by the tests with `cc`, the linker Rust itself uses: a test dependency of nothing
 * but the toolchain. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#define STEP_NS 16667000LL
#define WALL_START_S 1577836800LL /* 2020-01-01 00:00:00 UTC */
#define MONOTONIC_START_S 1LL

typedef int (*clock_gettime_fn)(clockid_t, struct timespec *);

/* Readings of the steady clocks made on the main thread (the only one that reads them: no
 * lock). */
static long long readings;

static int real_clock_gettime(clockid_t id, struct timespec *ts) {
    static clock_gettime_fn real;
    if (!real)
        real = (clock_gettime_fn)dlsym(RTLD_NEXT, "clock_gettime");
    return real(id, ts);
}

/* Where clock `id` starts when the main thread reads it, or -1 for the real clock. */
static long long start_s(clockid_t id) {
    if (syscall(SYS_gettid) != getpid())
        return -1;
    switch (id) {
    case CLOCK_REALTIME:
    case CLOCK_REALTIME_COARSE:
        return WALL_START_S;
    case CLOCK_MONOTONIC:
    case CLOCK_MONOTONIC_RAW:
    case CLOCK_MONOTONIC_COARSE:
    case CLOCK_BOOTTIME:
        return MONOTONIC_START_S;
    default:
        return -1;
    }
}

int clock_gettime(clockid_t id, struct timespec *ts) {
    long long start = start_s(id);
    if (start < 0)
        return real_clock_gettime(id, ts);
    long long ns = readings++ * STEP_NS;
    ts->tv_sec = start + ns / 1000000000LL;
    ts->tv_nsec = ns % 1000000000LL;
    return 0;
}

/* glxgears and es2gears' eglut time their animation with gettimeofday; games seed their
 * randomness with time(). */
time_t time(time_t *t) {
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    if (t)
        *t = ts.tv_sec;
    return ts.tv_sec;
}

int gettimeofday(struct timeval *restrict tv, void *restrict tz) {
    struct timespec ts;
    int r = clock_gettime(CLOCK_REALTIME, &ts);
    (void)tz;
    if (r == 0) {
        tv->tv_sec = ts.tv_sec;
        tv->tv_usec = ts.tv_nsec / 1000;
    }
    return r;
}
