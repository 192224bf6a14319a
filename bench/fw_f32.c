/* SPDX-License-Identifier: MIT */
/*
 * Float counterpart of port/cortex-m/example_isr.c, linked by bench/run.sh
 * only to measure the flash of each configuration's float controller on a
 * Cortex-M4F. The coefficient set comes from
 *   pneufrac design --config CFG --fs 20000 --arith float --format c --name pf_coeffs_f32
 */
#include <stdint.h>

#include "pneufrac/pf_controller.h"
#include "pf_coeffs_f32.h"

#define ADC_DATA (*(volatile float *)0x40012440u)
#define DAC_DATA (*(volatile float *)0x40007408u)

static pf_ctrl_f32 controller;

void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    DAC_DATA = pf_ctrl_step_f32(&controller, ADC_DATA);
}

/* The linker script's entry point; the image is measured, never run, so
 * no data or bss initialisation is needed. */
void Reset_Handler(void);
void Reset_Handler(void)
{
    (void)pf_ctrl_init_f32(&controller, &pf_coeffs_f32, 0, 0);
    TIM2_IRQHandler();
    for (;;) {
    }
}
