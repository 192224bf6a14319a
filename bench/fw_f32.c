/* SPDX-License-Identifier: MIT */
/*
 * Float counterpart of port/cortex-m/example_isr.c, linked by bench/run.sh
 * only to measure the flash of each configuration's float controller on a
 * Cortex-M4F. The coefficient set comes from
 *   pneufrac design --config CFG --fs 20000 --arith float --format c --name pf_coeffs_f32
 * or, with -DPF_EXAMPLE_BANK, its reduced-order bank from
 *   pneufrac-reduce --config CFG --fs 20000 --arith float --format c --name pf_coeffs_f32
 */
#include <stdint.h>

#ifdef PF_EXAMPLE_BANK
#include "pneufrac/pf_bank.h"
#include "pf_coeffs_f32.h"
static pf_bank_f32 controller;
#define CONTROLLER_INIT() pf_bank_init_f32(&controller, &pf_coeffs_f32, 0, 0)
#define CONTROLLER_STEP(e) pf_bank_step_f32(&controller, (e))
#else
#include "pneufrac/pf_controller.h"
#include "pf_coeffs_f32.h"
static pf_ctrl_f32 controller;
#define CONTROLLER_INIT() pf_ctrl_init_f32(&controller, &pf_coeffs_f32, 0, 0)
#define CONTROLLER_STEP(e) pf_ctrl_step_f32(&controller, (e))
#endif

#define ADC_DATA (*(volatile float *)0x40012440u)
#define DAC_DATA (*(volatile float *)0x40007408u)

void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    DAC_DATA = CONTROLLER_STEP(ADC_DATA);
}

/* The linker script's entry point; the image is measured, never run, so
 * no data or bss initialisation is needed. */
void Reset_Handler(void);
void Reset_Handler(void)
{
    (void)CONTROLLER_INIT();
    TIM2_IRQHandler();
    for (;;) {
    }
}
