/* SPDX-License-Identifier: MIT */
/*
 * The state every thread shares: the instances and what crosses between
 * the Modbus threads and the real-time loop.
 *
 * Crossing rules (see docs/pneufracd.md, "Threads"):
 *  - Modbus -> loop: live inputs through a triple buffer (pfd_live); built
 *    parameter sets through the `pending` pointer; tick, reset and
 *    clear-statistics requests as counters. All lock-free.
 *  - loop -> Modbus: one snapshot per sample through a triple buffer
 *    (pfd_snap); slot ownership through slot_state.
 *  - Modbus threads among themselves: pfd_daemon.regs_mx, held only while
 *    one request is validated and applied; commit_mx serialises commits
 *    and config-file writes.
 */
#ifndef PFD_STATE_H
#define PFD_STATE_H

#include <pthread.h>
#include <stdint.h>

#include "pfd_instance.h"
#include "pfd_settings.h"
#include "pfd_tbuf.h"

#define PFD_MAX_INSTANCES 64
#define PFD_NSLOTS 3

/** What the Modbus side hands to the loop each time a live register changes. */
typedef struct pfd_live {
    float e, sp, pv;
    float manual_out, failsafe_out;
    uint16_t input_sel;   /**< 0: e, 1: sp - pv */
    uint16_t mode;        /**< 0: auto, 1: manual */
    uint16_t watchdog_ms; /**< 0: off */
    uint32_t refresh;     /**< bumped by every write of e, sp or pv */
} pfd_live;

/* pfd_snap.flags */
#define PFD_SNAP_TRIPPED 0x2u
#define PFD_SNAP_MANUAL 0x4u
#define PFD_SNAP_TRANSFER 0x8u

/** What the loop publishes after every sample. */
typedef struct pfd_snap {
    pfd_sig sig;          /**< pc and pc_q15 are the final output */
    float e_used;
    uint16_t flags;
    uint32_t samples, overruns, jit_last_us, jit_max_us, wd_trips;
    uint32_t gen;         /**< generation of the parameter set that ran */
} pfd_snap;

/* slot_state values */
enum { PFD_SLOT_FREE = 0, PFD_SLOT_PENDING, PFD_SLOT_ACTIVE };

/** Holding registers as the Modbus side keeps them. */
typedef struct pfd_hold {
    pfd_live live;
    uint16_t param_lock;
    pfd_iparams staged;
} pfd_hold;

typedef struct pfd_inst {
    int unit;

    /* shared with the loop */
    pfd_tbuf in_tb;
    pfd_live in_buf[3];
    pfd_tbuf out_tb;
    pfd_snap out_buf[3];
    pfd_slot *slot[PFD_NSLOTS];
    int slot_state[PFD_NSLOTS]; /* atomic */
    pfd_slot *pending;          /* atomic */
    uint64_t tick_target;       /* atomic; Modbus adds */
    uint64_t tick_done;         /* atomic; loop stores */
    uint32_t reset_req, stats_req; /* atomic; Modbus increments */
    int64_t late_max_ns;        /* atomic; the worst lateness of a sample since
                                   the main thread last took it (pfd_overrun.h) */

    /* loop private */
    struct {
        pfd_slot *active;
        int active_idx;
        double offset;
        int64_t next_ns, last_ns;
        uint32_t wd_count, last_refresh, reset_seen, stats_seen;
        int tripped;
        pfd_snap s;
    } rt;

    /* Modbus side, under pfd_daemon.regs_mx. The staged registers are each
     * client's own (pfd_stage.h). */
    pfd_live live;          /* the live holding registers */
    uint16_t param_lock;
    uint64_t lock_holder;   /* the connection (pfd_who.id) holding param_lock;
                               0: none, which with --param-lock is everyone */
    pfd_iparams committed;
    pfd_rate rate;          /* how the committed set runs (also under commit_mx) */
    uint16_t commit_result, err_addr, err_param;
    /* Generation of the last set handed to the loop; every accepted commit
     * adds one, so it is also the commit count. The status compares it
     * with the generation the loop last ran: a count of sets published
     * and a count of sets switched in would disagree for ever once a
     * commit replaced a pending one that the loop never took. */
    uint32_t gen;
} pfd_inst;

