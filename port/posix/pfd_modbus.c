/* SPDX-License-Identifier: MIT */
#include "pfd_modbus.h"

#include <modbus/modbus.h>
#include <stdlib.h>
#include <string.h>

#include "pfd_audit.h"
#include "pfd_commit.h"
#include "pfd_loop.h"
#include "pfd_regmap.h"

static unsigned be16(const uint8_t *p) { return ((unsigned)p[0] << 8) | p[1]; }

static void put16(uint8_t *p, unsigned v)
{
    p[0] = (uint8_t)(v >> 8);
    p[1] = (uint8_t)(v & 0xFFu);
}

int pfd_mbap_length(const uint8_t *hdr)
{
    unsigned len = be16(hdr + 4);
    if (be16(hdr + 2) != 0 || len < 2 || len > PFD_ADU_MAX - 6)
        return -1;
    return 6 + (int)len;
}

/* The answer's MBAP header for a PDU of @p pdu_len bytes. */
static int answer(const uint8_t *req, uint8_t *rsp, unsigned pdu_len)
{
    memcpy(rsp, req, 2); /* transaction id */
    put16(rsp + 2, 0);
    put16(rsp + 4, pdu_len + 1);
    rsp[6] = req[6];
    return PFD_MBAP_LEN + (int)pdu_len;
}

/* An exception: the request's function code with bit 7 set (a function
 * code of 0x80 or more keeps it), then the code. */
static int exception(const uint8_t *req, uint8_t *rsp, int code)
{
    rsp[7] = (uint8_t)(req[7] | 0x80u);
    rsp[8] = (uint8_t)code;
    return answer(req, rsp, 2);
}

/* The holding registers as client @p s sees them: the live ones, the
 * lock, and its own staged set. Under regs_mx. */
static void client_hold(const pfd_session *s, const pfd_inst *in, pfd_hold *h)
{
    memset(h, 0, sizeof *h);
    h->live = in->live;
    h->param_lock = in->param_lock;
    pfd_stage_compose(s->stage[in->unit], NULL, &in->committed, &h->staged);
}

