/* SPDX-License-Identifier: MIT */
#include "pfd_loop.h"

#include <errno.h>
#include <limits.h>
#include <sched.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "pfd_log.h"
#include "pfd_overrun.h"
#include "pfd_sample.h"

static int64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void sleep_until(int64_t t)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(t / 1000000000);
    ts.tv_nsec = (long)(t % 1000000000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

/* The first instant after @p t on the grid of @p period, counted from the
 * clock's zero: instances of the same rate always wake together, so a
 * rate costs one wake-up a period whatever the number of its instances
 * (the load rule of pfd_rate.h counts on it). */
static int64_t grid_after(int64_t t, int64_t period)
{
    return (t / period + 1) * period;
}

static void freerun(pfd_daemon *d)
{
    int64_t now = mono_ns();
    int i;

    for (i = 0; i < d->n; i++) {
        d->inst[i]->rt.next_ns = grid_after(now, (int64_t)d->inst[i]->rt.active->period_ns);
        d->inst[i]->rt.last_ns = -1;
    }
    while (!pfd_stopping(d)) {
        /* Wake at least every 100 ms so a stop request is seen. */
        int64_t t_next = mono_ns() + 100000000;
        for (i = 0; i < d->n; i++)
            if (d->inst[i]->rt.next_ns < t_next)
                t_next = d->inst[i]->rt.next_ns;
        sleep_until(t_next);

        for (i = 0; i < d->n; i++) {
            pfd_inst *in = d->inst[i];
            int64_t t = mono_ns();
            int64_t period = (int64_t)in->rt.active->period_ns;
            int64_t late = t - in->rt.next_ns;
            uint32_t missed = 0;
            int64_t jitter = -1;
            const pfd_slot *before = in->rt.active;

            if (late < 0)
                continue;
            pfd_overrun_note(&in->late_max_ns, late);
            if (late >= period) {
                int64_t m = late / period;
                missed = m > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)m;
                in->rt.next_ns += m * period;
            }
            if (in->rt.last_ns >= 0) {
                /* Skipped periods stay in: an overrun shows as jitter >= T. */
                jitter = t - in->rt.last_ns - period;
                if (jitter < 0)
                    jitter = -jitter;
            }
            in->rt.last_ns = t;
            pfd_sample_run(in, &d->loop.jitter, missed, jitter);
            if (in->rt.active != before &&
                in->rt.active->period_ns != before->period_ns) {
                /* New sample rate: a new schedule, from its next grid point. */
                in->rt.next_ns = grid_after(t, (int64_t)in->rt.active->period_ns);
                in->rt.last_ns = -1;
            } else {
                in->rt.next_ns += period;
            }
        }
    }
}

static void timed_wait(pthread_cond_t *cv, pthread_mutex_t *mx, long ms)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    ts.tv_nsec += (ms % 1000) * 1000000L;
    ts.tv_sec += ms / 1000 + ts.tv_nsec / 1000000000L;
    ts.tv_nsec %= 1000000000L;
    pthread_cond_timedwait(cv, mx, &ts);
}

/* Lockstep: not real-time, so a mutex and condition variables are fine. */
static void lockstep(pfd_daemon *d)
{
    int i;

    pthread_mutex_lock(&d->tick_mx);
    while (!pfd_stopping(d)) {
        int work = 0;
        for (i = 0; i < d->n; i++)
            if (__atomic_load_n(&d->inst[i]->tick_target, __ATOMIC_ACQUIRE) >
                __atomic_load_n(&d->inst[i]->tick_done, __ATOMIC_ACQUIRE))
                work = 1;
        if (!work) {
            timed_wait(&d->work_cv, &d->tick_mx, 200);
            continue;
        }
        pthread_mutex_unlock(&d->tick_mx);
        for (i = 0; i < d->n; i++) {
            pfd_inst *in = d->inst[i];
            uint64_t target = __atomic_load_n(&in->tick_target, __ATOMIC_ACQUIRE);
            uint64_t done = __atomic_load_n(&in->tick_done, __ATOMIC_ACQUIRE);
            while (done < target && !pfd_stopping(d)) {
                pfd_sample_run(in, &d->loop.jitter, 0, -1);
                done++;
            }
            __atomic_store_n(&in->tick_done, done, __ATOMIC_RELEASE);
        }
        pthread_mutex_lock(&d->tick_mx);
        pthread_cond_broadcast(&d->done_cv);
    }
    pthread_cond_broadcast(&d->done_cv);
    pthread_mutex_unlock(&d->tick_mx);
}

static void *loop_main(void *arg)
{
    pfd_daemon *d = (pfd_daemon *)arg;
    volatile unsigned char stack[32768];
    size_t k;

    /* Named, so that top -H and /proc show the loop's own CPU time
     * (bench/bench_daemon.py compares it with the predicted load). */
    prctl(PR_SET_NAME, "pfd-loop", 0, 0, 0);
    /* Touch the stack now so that no page fault happens mid-sample. */
    for (k = 0; k < sizeof stack; k += 256)
        stack[k] = 0;
    if (d->set.external_clock)
        lockstep(d);
    else
        freerun(d);
    return NULL;
}

