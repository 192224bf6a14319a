/* SPDX-License-Identifier: MIT */
/*
 * pfd_loadgen: Modbus TCP load for the pneufracd benchmarks. N client
 * threads, each with its own libmodbus connection, send back-to-back FC03
 * (read 10 holding registers) or FC16 (write 10 holding registers: e, sp,
 * pv, their int16 mirrors and input_sel) for a fixed time and record each
 * transaction's latency. Prints one JSON line.
 *
 *   pfd_loadgen --port P [--host 127.0.0.1] [--clients N] [--fc 3|16]
 *               [--seconds S] [--unit U]
 */
#include <errno.h>
#include <modbus/modbus.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_CLIENTS 256
#define MAX_LAT (4u * 1024u * 1024u) /* per client */

typedef struct worker {
    pthread_t th;
    const char *host;
    int port, fc, unit;
    double seconds;
    uint32_t *lat_us;
    size_t n;
    unsigned long errors;
    int connect_failed;
} worker;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *run(void *arg)
{
    worker *w = (worker *)arg;
    modbus_t *ctx = modbus_new_tcp(w->host, w->port);
    /* e = 0, sp = 0, pv = 0 (floats), e_i16 = sp_i16 = pv_i16 = 0, input_sel 0 */
    uint16_t wr[10] = {0};
    uint16_t rd[10];
    double end;

    if (ctx == NULL || modbus_connect(ctx) != 0) {
        w->connect_failed = 1;
        if (ctx != NULL)
            modbus_free(ctx);
        return NULL;
    }
    modbus_set_slave(ctx, w->unit);
    modbus_set_response_timeout(ctx, 2, 0);
    end = now_s() + w->seconds;
    while (w->n < MAX_LAT) {
        double t0 = now_s(), t1;
        int rc;
        if (t0 >= end)
            break;
        rc = w->fc == 16 ? modbus_write_registers(ctx, 0, 10, wr)
                         : modbus_read_registers(ctx, 0, 10, rd);
        t1 = now_s();
        if (rc != 10) {
            w->errors++;
            if (errno == EBADF || errno == ECONNRESET || errno == EPIPE) {
                modbus_close(ctx);
                if (modbus_connect(ctx) != 0)
                    break;
            }
            continue;
        }
        w->lat_us[w->n++] = (uint32_t)((t1 - t0) * 1e6 + 0.5);
    }
    modbus_close(ctx);
    modbus_free(ctx);
    return NULL;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static int arg_int(const char *name, const char *v, int lo, int hi)
{
    char *e;
    long x = strtol(v, &e, 10);
    if (*v == '\0' || *e != '\0' || x < lo || x > hi) {
        fprintf(stderr, "pfd_loadgen: %s: '%s' is not an integer in %d..%d\n", name, v, lo, hi);
        exit(2);
    }
    return (int)x;
}

int main(int argc, char **argv)
{
    static worker ws[MAX_CLIENTS];
    const char *host = "127.0.0.1";
    int port = 1502, clients = 1, fc = 3, unit = 1, i;
    double seconds = 3.0, t0, elapsed;
    size_t total = 0, k = 0;
    unsigned long errors = 0;
    uint32_t *all;

    for (i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--host"))
            host = argv[i + 1];
        else if (!strcmp(argv[i], "--port"))
            port = arg_int("--port", argv[i + 1], 1, 65535);
        else if (!strcmp(argv[i], "--clients"))
            clients = arg_int("--clients", argv[i + 1], 1, MAX_CLIENTS);
        else if (!strcmp(argv[i], "--fc"))
            fc = arg_int("--fc", argv[i + 1], 3, 16);
        else if (!strcmp(argv[i], "--unit"))
            unit = arg_int("--unit", argv[i + 1], 0, 255);
        else if (!strcmp(argv[i], "--seconds"))
            seconds = arg_int("--seconds", argv[i + 1], 1, 3600);
        else {
            fprintf(stderr, "pfd_loadgen: unknown option '%s'\n", argv[i]);
            return 2;
        }
    }
    if (i != argc || (fc != 3 && fc != 16)) {
        fprintf(stderr, "usage: pfd_loadgen --port P [--clients N] [--fc 3|16] "
                        "[--seconds S] [--unit U] [--host H]\n");
        return 2;
    }
    t0 = now_s();
    for (i = 0; i < clients; i++) {
        ws[i].host = host;
        ws[i].port = port;
        ws[i].fc = fc;
        ws[i].unit = unit;
        ws[i].seconds = seconds;
        ws[i].lat_us = malloc(MAX_LAT * sizeof(uint32_t));
        if (ws[i].lat_us == NULL || pthread_create(&ws[i].th, NULL, run, &ws[i]) != 0) {
            fprintf(stderr, "pfd_loadgen: cannot start client %d\n", i);
            return 1;
        }
    }
    for (i = 0; i < clients; i++) {
        pthread_join(ws[i].th, NULL);
        total += ws[i].n;
        errors += ws[i].errors + (unsigned long)ws[i].connect_failed;
    }
    elapsed = now_s() - t0;
    all = malloc((total ? total : 1) * sizeof(uint32_t));
    if (all == NULL)
        return 1;
    for (i = 0; i < clients; i++) {
        memcpy(all + k, ws[i].lat_us, ws[i].n * sizeof(uint32_t));
        k += ws[i].n;
        free(ws[i].lat_us);
    }
    qsort(all, total, sizeof all[0], cmp_u32);
    printf("{\"fc\": %d, \"clients\": %d, \"transactions\": %lu, \"errors\": %lu, "
           "\"seconds\": %.3f, \"tps\": %.0f, \"p50_us\": %u, \"p99_us\": %u, \"max_us\": %u}\n",
           fc, clients, (unsigned long)total, errors, elapsed, (double)total / elapsed,
           total ? all[total / 2] : 0, total ? all[(size_t)(0.99 * (double)(total - 1))] : 0,
           total ? all[total - 1] : 0);
    free(all);
    return errors > 0 && total == 0 ? 1 : 0;
}
