/* SPDX-License-Identifier: MIT */
/**
 * @file pf_config.h
 * @brief Compile-time limits of pneufrac, overridable before inclusion
 *        (define them on the compiler command line or in a header named by
 *        PF_CONFIG_HEADER), in the style of lwIP's opt.h.
 *
 * They size the instance structs, so static allocation needs no malloc.
 */
#ifndef PNEUFRAC_PF_CONFIG_H
#define PNEUFRAC_PF_CONFIG_H

#ifdef PF_CONFIG_HEADER
#include PF_CONFIG_HEADER
#endif

/** Largest Oustaloup order N accepted by the design (2N+1 zero/pole pairs). */
#ifndef PF_MAX_ORDER
#define PF_MAX_ORDER 8
#endif

/** Largest number of first-order sections one operator may use:
 *  2N+1 from the product, plus 2 for the refined variant's correction factor. */
#define PF_MAX_SEC (2 * PF_MAX_ORDER + 3)

/** Largest number of sections of a Q15 operator: the Q15 runtime holds the
 *  Oustaloup realisation (2N+1 sections); the refined variant's two extra
 *  ones are float/double only, so Q15 instances and coefficient sets are
 *  sized by this. */
#define PF_Q15_MAX_SEC (2 * PF_MAX_ORDER + 1)

/** Most states of a reduced-order bank (pf_bank.h): real sections plus two
 *  per complex pair. Sizes its instances and coefficient sets; Example 6
 *  needs 11 at pneufrac-reduce's defaults, 16 for 2e-5 of its peak
 *  (docs/accuracy.md). */
#ifndef PF_BANK_MAX_ORDER
#define PF_BANK_MAX_ORDER 16
#endif

/** Pieces of the Q15 nozzle curve's table (pf_nozzle_q15), each a cubic
 *  through the curve: 38 bytes each, in a table apart from the
 *  coefficient set, so only a design with a nozzle holds one. 32 keep the
 *  curve within 2^-16 of its span for the paper's loop gains (the bound:
 *  docs/architecture.md, "Effects in Q15"). 0 leaves the curve out of the
 *  Q15 runtime, and its code out of the firmware:
 *  pf_ctrl_coeffs_q15_make_nz then refuses a nozzle (PF_E_UNSUPPORTED),
 *  and an exported table does not compile. Otherwise at least 4. */
#ifndef PF_Q15_NOZZLE_SEG
#define PF_Q15_NOZZLE_SEG 32
#endif

/** The table's room in pieces: at least one, as C has no empty arrays. */
#define PF_Q15_NOZZLE_CAP (PF_Q15_NOZZLE_SEG > 0 ? PF_Q15_NOZZLE_SEG : 1)

/** Largest |integer part| of an operator order (|alpha| < 2 rounds to <= 2). */
#define PF_MAX_INT 2

#endif /* PNEUFRAC_PF_CONFIG_H */