#if defined(__SANITIZE_ADDRESS__)
#define PFD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PFD_ASAN 1
#endif
#endif

static void lock_memory(const pfd_daemon *d)
{
#ifndef PFD_ASAN
    struct rlimit rl;
#endif

    if (!d->set.mlock) {
        pfd_log(PFD_LOG_INFO, "mlockall", "result=off reason=--no-mlock");
        return;
    }
#ifdef PFD_ASAN
    /* ASan's shadow memory is terabytes of reserved address space. */
    pfd_log(PFD_LOG_INFO, "mlockall", "result=skipped reason=address-sanitizer");
    return;
#else
    /* With a finite RLIMIT_MEMLOCK, MCL_FUTURE would make later thread
     * stacks fail to map; lock only when the limit cannot bite. */
    if (geteuid() != 0 &&
        (getrlimit(RLIMIT_MEMLOCK, &rl) != 0 || rl.rlim_cur != RLIM_INFINITY)) {
        pfd_log(PFD_LOG_WARN, "mlockall",
                "result=skipped reason=rlimit-memlock-finite");
        return;
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0)
        pfd_log(PFD_LOG_INFO, "mlockall", "result=locked");
    else
        pfd_log(PFD_LOG_WARN, "mlockall", "result=failed error=\"%s\"",
                strerror(errno));
#endif
}

int pfd_loop_start(pfd_daemon *d)
{
    pthread_attr_t attr;
    struct sched_param sp;
    int rc = -1;

    lock_memory(d);
    if (d->set.rt_priority > 0) {
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = d->set.rt_priority;
        pthread_attr_init(&attr);
        pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
        pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
        pthread_attr_setschedparam(&attr, &sp);
        rc = pthread_create(&d->loop.th, &attr, loop_main, d);
        pthread_attr_destroy(&attr);
        if (rc == 0)
            pfd_log(PFD_LOG_INFO, "loop-thread", "sched=fifo priority=%d",
                    d->set.rt_priority);
        else
            pfd_log(PFD_LOG_WARN, "loop-thread",
                    "sched=other reason=\"SCHED_FIFO %d not permitted: %s\"",
                    d->set.rt_priority, strerror(rc));
    }
    if (rc != 0) {
        rc = pthread_create(&d->loop.th, NULL, loop_main, d);
        if (rc != 0) {
            pfd_log(PFD_LOG_ERROR, "loop-thread", "error=\"%s\"", strerror(rc));
            return -1;
        }
        if (d->set.rt_priority <= 0)
            pfd_log(PFD_LOG_INFO, "loop-thread", "sched=other reason=--rt-priority-0");
    }
    d->loop.running = 1;
    pfd_log(PFD_LOG_INFO, "loop-start", "clock=%s instances=%d",
            pfd_clock_name(d->set.external_clock), d->n);
    return 0;
}

void pfd_loop_stop(pfd_daemon *d)
{
    pfd_request_stop(d);
    pthread_mutex_lock(&d->tick_mx);
    pthread_cond_broadcast(&d->work_cv);
    pthread_cond_broadcast(&d->done_cv);
    pthread_mutex_unlock(&d->tick_mx);
    if (d->loop.running) {
        pthread_join(d->loop.th, NULL);
        d->loop.running = 0;
    }
}

void pfd_loop_log_stats(const pfd_daemon *d)
{
    const pfd_jitter *jit = &d->loop.jitter;
    uint64_t samples = 0;
    int i;
    for (i = 0; i < d->n; i++)
        samples += d->inst[i]->rt.s.samples;
    pfd_log(PFD_LOG_INFO, "loop-stats",
            "instances=%d samples=%llu jitter_samples=%llu jitter_p50_us=%u "
            "jitter_p99_us=%u jitter_max_us=%.1f overruns=%llu",
            d->n, (unsigned long long)samples, (unsigned long long)jit->total,
            jit->total ? pfd_jitter_percentile(jit, 0.50) : 0,
            jit->total ? pfd_jitter_percentile(jit, 0.99) : 0,
            (double)jit->max_ns / 1000.0, (unsigned long long)jit->overruns);
}

int pfd_loop_tick(pfd_daemon *d, pfd_inst *in, unsigned n)
{
    uint64_t target = __atomic_add_fetch(&in->tick_target, (uint64_t)n,
                                         __ATOMIC_ACQ_REL);
    pthread_mutex_lock(&d->tick_mx);
    pthread_cond_signal(&d->work_cv);
    while (__atomic_load_n(&in->tick_done, __ATOMIC_ACQUIRE) < target &&
           !pfd_stopping(d))
        timed_wait(&d->done_cv, &d->tick_mx, 200);
    pthread_mutex_unlock(&d->tick_mx);
    return pfd_stopping(d) ? -1 : 0;
}