/* commit_result values */
enum {
    PFD_COMMIT_OK = 0,
    PFD_COMMIT_INVALID = 1, /**< a parameter is invalid: err_addr/err_param */
    PFD_COMMIT_SCALE = 2,   /**< q15: a coefficient does not fit; change in_fs/out_fs */
    PFD_COMMIT_BUSY = 3,    /**< no free slot (the loop is mid-switch) */
    PFD_COMMIT_FAILED = 4,  /**< any other library error */
    PFD_COMMIT_UNSAVED = 5, /**< applied and running, but the config file
                                 could not be written */
    PFD_COMMIT_UNSTABLE = 6, /**< the set's sampled loop would be unstable:
                                  err_addr names the culprit */
    PFD_COMMIT_LOAD = 7,    /**< the loop could not sustain the set within
                                 loop_budget: err_addr names substeps (if
                                 the set runs more than one) or fs */
    PFD_COMMIT_RATE = 8     /**< substeps 0, and the rule needs an internal
                                 rate beyond the limits: err_addr names the
                                 culprit (pfd_plausible.h) */
};

/** Period jitter over every sample of every instance, in 1 us bins; the
 *  last bin collects everything from PFD_JITTER_BINS us up. */
#define PFD_JITTER_BINS 10000
typedef struct pfd_jitter {
    uint32_t bin[PFD_JITTER_BINS + 1];
    uint64_t total, overruns;
    int64_t max_ns;
} pfd_jitter;

struct pfd_client;  /* pfd_server.c */
struct pfd_config;  /* pfd_config.h */
struct pfd_tls;     /* pfd_tls.h */
struct pf_ctrl_check_work; /* pf_controller.h */

typedef struct pfd_daemon {
    pfd_settings set;
    int n;
    pfd_inst *inst[PFD_MAX_INSTANCES];
    pfd_inst *by_unit[256];
    pthread_mutex_t regs_mx;
    pthread_mutex_t commit_mx;
    pf_ctrl_design *scratch; /* design scratch, under commit_mx */
    struct pf_ctrl_check_work *check; /* stability check scratch, under commit_mx */
    double wake_ns;          /* CPU cost of one loop wake-up, measured at start
                                (pfd_rate_measure_wakeup); 0 = not measured */
    int stop;                /* atomic */
    /* lockstep hand-shake */
    pthread_mutex_t tick_mx;
    pthread_cond_t work_cv, done_cv;

    /* the loop thread (pfd_loop.c) */
    struct {
        pthread_t th;
        int running;
        pfd_jitter jitter; /* written by the loop only, read after it stopped */
    } loop;

    /* the Modbus server (pfd_server.c) */
    struct {
        int listen_fd, tls_fd; /* -1: none */
        int reserve_fd;        /* spare fd, given up to refuse a client when
                                  the process is out of fds; -1: none */
        struct pfd_tls *tls;   /* NULL: no TLS listener */
        pthread_t accept_th;
        int accept_running;
        pfd_allow allow;
        pthread_mutex_t clients_mx;
        struct pfd_client *clients; /* n_slots slots, under clients_mx */
        int n_slots;           /* 2 x max_clients: evicted ones wind down */
        uint64_t next_id;      /* connection serial numbers, from 1 */
    } server;

    /* persistence (pfd_commit.c) */
    const char *config_path;              /* NULL: persistence off */
    const struct pfd_config *config_file; /* as read: its [daemon] is written back */
    struct pfd_config *persist_buf;       /* what is written, under commit_mx */
    int persist_failed;                   /* atomic: the last write failed */
} pfd_daemon;

/** Whether the daemon is stopping (pfd_loop_stop, pfd_server_stop). */
static inline int pfd_stopping(const pfd_daemon *d)
{
    return __atomic_load_n(&d->stop, __ATOMIC_ACQUIRE);
}

/** Ask every thread to stop. */
static inline void pfd_request_stop(pfd_daemon *d)
{
    __atomic_store_n(&d->stop, 1, __ATOMIC_RELEASE);
}

#endif
