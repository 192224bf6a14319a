/* SPDX-License-Identifier: MIT */
/*
 * Firmware example: the paper's Example 6 (FrDD) in Q15, run from a
 * sampling interrupt, everything allocated statically. The coefficient set
 * comes from the host as a header, so the firmware needs no libm, no FPU
 * and no design code. Two builds (scripts/firmware-check.sh links both,
 * with startup.c, to measure flash and RAM):
 *
 *  - the full controller (default), every Oustaloup section and the exact
 *    loop solution, as the library designs it; backlash and saturation can
 *    be switched on in its coefficient set:
 *      pneufrac design --config dd --fs 20000 --arith q15 --in-fs 1 --out-fs 0.01 --format c
 *    which needs pf_fracop_q15.c, pf_ctrl_q15.c and pf_nozzle_q15.c;
 *
 *  - -DPF_EXAMPLE_BANK: the same linear controller reduced on the host to
 *    the fewest states whose step response stays within 0.05 % of the full
 *    one's peak over 10 s (pf_bank.h): about 19 times fewer cycles per
 *    sample on a Cortex-M0+ (docs/benchmarks.md), no 64-bit helper; no in-loop
 *    effects:
 *      pneufrac-reduce --config dd --fs 20000 --in-fs 1 --out-fs 0.01 --format c
 *    which needs pf_bank_q15.c only.
 */
#include <stdint.h>

#ifdef PF_EXAMPLE_BANK
#include "pneufrac/pf_bank.h"
#include "pf_example6_bank.h" /* defines pf_example6_bank (pf_bank_coeffs_q15) */
static pf_bank_q15 controller;
#define CONTROLLER_INIT() pf_bank_init_q15(&controller, &pf_example6_bank, 0, 0)
#define CONTROLLER_STEP(e) pf_bank_step_q15(&controller, (e))
#else
#include "pneufrac/pf_controller.h"
#include "pf_example6_q15.h" /* defines pf_example6_q15 (pf_ctrl_coeffs_q15) */
static pf_ctrl_q15 controller;
#define CONTROLLER_INIT() pf_ctrl_init_q15(&controller, &pf_example6_q15, 0, 0)
#define CONTROLLER_STEP(e) pf_ctrl_step_q15(&controller, (e))
#endif

/* Memory-mapped I/O stand-ins: an ADC result and a DAC/PWM duty register. */
#define ADC_DATA (*(volatile int16_t *)0x40012440u)
#define DAC_DATA (*(volatile int16_t *)0x40007408u)

/* Sampling interrupt at 20 kHz: one Q15 sample in, one out. The step is
 * total (saturates, never fails), so the ISR has no error path. */
void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    DAC_DATA = CONTROLLER_STEP(ADC_DATA);
}

int main(void);
int main(void)
{
    /* No dead time in Example 6: no delay buffer. */
    if (CONTROLLER_INIT() != PF_OK)
        for (;;) {
        }
    for (;;) {
        /* the sampling timer interrupt does the work */
    }
}