/* Every register of @p space, as @p s sees it, into @p img. */
static void render(pfd_daemon *d, const pfd_session *s, pfd_inst *in, int space,
                   uint16_t *img)
{
    pfd_view v;
    pfd_hold h;

    pthread_mutex_lock(&d->regs_mx);
    client_hold(s, in, &h);
    v.inst = in;
    v.hold = &h;
    v.snap = (const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
    v.status = pfd_status_bits(d, in, v.snap, &h.staged);
    v.n_instances = (uint16_t)d->n;
    v.word_order = d->set.word_order;
    pfd_regmap_render(space, &v, img);
    pthread_mutex_unlock(&d->regs_mx);
}

/* Under regs_mx: why @p wl may not be applied now, or NULL. */
static const char *forbidden(const pfd_daemon *d, const pfd_session *s,
                             const pfd_inst *in, const pfd_wlist *wl)
{
    if (wl->access > s->who.access)
        return "access";
    /* Nobody holds a lock set by --param-lock (holder 0), so it closes
     * everything that is not open for every client, for good. */
    if (wl->guarded && in->param_lock && in->lock_holder != s->who.id)
        return "locked";
    if (wl->tick && !d->set.external_clock)
        return "internal-clock";
    return NULL;
}

/* Under regs_mx: the data writes of @p wl (not a commit): live settings
 * and the lock on the instance, staged parameters in the client's own
 * staging. @return 0, or -1 out of memory. */
static int apply(pfd_session *s, pfd_inst *in, const pfd_wlist *wl)
{
    if (wl->staged && s->stage[in->unit] == NULL) {
        s->stage[in->unit] = calloc(1, sizeof(pfd_stage));
        if (s->stage[in->unit] == NULL)
            return -1;
    }
    pfd_apply_settings(in, &s->who, wl);
    if (wl->staged)
        pfd_stage_record(s->stage[in->unit], wl);
    return 0;
}

/* Validated writes: permission, then data, commit, command, tick.
 * @return 0 done, > 0 MODBUS_EXCEPTION_* code, -1 drop the connection. */
static int execute(pfd_daemon *d, pfd_session *s, pfd_inst *in, const pfd_wlist *wl,
                   unsigned addr, unsigned cnt)
{
    const pfd_reg *bad;
    const char *why;
    int rc = 0;

    pthread_mutex_lock(&d->regs_mx);
    why = forbidden(d, s, in, wl);
    if (why != NULL) {
        pthread_mutex_unlock(&d->regs_mx);
        pfd_audit_refused(&s->who, in->unit, addr, cnt, MODBUS_EXCEPTION_ILLEGAL_FUNCTION, why);
        return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    }
    /* An int16 mirror's value depends on the committed in_fs, known only
     * here; a commit checks it again under commit_mx (pfd_commit). */
    bad = pfd_regmap_check_mirrors(wl, &in->committed);
    if (bad != NULL) {
        pthread_mutex_unlock(&d->regs_mx);
        pfd_audit_refused(&s->who, in->unit, bad->addr, 1,
                          MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE, "value");
        return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
    }
    if (wl->commit) {
        pthread_mutex_unlock(&d->regs_mx);
        rc = pfd_commit(d, in, &s->who, s->stage[in->unit], wl);
        if (rc != 0 && rc != MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE)
            return rc;
        /* Committed (perhaps not persisted): this client's staging is
         * now the committed set. */
        free(s->stage[in->unit]);
        s->stage[in->unit] = NULL;
        if (rc != 0)
            return rc;
    } else {
        rc = apply(s, in, wl);
        if (rc == 0 && wl->command == 1) {
            free(s->stage[in->unit]);
            s->stage[in->unit] = NULL;
        }
        pthread_mutex_unlock(&d->regs_mx);
        if (rc != 0)
            return MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE;
    }
    if (wl->command != 0)
        pfd_audit_command(&s->who, in->unit, wl->command);
    if (wl->command == 2)
        __atomic_add_fetch(&in->reset_req, 1u, __ATOMIC_ACQ_REL);
    else if (wl->command == 3)
        __atomic_add_fetch(&in->stats_req, 1u, __ATOMIC_ACQ_REL);
    if (wl->tick && pfd_loop_tick(d, in, wl->tick) != 0)
        return -1;
    return 0;
}

/* Decode and apply a write of @p cnt registers from @p addr, whose values
 * start at @p payload. @return 0, > 0 MODBUS_EXCEPTION_*, -1 drop. */
static int write_regs(pfd_daemon *d, pfd_session *s, pfd_inst *in, unsigned addr,
                      unsigned cnt, const uint8_t *payload)
{
    uint16_t vals[MODBUS_MAX_WRITE_REGISTERS];
    pfd_wlist wl;
    unsigned i;
    int rc;

    if (d->set.read_only) {
        pfd_audit_refused(&s->who, in->unit, addr, cnt, MODBUS_EXCEPTION_ILLEGAL_FUNCTION,
                          "read-only");
        return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    }
    for (i = 0; i < cnt; i++)
        vals[i] = (uint16_t)be16(payload + 2 * i);
    rc = pfd_regmap_decode(addr, cnt, vals, d->set.word_order, &wl);
    if (rc != 0) {
        pfd_audit_refused(&s->who, in->unit, addr, cnt, rc,
                          rc == MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS ? "address" : "value");
        return rc;
    }
    return execute(d, s, in, &wl, addr, cnt);
}

/* The registers [addr, addr+cnt) of @p space after a read: byte count,
 * then the values. @return the answer's length. */
static int read_answer(pfd_daemon *d, pfd_session *s, pfd_inst *in, int space,
                       unsigned addr, unsigned cnt, const uint8_t *req, uint8_t *rsp)
{
    uint16_t img[PFD_INPUT_SIZE > PFD_HOLD_SIZE ? PFD_INPUT_SIZE : PFD_HOLD_SIZE];
    unsigned i;

    render(d, s, in, space, img);
    rsp[7] = req[7];
    rsp[8] = (uint8_t)(2 * cnt);
    for (i = 0; i < cnt; i++)
        put16(rsp + 9 + 2 * i, img[addr + i]);
    return answer(req, rsp, 2 + 2 * cnt);
}

int pfd_request(pfd_daemon *d, pfd_session *s, const uint8_t *req, int len, uint8_t *rsp)
{
    const uint8_t *pdu = req + PFD_MBAP_LEN;
    const unsigned fc = req[7], pdu_len = (unsigned)(len - PFD_MBAP_LEN);
    pfd_inst *in = d->by_unit[req[6]];
    unsigned addr, cnt, waddr, wcnt;
    int rc;

    if (in == NULL)
        return exception(req, rsp, MODBUS_EXCEPTION_GATEWAY_TARGET);
    if (s->who.access < PFD_ACCESS_READ)
        return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);

    switch (fc) {
    case MODBUS_FC_READ_HOLDING_REGISTERS:
    case MODBUS_FC_READ_INPUT_REGISTERS: {
        int space = fc == MODBUS_FC_READ_HOLDING_REGISTERS ? PFD_HOLD : PFD_INPUT;
        unsigned size = space == PFD_HOLD ? PFD_HOLD_SIZE : PFD_INPUT_SIZE;
        if (pdu_len != 5)
            return -1;
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        if (cnt < 1 || cnt > MODBUS_MAX_READ_REGISTERS)
            return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        if (addr + cnt > size)
            return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
        return read_answer(d, s, in, space, addr, cnt, req, rsp);
    }
    case MODBUS_FC_WRITE_SINGLE_REGISTER:
        if (pdu_len != 5)
            return -1;
        rc = write_regs(d, s, in, be16(pdu + 1), 1, pdu + 3);
        if (rc != 0)
            return rc < 0 ? -1 : exception(req, rsp, rc);
        memcpy(rsp, req, (size_t)len); /* the echo */
        return len;
    case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
        if (pdu_len < 6)
            return -1;
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        if (cnt < 1 || cnt > MODBUS_MAX_WRITE_REGISTERS || pdu[5] != cnt * 2 ||
            pdu_len != 6 + cnt * 2)
            return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        rc = write_regs(d, s, in, addr, cnt, pdu + 6);
        if (rc != 0)
            return rc < 0 ? -1 : exception(req, rsp, rc);
        memcpy(rsp, req, PFD_MBAP_LEN + 5); /* function, address, count */
        return answer(req, rsp, 5);
    case MODBUS_FC_WRITE_AND_READ_REGISTERS:
        if (pdu_len < 10)
            return -1;
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        waddr = be16(pdu + 5);
        wcnt = be16(pdu + 7);
        if (cnt < 1 || cnt > MODBUS_MAX_WR_READ_REGISTERS || wcnt < 1 ||
            wcnt > MODBUS_MAX_WR_WRITE_REGISTERS || pdu[9] != wcnt * 2 ||
            pdu_len != 10 + wcnt * 2)
            return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        if (addr + cnt > PFD_HOLD_SIZE)
            return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
        rc = write_regs(d, s, in, waddr, wcnt, pdu + 10);
        if (rc != 0)
            return rc < 0 ? -1 : exception(req, rsp, rc);
        /* The read comes after the write, as the function code says, and
         * reads what a following FC03 would. */
        return read_answer(d, s, in, PFD_HOLD, addr, cnt, req, rsp);
    default:
        /* Including 0x80 and up, which libmodbus 3.1.6 answered with bit
         * 7 lost (FC 0x83 got 03 01). */
        return exception(req, rsp, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    }
}

void pfd_session_end(pfd_daemon *d, pfd_session *s)
{
    int i;

    pthread_mutex_lock(&d->regs_mx);
    for (i = 0; i < d->n; i++) {
        pfd_inst *in = d->inst[i];
        if (in->param_lock && in->lock_holder == s->who.id)
            pfd_release_lock(in, &s->who, "released-at-disconnect");
    }
    pthread_mutex_unlock(&d->regs_mx);
    for (i = 0; i < 256; i++) {
        free(s->stage[i]);
        s->stage[i] = NULL;
    }
}
