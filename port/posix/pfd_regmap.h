/* SPDX-License-Identifier: MIT */
/*
 * THE register map: one table (pfd_regs) that the server validates every
 * request against and from which `pneufracd --print-register-map` writes
 * docs/register-map.md. Every instance (unit id) has the same map.
 *
 * Encoding: 32-bit floats are IEEE-754 binary32 over two registers, u32
 * likewise, in the daemon's word order (--word-order): high word first
 * (ABCD, the default) or low word first (CDAB, which some SCADA systems
 * expect). Floats are packed here by hand: the float helpers of libmodbus
 * 3.1.6 are not used.
 */
#ifndef PFD_REGMAP_H
#define PFD_REGMAP_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "pfd_state.h"

#define PFD_REGMAP_VERSION 2

enum pfd_space { PFD_HOLD = 0, PFD_INPUT = 1 };
enum pfd_type { PFD_T_U16 = 0, PFD_T_I16, PFD_T_U32, PFD_T_F32 };
enum pfd_access { PFD_R = 0, PFD_RW, PFD_W };

/** The order of the two registers of a 32-bit value (f32, u32); within a
 *  register the bytes are big-endian, as Modbus has it. */
enum pfd_word_order {
    PFD_WORDS_ABCD = 0, /**< high word first (mbpoll -B) */
    PFD_WORDS_CDAB = 1, /**< low word first (mbpoll's default) */
    PFD_WORDS_COUNT
};

/** "abcd" or "cdab" (the option's and the config key's words). */
const char *pfd_word_order_name(int order);

/* pfd_reg.flags */
#define PFD_F_STAGED 0x01u  /**< staged parameter: each client's own (pfd_stage.h) */
#define PFD_F_REFRESH 0x02u /**< a write refreshes the watchdog */
#define PFD_F_ACTION 0x04u  /**< commit, command, tick: acts, reads as 0 */
#define PFD_F_LIVE 0x10u    /**< goes to the loop at once */
#define PFD_F_OPERATE 0x20u /**< the operate access may write it (else only
                                 engineer; pfd_access.h) */
#define PFD_F_OPEN 0x40u    /**< stays writable under another client's
                                 param_lock: the process inputs and tick */

/** Sizes of the two register spaces (every address below is mapped). */
#define PFD_HOLD_SIZE 67
#define PFD_INPUT_SIZE 86

/** A register. One that stages or mirrors a parameter of the library
 *  (param >= 0) takes its range, and its unit and description where the
 *  row gives none, from the library's parameter table (pf_param_info): use
 *  the accessors below, not min, max, unit and desc directly. */
typedef struct pfd_reg {
    uint8_t space, type, access, flags;
    uint16_t addr;
    uint16_t field;  /* what it reads or writes (pfd_regmap.c) */
    int16_t param;   /* pf_param_id, or PFD_NO_PARAM */
    double min, max; /* accepted write range (param < 0) */
    const char *name, *unit, *desc; /* unit, desc NULL: the library's */
} pfd_reg;

#define PFD_NO_PARAM (-1)

extern const pfd_reg pfd_regs[];
extern const unsigned pfd_nregs;

/** Number of registers a type spans. */
unsigned pfd_type_words(int type);

/** The entry whose registers contain @p addr, or NULL. */
const pfd_reg *pfd_reg_at(int space, unsigned addr);

/** The entry of @p space named @p name, or NULL. */
const pfd_reg *pfd_reg_named(int space, const char *name);

/** The write range of @p r: [min, max], or (min, max] when min_excl. */
double pfd_reg_min(const pfd_reg *r);
double pfd_reg_max(const pfd_reg *r);
int pfd_reg_min_excl(const pfd_reg *r);

/** The unit and the description of @p r (without the "staged: " or
 *  "committed: " that the register map adds to a parameter's). */
const char *pfd_reg_unit(const pfd_reg *r);
const char *pfd_reg_desc(const pfd_reg *r);

/** Whether a write of @p v is in @p r's range: finite, and within
 *  [min, max], or (min, max] when min_excl (for a library parameter:
 *  pf_param_check). */
int pfd_reg_in_range(const pfd_reg *r, double v);

/** That range as text, "[min .. max]" or "(min .. max]" (min_excl). */
void pfd_reg_format_range(const pfd_reg *r, char *buf, size_t n);

/** Everything a read can show. */
typedef struct pfd_view {
    const pfd_inst *inst;   /* committed, commit status */
    const pfd_hold *hold;   /* the holding registers as this client sees them */
    const pfd_snap *snap;   /* the loop's latest sample */
    uint16_t status;        /* composed status bits (pfd_modbus.c) */
    uint16_t n_instances;
    int word_order;         /* enum pfd_word_order */
} pfd_view;

/** Every register of @p space into @p img (PFD_HOLD_SIZE or PFD_INPUT_SIZE words). */
void pfd_regmap_render(int space, const pfd_view *v, uint16_t *img);

/** One decoded, range-checked write. */
typedef struct pfd_write {
    const pfd_reg *r;
    double v;   /* the value (integers exactly) */
} pfd_write;

typedef struct pfd_wlist {
    pfd_write w[128];
    unsigned n;
    unsigned staged, refresh, live, lock; /* any write of that kind */
    unsigned guarded;                     /* any register a lock closes */
    int access;                           /* the access the request needs */
    uint16_t commit, command, tick;       /* action values; 0 = none */
} pfd_wlist;

/** Decode holding registers [addr, addr+count) from @p vals, whose 32-bit
 *  values are in @p word_order (enum pfd_word_order). Every
 *  register must be mapped and writable and every 32-bit field written
 *  whole (else MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS); every value must be
 *  in range (else MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE).
 *  @return 0 or the exception code; nothing is applied here. */
int pfd_regmap_decode(unsigned addr, unsigned count, const uint16_t *vals,
                      int word_order, pfd_wlist *out);

/** Whether the int16 mirror writes of @p wl, converted with @p committed's
 *  in_fs, land inside the range of the f32 register each one writes (e_i16
 *  writes e, ...). The raw int16 is always in its own range; what it
 *  means is not: with in_fs = 1e12, e_i16 = 32767 would set e = 1e12,
 *  past e's documented 1e9. Checked where in_fs is known, under regs_mx.
 *  @return NULL, or the first mirror register whose value is out of range
 *  (for the refusal's log). */
const pfd_reg *pfd_regmap_check_mirrors(const pfd_wlist *wl, const pfd_iparams *committed);

/** Apply the data writes (not the actions) of @p wl to @p h. The int16
 *  mirrors convert with @p committed's in_fs. */
void pfd_regmap_apply(pfd_hold *h, const pfd_iparams *committed,
                      const pfd_wlist *wl);

/** What holding data register @p r (not an action) reads from @p h; the
 *  int16 mirrors convert with @p committed's in_fs. */
double pfd_regmap_hold_value(const pfd_reg *r, const pfd_hold *h,
                             const pfd_iparams *committed);

/** Holding address of the staged register for a pfd_fail parameter id,
 *  or 0xFFFF. */
uint16_t pfd_regmap_staged_addr(int param);

/** The Markdown table of docs/register-map.md. */
void pfd_regmap_print_md(FILE *f);

/** A 32-bit value into, or out of, two registers in @p word_order. */
void pfd_u32_pack(uint32_t u, int word_order, uint16_t *w);
uint32_t pfd_u32_unpack(const uint16_t *w, int word_order);
void pfd_f32_pack(float v, int word_order, uint16_t *w);
float pfd_f32_unpack(const uint16_t *w, int word_order);

#endif
