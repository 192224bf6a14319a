/* SPDX-License-Identifier: MIT */
/*
 * Firmware example: the paper's Example 6 (FrDD) as a Q15 controller run
 * from a sampling interrupt, everything allocated statically.
 *
 * The coefficient set comes from the host, exported as a header by
 *   pneufrac design --config dd --fs 20000 --in-fs 1 --out-fs 0.01 --format c
 * so the firmware needs no libm, no FPU and no design code. The image is
 * linked by scripts/firmware-check.sh to measure flash and RAM.
 */
#include <stdint.h>

#include "pneufrac/pf_controller.h"
#include "pf_example6_q15.h" /* defines pf_example6_q15 (pf_ctrl_coeffs_q15) */

/* Memory-mapped I/O stand-ins: an ADC result and a DAC/PWM duty register. */
#define ADC_DATA (*(volatile int16_t *)0x40012440u)
#define DAC_DATA (*(volatile int16_t *)0x40007408u)

static pf_ctrl_q15 controller;

/* Sampling interrupt at 20 kHz: one Q15 sample in, one out. The step is
 * total (saturates, never fails), so the ISR has no error path. */
void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    DAC_DATA = pf_ctrl_step_q15(&controller, ADC_DATA);
}

int main(void);
int main(void)
{
    /* No dead time in Example 6: no delay buffer. */
    if (pf_ctrl_init_q15(&controller, &pf_example6_q15, 0, 0) != PF_OK)
        for (;;) {
        }
    for (;;) {
        /* the sampling timer interrupt does the work */
    }
}

/* Minimal start-up so the image links as a real one would. */
extern uint32_t _estack, _sdata, _edata, _sidata, _sbss, _ebss;
void Reset_Handler(void);
void Reset_Handler(void)
{
    uint32_t *src = &_sidata, *dst = &_sdata;
    while (dst < &_edata)
        *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss;)
        *dst++ = 0;
    (void)main();
    for (;;) {
    }
}

__attribute__((section(".isr_vector"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))(&_estack), Reset_Handler, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, /* 16 system exceptions */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, TIM2_IRQHandler,
};
